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
    auto e = [&](double zz) { return plane_contact(zz, r, 0.0, +1, kn, l, 0.0, 0.0).energy; };
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
