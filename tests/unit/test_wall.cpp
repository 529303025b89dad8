// Unit tests of the node-plane contact (ncf_wall.h) and its use of the shared friction law.

#include "ncf_contact.h"
#include "ncf_wall.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace NCF;

TEST(Wall, PenetrationAndForceBothSides)
{
  // lower plate at z = 0, node of radius 34.5 um at 30 um: g = 4.5 um
  auto lo = plane_contact(30e-6, 34.5e-6, 0.0, +1, 1e7, 2e-4, 0.0, 0.0);
  EXPECT_TRUE(lo.contact);
  EXPECT_NEAR(lo.penetration, 4.5e-6, 1e-18);
  EXPECT_NEAR(lo.force, 1e7 * 2e-4 * 4.5e-6, 1e-15);
  // upper plate at z = 1 mm, node at 1 mm - 30 um
  auto up = plane_contact(1e-3 - 30e-6, 34.5e-6, 1e-3, -1, 1e7, 2e-4, 0.0, 0.0);
  EXPECT_NEAR(up.penetration, 4.5e-6, 1e-15);
  EXPECT_NEAR(up.force, lo.force, 1e-12);
  // out of contact
  EXPECT_FALSE(plane_contact(40e-6, 34.5e-6, 0.0, +1, 1e7, 2e-4, 0.0, 0.0).contact);
}

TEST(Wall, ForceIsMinusEnergyDerivative)
{
  const double kn = 3e7, l = 1.5e-4, r = 34.5e-6, h = 1e-12;
  for (double z : {1e-6, 20e-6, 34e-6}) {
    auto e = [&](double zz) {
      return plane_contact(zz, r, 0.0, +1, kn, l, 0.0, 0.0).energy;
    };
    const double fd = -(e(z + h) - e(z - h)) / (2 * h);    // force along +z on the node
    EXPECT_NEAR(plane_contact(z, r, 0.0, +1, kn, l, 0.0, 0.0).force, fd, 1e-6 * std::fabs(fd));
  }
}

TEST(Wall, DampingResistsApproachAndNeverPulls)
{
  const double kn = 1e7, l = 2e-4, c = 50.0;
  // node moving down into the lower plate: more force
  auto in = plane_contact(30e-6, 34.5e-6, 0.0, +1, kn, l, c, -1.0);
  auto out = plane_contact(30e-6, 34.5e-6, 0.0, +1, kn, l, c, +1.0);
  EXPECT_GT(in.force, out.force);
  // leaving fast: damping would pull, the force is clipped at zero
  auto fast = plane_contact(34e-6, 34.5e-6, 0.0, +1, kn, l, c, +100.0);
  EXPECT_EQ(fast.force, 0.0);
}

TEST(Wall, FrictionSticksThenSlidesAtMuFn)
{
  Vec3 slip, n{0, 0, 1};
  const double kt = 1e3, fn = 2e-3, mu = 0.3, dt = 1e-7;
  // small tangential motion: elastic, below mu fn
  auto r1 = friction_step(slip, n, Vec3{1e-2, 0, 0}, dt, kt, fn, mu);
  EXPECT_FALSE(r1.sliding);
  EXPECT_NEAR(r1.force.x, -kt * 1e-9, 1e-18);
  // keep moving: the force saturates at mu fn, opposite to the motion
  FrictionResult r;
  for (int k = 0; k < 10000; k++) r = friction_step(slip, n, Vec3{1e-2, 0, 0}, dt, kt, fn, mu);
  EXPECT_TRUE(r.sliding);
  EXPECT_NEAR(r.force.x, -mu * fn, 1e-15);
  EXPECT_NEAR(r.force.z, 0.0, 1e-20);
}

// ---------------------------------------------------------------- holes in a plate

TEST(WallHoles, WeightIsZeroInsideOneOutsideAndContinuousOnTheRim)
{
  const double cx[1] = {1e-3}, cy[1] = {2e-3}, R = 0.3e-3, rim = 34.5e-6;
  auto w = [&](double rho) {
    return hole_weight(1e-3 + rho, 2e-3, cx, cy, 1, R, rim, 0, 0).w;
  };
  EXPECT_EQ(w(0.0), 0.0);
  EXPECT_EQ(w(R), 0.0);
  EXPECT_EQ(w(R + rim), 1.0);
  EXPECT_EQ(w(1e-3), 1.0);
  EXPECT_NEAR(w(R + 0.5 * rim), 0.5, 1e-12);
  // continuous at both ends of the rim, and rising across it
  EXPECT_NEAR(w(R + 1e-12), 0.0, 1e-12);
  EXPECT_NEAR(w(R + rim - 1e-12), 1.0, 1e-12);
  double prev = 0.0;
  for (int k = 1; k <= 20; k++) {
    const double v = w(R + rim * k / 20.0);
    EXPECT_GT(v, prev);
    prev = v;
  }
  // no holes: the plate everywhere
  EXPECT_EQ(hole_weight(0.0, 0.0, cx, cy, 0, R, rim, 0, 0).w, 1.0);
}

TEST(WallHoles, InPlaneForceIsMinusTheEnergyGradient)
{
  // a node on the rim of the nearer of two holes, in a periodic plane, pressed into the lower
  // plate: energy w(x, y) E(z); the force the fix applies is -E grad w in the plane, w F along z
  const double cx[2] = {0.2e-3, 1.4e-3}, cy[2] = {0.1e-3, 0.9e-3}, R = 0.25e-3, rim = 34.5e-6;
  const double lx = 2e-3, ly = 1.2e-3, kn = 2e9, l = 2e-4, r = 34.5e-6, h = 1e-11;
  auto energy = [&](double x, double y, double z) {
    return hole_weight(x, y, cx, cy, 2, R, rim, lx, ly).w *
        plane_contact(z, r, 0.0, +1, kn, l, 0.0, 0.0).energy;
  };
  // the hole at (0.2, 0.1) mm reached through the periodic images across both corners
  const double rho = R + 0.37 * rim, ang = 2.4;
  const double x = 0.2e-3 + rho * std::cos(ang) + lx, y = 0.1e-3 + rho * std::sin(ang) + ly;
  const double z = 25e-6;
  const auto hw = hole_weight(x, y, cx, cy, 2, R, rim, lx, ly);
  ASSERT_GT(hw.w, 0.0);
  ASSERT_LT(hw.w, 1.0);
  const auto c = plane_contact(z, r, 0.0, +1, kn, l, 0.0, 0.0);
  const double f[3] = {-c.energy * hw.gx, -c.energy * hw.gy, hw.w * c.force};
  const double fd[3] = {-(energy(x + h, y, z) - energy(x - h, y, z)) / (2 * h),
                        -(energy(x, y + h, z) - energy(x, y - h, z)) / (2 * h),
                        -(energy(x, y, z + h) - energy(x, y, z - h)) / (2 * h)};
  for (int d = 0; d < 3; d++) EXPECT_NEAR(f[d], fd[d], 1e-6 * std::fabs(fd[d]) + 1e-15) << d;
  // it pulls toward the hole's centre (the energy is lower over the hole)
  EXPECT_LT(f[0] * std::cos(ang) + f[1] * std::sin(ang), 0.0);
}

TEST(WallHoles, OverlapOfRimsAndOfPeriodicImagesIsFound)
{
  const double R = 0.3e-3, rim = 50e-6;
  const double cx[2] = {1e-3, 1e-3 + 2 * (R + rim) + 1e-9}, cy[2] = {1e-3, 1e-3};
  EXPECT_FALSE(holes_overlap(cx, cy, 2, R, rim, 0, 0));
  const double cx2[2] = {1e-3, 1e-3 + 2 * (R + rim) - 1e-9};
  EXPECT_TRUE(holes_overlap(cx2, cy, 2, R, rim, 0, 0));
  // apart in the box, but close through the periodic image in x
  const double cx3[2] = {0.1e-3, 4.9e-3};
  EXPECT_TRUE(holes_overlap(cx3, cy, 2, R, rim, 5e-3, 0));
  EXPECT_FALSE(holes_overlap(cx3, cy, 2, R, rim, 0, 0));
  // one hole in a box narrower than the hole and its rim overlaps its own image
  EXPECT_TRUE(holes_overlap(cx, cy, 1, R, rim, 0.6e-3, 0));
  EXPECT_FALSE(holes_overlap(cx, cy, 1, R, rim, 0.8e-3, 0.8e-3));
}
