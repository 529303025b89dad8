/* ----------------------------------------------------------------------
   USER-NCF: engine-free orientation statistics of chain segments (see ncf_orient.h)
------------------------------------------------------------------------- */

#include "ncf_orient.h"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace NCF {

static constexpr double RAD2DEG = 57.295779513082320876;
static constexpr int NHEAD = 10;

double axial_deviation(double dx, double dy, double nominal_deg)
{
  double d = std::atan2(dy, dx) * RAD2DEG - nominal_deg;
  // axes: fold into (-90, 90]
  d = std::fmod(d, 180.0);
  if (d <= -90.0) d += 180.0;
  if (d > 90.0) d -= 180.0;
  return d;
}

OrientStats::OrientStats(int nbins, double range) :
    nb(nbins), range_deg(range), sums(NHEAD + nbins, 0.0)
{
}

void OrientStats::add(double dx, double dy, double dz, double nominal_deg)
{
  const double lp = std::sqrt(dx * dx + dy * dy);
  const double l = std::sqrt(lp * lp + dz * dz);
  if (!(l > 0.0)) return;
  // orientation tensor of the 3D direction, weighted by the 3D length
  const double n[3] = {dx / l, dy / l, dz / l};
  sums[3] += l * n[0] * n[0];
  sums[4] += l * n[1] * n[1];
  sums[5] += l * n[2] * n[2];
  sums[6] += l * n[0] * n[1];
  sums[7] += l * n[0] * n[2];
  sums[8] += l * n[1] * n[2];
  if (!(lp > 0.0)) return;    // a vertical segment has no in-plane angle
  const double d = axial_deviation(dx, dy, nominal_deg);
  sums[0] += lp;
  sums[1] += lp * d;
  sums[2] += lp * d * d;
  if (std::fabs(d) > range_deg) {
    sums[9] += lp;
    return;
  }
  int b = (int) std::floor((d + range_deg) / (2.0 * range_deg) * nb);
  if (b >= nb) b = nb - 1;
  if (b < 0) b = 0;
  sums[NHEAD + b] += lp;
}

double OrientStats::mean() const
{
  return sums[0] > 0.0 ? sums[1] / sums[0] : 0.0;
}

double OrientStats::stddev() const
{
  if (!(sums[0] > 0.0)) return 0.0;
  const double m = mean(), v = sums[2] / sums[0] - m * m;
  return v > 0.0 ? std::sqrt(v) : 0.0;
}

double OrientStats::outside_fraction() const
{
  return sums[0] > 0.0 ? sums[9] / sums[0] : 0.0;
}

double OrientStats::bin_centre(int b) const
{
  return -range_deg + (b + 0.5) * 2.0 * range_deg / nb;
}

double OrientStats::density(int b) const
{
  const double width = 2.0 * range_deg / nb;
  return sums[0] > 0.0 ? sums[NHEAD + b] / (sums[0] * width) : 0.0;
}

void OrientStats::tensor(double a[3][3]) const
{
  double w = sums[3] + sums[4] + sums[5];    // sum of l (trace of sum l n n)
  if (!(w > 0.0)) w = 1.0;
  a[0][0] = sums[3] / w;
  a[1][1] = sums[4] / w;
  a[2][2] = sums[5] / w;
  a[0][1] = a[1][0] = sums[6] / w;
  a[0][2] = a[2][0] = sums[7] / w;
  a[1][2] = a[2][1] = sums[8] / w;
}

namespace {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solve(const OrientStats &s)
  {
    double a[3][3];
    s.tensor(a);
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) m(i, j) = a[i][j];
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m);
  }
}    // namespace

double OrientStats::principal_angle() const
{
  const auto es = solve(*this);
  const Eigen::Vector3d v = es.eigenvectors().col(2);    // eigenvalues in increasing order
  double ang = std::atan2(v(1), v(0)) * RAD2DEG;
  ang = std::fmod(ang, 180.0);
  if (ang < 0.0) ang += 180.0;
  return ang;    // axis angle in [0, 180)
}

double OrientStats::principal_value() const
{
  return solve(*this).eigenvalues()(2);
}

}    // namespace NCF
