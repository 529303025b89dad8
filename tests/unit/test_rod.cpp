// Unit tests of the engine-free rod kernel (ncf_rod.h): analytic values, finite-difference
// force = -dE/dr, compression options, the critical time step.

#include "ncf_rod.h"

#include <gtest/gtest.h>

#include <cmath>

using NCF::rod_force;
using NCF::RodParams;

TEST(Rod, AnalyticTensionAndEnergy)
{
  RodParams p{450.0, 0.0, 1.0};
  const double l0 = 2.0e-4, r = 2.02e-4;    // 1 % strain
  auto res = rod_force(p, l0, r);
  EXPECT_NEAR(res.axial, 450.0 * 0.01, 1e-12);
  EXPECT_NEAR(res.energy, 0.5 * (450.0 / l0) * 2e-6 * 2e-6, 1e-15);
  // LAMMPS convention: force on node 1 is fpair * (x1 - x2): a stretched bond pulls node 1 back
  EXPECT_NEAR(res.fpair * r, -res.axial, 1e-12);
}

TEST(Rod, ShrinkMovesTheRestLength)
{
  RodParams p{10.0, 0.16, 1.0};
  const double l0 = 1.0;
  EXPECT_NEAR(rod_force(p, l0, 0.84).axial, 0.0, 1e-14);
  // stiffness stays EA / L0 (not EA / (L0 (1 - s)))
  EXPECT_NEAR(rod_force(p, l0, 0.94).axial, 10.0 * 0.1, 1e-12);
}

class RodFD : public ::testing::TestWithParam<std::tuple<double, double, double>> {};

TEST_P(RodFD, ForceIsMinusEnergyDerivative)
{
  auto [shrink, compression, strain] = GetParam();
  RodParams p{123.0, shrink, compression};
  const double l0 = 3.0e-4;
  const double r = l0 * (1.0 - shrink) * (1.0 + strain);
  const double h = 1e-6 * l0;
  const double dE = (rod_force(p, l0, r + h).energy - rod_force(p, l0, r - h).energy) / (2 * h);
  const double f = rod_force(p, l0, r).axial;    // = dE/dr
  EXPECT_NEAR(f, dE, 1e-6 * std::fabs(f) + 1e-9) << "shrink " << shrink << " c " << compression
                                                  << " strain " << strain;
}

INSTANTIATE_TEST_SUITE_P(Grid, RodFD,
                         ::testing::Combine(::testing::Values(0.0, 0.17),
                                            ::testing::Values(1.0, 0.3, 0.0),
                                            ::testing::Values(-0.02, -1e-3, 2e-3, 0.05)));

TEST(Rod, TensionOnlyCarriesNoCompression)
{
  RodParams p{10.0, 0.0, 0.0};
  auto res = rod_force(p, 1.0, 0.9);
  EXPECT_EQ(res.axial, 0.0);
  EXPECT_EQ(res.energy, 0.0);
  EXPECT_GT(rod_force(p, 1.0, 1.1).axial, 0.0);
}

TEST(Rod, CoincidentNodesGiveFiniteValues)
{
  RodParams p{10.0, 0.0, 1.0};
  auto res = rod_force(p, 1.0, 0.0);
  EXPECT_TRUE(std::isfinite(res.fpair));
  EXPECT_EQ(res.fpair, 0.0);
  EXPECT_NEAR(res.energy, 5.0, 1e-14);
}

TEST(Rod, CriticalTimeStepIsLengthOverWaveSpeed)
{
  // E = 120 GPa, rho = 905 kg/m^3, d = 69 um, L0 = 0.2 mm: c = 11515 m/s, dt_c = 17.4 ns
  const double E = 120e9, rho = 905.0, A = M_PI * 0.25 * 69e-6 * 69e-6, l0 = 2e-4;
  const double dt = NCF::rod_critical_dt(l0, E * A, rho * A);
  EXPECT_NEAR(dt, l0 / std::sqrt(E / rho), 1e-20);
  EXPECT_NEAR(dt, 1.7368e-8, 1e-11);
}
