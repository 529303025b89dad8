// Unit tests of the engine-free contact law (ncf_contact.h): force = -dE/dx by finite
// differences, force and moment balance, continuity from crossing to exactly parallel, parallel
// contact proportional to the overlap length and independent of the mesh, no double counting at
// shared nodes, degenerate cases finite, Coulomb slip spring; node caps at kinks, also against a
// brute-force quadrature of their energy.

#include "ncf_contact.h"
#include "ncf_random_geometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using NCF::friction_step;
using NCF::segment_contact;
using NCF::SegmentContact;
using NCF::Vec3;

namespace {

const double D = 69e-6;          // contact distance (equal diameters 69 um)
const double KN = 1e7;           // normal stiffness per length [Pa]
const double RAMP = 0.25 * D;    // ramp half-width

double energy_of(const Vec3 x[4])
{
  return segment_contact(x[0], x[1], x[2], x[3], D, KN, RAMP).energy;
}

Vec3 resultant(const SegmentContact &c)
{
  return c.f[0] + c.f[1] + c.f[2] + c.f[3];
}
Vec3 moment(const SegmentContact &c, const Vec3 x[4])
{
  Vec3 m;
  for (int n = 0; n < 4; n++) m += NCF::cross(x[n], c.f[n]);
  return m;
}

bool finite(const SegmentContact &c)
{
  bool ok = std::isfinite(c.energy) && std::isfinite(c.fn) && std::isfinite(c.xi) &&
      std::isfinite(c.t) && std::isfinite(c.length);
  for (int n = 0; n < 4; n++)
    for (int d = 0; d < 3; d++) ok = ok && std::isfinite(c.f[n][d]);
  return ok;
}

// sum of the contact of every segment of chain a against every segment of chain b
struct ChainSum {
  double energy = 0.0;
  std::vector<Vec3> fa, fb;
  int active = 0;
};
ChainSum chain_contact(const std::vector<Vec3> &a, const std::vector<Vec3> &b)
{
  ChainSum out;
  out.fa.assign(a.size(), Vec3());
  out.fb.assign(b.size(), Vec3());
  for (size_t i = 0; i + 1 < a.size(); i++)
    for (size_t j = 0; j + 1 < b.size(); j++) {
      auto c = segment_contact(a[i], a[i + 1], b[j], b[j + 1], D, KN, RAMP);
      if (!c.active) continue;
      out.active++;
      out.energy += c.energy;
      out.fa[i] += c.f[0];
      out.fa[i + 1] += c.f[1];
      out.fb[j] += c.f[2];
      out.fb[j + 1] += c.f[3];
    }
  return out;
}

std::vector<Vec3> straight_chain(Vec3 start, Vec3 dir, double length, double mesh)
{
  const int n = (int) std::lround(length / mesh);
  std::vector<Vec3> x;
  for (int i = 0; i <= n; i++) x.push_back(start + (length * i / n) * dir);
  return x;
}

}    // namespace

TEST(Contact, ForceIsMinusEnergyGradient)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int tested = 0;
  for (int trial = 0; trial < 400 && tested < 120; trial++) {
    const double L = 2e-4;
    Vec3 x[4];
    x[0] = Vec3(-0.5 * L, 0.0, 0.0) + 0.3 * L * Vec3(u(rng), u(rng), u(rng));
    x[1] = Vec3(0.5 * L, 0.0, 0.0) + 0.3 * L * Vec3(u(rng), u(rng), u(rng));
    // B: crossing, nearly parallel or parallel, at a distance below D
    const double ang = (trial % 4 == 0) ? 0.0 : (trial % 4 == 1 ? 1e-3 * u(rng) : 1.5 * u(rng));
    const Vec3 dir(std::cos(ang), std::sin(ang), 0.0);
    const Vec3 c = Vec3(0.3 * L * u(rng), 0.3 * L * u(rng), D * (0.6 + 0.35 * u(rng)));
    x[2] = c - 0.5 * L * dir;
    x[3] = c + 0.5 * L * dir;
    auto res = segment_contact(x[0], x[1], x[2], x[3], D, KN, RAMP);
    if (!res.active) continue;
    tested++;
    const double h = 1e-6 * D;
    double fmax = 0.0;
    for (int n = 0; n < 4; n++) fmax = std::max(fmax, NCF::norm(res.f[n]));
    for (int n = 0; n < 4; n++)
      for (int d = 0; d < 3; d++) {
        Vec3 xp[4] = {x[0], x[1], x[2], x[3]}, xm[4] = {x[0], x[1], x[2], x[3]};
        double *pp = (d == 0) ? &xp[n].x : (d == 1 ? &xp[n].y : &xp[n].z);
        double *pm = (d == 0) ? &xm[n].x : (d == 1 ? &xm[n].y : &xm[n].z);
        *pp += h;
        *pm -= h;
        const double fd = -(energy_of(xp) - energy_of(xm)) / (2.0 * h);
        EXPECT_NEAR(res.f[n][d], fd, 1e-6 * fmax + 1e-12)
            << "trial " << trial << " node " << n << " dim " << d;
      }
  }
  EXPECT_GE(tested, 100);
}

TEST(Contact, ForceAndMomentBalance)
{
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; trial++) {
    const double L = 2e-4;
    Vec3 x[4] = {Vec3(-L / 2, 0, 0) + 0.4 * L * Vec3(u(rng), u(rng), u(rng)),
                 Vec3(L / 2, 0, 0) + 0.4 * L * Vec3(u(rng), u(rng), u(rng)),
                 Vec3(0, -L / 2, 0.5 * D) + 0.4 * L * Vec3(u(rng), u(rng), u(rng)),
                 Vec3(0, L / 2, 0.5 * D) + 0.4 * L * Vec3(u(rng), u(rng), u(rng))};
    auto c = segment_contact(x[0], x[1], x[2], x[3], D, KN, RAMP);
    if (!c.active) continue;
    double fmax = 0.0;
    for (int n = 0; n < 4; n++) fmax = std::max(fmax, NCF::norm(c.f[n]));
    EXPECT_LT(NCF::norm(resultant(c)), 1e-12 * fmax);
    EXPECT_LT(NCF::norm(moment(c, x)), 1e-11 * fmax * L);
  }
}

TEST(Contact, ContinuousFromCrossingToExactlyParallel)
{
  // B (long) rotated about the common normal through the contact: crossing at 90 deg down to
  // exactly parallel. The total normal force changes smoothly with the angle (no jump anywhere,
  // in particular none between 1e-12 rad and 0).
  const double L = 2e-4, gap = 0.98 * D;
  auto force_at = [&](double ang) {
    const Vec3 a0(-L / 2, 0, 0), a1(L / 2, 0, 0);
    const Vec3 dir(std::cos(ang), std::sin(ang), 0);
    const Vec3 b0 = Vec3(0, 0, gap) - 2.0 * L * dir, b1 = Vec3(0, 0, gap) + 2.0 * L * dir;
    auto c = segment_contact(a0, a1, b0, b1, D, KN, RAMP);
    EXPECT_TRUE(finite(c));
    return c.fn;
  };
  double prev = force_at(M_PI / 2);
  const int n = 2000;
  double maxjump = 0.0;
  for (int k = 1; k <= n; k++) {
    const double ang = M_PI / 2 * (1.0 - double(k) / n);
    const double f = force_at(ang);
    maxjump = std::max(maxjump, std::fabs(f - prev));
    prev = f;
  }
  const double fpar = force_at(0.0);
  // parallel: F = kn h(gap) (gap / D) L  (the whole of A is inside B's cylinder)
  const double hpen = (D * D - gap * gap) / (2 * D);
  EXPECT_NEAR(fpar, KN * hpen * gap / D * L, 1e-9 * fpar);
  // the force ramps from the crossing value to the parallel value without jumps: the largest
  // step over 2000 angle steps is a small fraction of the range
  EXPECT_LT(maxjump, 0.02 * fpar);
  for (double ang : {1e-4, 1e-6, 1e-8, 1e-10, 1e-12})
    EXPECT_NEAR(force_at(ang), fpar, 2e-3 * fpar + 10 * ang * fpar) << "angle " << ang;
  EXPECT_GT(force_at(M_PI / 2), 0.0);
}

TEST(Contact, ParallelForceProportionalToOverlapAndMeshIndependent)
{
  // chain A above chain B, parallel, overlapping over a length l; nodes of A not aligned with
  // B's. Total force = kn h (gap / D) l for mesh 0.2, 0.1 and 0.05 mm, within 2 %; no torque on A.
  const double gap = 0.97 * D, hpen = (D * D - gap * gap) / (2 * D);
  for (double overlap : {0.6e-3, 1.0e-3}) {
    std::vector<double> forces;
    for (double mesh : {0.2e-3, 0.1e-3, 0.05e-3}) {
      auto b = straight_chain(Vec3(-1e-3, 0, 0), Vec3(1, 0, 0), 4e-3, mesh);
      auto a = straight_chain(Vec3(0.0123e-3, 0, gap), Vec3(1, 0, 0), overlap, mesh * 0.93);
      auto s = chain_contact(a, b);
      Vec3 fa, ma;
      const Vec3 ca = 0.5 * (a.front() + a.back());
      for (size_t i = 0; i < a.size(); i++) {
        fa += s.fa[i];
        ma += NCF::cross(a[i] - ca, s.fa[i]);
      }
      const double expect = KN * hpen * gap / D * overlap;
      EXPECT_NEAR(fa.z, expect, 0.02 * expect) << "mesh " << mesh << " overlap " << overlap;
      EXPECT_NEAR(fa.x, 0.0, 1e-9 * expect);
      EXPECT_NEAR(fa.y, 0.0, 1e-9 * expect);
      EXPECT_LT(NCF::norm(ma), 1e-6 * expect * overlap) << "spurious torque, mesh " << mesh;
      forces.push_back(fa.z);
    }
    for (double f : forces) EXPECT_NEAR(f, forces[0], 0.02 * forces[0]);
  }
}

TEST(Contact, NoDoubleCountingAtSharedNodes)
{
  // a short crossing segment slides along a chain of 0.2 mm segments: the total force is the
  // same as against one long segment, wherever the crossing sits relative to the nodes
  const double gap = 0.95 * D;
  auto b = straight_chain(Vec3(-1e-3, 0, 0), Vec3(1, 0, 0), 2e-3, 0.2e-3);
  const std::vector<Vec3> blong = {b.front(), b.back()};
  for (double ang : {M_PI / 2, 0.3}) {
    const Vec3 dir(std::cos(ang), std::sin(ang), 0);
    double fref = -1.0;
    for (int k = 0; k <= 100; k++) {
      const Vec3 c(-0.3e-3 + 0.4e-3 * k / 100.0, 0, gap);
      const std::vector<Vec3> a = {c - 1e-4 * dir, c + 1e-4 * dir};
      auto s = chain_contact(a, b), s1 = chain_contact(a, blong);
      const double f = (s.fa[0] + s.fa[1]).z, f1 = (s1.fa[0] + s1.fa[1]).z;
      EXPECT_NEAR(f, f1, 1e-9 * f1) << "angle " << ang << " position " << k;
      if (fref < 0) fref = f;
      EXPECT_NEAR(f, fref, 1e-9 * fref);
    }
  }
}

TEST(Contact, DegenerateCasesAreFinite)
{
  const Vec3 o(0, 0, 0), x1(1e-4, 0, 0), y1(0, 1e-4, 0);
  struct Deg {
    const char *name;
    Vec3 a0, a1, b0, b1;
  } cases[] = {
      {"axes crossing at zero distance", Vec3(-1e-4, 0, 0), x1, Vec3(0, -1e-4, 0), y1},
      {"coincident segments", o, x1, o, x1},
      {"collinear overlapping", o, x1, Vec3(0.5e-4, 0, 0), Vec3(1.5e-4, 0, 0)},
      {"zero-length A", Vec3(0, 0, 1e-5), Vec3(0, 0, 1e-5), Vec3(-1e-4, 0, 0), x1},
      {"zero-length B", Vec3(-1e-4, 0, 0), x1, Vec3(0, 0, 1e-5), Vec3(0, 0, 1e-5)},
      {"very short A", Vec3(0, 0, 1e-5), Vec3(1e-15, 0, 1e-5), Vec3(-1e-4, 0, 0), x1},
      {"very short B", Vec3(-1e-4, 0, 1e-5), x1, Vec3(0, 0, 0), Vec3(0, 1e-13, 0)},
      {"short B (shorter than the ramps)", Vec3(-1e-4, 0, 1e-5), x1, Vec3(0, 0, 0),
       Vec3(0, 1e-6, 0)},
      {"A point on B's axis", Vec3(0, 0, 0), Vec3(0, 0, 1e-4), Vec3(-1e-4, 0, 0), x1},
  };
  for (const auto &c : cases) {
    auto r = segment_contact(c.a0, c.a1, c.b0, c.b1, D, KN, RAMP);
    EXPECT_TRUE(finite(r)) << c.name;
    for (int n = 0; n < 4; n++) EXPECT_LT(NCF::norm(r.f[n]), KN * D * 1e-3) << c.name;
  }
}

TEST(Contact, NearlyParallelRootsAreStable)
{
  // penetration interval endpoints computed without cancellation: the energy is monotone and
  // smooth for angles from 1e-3 down to 1e-15 rad
  const double L = 2e-4, gap = 0.99 * D;
  double prev = 0.0;
  for (int k = 3; k <= 15; k++) {
    const double ang = std::pow(10.0, -k);
    const Vec3 dir(std::cos(ang), std::sin(ang), 0), c(0, 0, gap);
    auto r = segment_contact(Vec3(-L / 2, 0, 0), Vec3(L / 2, 0, 0), c - L * dir, c + L * dir, D, KN,
                             RAMP);
    ASSERT_TRUE(r.active);
    if (k > 3) EXPECT_NEAR(r.energy, prev, 1e-4 * prev);
    prev = r.energy;
  }
}

TEST(Contact, PrefilterNeverDropsAnActiveContact)
{
  // segment_contact_possible is false only where segment_contact is inactive: random segment
  // pairs around the contact distance (crossing, oblique, nearly and exactly parallel, end to
  // end, short segments), and the prefilter rejects most of the far ones
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto rvec = [&](double s) {
    return Vec3(s * u(rng), s * u(rng), s * u(rng));
  };
  int active = 0, rejected = 0, kept_inactive = 0;
  for (int k = 0; k < 200000; k++) {
    const double la = 2e-4 * (0.05 + std::fabs(u(rng))), lb = 2e-4 * (0.05 + std::fabs(u(rng)));
    Vec3 ea = rvec(1.0), eb = rvec(1.0);
    if (k % 4 == 1) eb = ea + rvec(1e-3);    // nearly parallel
    if (k % 4 == 2) eb = ea;                 // exactly parallel
    ea = (1.0 / NCF::norm(ea)) * ea;
    eb = (1.0 / NCF::norm(eb)) * eb;
    const Vec3 a0 = rvec(1e-4), a1 = a0 + la * ea;
    const Vec3 b0 = rvec(1.5e-4), b1 = b0 + lb * eb;
    const bool possible = NCF::segment_contact_possible(a0, a1, b0, b1, D, RAMP);
    const auto c = segment_contact(a0, a1, b0, b1, D, KN, RAMP);
    if (c.active) {
      active++;
      EXPECT_TRUE(possible) << "k " << k;
    } else if (!possible) {
      rejected++;
    } else {
      kept_inactive++;
    }
  }
  EXPECT_GT(active, 10000);
  EXPECT_GT(rejected, 10 * kept_inactive);
}

TEST(Friction, StickBelowCapSlideAtCap)
{
  Vec3 slip;
  const Vec3 n(0, 0, 1), v(1e-3, 0, 0);
  const double kt = 1e6, fn = 0.5, mu = 0.3, dt = 1e-6;
  // stick: the force grows as kt * slip
  for (int i = 1; i <= 100; i++) {
    auto r = friction_step(slip, n, v, dt, kt, fn, mu);
    EXPECT_FALSE(r.sliding);
    EXPECT_NEAR(r.force.x, -kt * i * dt * v.x, 1e-12 * kt * i * dt * v.x);
  }
  // after enough slip: capped at mu fn, opposing the motion
  for (int i = 0; i < 1000; i++) friction_step(slip, n, v, dt, kt, fn, mu);
  auto r = friction_step(slip, n, v, dt, kt, fn, mu);
  EXPECT_TRUE(r.sliding);
  EXPECT_NEAR(r.force.x, -mu * fn, 1e-14);
  EXPECT_NEAR(NCF::norm(slip), mu * fn / kt, 1e-15);
  // a normal velocity does not load the spring; the stored slip stays tangential
  Vec3 s2;
  friction_step(s2, n, Vec3(0, 0, 1.0), dt, kt, fn, mu);
  EXPECT_EQ(NCF::norm(s2), 0.0);
  Vec3 s3(1e-8, 0, 1e-8);
  auto r3 = friction_step(s3, n, Vec3(), dt, kt, fn, mu);
  EXPECT_NEAR(s3.z, 0.0, 1e-22);
  EXPECT_NEAR(NCF::norm(s3), std::sqrt(2.0) * 1e-8, 1e-20);    // magnitude kept by the rotation
  EXPECT_NEAR(NCF::norm(r3.force), kt * std::sqrt(2.0) * 1e-8, 1e-12);
  EXPECT_FALSE(r3.sliding);
  // the setup of a run (advance false): the force of the stored slip, the slip as it is; after
  // a sliding step, that step's force bit for bit
  const Vec3 kept = slip;
  auto rs = friction_step(slip, n, Vec3(5.0, 2.0, 0), dt, kt, fn, mu, false);
  EXPECT_EQ(slip.x, kept.x);
  EXPECT_EQ(slip.y, kept.y);
  EXPECT_EQ(rs.force.x, r.force.x);
  EXPECT_EQ(rs.force.y, r.force.y);
  EXPECT_FALSE(rs.sliding);
  // mu = 0: no force, no history
  Vec3 s4(1e-5, 0, 0);
  auto r4 = friction_step(s4, n, v, dt, kt, fn, 0.0);
  EXPECT_EQ(NCF::norm(r4.force), 0.0);
  EXPECT_EQ(NCF::norm(s4), 0.0);
}

// ---------------------------------------------------------------- node caps at kinks

namespace {
double node_energy(const Vec3 x[5])
{
  return NCF::node_contact(x[0], x[1], x[2], x[3], x[4], D, KN, RAMP).energy;
}
}    // namespace

TEST(NodeContact, ForceIsMinusEnergyGradientAndBalanced)
{
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int tested = 0;
  for (int trial = 0; trial < 2000 && tested < 100; trial++) {
    const double L = 1e-4;
    // a kinked chain p - n - q (kink 40..150 deg) and a segment A near the convex side of n
    const double kink = (trial % 2) ? 0.7 + 1.9 * (0.5 + 0.5 * u(rng))
                                    : M_PI - 0.2 * (0.5 + 0.5 * u(rng));
    const Vec3 n(0, 0, 0);
    const Vec3 p = n + L * Vec3(-std::cos(0.5 * kink), -std::sin(0.5 * kink), 0);
    const Vec3 q = n + L * Vec3(std::cos(0.5 * kink), -std::sin(0.5 * kink), 0);
    const Vec3 c = Vec3(0.3 * D * u(rng), 0.8 * D + 0.25 * D * u(rng), 0.3 * D * u(rng));
    const double ang = 3.0 * u(rng), tilt = 0.5 * u(rng);
    const Vec3 dir(std::cos(ang) * std::cos(tilt), std::sin(tilt), std::sin(ang) * std::cos(tilt));
    Vec3 x[5] = {c - 0.6 * L * dir, c + 0.6 * L * dir, p, n, q};
    auto r = NCF::node_contact(x[0], x[1], x[2], x[3], x[4], D, KN, RAMP);
    if (!r.active) continue;
    tested++;
    double fmax = 0.0;
    Vec3 fsum, msum;
    for (int k = 0; k < 5; k++) {
      fmax = std::max(fmax, NCF::norm(r.f[k]));
      fsum += r.f[k];
      msum += NCF::cross(x[k], r.f[k]);
    }
    EXPECT_LT(NCF::norm(fsum), 1e-12 * fmax);
    EXPECT_LT(NCF::norm(msum), 1e-11 * fmax * L);
    const double h = 1e-6 * D;
    for (int k = 0; k < 5; k++)
      for (int d = 0; d < 3; d++) {
        Vec3 xp[5], xm[5];
        for (int m = 0; m < 5; m++) xp[m] = xm[m] = x[m];
        double *pp = (d == 0) ? &xp[k].x : (d == 1 ? &xp[k].y : &xp[k].z);
        double *pm = (d == 0) ? &xm[k].x : (d == 1 ? &xm[k].y : &xm[k].z);
        *pp += h;
        *pm -= h;
        const double fd = -(node_energy(xp) - node_energy(xm)) / (2.0 * h);
        EXPECT_NEAR(r.f[k][d], fd, 1e-6 * fmax + 1e-12) << "trial " << trial << " node " << k;
      }
  }
  EXPECT_GE(tested, 50);
}

TEST(NodeContact, NothingOnAStraightChain)
{
  // on a straight chain the two ramps cover the node's sphere exactly: no cap contact
  const Vec3 p(-1e-4, 0, 0), n(0, 0, 0), q(1e-4, 0, 0);
  for (double off : {0.0, 0.3 * D, 0.9 * D})
    for (double ang : {0.0, 0.4, M_PI / 2}) {
      const Vec3 c(off, 0.0, 0.8 * D), dir(std::cos(ang), std::sin(ang), 0);
      auto r = NCF::node_contact(c - 1e-4 * dir, c + 1e-4 * dir, p, n, q, D, KN, RAMP);
      auto ref = segment_contact(c - 1e-4 * dir, c + 1e-4 * dir, p, n, D, KN, RAMP);
      EXPECT_LT(r.energy, 1e-12 * (ref.energy + 1e-30)) << off << " " << ang;
    }
}

TEST(NodeContact, KinkConvexSideIsCovered)
{
  // a short segment pressed onto the outside of a 90 deg kink along the bisector: with the node
  // cap the force is close to that on a straight chain at the same penetration; without it, it
  // would be a small fraction
  const double L = 1e-4, gap = 0.9 * D;
  const Vec3 n(0, 0, 0), p = L * Vec3(-std::sqrt(0.5), -std::sqrt(0.5), 0),
                         q = L * Vec3(std::sqrt(0.5), -std::sqrt(0.5), 0);
  const Vec3 a0(0, gap, -0.6 * L), a1(0, gap, 0.6 * L);    // across the kink's plane
  auto s1 = segment_contact(a0, a1, p, n, D, KN, RAMP),
       s2 = segment_contact(a0, a1, n, q, D, KN, RAMP);
  auto cap = NCF::node_contact(a0, a1, p, n, q, D, KN, RAMP);
  const double without = (s1.f[0] + s1.f[1] + s2.f[0] + s2.f[1]).y;
  const double with = without + (cap.f[0] + cap.f[1]).y;
  auto straight = segment_contact(a0, a1, Vec3(-L, 0, 0), Vec3(L, 0, 0), D, KN, RAMP);
  const double ref = (straight.f[0] + straight.f[1]).y;
  EXPECT_GT(with, 0.9 * ref);
  EXPECT_LT(with, 1.1 * ref);
  EXPECT_LT(without, 0.5 * ref) << "the ramps alone leave the convex side of the kink uncovered";
}

// ---------------------------------------------------------------- node caps: brute force

namespace {
// An independent reference for node_contact: the energy (ncf_contact.h)
//   E = (k_n / 2) * integral over A of max(0, 1 - W_pn - W_nq - tol)^2 (h_n^2 + kappa h_c^2) dx
// evaluated point by point and integrated by composite Gauss-Legendre quadrature between the
// points where the integrand is not smooth (found independently: where the weights have their
// corners, where A crosses the spheres of radius D and D_c around n, and the zeros of the
// deficit, by bisection), which makes it accurate to round-off; the forces from it by central
// differences.
constexpr double CAP_DEFICIT_TOL = 1e-9;    // the tolerance of the law (ncf_contact.cpp)

// W of a segment of length l at arc position s: 1 on [e, l - e], 0 outside [-e, l + e], linear
// ramps between (a tent below 1 if l < 2e)
double cap_weight(double s, double l, double e)
{
  const double up = (s + e) / (2.0 * e), down = (l + e - s) / (2.0 * e);
  return std::max(0.0, std::min(1.0, std::min(up, down)));
}

struct CapReference {
  Vec3 a0, da, p, n, e1, e2;
  double la, l1, l2, core;
  explicit CapReference(const Vec3 x[5], double kappa) :
      a0(x[0]), da(x[1] - x[0]), p(x[2]), n(x[3]), la(NCF::norm(x[1] - x[0])),
      l1(NCF::norm(x[3] - x[2])), l2(NCF::norm(x[4] - x[3])), core(kappa)
  {
    e1 = (1.0 / l1) * (x[3] - x[2]);
    e2 = (1.0 / l2) * (x[4] - x[3]);
  }
  double deficit(double xi) const
  {
    const Vec3 x = a0 + xi * da;
    const double w1 = cap_weight(NCF::dot(x - p, e1), l1, RAMP);
    const double w2 = cap_weight(NCF::dot(x - n, e2), l2, RAMP);
    return 1.0 - w1 - w2 - CAP_DEFICIT_TOL;
  }
  // energy per unit length of A at A0 + xi (A1 - A0)
  double density(double xi) const
  {
    const double def = std::max(0.0, deficit(xi));
    const double r2 = NCF::norm2(a0 + xi * da - n), dcore = D / std::sqrt(3.0);
    const double h = std::max(0.0, (D * D - r2) / (2.0 * D));
    const double hc = std::max(0.0, (dcore * dcore - r2) / (2.0 * dcore));
    return 0.5 * KN * def * def * (h * h + core * hc * hc);
  }
  // the roots of |a0 + xi da - n| = r
  bool sphere(double r, double &x0, double &x1) const
  {
    const Vec3 w0 = a0 - n;
    const double qa = NCF::norm2(da), qb = NCF::dot(w0, da), qc = NCF::norm2(w0) - r * r;
    const double disc = qb * qb - qa * qc;
    if (!(disc > 0.0)) return false;
    x0 = (-qb - std::sqrt(disc)) / qa;
    x1 = (-qb + std::sqrt(disc)) / qa;
    return true;
  }
  double energy() const
  {
    double xa, xb;
    if (!sphere(D, xa, xb)) return 0.0;
    xa = std::max(0.0, xa);
    xb = std::min(1.0, xb);
    if (!(xb > xa)) return 0.0;
    std::vector<double> br = {xa, xb};
    auto add = [&](double x) {
      if (x > xa && x < xb) br.push_back(x);
    };
    double c0, c1;
    if (sphere(D / std::sqrt(3.0), c0, c1)) {
      add(c0);
      add(c1);
    }
    const Vec3 u[2] = {e1, e2}, o[2] = {p, n};
    const double l[2] = {l1, l2};
    for (int k = 0; k < 2; k++) {
      const double s0 = NCF::dot(a0 - o[k], u[k]), s1 = NCF::dot(da, u[k]);
      if (std::fabs(s1) < 1e-12 * la) continue;
      for (double c : {-RAMP, RAMP, 0.5 * l[k], l[k] - RAMP, l[k] + RAMP}) add((c - s0) / s1);
    }
    std::sort(br.begin(), br.end());
    // the zeros of the deficit (linear between the corners of the weights)
    const size_t nb = br.size();
    for (size_t i = 0; i + 1 < nb; i++) {
      double a = br[i], b = br[i + 1], fa = deficit(a);
      if ((fa > 0.0) == (deficit(b) > 0.0)) continue;
      for (int it = 0; it < 100; it++) {
        const double m = 0.5 * (a + b), fm = deficit(m);
        if ((fm > 0.0) == (fa > 0.0)) {
          a = m;
          fa = fm;
        } else {
          b = m;
        }
      }
      br.push_back(0.5 * (a + b));
    }
    std::sort(br.begin(), br.end());
    // 5-point Gauss-Legendre on 4 subintervals of each piece (the integrand has degree 6 there)
    static const double gx[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                 0.9061798459386640};
    static const double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                 0.4786286704993665, 0.2369268850561891};
    double e = 0.0;
    for (size_t i = 0; i + 1 < br.size(); i++)
      for (int j = 0; j < 4; j++) {
        const double a = br[i] + (br[i + 1] - br[i]) * j / 4.0;
        const double b = br[i] + (br[i + 1] - br[i]) * (j + 1) / 4.0;
        for (int k = 0; k < 5; k++)
          e += 0.5 * (b - a) * gw[k] * density(0.5 * (a + b) + 0.5 * (b - a) * gx[k]);
      }
    return la * e;
  }
};

}    // namespace

TEST(NodeContact, MatchesBruteForceQuadrature)
{
  // random kinks (0..60 deg, segments of the chain from shorter than 2 ramps to a few D), A of
  // several lengths at random positions and orientations within about D of the node, without
  // and with core: the energy against the reference quadrature, the forces against its central
  // differences, the penetration against the closest points
  std::mt19937 rng(2718);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double lengths[4] = {0.3 * D, 0.7 * D, 1.5 * D, 3.0 * D};    // 2 e = 0.5 D
  const double alengths[3] = {0.4 * D, 1.2 * D, 3.0 * D};
  int tested = 0, tested_core = 0, short_chain = 0, short_a = 0;
  double worst_e = 0.0, worst_f = 0.0;
  int trials = 0;
  for (int trial = 0; trial < 5000 && tested < 300; trial++) {
    trials++;
    const double kink = (M_PI / 3.0) * u(rng), core = (trial % 2) ? NCF::DEFAULT_CORE : 0.0;
    const NCF_TEST::Kink kk = NCF_TEST::random_kink(rng, kink);
    const Vec3 &e1 = kk.e1, &e2 = kk.e2, &bn = kk.bn;    // convex side: +bn
    const double l1 = lengths[rng() % 4], l2 = lengths[rng() % 4], la = alengths[rng() % 3];
    const Vec3 n(1e-4 * u(rng), 1e-4 * u(rng), 1e-4 * u(rng));
    // A through a point within about D of n, mostly on the convex side
    Vec3 off = NCF_TEST::random_unit_vector(rng);
    if (trial % 5) off = (1.0 / NCF::norm(bn + 0.8 * off)) * (bn + 0.8 * off);
    const Vec3 c = n + (D * (0.1 + 0.95 * u(rng))) * off, dir = NCF_TEST::random_unit_vector(rng);
    const Vec3 a0 = c - (la * u(rng)) * dir;
    const Vec3 x[5] = {a0, a0 + la * dir, n - l1 * e1, n, n + l2 * e2};

    const auto r = NCF::node_contact(x[0], x[1], x[2], x[3], x[4], D, KN, RAMP, core);
    // the scale of the energy: all of A's part within D of n at full deficit
    const double escale = 0.5 * KN * 0.25 * D * D * (1.0 + core / 3.0) * std::min(la, 2.0 * D);
    const CapReference ref(x, core);
    const double eref = ref.energy();
    if (!(eref > 1e-6 * escale)) {
      // nothing (or next to nothing) to integrate: node_contact agrees
      EXPECT_LT(std::fabs(r.energy - eref), 1e-12 * escale) << "trial " << trial;
      continue;
    }
    tested++;
    tested_core += core > 0.0 && NCF::point_segment_dist2(x[0], x[1], n) < D * D / 3.0;
    short_chain += std::min(l1, l2) < 2.0 * RAMP;
    short_a += la < 2.0 * RAMP;
    ASSERT_TRUE(r.active) << "trial " << trial;
    const double dist = std::sqrt(NCF::closest_points_segments(x[0], x[1], n, n).dist2);
    EXPECT_NEAR(r.penetration, std::max(0.0, D - dist), 1e-12 * D) << "trial " << trial;
    const double de = std::fabs(r.energy - eref) / eref;
    worst_e = std::max(worst_e, de);
    EXPECT_LT(de, 1e-9) << "trial " << trial << ": " << r.energy << " vs " << eref;

    // forces: central differences of the reference
    const double h = 1e-6 * D;
    Vec3 fd[5];
    double fmax = 0.0;
    for (int k = 0; k < 5; k++) {
      double g[3];
      for (int d = 0; d < 3; d++) {
        Vec3 xp[5], xm[5];
        for (int m = 0; m < 5; m++) xp[m] = xm[m] = x[m];
        double *pp = (d == 0) ? &xp[k].x : (d == 1 ? &xp[k].y : &xp[k].z);
        double *pm = (d == 0) ? &xm[k].x : (d == 1 ? &xm[k].y : &xm[k].z);
        *pp += h;
        *pm -= h;
        g[d] = -(CapReference(xp, core).energy() - CapReference(xm, core).energy()) / (2.0 * h);
      }
      fd[k] = Vec3(g[0], g[1], g[2]);
      fmax = std::max(fmax, NCF::norm(fd[k]));
    }
    for (int k = 0; k < 5; k++) {
      const double df = NCF::norm(r.f[k] - fd[k]) / fmax;
      worst_f = std::max(worst_f, df);
      EXPECT_LT(df, 1e-6) << "trial " << trial << " node " << k << ": (" << r.f[k].x << ", "
                          << r.f[k].y << ", " << r.f[k].z << ") vs (" << fd[k].x << ", " << fd[k].y
                          << ", " << fd[k].z << ")";
    }
  }
  EXPECT_GE(tested, 300);
  EXPECT_GE(tested_core, 30);
  EXPECT_GE(short_chain, 30);
  EXPECT_GE(short_a, 30);
  std::printf("node caps against the brute-force quadrature: %d configurations (A in the core: "
              "%d; shorter than 2 ramps: a chain segment %d, A %d); worst relative error "
              "energy %.2g, forces %.2g (%d trials)\n",
              tested, tested_core, short_chain, short_a, worst_e, worst_f, trials);
}
