// Unit tests of the engine-free needle contact (ncf_needle.h): force = -dE/dx by finite
// differences, force balance between chain and needle, monotonic force with penetration, radial
// push next to and exactly on the axis, continuity at the apex and the shoulder, no NaN.

#include "ncf_needle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using NCF::Needle;
using NCF::needle_contact;
using NCF::NeedleContact;
using NCF::Vec3;

namespace {

const double R = 0.25e-3, TIP = 0.3e-3, RC = 34.5e-6, KN = 2e9;

Needle needle(double zapex = 0.0, int direction = -1)
{
  Needle n;
  n.x = 1.0e-3;
  n.y = 2.0e-3;
  n.zapex = zapex;
  n.direction = direction;
  n.radius = R;
  n.tip = TIP;
  n.length = 2e-3;
  return n;
}

bool finite(const NeedleContact &c)
{
  bool ok = std::isfinite(c.energy) && std::isfinite(c.penetration);
  for (int d = 0; d < 3; d++)
    ok = ok && std::isfinite(c.f[0][d]) && std::isfinite(c.f[1][d]) && std::isfinite(c.fneedle[d]);
  return ok;
}

Vec3 total(const NeedleContact &c)
{
  return c.f[0] + c.f[1];
}

// point at distance r from the axis in direction phi, height z
Vec3 at(const Needle &n, double r, double phi, double z)
{
  return {n.x + r * std::cos(phi), n.y + r * std::sin(phi), z};
}

// a straight chain p0-p1 cut into m segments: node forces (the sum over its segments)
struct Chain {
  std::vector<Vec3> x, f;
  double energy = 0.0;
  bool finite = true;
};
Chain chain(const Vec3 &p0, const Vec3 &p1, int m, const Needle &n)
{
  Chain c;
  for (int k = 0; k <= m; k++) c.x.push_back(NCF::lerp(p0, p1, double(k) / m));
  c.f.assign(m + 1, Vec3());
  for (int k = 0; k < m; k++) {
    const NeedleContact s = needle_contact(c.x[k], c.x[k + 1], RC, n, KN);
    c.finite = c.finite && finite(s);
    c.f[k] += s.f[0];
    c.f[k + 1] += s.f[1];
    c.energy += s.energy;
  }
  return c;
}
Vec3 total(const Chain &c)
{
  Vec3 t;
  for (const Vec3 &f : c.f) t += f;
  return t;
}

}    // namespace

TEST(NeedleProfile, RadiusAlongTheNeedle)
{
  const Needle n = needle(0.0, -1);
  double d;
  EXPECT_DOUBLE_EQ(NCF::needle_radius(n, 0.0, &d), 0.0);    // apex
  EXPECT_DOUBLE_EQ(d, R / TIP);
  EXPECT_DOUBLE_EQ(NCF::needle_radius(n, 0.5 * TIP), 0.5 * R);      // linear point
  EXPECT_DOUBLE_EQ(NCF::needle_radius(n, -0.5 * TIP), -0.5 * R);    // extended below the apex
  EXPECT_DOUBLE_EQ(NCF::needle_radius(n, 1.2 * TIP, &d), R);        // shaft
  EXPECT_EQ(d, 0.0);
  EXPECT_DOUBLE_EQ(NCF::needle_radius(n, n.length - 0.5 * TIP), 0.5 * R);    // mirrored far end
  // direction up: the point looks up, the shaft is below the apex
  const Needle up = needle(0.0, 1);
  EXPECT_DOUBLE_EQ(NCF::needle_radius(up, -0.5 * TIP, &d), 0.5 * R);
  EXPECT_DOUBLE_EQ(d, -R / TIP);
  // the rounded shoulder: radius and slope continuous at both of its ends and in between
  const double b = NCF::NEEDLE_SHOULDER;
  for (double t : {1.0 - b, 1.0, 1.0 + b}) {
    const double eps = 1e-9 * TIP;
    double d1, d2;
    const double r1 = NCF::needle_radius(n, t * TIP - eps, &d1);
    const double r2 = NCF::needle_radius(n, t * TIP + eps, &d2);
    EXPECT_NEAR(r1, r2, 3 * eps * R / TIP) << t;
    EXPECT_NEAR(d1, d2, 1e-6 * R / TIP) << t;
    EXPECT_LE(NCF::needle_radius(n, t * TIP), R);
  }
  // the slope is the derivative of the radius all along, the far (mirrored) end included, for
  // both directions
  for (const Needle &m : {n, up})
    for (double u : {0.3, 0.7, 0.95, 1.5, 5.0}) {
      for (double z : {-m.direction * u * TIP, -m.direction * (m.length - u * TIP)}) {
        const double h = 1e-7 * TIP;
        double slope;
        NCF::needle_radius(m, z, &slope);
        const double fd = (NCF::needle_radius(m, z + h) - NCF::needle_radius(m, z - h)) / (2 * h);
        EXPECT_NEAR(slope, fd, 1e-6 * R / TIP) << "direction " << m.direction << ", z " << z;
      }
    }
}

TEST(NeedleContact, ForceIsMinusTheEnergyGradient)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int tested = 0;
  for (int trial = 0; trial < 400; trial++) {
    const Needle n = needle(U(rng) * 0.4e-3, trial % 3 == 0 ? 1 : -1);
    // segments around the point and the shaft, of every inclination and length
    const double len = (0.05 + 0.5 * (1 + U(rng))) * 1e-3;
    const Vec3 c = at(n, std::fabs(U(rng)) * 1.2 * (R + RC), M_PI * U(rng),
                      n.zapex - n.direction * (0.1 + 0.5 * U(rng)) * 1e-3);
    Vec3 dir{U(rng), U(rng), (trial % 4 == 0 ? 1.0 : 0.2) * U(rng)};
    dir = (1.0 / NCF::norm(dir)) * dir;
    Vec3 x[2] = {c - (0.5 * len + 0.3 * len * U(rng)) * dir, c + 0.5 * len * dir};
    const NeedleContact ct = needle_contact(x[0], x[1], RC, n, KN);
    ASSERT_TRUE(finite(ct));
    if (!ct.active) continue;
    tested++;
    const double h = 1e-6 * R, scale = KN * (R + RC) * len;
    for (int a = 0; a < 2; a++)
      for (int d = 0; d < 3; d++) {
        Vec3 p[2] = {x[0], x[1]}, m[2] = {x[0], x[1]};
        double *pp = &p[a].x, *mm = &m[a].x;
        pp[d] += h;
        mm[d] -= h;
        const double fd = -(needle_contact(p[0], p[1], RC, n, KN).energy -
                            needle_contact(m[0], m[1], RC, n, KN).energy) /
            (2 * h);
        EXPECT_NEAR(ct.f[a][d], fd, 1e-5 * scale)
            << "trial " << trial << " node " << a << " d " << d;
      }
  }
  EXPECT_GT(tested, 150);
}

TEST(NeedleContact, ForcesBalanceAndNoMomentAboutTheAxis)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int tested = 0;
  for (int trial = 0; trial < 200; trial++) {
    const Needle n = needle(0.0, -1);
    const Vec3 c = at(n, std::fabs(U(rng)) * (R + RC), M_PI * U(rng), 0.3e-3 * (1 + U(rng)));
    const Vec3 dir{U(rng), U(rng), 0.3 * U(rng)};
    const Vec3 x0 = c - 0.2e-3 * dir, x1 = c + 0.3e-3 * dir;
    const NeedleContact ct = needle_contact(x0, x1, RC, n, KN);
    if (!ct.active) continue;
    tested++;
    const Vec3 s = total(ct) + ct.fneedle;
    const double scale = NCF::norm(ct.fneedle) + NCF::norm(ct.f[0]) + NCF::norm(ct.f[1]);
    EXPECT_NEAR(NCF::norm(s), 0.0, 1e-14 * scale);
    // a body of revolution takes no moment about its own axis
    const Vec3 axis{n.x, n.y, 0.0};
    const double mz = NCF::cross(x0 - axis, ct.f[0]).z + NCF::cross(x1 - axis, ct.f[1]).z;
    EXPECT_NEAR(mz, 0.0, 1e-10 * scale * (R + RC)) << trial;
  }
  EXPECT_GT(tested, 100);
  // a whole chain (ends out of reach) is pushed away from the axis and, by a point looking
  // down, not up (single segments also carry end terms along themselves that cancel in a chain)
  for (int trial = 0; trial < 200; trial++) {
    const Needle n = needle(0.0, -1);
    const Vec3 c = at(n, std::fabs(U(rng)) * (R + RC), M_PI * U(rng), 0.3e-3 * (1 + U(rng)));
    const double phi = M_PI * U(rng);
    const Vec3 dir{std::cos(phi), std::sin(phi), 0.2 * U(rng)};
    const Chain ch = chain(c - 0.8e-3 * dir, c + 0.7e-3 * dir, 7, n);
    ASSERT_TRUE(ch.finite);
    const Vec3 f = total(ch);
    // horizontal offset of the chain's line from the axis
    const Vec3 s = NCF::cross(Vec3(0, 0, 1), Vec3(dir.x, dir.y, 0.0));
    const double side = (c.x - n.x) * s.x + (c.y - n.y) * s.y;
    EXPECT_GE(side * (f.x * s.x + f.y * s.y), -1e-9 * KN * R * R * std::fabs(side)) << trial;
    EXPECT_LE(f.z, 1e-9 * KN * R * R) << trial;
  }
}

TEST(NeedleContact, ParallelToTheShaftForceIsKnGLUpToTheAxis)
{
  // a vertical segment along the shaft at distance d: F = kn (R + rc - d) L, radial, growing
  // monotonically all the way to the axis
  const Needle n = needle(-1e-3, -1);
  const double L = 0.2e-3, phi = 0.7;
  double last = 0.0;
  for (double d : {R + RC, 0.28e-3, 0.2e-3, 0.1e-3, 1e-5, 1e-7, 1e-9 * R, 0.0}) {
    const Vec3 x0 = at(n, d, phi, 0.0), x1 = at(n, d, phi, L);
    const NeedleContact c = needle_contact(x0, x1, RC, n, KN);
    ASSERT_TRUE(finite(c));
    const Vec3 f = total(c);
    const double g = R + RC - d;
    EXPECT_NEAR(NCF::norm(f), KN * g * L, 1e-12 * KN * R * L) << d;
    EXPECT_NEAR(f.z, 0.0, 1e-12 * KN * R * L);
    if (d > 0.0) {
      // radial (to the round-off of the position, 1e-16 m / d)
      EXPECT_NEAR(f.x, KN * g * L * std::cos(phi), 1e-5 * KN * R * L) << d;
      EXPECT_NEAR(f.y, KN * g * L * std::sin(phi), 1e-5 * KN * R * L) << d;
    } else {
      EXPECT_NEAR(f.x, KN * g * L, 1e-12 * KN * R * L);    // on the axis: +x, deterministic
    }
    EXPECT_GE(NCF::norm(f), last);
    last = NCF::norm(f);
  }
  EXPECT_GT(last, 0.9 * KN * (R + RC) * L);    // full force on the axis (the old law: zero)
}

TEST(NeedleContact, RadialSegmentPushedOutMonotonically)
{
  // a horizontal segment pointing radially away from the axis, its inner node at distance d,
  // at a height on the point of the needle: the radial force grows as d falls, down to 1e-9 R
  const Needle n = needle(-0.15e-3, -1);
  const double phi = -2.1, L = 0.2e-3;
  double last = 0.0;
  for (double d : {0.15e-3, 0.1e-3, 0.05e-3, 1e-5, 1e-6, 1e-9 * R}) {
    const Vec3 x0 = at(n, d, phi, 0.0), x1 = at(n, d + L, phi, 0.0);
    const NeedleContact c = needle_contact(x0, x1, RC, n, KN);
    ASSERT_TRUE(finite(c));
    ASSERT_TRUE(c.active) << d;
    const Vec3 f = total(c);
    const double radial = f.x * std::cos(phi) + f.y * std::sin(phi);
    const double side = -f.x * std::sin(phi) + f.y * std::cos(phi);
    EXPECT_GT(radial, last) << d;
    EXPECT_NEAR(side, 0.0, 1e-9 * radial) << d;
    EXPECT_LT(f.z, 0.0);    // the point pushes down as well
    // the node near the axis pushed outward along the segment
    EXPECT_GT(c.f[0].x * std::cos(phi) + c.f[0].y * std::sin(phi), 0.5 * radial) << d;
    last = radial;
  }
}

TEST(NeedleContact, ChainOffsetByABillionthOfRIsPushedOut)
{
  // A straight chain crossing the shaft 1e-9 R from the axis. Moving its nodes along itself does
  // not change the chain, so the push acts sideways: away from the axis, growing with the offset
  // (the crossing through the axis is an unstable equilibrium: a negative sideways stiffness of
  // order 2 kn g ln(c / offset)), and zero exactly through it.
  const Needle n = needle(-1e-3, -1);
  for (double phi : {0.0, 0.4, 2.0}) {
    const Vec3 t{std::cos(phi), std::sin(phi), 0.0}, s{-std::sin(phi), std::cos(phi), 0.0};
    const Vec3 axis = at(n, 0.0, 0.0, 0.0);
    double last = 0.0;
    for (double off : {1e-9 * R, 1e-7 * R, 1e-5 * R, 1e-3 * R, 0.1 * R, 0.3 * R}) {
      const Vec3 base = axis + off * s;
      const Chain c = chain(base - 0.65e-3 * t, base + 0.55e-3 * t, 12, n);
      ASSERT_TRUE(c.finite);
      const double side = NCF::dot(total(c), s);
      EXPECT_GT(side, last) << off;
      EXPECT_GT(side / off, 2.0 * KN * R) << off;    // negative stiffness of at least 2 kn R
      for (const Vec3 &f : c.f) EXPECT_NEAR(f.z, 0.0, 1e-12 * KN * R * R);
      last = side;
    }
    const Chain c0 = chain(axis - 0.65e-3 * t, axis + 0.55e-3 * t, 12, n);
    ASSERT_TRUE(c0.finite);
    EXPECT_NEAR(NCF::dot(total(c0), s), 0.0, 1e-9 * KN * R * R);
  }
}

TEST(NeedleContact, HingedChainOffsetByABillionthOfREscapesSideways)
{
  // the same chain as a string of lumped masses (0.1 mm elements, 69 um carbon, stiff axial
  // springs, free hinges) held across the shaft: it leaves the needle sideways, to the side of
  // its offset, within a few microseconds
  const Needle n = needle(-1e-3, -1);
  const double l = 0.1e-3, m = 1800 * M_PI * RC * RC * l, ka = 120e9 * M_PI * RC * RC / l;
  const double dt = 0.2 * std::sqrt(m / ka);
  const int N = 13;
  std::vector<Vec3> x(N), v(N), f(N);
  for (int k = 0; k < N; k++) x[k] = at(n, 0.0, 0.0, 0.0) + Vec3((k - 6.5) * l, 1e-9 * R, 0.0);
  auto forces = [&]() {
    for (auto &q : f) q = Vec3();
    double e = 0.0;
    for (int k = 0; k + 1 < N; k++) {
      const NeedleContact c = needle_contact(x[k], x[k + 1], RC, n, KN);
      f[k] += c.f[0];
      f[k + 1] += c.f[1];
      e += c.energy;
      const Vec3 d = x[k + 1] - x[k];
      const double len = NCF::norm(d), fs = ka * (len - l);
      f[k] += (fs / len) * d;
      f[k + 1] -= (fs / len) * d;
    }
    return e;
  };
  forces();
  const double e0 = forces();
  ASSERT_GT(e0, 0.0);
  double e = e0;
  int steps = 0;
  for (; steps < 200000 && e > 0.0; steps++) {
    for (int k = 0; k < N; k++) {
      v[k] += (dt / m) * f[k];
      v[k] = 0.999 * v[k];    // light damping
      x[k] += dt * v[k];
    }
    e = forces();
  }
  EXPECT_EQ(e, 0.0) << "still in contact after " << steps * dt << " s";
  for (const Vec3 &q : x) {
    EXPECT_TRUE(std::isfinite(q.y));
    EXPECT_GT(q.y - n.y, 0.0);    // every node went to the side of the offset
  }
  std::printf("hinged chain 1e-9 R off the axis: out of the needle after %d steps, %.3g us\n",
              steps, 1e6 * steps * dt);
}

TEST(NeedleContact, ChainUnderThePointIsPushedOutAndDown)
{
  // a horizontal chain under the descending point, a little off the axis: outward (sideways)
  // and down along the cone's normal, never up or inward; the horizontal push grows as the
  // point comes down
  const double off = 0.05e-3;
  double last = 0.0;
  for (double zapex : {-0.03e-3, -0.05e-3, -0.1e-3, -0.2e-3, -0.3e-3, -0.5e-3}) {
    const Needle n = needle(zapex, -1);
    const Vec3 x0{n.x - 0.4e-3, n.y + off, 0.0}, x1{n.x + 0.4e-3, n.y + off, 0.0};
    const NeedleContact c = needle_contact(x0, x1, RC, n, KN);
    ASSERT_TRUE(finite(c));
    ASSERT_TRUE(c.active) << zapex;
    const Vec3 f = total(c);
    EXPECT_GT(f.y, last) << zapex;
    EXPECT_LE(f.z, 0.0);
    last = f.y;
  }
}

TEST(NeedleContact, ContinuousAcrossApexAndShoulder)
{
  // a chain held at offset 0.3 R while the needle moves through it in small steps: energy and
  // forces change by O(step), no jump where the apex, the contact's onset or the shoulder pass
  const double step = 1e-9;
  Needle n = needle(0.0, -1);
  const Vec3 x0{n.x - 0.3e-3, n.y + 0.3 * R, 0.0}, x1{n.x + 0.35e-3, n.y + 0.3 * R, 0.0};
  NeedleContact prev = needle_contact(x0, x1, RC, n, KN);
  double maxjump = 0.0, fmax = 0.0;
  for (double z = 0.05e-3; z > -0.5e-3; z -= step * 37) {
    n.zapex = z;
    const NeedleContact c = needle_contact(x0, x1, RC, n, KN);
    ASSERT_TRUE(finite(c));
    const double jump = NCF::norm(total(c) - total(prev)) + NCF::norm(c.f[0] - prev.f[0]);
    maxjump = std::max(maxjump, jump);
    fmax = std::max(fmax, NCF::norm(total(c)));
    prev = c;
  }
  EXPECT_GT(fmax, 1.0);
  // force change per step of 37 nm: bounded by the contact stiffness times the step
  EXPECT_LT(maxjump, 20 * KN * 1e-3 * step * 37) << fmax;
  // across the shoulder in particular (chain at the height where the point meets the shaft)
  for (double t : {1.0 - NCF::NEEDLE_SHOULDER, 1.0, 1.0 + NCF::NEEDLE_SHOULDER}) {
    Needle a = needle(-t * TIP - 1e-10), b = needle(-t * TIP + 1e-10);
    const NeedleContact ca = needle_contact(x0, x1, RC, a, KN),
                        cb = needle_contact(x0, x1, RC, b, KN);
    EXPECT_NEAR(total(ca).z, total(cb).z, 1e-5 * NCF::norm(total(ca))) << t;
    EXPECT_NEAR(total(ca).y, total(cb).y, 1e-5 * NCF::norm(total(ca))) << t;
  }
}

TEST(NeedleContact, DegenerateInputsStayFinite)
{
  const Needle n = needle(-1e-3, -1);
  const Vec3 axis = at(n, 0.0, 0.0, 0.0);
  const Vec3 cases[][2] = {
      {axis, axis},                                              // zero length on the axis
      {axis, axis + Vec3(0, 0, 1e-4)},                           // along the axis
      {axis, axis + Vec3(1e-4, 0, 0)},                           // starting on the axis
      {axis - Vec3(1e-4, 0, 0), axis + Vec3(1e-4, 0, 0)},        // through the axis, symmetric
      {axis + Vec3(0, 0, 1e-300), axis + Vec3(1e-300, 0, 0)},    // tiny
      {axis + Vec3(1e-200, 0, 0), axis + Vec3(0, 0, 1e-4)},
      {axis - Vec3(1e-4, 1e-4, 0), axis + Vec3(1e-4, 1e-4, 1e-300)},
  };
  for (const auto &s : cases) {
    for (int flip = 0; flip < 2; flip++) {
      const NeedleContact c = needle_contact(s[flip], s[1 - flip], RC, n, KN);
      EXPECT_TRUE(finite(c)) << s[0].x << " " << s[1].x;
    }
  }
  // exactly on the axis the direction does not depend on the order of the nodes
  const NeedleContact a = needle_contact(axis, axis + Vec3(0, 0, 1e-4), RC, n, KN);
  const NeedleContact b = needle_contact(axis + Vec3(0, 0, 1e-4), axis, RC, n, KN);
  EXPECT_GT(a.f[0].x, 0.0);
  EXPECT_DOUBLE_EQ(a.f[0].x, b.f[1].x);
  EXPECT_DOUBLE_EQ(a.f[1].x, b.f[0].x);
  // a chain exactly through the axis: its nodes pushed apart, no sideways force
  const Chain c = chain(axis - Vec3(0.55e-3, 0, 0), axis + Vec3(0.45e-3, 0, 0), 10, n);
  ASSERT_TRUE(c.finite);
  EXPECT_LT(c.f[5].x, 0.0);    // node at x = -0.05 mm
  EXPECT_GT(c.f[6].x, 0.0);    // node at x = +0.05 mm
  EXPECT_NEAR(total(c).y, 0.0, 1e-12 * std::fabs(c.f[6].x));
}

TEST(NeedleContact, OutOfReachAndMeshIndependence)
{
  const Needle n = needle(-1e-3, -1);
  // horizontally out of reach, above the needle's end, below its point
  EXPECT_FALSE(
      needle_contact(at(n, R + RC + 1e-9, 0.0, 0.0), at(n, R + 2e-4, 0.0, 0.0), RC, n, KN).active);
  EXPECT_FALSE(needle_contact(at(n, 0.1 * R, 0.0, 1.01e-3 + RC * TIP / R),
                              at(n, 0.1 * R, 1.0, 1.02e-3), RC, n, KN)
                   .active);
  EXPECT_FALSE(needle_contact(at(n, 0.0, 0.0, -1e-3 - RC * TIP / R - 1e-9),
                              at(n, 0.1 * R, 0.0, -1.1e-3), RC, n, KN)
                   .active);
  // a straight chain across the shaft cut into 1, 2 or 5 segments: the same energy and force
  // on the chain to within the quadrature error (8 Gauss points: below 0.5 %)
  const Vec3 p0{n.x - 0.5e-3, n.y + 0.4 * R, 0.0}, p1{n.x + 0.6e-3, n.y + 0.4 * R, 0.0};
  double e1 = 0.0, f1 = 0.0;
  for (int m : {1, 2, 5}) {
    double e = 0.0, fy = 0.0;
    for (int k = 0; k < m; k++) {
      const NeedleContact c = needle_contact(NCF::lerp(p0, p1, double(k) / m),
                                             NCF::lerp(p0, p1, double(k + 1) / m), RC, n, KN);
      e += c.energy;
      fy += total(c).y;
    }
    if (m == 1) e1 = e, f1 = fy;
    EXPECT_NEAR(e, e1, 5e-3 * e1) << m;
    EXPECT_NEAR(fy, f1, 5e-3 * f1) << m;
    EXPECT_GT(fy, 0.0);
  }
}
