// The symmetric contact law of pair_style ncf/contact (chain_contact, ncf_contact.h): the mean of
// segment A against B and B against A, with the node caps at half weight. Tested: the same result
// whichever segment is A, bit for bit; force = -dE/dx and balance; on straight crossings the same as
// one way; two kinked chains in contact give the same energy and forces whichever chain is taken as
// A (where the one-way law differs, so the test can tell); the convex side of a kink is covered;
// the batched version against the scalar one.

#include "ncf_contact.h"
#include "ncf_random_geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using NCF::SegmentContact;
using NCF::Vec3;

namespace {

const double D = 69e-6;
const double KN = 1e9;
const double RAMP = 0.25 * D;

struct Pair {
  Vec3 x[4];    // a0, a1, b0, b1
};

// pairs within D of each other: crossings anywhere along both segments (in the ramps, over the
// nodes, beyond them), nearly parallel pairs, short segments, contacts in the core
std::vector<Pair> random_pairs(int n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Pair> out;
  for (int k = 0; k < n; k++) {
    const double la = (k % 5 == 0 ? 0.4 : 2.0) * 1e-4 * (1.0 + 0.3 * u(rng));
    const double lb = (k % 7 == 0 ? 0.4 : 2.0) * 1e-4 * (1.0 + 0.3 * u(rng));
    const Vec3 ea = NCF_TEST::random_unit_vector(rng);
    Vec3 eb = NCF_TEST::random_unit_vector(rng);
    if (k % 6 == 1) eb = (1.0 / NCF::norm(ea + 1e-3 * eb)) * (ea + 1e-3 * eb);
    // the closest points anywhere from 0.2 D before the start to 0.2 D past the end of each
    const double sa = (-0.2 * D + (la + 0.4 * D) * 0.5 * (1.0 + u(rng)));
    const double sb = (-0.2 * D + (lb + 0.4 * D) * 0.5 * (1.0 + u(rng)));
    Vec3 off = NCF::cross(ea, eb);
    if (NCF::norm(off) < 1e-6) off = NCF::cross(ea, Vec3(0.3, 0.5, 0.8));
    off = (1.0 / NCF::norm(off)) * off;
    const double gap = D * (k % 9 == 0 ? 0.3 : 0.95) * 0.5 * (1.5 + u(rng));
    const Vec3 a0(1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng));
    const Vec3 pa = a0 + sa * ea, pb = pa + gap * off;
    Pair p;
    p.x[0] = a0;
    p.x[1] = a0 + la * ea;
    p.x[2] = pb - sb * eb;
    p.x[3] = pb + (lb - sb) * eb;
    out.push_back(p);
  }
  return out;
}

SegmentContact law(const Vec3 *x)
{
  NCF::ContactOptions opt;
  opt.core = NCF::DEFAULT_CORE;
  return NCF::chain_contact(x[0], x[1], x[2], x[3], D, KN, RAMP, true, opt);
}

double fscale(const SegmentContact &c)
{
  double s = 0.0;
  for (int m = 0; m < 4; m++) s = std::max(s, NCF::norm(c.f[m]));
  return s;
}

}    // namespace

// swapping A and B gives the same contact seen from the other side, bit for bit: the same energy,
// normal force, length and penetration, the forces on the same nodes, the normal reversed and the
// contact points exchanged
TEST(SymmetricContact, SameWhicheverSegmentIsA)
{
  int active = 0, ways_differ = 0;
  for (const Pair &p : random_pairs(20000, 3)) {
    const SegmentContact c = law(p.x);
    const Vec3 s[4] = {p.x[2], p.x[3], p.x[0], p.x[1]};
    const SegmentContact r = law(s);
    ASSERT_EQ(c.active, r.active);
    if (!c.active) continue;
    active++;
    EXPECT_EQ(c.energy, r.energy);
    EXPECT_EQ(c.fn, r.fn);
    EXPECT_EQ(c.length, r.length);
    EXPECT_EQ(c.penetration, r.penetration);
    EXPECT_EQ(c.xi, r.t);
    EXPECT_EQ(c.t, r.xi);
    for (int d = 0; d < 3; d++) {
      EXPECT_EQ(c.normal[d], -r.normal[d]);
      for (int m = 0; m < 4; m++) EXPECT_EQ(c.f[m][d], r.f[(m + 2) % 4][d]);
    }
    // the one-way law is not symmetric on many of these pairs (what the mean is for)
    const SegmentContact ab = NCF::segment_contact(p.x[0], p.x[1], p.x[2], p.x[3], D, KN, RAMP);
    const SegmentContact ba = NCF::segment_contact(s[0], s[1], s[2], s[3], D, KN, RAMP);
    ways_differ += std::fabs(ab.energy - ba.energy) > 1e-3 * std::max(ab.energy, ba.energy);
  }
  EXPECT_GT(active, 10000);
  EXPECT_GT(ways_differ, 1000) << "the pairs must include cases where the two ways differ";
}

TEST(SymmetricContact, ForceIsMinusEnergyGradientAndBalanced)
{
  int tested = 0;
  for (const Pair &p : random_pairs(600, 8)) {
    const SegmentContact c = law(p.x);
    if (!c.active || !(c.energy > 0.0)) continue;
    tested++;
    const double fmax = fscale(c), h = 1e-6 * D;
    Vec3 sum, mom;
    for (int n = 0; n < 4; n++) {
      sum += c.f[n];
      mom += NCF::cross(p.x[n], c.f[n]);
      for (int d = 0; d < 3; d++) {
        Pair pp = p, pm = p;
        const Vec3 dh(d == 0 ? h : 0.0, d == 1 ? h : 0.0, d == 2 ? h : 0.0);
        pp.x[n] += dh;
        pm.x[n] -= dh;
        const double fd = -(law(pp.x).energy - law(pm.x).energy) / (2.0 * h);
        EXPECT_NEAR(c.f[n][d], fd, 2e-6 * fmax + 1e-12) << "pair " << tested << " node " << n;
      }
    }
    EXPECT_LT(NCF::norm(sum), 1e-9 * fmax);
    EXPECT_LT(NCF::norm(mom), 1e-9 * fmax * 2e-3);    // (positions up to 2 mm from the origin)
  }
  EXPECT_GT(tested, 250);
}

// two straight segments crossing inside both (clear of the ramps): both ways give the same
// integral, so the mean is the one-way law
TEST(SymmetricContact, StraightCrossingEqualsTheOneWayLaw)
{
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 200; k++) {
    const double ang = 0.8 + 0.7 * 0.5 * (1.0 + u(rng)), L = 4e-4;
    const Vec3 a0(-0.5 * L, 0, 0), a1(0.5 * L, 0, 0);
    const Vec3 dir(std::cos(ang), std::sin(ang), 0);
    const Vec3 c(0.1 * L * u(rng), 0, D * (0.7 + 0.25 * u(rng)));
    const Vec3 x[4] = {a0, a1, c - 0.5 * L * dir, c + 0.5 * L * dir};
    const SegmentContact m = law(x);
    NCF::ContactOptions opt;
    opt.core = NCF::DEFAULT_CORE;
    const SegmentContact one = NCF::segment_contact(x[0], x[1], x[2], x[3], D, KN, RAMP, true, opt);
    ASSERT_TRUE(m.active);
    EXPECT_NEAR(m.energy, one.energy, 1e-10 * one.energy);
    EXPECT_NEAR(m.fn, one.fn, 1e-9 * one.fn);
    for (int n = 0; n < 4; n++)
      for (int d = 0; d < 3; d++) EXPECT_NEAR(m.f[n][d], one.f[n][d], 1e-9 * fscale(one));
  }
}

namespace {

// contact of chain a with chain b (polylines): every segment pair by `pair_law`, every node cap
// (interior nodes of either chain against the segments of the other) with the stiffness
// cap_kn; energy and the forces on the nodes of a and b
struct ChainSum {
  double energy = 0.0;
  std::vector<Vec3> fa, fb;
};
template <class Law>
ChainSum chain_sum(const std::vector<Vec3> &a, const std::vector<Vec3> &b, Law pair_law,
                   double cap_kn)
{
  ChainSum out;
  out.fa.assign(a.size(), Vec3());
  out.fb.assign(b.size(), Vec3());
  for (size_t i = 0; i + 1 < a.size(); i++)
    for (size_t j = 0; j + 1 < b.size(); j++) {
      const SegmentContact c = pair_law(a[i], a[i + 1], b[j], b[j + 1]);
      if (!c.active) continue;
      out.energy += c.energy;
      out.fa[i] += c.f[0];
      out.fa[i + 1] += c.f[1];
      out.fb[j] += c.f[2];
      out.fb[j + 1] += c.f[3];
    }
  auto caps = [&](const std::vector<Vec3> &seg, std::vector<Vec3> &fs,
                  const std::vector<Vec3> &nodes, std::vector<Vec3> &fn) {
    for (size_t i = 0; i + 1 < seg.size(); i++)
      for (size_t k = 1; k + 1 < nodes.size(); k++) {
        const auto c = NCF::node_contact(seg[i], seg[i + 1], nodes[k - 1], nodes[k], nodes[k + 1],
                                         D, cap_kn, RAMP, NCF::DEFAULT_CORE);
        if (!c.active) continue;
        out.energy += c.energy;
        fs[i] += c.f[0];
        fs[i + 1] += c.f[1];
        fn[k - 1] += c.f[2];
        fn[k] += c.f[3];
        fn[k + 1] += c.f[4];
      }
  };
  caps(a, out.fa, b, out.fb);
  caps(b, out.fb, a, out.fa);
  return out;
}

// a thin chain wrapped around a straight one (a kink at every node), or two zigzag chains
// crossing
std::vector<Vec3> helix(double radius, double pitch, int nodes, double per_turn)
{
  std::vector<Vec3> x;
  for (int k = 0; k < nodes; k++) {
    const double phi = 2.0 * M_PI * k / per_turn;
    x.push_back(Vec3(pitch * phi / (2.0 * M_PI), radius * std::cos(phi), radius * std::sin(phi)));
  }
  return x;
}

double worst_force_diff(const ChainSum &p, const ChainSum &q)
{
  double w = 0.0, s = 0.0;
  for (size_t k = 0; k < p.fa.size(); k++) {
    w = std::max(w, NCF::norm(p.fa[k] - q.fa[k]));
    s = std::max(s, NCF::norm(p.fa[k]));
  }
  for (size_t k = 0; k < p.fb.size(); k++) {
    w = std::max(w, NCF::norm(p.fb[k] - q.fb[k]));
    s = std::max(s, NCF::norm(p.fb[k]));
  }
  return w / s;
}

}    // namespace

// A kinked chain in contact with another, summed with either chain as A: the same energy and
// forces to round-off with the symmetric law (caps at CAP_WEIGHT); the one-way law (caps at full
// weight, as the pair style had it) differs by far more, so the comparison can fail
TEST(SymmetricContact, KinkedChainsTheSameWhicheverChainIsA)
{
  const double kth = NCF::CAP_WEIGHT * KN;
  auto sym = [](const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1) {
    NCF::ContactOptions opt;
    opt.core = NCF::DEFAULT_CORE;
    return NCF::chain_contact(a0, a1, b0, b1, D, KN, RAMP, false, opt);
  };
  auto one = [](const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1) {
    NCF::ContactOptions opt;
    opt.core = NCF::DEFAULT_CORE;
    return NCF::segment_contact(a0, a1, b0, b1, D, KN, RAMP, false, opt);
  };
  // a thin chain (a 30 deg kink at every node) wrapped around a straight one pressed onto it
  // (contact distance D, helix radius 0.85 D), and a zigzag crossing another zigzag
  std::vector<std::pair<std::vector<Vec3>, std::vector<Vec3>>> scenes;
  scenes.push_back({helix(0.85 * D, 0.5 * D, 25, 12.0),
                    {Vec3(-4 * D, 0, 0), Vec3(-D, 0, 0), Vec3(2 * D, 0, 0), Vec3(5 * D, 0, 0),
                     Vec3(8 * D, 0, 0)}});
  std::vector<Vec3> z1, z2;
  for (int k = 0; k < 9; k++) {
    z1.push_back(Vec3((k - 4) * 1.3 * D, (k % 2) * 0.6 * D, 0.1 * D * (k % 3)));
    z2.push_back(
        Vec3((k % 2) * 0.7 * D - 0.2 * D, (k - 4) * 1.1 * D, 0.8 * D + 0.05 * D * (k % 3)));
  }
  scenes.push_back({z1, z2});
  for (size_t s = 0; s < scenes.size(); s++) {
    const auto &a = scenes[s].first, &b = scenes[s].second;
    const ChainSum ab = chain_sum(a, b, sym, kth), ba = chain_sum(b, a, sym, kth);
    ASSERT_GT(ab.energy, 0.0) << "scene " << s;
    // (ba's node forces with the chains exchanged)
    ChainSum bs = ba;
    std::swap(bs.fa, bs.fb);
    EXPECT_NEAR(ab.energy, ba.energy, 1e-12 * ab.energy) << "scene " << s;
    EXPECT_LT(worst_force_diff(ab, bs), 1e-12) << "scene " << s;
    const ChainSum oab = chain_sum(a, b, one, KN), oba = chain_sum(b, a, one, KN);
    EXPECT_GT(std::fabs(oab.energy - oba.energy), 0.01 * oab.energy)
        << "scene " << s << ": the one-way law should depend on which chain is A here";
    printf("scene %zu: symmetric %.6g J (both ways); one way %.6g / %.6g J\n", s, ab.energy,
           oab.energy, oba.energy);
  }
}

// A straight segment pressed onto the outside of a 90 deg kink (the corner of a chain of
// cylinders jointed by spheres) along the bisector, across the kink's plane. A against the kinked
// chain sees the corner as the node's sphere (the cap fills the ramps' gap: as much force as a
// straight chain at the same distance); the kinked chain against A sees its axis leave A at once
// (a quarter of it). The symmetric law takes the mean: 0.6-0.7 of the straight crossing at
// penetrations of 0.05-0.2 D, as for a sphere pressed on a cylinder against two crossed cylinders
// of the same radius at the same penetration (contact areas in the ratio 1/sqrt 2 by Hertz's
// geometry). Without the caps it would be a quarter.
TEST(SymmetricContact, KinkConvexSideIsCovered)
{
  const double L = 1e-4;
  const Vec3 n(0, 0, 0), p = L * Vec3(-std::sqrt(0.5), -std::sqrt(0.5), 0),
                         q = L * Vec3(std::sqrt(0.5), -std::sqrt(0.5), 0);
  for (double gap : {0.95 * D, 0.9 * D, 0.8 * D}) {
    const Vec3 a0(0, gap, -0.6 * L), a1(0, gap, 0.6 * L);
    const auto s1 = NCF::chain_contact(a0, a1, p, n, D, KN, RAMP),
               s2 = NCF::chain_contact(a0, a1, n, q, D, KN, RAMP);
    const auto cap = NCF::node_contact(a0, a1, p, n, q, D, NCF::CAP_WEIGHT * KN, RAMP);
    const double without = (s1.f[0] + s1.f[1] + s2.f[0] + s2.f[1]).y;
    const double with = without + (cap.f[0] + cap.f[1]).y;
    const auto straight = NCF::chain_contact(a0, a1, Vec3(-L, 0, 0), Vec3(L, 0, 0), D, KN, RAMP);
    const double ref = (straight.f[0] + straight.f[1]).y;
    EXPECT_GT(with, 0.55 * ref) << "gap " << gap / D << " D";
    EXPECT_LT(with, 0.75 * ref) << "gap " << gap / D << " D";
    EXPECT_LT(without, 0.25 * ref) << "the caps carry the sphere of the corner";
  }
}

// chain_contact_batch against chain_contact lane by lane (to round-off); lanes it leaves to the
// scalar law counted
TEST(SymmetricContact, BatchEqualsTheScalarLaw)
{
  const std::vector<Pair> pairs = random_pairs(20000, 21);
  int fast_active = 0, left = 0;
  NCF::ContactBatch b;
  for (size_t start = 0; start < pairs.size(); start += NCF::CONTACT_BATCH) {
    b.n = (int) std::min<size_t>(NCF::CONTACT_BATCH, pairs.size() - start);
    for (int l = 0; l < b.n; l++) {
      const Pair &p = pairs[start + l];
      b.set(l, p.x[0], p.x[1], p.x[2], p.x[3], D, KN, RAMP);
    }
    NCF::chain_contact_batch(b, NCF::DEFAULT_CORE);
    for (int l = 0; l < b.n; l++) {
      const Pair &p = pairs[start + l];
      NCF::ContactOptions opt;
      opt.core = NCF::DEFAULT_CORE;
      const auto ref = NCF::chain_contact(p.x[0], p.x[1], p.x[2], p.x[3], D, KN, RAMP, false, opt);
      if (b.status[l] < 0.0) {
        left++;
        continue;
      }
      const auto c = b.result(l);
      ASSERT_EQ(c.active, ref.active) << "pair " << start + l;
      if (!ref.active) continue;
      fast_active++;
      const double fs = fscale(ref), tol = 1e-9;
      EXPECT_NEAR(c.energy, ref.energy, tol * ref.energy);
      for (int m = 0; m < 4; m++)
        for (int d = 0; d < 3; d++) EXPECT_NEAR(c.f[m][d], ref.f[m][d], tol * fs);
      EXPECT_NEAR(c.fn, ref.fn, tol * fs);
      EXPECT_NEAR(NCF::norm(c.normal - ref.normal), 0.0, tol);
      EXPECT_NEAR(c.xi, ref.xi, tol);
      EXPECT_NEAR(c.t, ref.t, tol);
      EXPECT_NEAR(c.length, ref.length, tol * ref.length);
    }
  }
  EXPECT_GT(fast_active, 4000);
  EXPECT_GT(left, 100);
  printf("%d contacts by the batch, %d pairs left to the scalar law\n", fast_active, left);
}
