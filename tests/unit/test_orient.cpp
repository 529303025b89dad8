// Unit tests of the orientation statistics (ncf_orient.h).

#include "ncf_orient.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace NCF;

static const double DEG = M_PI / 180.0;

TEST(Orient, DeviationIsAnAxisAngle)
{
  EXPECT_NEAR(axial_deviation(1, 0, 0), 0.0, 1e-12);
  EXPECT_NEAR(axial_deviation(-1, 0, 0), 0.0, 1e-12);    // reversed segment, same axis
  EXPECT_NEAR(axial_deviation(1, 1, 45), 0.0, 1e-12);
  EXPECT_NEAR(axial_deviation(-1, -1, 45), 0.0, 1e-12);
  EXPECT_NEAR(axial_deviation(1, 1, -45), 90.0, 1e-12);
  EXPECT_NEAR(axial_deviation(0, 1, 0), 90.0, 1e-12);
  EXPECT_NEAR(axial_deviation(std::cos(2 * DEG), std::sin(2 * DEG), 0), 2.0, 1e-12);
  EXPECT_NEAR(axial_deviation(-std::cos(2 * DEG), -std::sin(2 * DEG), 0), 2.0, 1e-12);
  EXPECT_NEAR(axial_deviation(std::cos(88 * DEG), std::sin(88 * DEG), 90), -2.0, 1e-12);
  EXPECT_NEAR(axial_deviation(-std::cos(92 * DEG), -std::sin(92 * DEG), 90), 2.0, 1e-12);
}

TEST(Orient, GaussianSampleGivesItsMeanAndStd)
{
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.5, 3.0);
  OrientStats s(60, 15.0);
  double sum = 0, sum2 = 0;
  const int n = 20000;
  for (int i = 0; i < n; i++) {
    const double a = g(rng);
    sum += a;
    sum2 += a * a;
    s.add(2e-4 * std::cos(a * DEG), 2e-4 * std::sin(a * DEG), 0.0, 0.0);
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(s.mean(), mean, 1e-9);
  EXPECT_NEAR(s.stddev(), sd, 1e-9);
  // the density integrates to the share inside the range
  double integral = 0;
  for (int b = 0; b < s.nbins(); b++) integral += s.density(b) * 2 * s.range() / s.nbins();
  EXPECT_NEAR(integral + s.outside_fraction(), 1.0, 1e-12);
  // peak of the density near the mean, value near 1/(sqrt(2 pi) sigma)
  int best = 0;
  for (int b = 0; b < s.nbins(); b++)
    if (s.density(b) > s.density(best)) best = b;
  EXPECT_NEAR(s.bin_centre(best), 0.5, 1.0);
  EXPECT_NEAR(s.density(best), 1.0 / (std::sqrt(2 * M_PI) * 3.0), 0.012);
  // aligned fibres: principal axis at the mean angle, eigenvalue close to 1
  EXPECT_NEAR(s.principal_angle(), 0.5, 0.1);
  EXPECT_GT(s.principal_value(), 0.99);
}

TEST(Orient, SegmentsAreWeightedByLengthSoTheMeshDoesNotMatter)
{
  OrientStats coarse(30, 10.0), fine(30, 10.0);
  const double a = 3 * DEG, b = -1 * DEG;
  coarse.add(4e-4 * std::cos(a), 4e-4 * std::sin(a), 0, 0);
  coarse.add(2e-4 * std::cos(b), 2e-4 * std::sin(b), 0, 0);
  for (int k = 0; k < 4; k++) fine.add(1e-4 * std::cos(a), 1e-4 * std::sin(a), 0, 0);
  for (int k = 0; k < 2; k++) fine.add(1e-4 * std::cos(b), 1e-4 * std::sin(b), 0, 0);
  EXPECT_NEAR(coarse.mean(), fine.mean(), 1e-12);
  EXPECT_NEAR(coarse.stddev(), fine.stddev(), 1e-12);
  for (int k = 0; k < 30; k++) EXPECT_NEAR(coarse.density(k), fine.density(k), 1e-9);
  EXPECT_NEAR(coarse.mean(), (2 * 3.0 + 1 * -1.0) / 3, 1e-12);
}

TEST(Orient, PrincipalAxisOfAMinus45Layer)
{
  OrientStats s(10, 10.0);
  for (double d : {-1.0, 0.0, 1.0}) {
    const double t = (-45 + d) * DEG;
    s.add(std::cos(t), std::sin(t), 0.05, -45);
  }
  EXPECT_NEAR(s.principal_angle(), 135.0, 0.01);    // the axis -45 deg, as an angle in [0, 180)
  EXPECT_NEAR(s.mean(), 0.0, 1e-12);
}
