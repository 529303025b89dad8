// Unit tests of the engine-free geometry kernel (ncf_geometry.h): closest points of two segments
// for crossing, skew, parallel, collinear, touching and degenerate (zero-length) segments.

#include "ncf_geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using NCF::closest_points_segments;
using NCF::Vec3;

namespace {
struct Case {
  const char *name;
  Vec3 p0, p1, q0, q1;
  double s, t, dist;
};
}    // namespace

TEST(Geometry, ClosestPointsTable)
{
  const Case cases[] = {
      {"crossing at right angles", {-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}, 0.5, 0.5, 1.0},
      {"skew, ends clamp", {0, 0, 0}, {1, 0, 0}, {2, -1, 1}, {2, 1, 1}, 1.0, 0.5, std::sqrt(2.0)},
      {"axes touching", {-1, 0, 0}, {1, 0, 0}, {0.5, -1, 0}, {0.5, 1, 0}, 0.75, 0.5, 0.0},
      {"parallel overlap -> middle of overlap",
       {0, 0, 0},
       {4, 0, 0},
       {1, 0, 2},
       {7, 0, 2},
       0.625,
       (2.5 - 1.0) / 6.0,
       2.0},
      {"parallel, no overlap",
       {0, 0, 0},
       {1, 0, 0},
       {3, 1, 0},
       {5, 1, 0},
       1.0,
       0.0,
       std::sqrt(5.0)},
      {"anti-parallel overlap", {0, 0, 0}, {2, 0, 0}, {3, 0, 1}, {1, 0, 1}, 0.75, 0.75, 1.0},
      {"collinear, separated", {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, 1.0, 0.0, 1.0},
      {"point vs segment", {0.3, 1, 0}, {0.3, 1, 0}, {0, 0, 0}, {1, 0, 0}, 0.0, 0.3, 1.0},
      {"segment vs point", {0, 0, 0}, {2, 0, 0}, {3, 0, 0}, {3, 0, 0}, 1.0, 0.0, 1.0},
      {"point vs point", {0, 0, 0}, {0, 0, 0}, {0, 3, 4}, {0, 3, 4}, 0.0, 0.0, 5.0},
  };
  for (const auto &c : cases) {
    auto cp = closest_points_segments(c.p0, c.p1, c.q0, c.q1);
    EXPECT_NEAR(cp.s, c.s, 1e-12) << c.name;
    EXPECT_NEAR(cp.t, c.t, 1e-12) << c.name;
    EXPECT_NEAR(std::sqrt(cp.dist2), c.dist, 1e-12) << c.name;
  }
}

TEST(Geometry, ClosestPointsAreAMinimumOverRandomSegments)
{
  // brute force: no sampled pair of points is closer than the returned pair
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 300; trial++) {
    Vec3 p0(u(rng), u(rng), u(rng)), p1(u(rng), u(rng), u(rng));
    Vec3 q0(u(rng), u(rng), u(rng)), q1(u(rng), u(rng), u(rng));
    if (trial % 3 == 0) q1 = q0 + (p1 - p0) * 0.7;    // parallel
    if (trial % 5 == 0) q1 = q0;                      // degenerate
    auto cp = closest_points_segments(p0, p1, q0, q1);
    ASSERT_GE(cp.s, 0.0);
    ASSERT_LE(cp.s, 1.0);
    ASSERT_GE(cp.t, 0.0);
    ASSERT_LE(cp.t, 1.0);
    const Vec3 a = NCF::lerp(p0, p1, cp.s), b = NCF::lerp(q0, q1, cp.t);
    EXPECT_NEAR(NCF::norm2(a - b), cp.dist2, 1e-12);
    double best = 1e300;
    for (int i = 0; i <= 200; i++)
      for (int j = 0; j <= 200; j++)
        best =
            std::min(best, NCF::norm2(NCF::lerp(p0, p1, i / 200.0) - NCF::lerp(q0, q1, j / 200.0)));
    EXPECT_LE(std::sqrt(cp.dist2), std::sqrt(best) + 1e-12) << "trial " << trial;
  }
}

TEST(Geometry, ClosestPointsContinuousTowardsParallel)
{
  // rotating one segment towards parallel: the distance changes continuously
  const Vec3 p0(0, 0, 0), p1(1, 0, 0);
  double prev = -1.0;
  for (int k = 0; k <= 60; k++) {
    const double ang = (k < 60) ? 1e-1 * std::pow(0.5, k) : 0.0;
    const Vec3 q0(0.2, 0, 0.5), q1 = q0 + Vec3(std::cos(ang), std::sin(ang), 0.0);
    auto cp = closest_points_segments(p0, p1, q0, q1);
    const double d = std::sqrt(cp.dist2);
    if (prev >= 0.0) EXPECT_NEAR(d, prev, 0.1 * std::pow(0.5, k - 1) + 1e-14);
    EXPECT_NEAR(d, 0.5, 0.2);
    prev = d;
  }
}

// the point-segment distance is the general closest-point search with a point for the second
// segment, and no farther than either end or the foot of the perpendicular when it lies inside
TEST(Geometry, PointSegmentDistanceMatchesClosestPoints)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 2000; k++) {
    const Vec3 p0(u(rng), u(rng), u(rng)), p1(u(rng), u(rng), u(rng)), q(u(rng), u(rng), u(rng));
    const double d2 = NCF::point_segment_dist2(p0, p1, q);
    EXPECT_NEAR(d2, NCF::closest_points_segments(p0, p1, q, q).dist2, 1e-14);
    EXPECT_LE(d2, NCF::norm2(q - p0) + 1e-15);
    EXPECT_LE(d2, NCF::norm2(q - p1) + 1e-15);
  }
  // the foot inside: distance from the line
  EXPECT_NEAR(NCF::point_segment_dist2(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 3, 4)), 25.0, 1e-12);
  // beyond an end, and a degenerate segment
  EXPECT_NEAR(NCF::point_segment_dist2(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(5, 4, 0)), 25.0, 1e-12);
  EXPECT_NEAR(NCF::point_segment_dist2(Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 4)), 9.0, 1e-12);
}
