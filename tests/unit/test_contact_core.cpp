// Unit tests of the two options of the contact law (ncf_contact.h, ContactOptions): the stiff core
// that keeps the force per length rising for deep penetrations, and the extension of segments at
// free chain ends (end caps). Force = -dE/dx by finite differences with both options, force and
// moment balance, the force curve of two parallel chains, and the coverage of a crossing at a
// free end compared with one in the middle of the chains.

#include "ncf_contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

using NCF::ContactOptions;
using NCF::segment_contact;
using NCF::Vec3;

namespace {

const double D = 69e-6;          // contact distance (equal diameters 69 um)
const double KN = 1e7;           // normal stiffness per length [Pa]
const double RAMP = 0.25 * D;    // ramp half-width
const double KAPPA = 10.0;       // core stiffness factor

double &coord(Vec3 &v, int d)
{
  return d == 0 ? v.x : (d == 1 ? v.y : v.z);
}

// compares forces f[k] with -dE/dx of energy() by central differences, and checks force and
// moment balance
void check_gradient(std::vector<Vec3> x, const std::vector<Vec3> &f,
                    const std::function<double(const std::vector<Vec3> &)> &energy,
                    const std::string &what)
{
  double fmax = 0.0;
  Vec3 fsum, msum;
  for (size_t k = 0; k < x.size(); k++) {
    fmax = std::max(fmax, NCF::norm(f[k]));
    fsum += f[k];
    msum += NCF::cross(x[k], f[k]);
  }
  ASSERT_GT(fmax, 0.0) << what;
  EXPECT_LT(NCF::norm(fsum), 1e-11 * fmax) << what;
  EXPECT_LT(NCF::norm(msum), 1e-11 * fmax * 2e-4) << what;
  const double h = 1e-7 * D;
  for (size_t k = 0; k < x.size(); k++)
    for (int d = 0; d < 3; d++) {
      std::vector<Vec3> xp = x, xm = x;
      coord(xp[k], d) += h;
      coord(xm[k], d) -= h;
      const double fd = -(energy(xp) - energy(xm)) / (2.0 * h);
      EXPECT_NEAR(f[k][d], fd, 2e-6 * fmax) << what << " node " << k << " dim " << d;
    }
}

// force per unit length between two long parallel straight chains (mesh 0.1 mm, 2 mm long) at
// axis distance r, measured on the middle 1 mm of chain A (no end effects)
double parallel_force_per_length(double r, double core)
{
  const double mesh = 1e-4;
  const int n = 20;
  ContactOptions opt;
  opt.core = core;
  double fz = 0.0;
  for (int i = 5; i < 15; i++)
    for (int j = 0; j < n; j++) {
      const Vec3 a0(i * mesh, 0, r), a1((i + 1) * mesh, 0, r);
      const Vec3 b0(j * mesh, 0, 0), b1((j + 1) * mesh, 0, 0);
      const auto c = segment_contact(a0, a1, b0, b1, D, KN, RAMP, false, opt);
      if (c.active) fz += c.f[0].z + c.f[1].z;
    }
  return fz / (10 * mesh);
}

}    // namespace

TEST(ContactCore, ForceIsMinusEnergyGradientDeepInside)
{
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int in_core = 0, tested = 0;
  for (int trial = 0; trial < 600 && tested < 150; trial++) {
    const double L = 2e-4;
    std::vector<Vec3> x(4);
    x[0] = Vec3(-0.5 * L, 0.0, 0.0) + 0.2 * L * Vec3(u(rng), u(rng), u(rng));
    x[1] = Vec3(0.5 * L, 0.0, 0.0) + 0.2 * L * Vec3(u(rng), u(rng), u(rng));
    const double ang = (trial % 3 == 0) ? 1e-3 * u(rng) : 1.5 * u(rng);
    const Vec3 dir(std::cos(ang), std::sin(ang), 0.0);
    // distances from 0.05 D to 0.95 D: deep inside the core as well
    const Vec3 c = Vec3(0.3 * L * u(rng), 0.3 * L * u(rng), D * (0.5 + 0.45 * u(rng)));
    x[2] = c - 0.5 * L * dir;
    x[3] = c + 0.5 * L * dir;
    ContactOptions opt;
    opt.core = KAPPA;
    // free ends on some of the four nodes
    for (int k = 0; k < 4; k++) opt.ext[k] = (trial >> k) & 1 ? 0.5 * D : 0.0;
    const auto res = segment_contact(x[0], x[1], x[2], x[3], D, KN, RAMP, true, opt);
    if (!res.active) continue;
    tested++;
    if (res.penetration > (1.0 - NCF::CORE_FRACTION) * D) in_core++;
    auto energy = [&](const std::vector<Vec3> &y) {
      return segment_contact(y[0], y[1], y[2], y[3], D, KN, RAMP, false, opt).energy;
    };
    check_gradient(x, {res.f[0], res.f[1], res.f[2], res.f[3]}, energy,
                   "trial " + std::to_string(trial));
  }
  EXPECT_GE(tested, 120);
  EXPECT_GE(in_core, 30);    // the core was exercised
}

TEST(ContactCore, NodeCapForceIsMinusEnergyGradientDeepInside)
{
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int tested = 0, in_core = 0;
  for (int trial = 0; trial < 3000 && tested < 80; trial++) {
    const double L = 1e-4;
    const double kink = 0.7 + 1.9 * (0.5 + 0.5 * u(rng));
    const Vec3 n(0, 0, 0);
    const Vec3 p = n + L * Vec3(-std::cos(0.5 * kink), -std::sin(0.5 * kink), 0);
    const Vec3 q = n + L * Vec3(std::cos(0.5 * kink), -std::sin(0.5 * kink), 0);
    const Vec3 c = Vec3(0.2 * D * u(rng), 0.5 * D + 0.45 * D * u(rng), 0.2 * D * u(rng));
    const double ang = 3.0 * u(rng), tilt = 0.5 * u(rng);
    const Vec3 dir(std::cos(ang) * std::cos(tilt), std::sin(tilt), std::sin(ang) * std::cos(tilt));
    std::vector<Vec3> x = {c - 0.6 * L * dir, c + 0.6 * L * dir, p, n, q};
    const auto r = NCF::node_contact(x[0], x[1], x[2], x[3], x[4], D, KN, RAMP, KAPPA);
    if (!r.active) continue;
    tested++;
    if (r.penetration > (1.0 - NCF::CORE_FRACTION) * D) in_core++;
    auto energy = [&](const std::vector<Vec3> &y) {
      return NCF::node_contact(y[0], y[1], y[2], y[3], y[4], D, KN, RAMP, KAPPA).energy;
    };
    check_gradient(x, {r.f[0], r.f[1], r.f[2], r.f[3], r.f[4]}, energy,
                   "trial " + std::to_string(trial));
  }
  EXPECT_GE(tested, 60);
  EXPECT_GE(in_core, 10);
}

TEST(ContactCore, UnchangedOutsideTheCore)
{
  // above D_c the core adds nothing: same energy and forces to round-off
  ContactOptions opt;
  opt.core = KAPPA;
  for (double r : {0.99 * D, 0.8 * D, 0.6 * D, 0.58 * D})
    for (double ang : {0.0, 0.3, M_PI / 2}) {
      const Vec3 dir(std::cos(ang), std::sin(ang), 0.0), c(0.2e-4, 0.1e-4, r);
      const Vec3 a0(-1e-4, 0, 0), a1(1e-4, 0, 0);
      const auto plain = segment_contact(a0, a1, c - 1e-4 * dir, c + 1e-4 * dir, D, KN, RAMP);
      const auto cored =
          segment_contact(a0, a1, c - 1e-4 * dir, c + 1e-4 * dir, D, KN, RAMP, true, opt);
      EXPECT_NEAR(cored.energy, plain.energy, 1e-12 * plain.energy) << r / D << " " << ang;
      for (int k = 0; k < 4; k++)
        EXPECT_LT(NCF::norm(cored.f[k] - plain.f[k]), 1e-12 * NCF::norm(plain.f[k]) + 1e-30);
    }
}

TEST(ContactCore, ParallelForceRisesToDeepPenetration)
{
  // plain law: k_n h r / D per length, h = (D^2 - r^2) / 2D; it peaks at r = D / sqrt(3)
  const double r0 = 0.95 * D;
  EXPECT_NEAR(parallel_force_per_length(r0, 0.0), KN * (D * D - r0 * r0) / (2.0 * D) * r0 / D,
              1e-9 * KN * D);
  // with the core the force per length keeps rising down to r = 0.36 D (penetration 0.64 D)
  double prev = 0.0, prev_plain = 0.0;
  bool plain_falls = false;
  for (double r = 0.98 * D; r > 0.36 * D; r -= 0.02 * D) {
    const double f = parallel_force_per_length(r, KAPPA);
    const double fp = parallel_force_per_length(r, 0.0);
    EXPECT_GT(f, prev) << "r/D " << r / D;
    EXPECT_GE(f, fp * (1.0 - 1e-12));
    if (fp < prev_plain) plain_falls = true;
    prev = f;
    prev_plain = fp;
  }
  EXPECT_TRUE(plain_falls);    // without the core the force falls beyond penetration 0.42 D
  // the largest force per length grows more than fivefold (0.19 -> 1.26 k_n D)
  double peak = 0.0, peak_plain = 0.0;
  for (double r = 0.99 * D; r > 0.01 * D; r -= 0.01 * D) {
    peak = std::max(peak, parallel_force_per_length(r, KAPPA));
    peak_plain = std::max(peak_plain, parallel_force_per_length(r, 0.0));
  }
  EXPECT_NEAR(peak_plain / (KN * D), 1.0 / (3.0 * std::sqrt(3.0)), 2e-3);
  EXPECT_GT(peak / (KN * D), 1.2);
}

namespace {
// normal force on a chain A (mesh 0.1 mm) crossed at right angles by chain B, both with the
// crossing at distance `where` from A's last node (A's free end at x = 0, extending to -x) and B
// crossing at its own free end too when b_end; ext: extension at free ends
double crossing_force(double where, bool b_end, double ext)
{
  const double mesh = 1e-4, g = 0.1 * D;
  std::vector<Vec3> a, b;
  for (int i = 0; i <= 6; i++) a.push_back(Vec3(-i * mesh, 0, 0));
  const double bx = -where;
  if (b_end)
    for (int j = 0; j <= 6; j++) b.push_back(Vec3(bx, -j * mesh, D - g));
  else
    for (int j = -3; j <= 3; j++) b.push_back(Vec3(bx, j * mesh + 0.37 * mesh, D - g));
  double fz = 0.0;
  for (size_t i = 0; i + 1 < a.size(); i++)
    for (size_t j = 0; j + 1 < b.size(); j++) {
      ContactOptions opt;
      opt.ext[0] = (i == 0) ? ext : 0.0;    // a[0] is A's free end
      opt.ext[2] = (b_end && j == 0) ? ext : 0.0;
      const auto c = segment_contact(a[i], a[i + 1], b[j], b[j + 1], D, KN, RAMP, false, opt);
      if (c.active) fz += c.f[2].z + c.f[3].z;
    }
  return fz;
}
}    // namespace

TEST(ContactEnds, CrossingAtAFreeEndIsFullyCovered)
{
  const double ext = 0.5 * D;
  const double mid = crossing_force(3e-4, false, ext);    // far from any end
  ASSERT_GT(mid, 0.0);
  // without the extension a crossing right at A's free end carries only part of the force, and
  // at two free ends even less; with it, the full force
  EXPECT_LT(crossing_force(0.0, false, 0.0), 0.75 * mid);
  EXPECT_LT(crossing_force(0.0, true, 0.0), 0.5 * mid);
  EXPECT_NEAR(crossing_force(0.0, false, ext), mid, 1e-9 * mid);
  EXPECT_NEAR(crossing_force(0.0, true, ext), mid, 1e-9 * mid);
  // the force fades out beyond the end, never growing on the way
  double prev = mid * (1.0 + 1e-9);
  for (double w = 0.0; w > -2.0 * D; w -= 0.05 * D) {
    const double f = crossing_force(w, true, ext);
    EXPECT_LE(f, prev) << "crossing " << -w / D << " D beyond the ends";
    prev = f;
  }
  EXPECT_EQ(crossing_force(-1.5 * D, true, ext), 0.0);
}

// The law's closed-form integration against a plain reference: the energy E = (k_n / 2) L_A
// integral over xi in [0, 1] of W(s) (h^2 + kappa h_c^2), and the contact length l_c = L_A
// integral of W where h > 0, summed with a composite 3-point Gauss rule over 4000 sub-intervals
// straight from the definitions in ncf_contact.h (distance from B's infinite line, arc position
// of the projection on B, weight ramps of half-width e). Random pairs: crossings, nearly
// parallel and parallel pairs, short segments B (L_B < 2 e), penetrations into the core, with
// and without it.
namespace {
struct Reference {
  double energy = 0.0, length = 0.0;
};
Reference reference_law(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1, double core)
{
  const Vec3 da = a1 - a0, u = b1 - b0;
  const double la = NCF::norm(da), lb = NCF::norm(u);
  const Vec3 eb = (1.0 / lb) * u;
  const double dcore = NCF::CORE_FRACTION * D;
  // the integrand at xi: W (h^2 + kappa h_c^2) / 2 and W where h > 0
  auto at = [&](double xi, double &e, double &l) {
    const Vec3 x = a0 + xi * da;
    const double s = NCF::dot(x - b0, eb);
    const double r2 = NCF::norm2(x - b0 - s * eb);
    const double w =
        std::min(1.0, std::max(0.0, std::min(0.5 + s / (2 * RAMP), 0.5 + (lb - s) / (2 * RAMP))));
    const double h = std::max(0.0, (D * D - r2) / (2 * D));
    const double hc = std::max(0.0, (dcore * dcore - r2) / (2 * dcore));
    e = 0.5 * w * (h * h + core * hc * hc);
    l = h > 0.0 ? w : 0.0;
  };
  // the part of [0, 1] where the integrand is non-zero, from a fine scan (one step around it)
  const int nscan = 100000;
  double xlo = 1.0, xhi = 0.0;
  for (int k = 0; k <= nscan; k++) {
    double e, l;
    at((double) k / nscan, e, l);
    if (l > 0.0) {
      xlo = std::min(xlo, std::max(0.0, (k - 1.0) / nscan));
      xhi = std::max(xhi, std::min(1.0, (k + 1.0) / nscan));
    }
  }
  Reference out;
  if (!(xhi > xlo)) return out;
  const int n = 4000;
  const double gx[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, gw[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  const double dx = (xhi - xlo) / n;
  for (int k = 0; k < n; k++)
    for (int q = 0; q < 3; q++) {
      double e, l;
      at(xlo + (k + 0.5 + 0.5 * gx[q]) * dx, e, l);
      out.energy += 0.5 * gw[q] * dx * KN * la * e;
      out.length += 0.5 * gw[q] * dx * la * l;
    }
  return out;
}
}    // namespace

TEST(ContactReference, ClosedFormMatchesDirectQuadrature)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int compared = 0, deep = 0;
  for (int trial = 0; trial < 300; trial++) {
    const double L = trial % 5 == 0 ? 0.3 * RAMP : 2e-4;    // short B now and then
    const double ang = trial % 3 == 0 ? 1e-4 * U(rng) : (trial % 3 == 1 ? 0.0 : 1.5 * U(rng));
    const Vec3 b0(0, 0, 0), b1(L, 0, 0);
    const double pen = (0.5 + 0.5 * U(rng)) * (trial % 4 == 0 ? 0.7 : 0.2) * D;
    const double la = 2e-4, c = std::cos(ang), sn = std::sin(ang);
    const Vec3 mid(0.5 * L + 0.6 * L * U(rng), 0.3 * D * U(rng), D - pen);
    const Vec3 dir(c, sn, 0.05 * U(rng));
    const Vec3 a0 = mid - (0.5 * la * (0.5 + 0.5 * U(rng))) * dir;
    const Vec3 a1 = mid + (0.5 * la * (0.5 + 0.5 * U(rng))) * dir;
    for (double core : {0.0, KAPPA}) {
      ContactOptions opt;
      opt.core = core;
      const auto cf = segment_contact(a0, a1, b0, b1, D, KN, RAMP, false, opt);
      const Reference ref = reference_law(a0, a1, b0, b1, core);
      if (!(ref.energy > 0.0)) {
        EXPECT_LT(cf.energy, 1e-12 * KN * D * D * la) << "trial " << trial;
        continue;
      }
      compared++;
      if (std::fabs(mid.z) < NCF::CORE_FRACTION * D && core > 0.0) deep++;
      EXPECT_NEAR(cf.energy, ref.energy, 1e-6 * ref.energy)
          << "trial " << trial << " core " << core;
      EXPECT_NEAR(cf.length, ref.length, 1e-3 * ref.length + 1e-4 * la)
          << "trial " << trial << " core " << core;
    }
  }
  EXPECT_GT(compared, 300);
  EXPECT_GT(deep, 20);
}
