// The batched contact law (segment_contact_batch, ncf_contact.h) against the scalar law
// segment_contact as the reference: every lane the batch evaluates must give the same contact
// (status, energy, forces, normal force and direction, contact point, contact length) to
// round-off, and the lanes it leaves to the scalar law must be the cases it does not cover. The
// random pairs mix crossings, pairs in the ramps and on the plateau of B's weight, contacts deep
// in the core, nearly and exactly parallel pairs, short segments and touching axes.

#include "ncf_contact.h"
#include "ncf_random_geometry.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

using NCF::ContactBatch;
using NCF::Vec3;

namespace {

const double D = 69e-6;
const double KN = 1e9;
const double RAMP = 0.25 * D;

struct Pair {
  Vec3 a0, a1, b0, b1;
};

std::vector<Pair> random_pairs(int n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<Pair> out;
  for (int k = 0; k < n; k++) {
    const int kind = k % 8;
    const double lb = kind == 5 ? 1.5 * RAMP * (1.0 + U(rng)) : 2e-4 * (1.0 + 0.3 * U(rng));
    const double la = kind == 6 ? 0.5 * RAMP * (1.0 + U(rng)) : 2e-4 * (1.0 + 0.3 * U(rng));
    double ang = 1.5 * U(rng);
    if (kind == 3) ang = 1e-4 * U(rng);    // nearly parallel
    if (kind == 4) ang = 0.0;              // exactly parallel
    const double pen = (kind == 2 ? 0.7 : 0.15) * D * (0.5 + 0.5 * U(rng));
    double gap = D - pen;
    if (kind == 7) gap = 1e-12 * U(rng);    // axes (nearly) touching
    // A crosses B's line near an arbitrary point of B (plateau or ramps), slightly tilted
    const double sB = lb * (0.5 + 0.7 * U(rng));
    const Vec3 b0(0, 0, 0), b1(lb, 0, 0);
    const Vec3 c(sB, 0.2 * D * U(rng), gap);
    const Vec3 d0(std::cos(ang), std::sin(ang), 0.1 * U(rng));
    const Vec3 dir = (1.0 / NCF::norm(d0)) * d0;
    const double back = la * (0.5 + 0.4 * U(rng));
    out.push_back({c - back * dir, c + (la - back) * dir, b0, b1});
  }
  return out;
}

// the batch's lanes from the pairs from `start` on (as many as fit)
void fill_batch(ContactBatch &b, const std::vector<Pair> &pairs, size_t start)
{
  b.n = (int) std::min<size_t>(NCF::CONTACT_BATCH, pairs.size() - start);
  for (int l = 0; l < b.n; l++) {
    const Pair &p = pairs[start + l];
    b.set(l, p.a0, p.a1, p.b0, p.b1, D, KN, RAMP);
  }
}

double scale_of(const NCF::SegmentContact &c)
{
  double s = 0.0;
  for (int m = 0; m < 4; m++) s = std::max(s, NCF::norm(c.f[m]));
  return s;
}

}    // namespace

TEST(ContactBatch, EqualsTheScalarLawLaneByLane)
{
  for (double core : {0.0, NCF::DEFAULT_CORE}) {
    const std::vector<Pair> pairs = random_pairs(40000, 5);
    NCF::ContactOptions opt;
    opt.core = core;
    int fast = 0, fast_active = 0, left = 0, left_active = 0;
    ContactBatch b;
    for (size_t start = 0; start < pairs.size(); start += NCF::CONTACT_BATCH) {
      fill_batch(b, pairs, start);
      NCF::segment_contact_batch(b, core);
      for (int l = 0; l < b.n; l++) {
        const Pair &p = pairs[start + l];
        const auto ref = NCF::segment_contact(p.a0, p.a1, p.b0, p.b1, D, KN, RAMP, false, opt);
        const int k = (int) (start + l);
        if (b.status[l] < 0.0) {
          left++;
          left_active += ref.active;
          continue;
        }
        fast++;
        const auto c = b.result(l);
        ASSERT_EQ(c.active, ref.active) << "pair " << k << " core " << core;
        if (!ref.active) continue;
        fast_active++;
        const double fs = scale_of(ref), tol = 1e-9;
        EXPECT_NEAR(c.energy, ref.energy, tol * ref.energy) << "pair " << k;
        for (int m = 0; m < 4; m++)
          for (int d = 0; d < 3; d++)
            EXPECT_NEAR(c.f[m][d], ref.f[m][d], tol * fs) << "pair " << k << " node " << m;
        EXPECT_NEAR(c.fn, ref.fn, tol * fs) << "pair " << k;
        EXPECT_NEAR(NCF::norm(c.normal - ref.normal), 0.0, tol) << "pair " << k;
        EXPECT_NEAR(c.xi, ref.xi, tol) << "pair " << k;
        EXPECT_NEAR(c.t, ref.t, tol) << "pair " << k;
        EXPECT_NEAR(c.length, ref.length, tol * ref.length) << "pair " << k;
      }
    }
    // both sides are exercised: the batch takes the crossings (nine in ten of these pairs
    // without the core), the scalar law the rest (parallel, short, touching, across the core)
    EXPECT_GT(fast_active, 25000) << "core " << core;
    EXPECT_GT(left_active, 1000) << "core " << core;
    printf("core %g: %d pairs evaluated by the batch (%d in contact), %d left to the scalar law "
           "(%d in contact)\n",
           core, fast, fast_active, left, left_active);
  }
}

// The batched dashpot and friction (tangential_batch) against contact_tangential: the same
// operations in the same order, so the same bits, on contacts of the batched law. Random
// velocities (slow: sticking; fast: sliding), slips in and out of the tangent plane and zero,
// lanes without friction, without damping, with a dashpot strong enough to be clamped at -fn,
// zero stiffness, and lanes not in contact (left alone).
TEST(TangentialBatch, EqualsContactTangentialBitwise)
{
  const std::vector<Pair> pairs = random_pairs(64000, 11);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double dt = 1e-8;
  int sliding = 0, sticking = 0, clamped = 0, compared = 0;
  ContactBatch b;
  NCF::TangentialBatch t;
  for (size_t start = 0; start < pairs.size(); start += NCF::CONTACT_BATCH) {
    fill_batch(b, pairs, start);
    NCF::segment_contact_batch(b, NCF::DEFAULT_CORE);
    Vec3 slip[NCF::CONTACT_BATCH], vel[NCF::CONTACT_BATCH][4];
    for (int l = 0; l < b.n; l++) {
      const int kind = (int) ((start + l) % 9);
      for (int m = 0; m < 4; m++) {
        vel[l][m] = (kind == 3 ? 10.0 : 0.01) * Vec3(U(rng), U(rng), U(rng));
        for (int d = 0; d < 3; d++) t.v[3 * m + d][l] = vel[l][m][d];
      }
      const Vec3 n(b.normal[0][l], b.normal[1][l], b.normal[2][l]);
      slip[l] = 1e-6 * Vec3(U(rng), U(rng), U(rng));
      if (kind == 1) slip[l] = slip[l] - NCF::dot(slip[l], n) * n;    // in the tangent plane
      if (kind == 2) slip[l] = Vec3();
      t.kt[l] = kind == 4 ? 0.0 : 1e9 * (1.0 + U(rng));
      t.mu[l] = kind == 5 ? 0.0 : 0.3;
      t.damp[l] = kind == 6 ? 0.0 : (kind == 7 ? 1e6 : 1e2) * (1.0 + U(rng));
      for (int d = 0; d < 3; d++) t.slip[d][l] = slip[l][d];
    }
    ContactBatch before = b;
    NCF::tangential_batch(b, t, dt);
    for (int l = 0; l < b.n; l++) {
      const int k = (int) (start + l);
      if (!(before.status[l] > 0.0)) continue;
      NCF::SegmentContact c = before.result(l);
      Vec3 s = slip[l];
      const double energy = NCF::contact_tangential(c, vel[l], s, t.kt[l], t.mu[l], t.damp[l], dt);
      const NCF::SegmentContact got = b.result(l);
      for (int m = 0; m < 4; m++)
        for (int d = 0; d < 3; d++) ASSERT_EQ(got.f[m][d], c.f[m][d]) << "pair " << k;
      ASSERT_EQ(t.energy[l], energy) << "pair " << k;
      if (t.mu[l] > 0.0 && c.fn > 0.0)
        for (int d = 0; d < 3; d++) ASSERT_EQ(t.slip[d][l], s[d]) << "pair " << k;
      compared++;
      if (!(t.mu[l] > 0.0 && t.kt[l] > 0.0)) continue;
      // which regime the lane was in (the dashpot clamped at -fn leaves no friction)
      const Vec3 vrel = ((1.0 - c.xi) * vel[l][0] + c.xi * vel[l][1]) -
          ((1.0 - c.t) * vel[l][2] + c.t * vel[l][3]);
      const double fd = -t.damp[l] * before.length[l] * NCF::dot(vrel, before.result(l).normal);
      const double fn = before.fn[l] + std::max(fd, -before.fn[l]);
      if (!(fn > 0.0))
        clamped++;
      else if (NCF::norm(s) * t.kt[l] * before.length[l] < 0.3 * fn * (1.0 - 1e-9))
        sticking++;
      else
        sliding++;
    }
  }
  EXPECT_GT(compared, 40000);
  EXPECT_GT(sliding, 1000);
  EXPECT_GT(sticking, 1000);
  EXPECT_GT(clamped, 100);
  printf("%d contacts compared: %d sticking, %d sliding, %d with the dashpot clamped\n", compared,
         sticking, sliding, clamped);
}

// The setup of a run (advance false): the friction force of the stored slip, the slip left as it
// is; with the slip a step kept, that step's force bit for bit (so a run cut into pieces is the
// same run). Without a dashpot (a setup has the full-step velocities, a step the half-step ones);
// other velocities in the setup play no role. Batched and scalar alike.
TEST(TangentialBatch, SetupGivesTheForceOfTheStepBefore)
{
  const std::vector<Pair> pairs = random_pairs(16000, 12);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double dt = 1e-8;
  int compared = 0, sliding = 0;
  ContactBatch b;
  NCF::TangentialBatch t;
  for (size_t start = 0; start < pairs.size(); start += NCF::CONTACT_BATCH) {
    fill_batch(b, pairs, start);
    NCF::segment_contact_batch(b, NCF::DEFAULT_CORE);
    for (int l = 0; l < b.n; l++) {
      const double speed = (start / NCF::CONTACT_BATCH) % 2 ? 10.0 : 0.01;
      for (int k = 0; k < 12; k++) t.v[k][l] = speed * U(rng);
      for (int d = 0; d < 3; d++) t.slip[d][l] = 1e-6 * U(rng);
      t.kt[l] = 1e9 * (1.0 + U(rng));
      t.mu[l] = 0.3;
      t.damp[l] = 0.0;
    }
    const ContactBatch law = b;
    NCF::tangential_batch(b, t, dt);    // a step
    ContactBatch setup = law;
    NCF::TangentialBatch ts = t;    // the slips the step kept, other velocities
    for (int l = 0; l < b.n; l++)
      for (int k = 0; k < 12; k++) ts.v[k][l] = U(rng);
    NCF::tangential_batch(setup, ts, dt, false);
    for (int l = 0; l < b.n; l++) {
      if (!(law.status[l] > 0.0)) continue;
      const int k = (int) (start + l);
      NCF::SegmentContact c = law.result(l);
      Vec3 s(t.slip[0][l], t.slip[1][l], t.slip[2][l]);
      const Vec3 kept = s;
      Vec3 vel[4];
      for (int m = 0; m < 4; m++)
        vel[m] = Vec3(ts.v[3 * m][l], ts.v[3 * m + 1][l], ts.v[3 * m + 2][l]);
      NCF::contact_tangential(c, vel, s, t.kt[l], t.mu[l], 0.0, dt, false);
      const NCF::SegmentContact got = setup.result(l), step = b.result(l);
      for (int m = 0; m < 4; m++)
        for (int d = 0; d < 3; d++) {
          ASSERT_EQ(got.f[m][d], step.f[m][d]) << "pair " << k;
          ASSERT_EQ(c.f[m][d], step.f[m][d]) << "pair " << k;
        }
      for (int d = 0; d < 3; d++) {
        ASSERT_EQ(ts.slip[d][l], t.slip[d][l]) << "pair " << k;
        ASSERT_EQ(s[d], kept[d]) << "pair " << k;
      }
      compared++;
      if (NCF::norm(kept) * t.kt[l] * law.length[l] >= 0.3 * law.fn[l] * (1.0 - 1e-9)) sliding++;
    }
  }
  EXPECT_GT(compared, 10000);
  EXPECT_GT(sliding, 1000);
  EXPECT_GT(compared - sliding, 1000);
}

// Segments at free chain ends: extending them (extend_segment), the batched law and
// unextend_contact give what segment_contact gives with ContactOptions::ext (the scalar reference
// of the end caps, which the pair style evaluates through virtual end nodes)
TEST(ContactBatch, ExtendedSegmentsEqualTheScalarLaw)
{
  const std::vector<Pair> pairs = random_pairs(8000, 9);
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> coin(0, 1);
  int compared = 0;
  ContactBatch b;
  b.n = 0;
  std::vector<std::array<double, 4>> exts;
  std::vector<int> ids;
  auto check = [&]() {
    NCF::segment_contact_batch(b, NCF::DEFAULT_CORE);
    for (int l = 0; l < b.n; l++) {
      if (b.status[l] < 0.0) continue;
      const Pair &p = pairs[ids[l]];
      NCF::ContactOptions opt;
      opt.core = NCF::DEFAULT_CORE;
      for (int m = 0; m < 4; m++) opt.ext[m] = exts[l][m];
      const auto ref = NCF::segment_contact(p.a0, p.a1, p.b0, p.b1, D, KN, RAMP, false, opt);
      NCF::SegmentContact c = b.result(l);
      ASSERT_EQ(c.active, ref.active) << "pair " << ids[l];
      if (!c.active) continue;
      NCF::unextend_contact(p.a0, p.a1, p.b0, p.b1, exts[l].data(), c);
      compared++;
      const double fs = scale_of(ref), tol = 1e-9;
      for (int m = 0; m < 4; m++)
        for (int d = 0; d < 3; d++)
          EXPECT_NEAR(c.f[m][d], ref.f[m][d], tol * fs) << "pair " << ids[l] << " node " << m;
      EXPECT_NEAR(c.energy, ref.energy, tol * ref.energy) << "pair " << ids[l];
      EXPECT_NEAR(c.xi, ref.xi, tol) << "pair " << ids[l];
      EXPECT_NEAR(c.t, ref.t, tol) << "pair " << ids[l];
    }
    b.n = 0;
    exts.clear();
    ids.clear();
  };
  for (int k = 0; k < (int) pairs.size(); k++) {
    std::array<double, 4> e;
    for (double &v : e) v = coin(rng) ? NCF::DEFAULT_ENDCAP * D : 0.0;
    Vec3 q[4] = {pairs[k].a0, pairs[k].a1, pairs[k].b0, pairs[k].b1};
    NCF::extend_segment(q[0], q[1], e[0], e[1]);
    NCF::extend_segment(q[2], q[3], e[2], e[3]);
    b.set(b.n++, q[0], q[1], q[2], q[3], D, KN, RAMP);
    exts.push_back(e);
    ids.push_back(k);
    if (b.n == NCF::CONTACT_BATCH) check();
  }
  if (b.n > 0) check();
  EXPECT_GT(compared, 4000);
}

// ---------------------------------------------------------------- node caps

namespace {

struct Cap {
  Vec3 x[5];    // a0, a1, p, n, q
};

// Random caps: a kink of up to max_kink at n (chain p-n-q), chain segments and A of the lengths
// given (each drawn from the list, times 1 +- 30 % when jitter), A through a point within about D
// of n, mostly on the convex side of the kink, in any direction (some exactly perpendicular or
// parallel to a chain segment)
std::vector<Cap> random_caps(int count, unsigned seed, double max_kink,
                             const std::vector<double> &lengths,
                             const std::vector<double> &alengths, bool jitter)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Cap> out;
  for (int k = 0; k < count; k++) {
    const double kink = max_kink * u(rng);
    const NCF_TEST::Kink kk = NCF_TEST::random_kink(rng, kink);
    const Vec3 &e1 = kk.e1, &e2 = kk.e2, &bn = kk.bn;    // convex side: +bn
    auto draw = [&](const std::vector<double> &from) {
      return from[rng() % from.size()] * (jitter ? 1.0 + 0.3 * (2.0 * u(rng) - 1.0) : 1.0);
    };
    const double l1 = draw(lengths), l2 = draw(lengths), la = draw(alengths);
    const Vec3 n(1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng));
    Vec3 off = NCF_TEST::random_unit_vector(rng);
    if (k % 5) off = (1.0 / NCF::norm(bn + 0.8 * off)) * (bn + 0.8 * off);
    const Vec3 c = n + (D * (0.1 + 0.95 * u(rng))) * off;
    Vec3 dir = NCF_TEST::random_unit_vector(rng);
    // one in seven perpendicular to a chain segment (its arc position constant along A), one in
    // seven parallel to it
    const Vec3 ek = (k / 7) % 2 ? e1 : e2;
    if (k % 7 == 3) dir = (1.0 / NCF::norm(NCF::cross(ek, dir))) * NCF::cross(ek, dir);
    if (k % 7 == 5) dir = ek;
    const Vec3 a0 = c - (la * u(rng)) * dir;
    out.push_back({{a0, a0 + la * dir, n - l1 * e1, n, n + l2 * e2}});
  }
  return out;
}

struct CapStats {
  int batch = 0, batch_active = 0, left = 0, left_active = 0, concave = 0;
  double worst_e = 0.0, worst_f = 0.0;
};

// every lane of the batch that it evaluates against node_contact
CapStats check_caps(const std::vector<Cap> &caps, double core)
{
  CapStats s;
  NCF::CapBatch b;
  for (size_t start = 0; start < caps.size(); start += NCF::CAP_BATCH) {
    b.n = (int) std::min<size_t>(NCF::CAP_BATCH, caps.size() - start);
    for (int l = 0; l < b.n; l++) {
      const Vec3 *x = caps[start + l].x;
      const double r[5][3] = {{x[0].x, x[0].y, x[0].z},
                              {x[1].x, x[1].y, x[1].z},
                              {x[2].x, x[2].y, x[2].z},
                              {x[3].x, x[3].y, x[3].z},
                              {x[4].x, x[4].y, x[4].z}};
      b.set(l, r[0], r[1], r[2], r[3], r[4], D, KN, RAMP);
    }
    NCF::node_contact_batch(b, core);
    for (int l = 0; l < b.n; l++) {
      const Vec3 *x = caps[start + l].x;
      const int k = (int) (start + l);
      const auto ref = NCF::node_contact(x[0], x[1], x[2], x[3], x[4], D, KN, RAMP, core);
      if (b.status[l] < 0.0) {
        EXPECT_EQ(b.status[l], -1.0) << "cap " << k;
        s.left++;
        s.left_active += ref.active;
        continue;
      }
      s.batch++;
      EXPECT_TRUE(b.status[l] == 0.0 || b.status[l] == 1.0) << "cap " << k;
      const NCF::NodeContact c = b.result(l);
      EXPECT_EQ(c.active, ref.active)
          << "cap " << k << " core " << core << ": energy " << b.energy[l] << " vs " << ref.energy;
      if (!ref.active || !c.active) continue;
      s.batch_active++;
      double fs = 0.0;
      for (int m = 0; m < 5; m++) fs = std::max(fs, NCF::norm(ref.f[m]));
      const double de = std::fabs(c.energy - ref.energy) / ref.energy;
      s.worst_e = std::max(s.worst_e, de);
      EXPECT_LT(de, 1e-9) << "cap " << k << " core " << core << ": " << c.energy << " vs "
                          << ref.energy;
      for (int m = 0; m < 5; m++) {
        const double df = NCF::norm(c.f[m] - ref.f[m]) / fs;
        s.worst_f = std::max(s.worst_f, df);
        EXPECT_LT(df, 1e-9) << "cap " << k << " core " << core << " node " << m << ": (" << c.f[m].x
                            << ", " << c.f[m].y << ", " << c.f[m].z << ") vs (" << ref.f[m].x
                            << ", " << ref.f[m].y << ", " << ref.f[m].z << ")";
      }
      EXPECT_NEAR(c.penetration, ref.penetration, 1e-12 * D) << "cap " << k;
    }
  }
  return s;
}

}    // namespace

// The batched caps (node_contact_batch) against node_contact: random kinks of 0 to 60 degrees,
// chain segments and A from shorter than 2 ramps to a few D (and of the bench's mesh, 0.2 mm),
// A anywhere within about D of the node, mostly on the convex side, without and with core. Every
// lane the batch evaluates gives node_contact's contact (active or not, energy, forces on the
// five nodes, penetration) to round-off; the lanes it leaves to node_contact are those with a
// chain segment shorter than D + e.
TEST(CapBatch, EqualsNodeContactLaneByLane)
{
  const std::vector<double> lengths = {0.3 * D, 0.7 * D, 1.2 * D, 1.3 * D, 1.5 * D, 3.0 * D, 2e-4};
  const std::vector<double> alengths = {0.05 * D, 0.4 * D, 1.2 * D, 3.0 * D, 2e-4};
  for (double core : {0.0, NCF::DEFAULT_CORE}) {
    const std::vector<Cap> caps = random_caps(20000, 17, M_PI / 3.0, lengths, alengths, true);
    const CapStats s = check_caps(caps, core);
    // both sides are exercised
    EXPECT_GT(s.batch_active, 4000) << "core " << core;
    EXPECT_GT(s.batch - s.batch_active, 500) << "core " << core;
    EXPECT_GT(s.left_active, 1000) << "core " << core;
    printf("core %g: %d caps evaluated by the batch (%d active), %d left to node_contact (%d "
           "active); worst relative error energy %.2g, forces %.2g\n",
           core, s.batch, s.batch_active, s.left, s.left_active, s.worst_e, s.worst_f);
  }
}

// On caps like the bench's (mesh 0.2 mm = 2.9 D, kinks up to 30 degrees, A a chain segment of
// the same mesh) the batch evaluates nearly all caps itself
TEST(CapBatch, HandlesBenchLikeCaps)
{
  for (double core : {0.0, NCF::DEFAULT_CORE}) {
    const std::vector<Cap> caps = random_caps(8000, 23, M_PI / 6.0, {2e-4}, {2e-4}, true);
    const CapStats s = check_caps(caps, core);
    const double left = (double) s.left / (s.batch + s.left);
    EXPECT_LT(left, 0.01) << "core " << core;
    EXPECT_GT(s.batch_active, 1000) << "core " << core;
    printf("bench-like caps, core %g: %d in the batch (%d active), %d (%.2g %%) left to "
           "node_contact\n",
           core, s.batch, s.batch_active, s.left, 100.0 * left);
  }
}

// fill_lanes_from_rows: every lane gets the positions (and velocities) of its four nodes' rows,
// bit for bit, for every number of lanes (whole groups of four and the rest), with and without
// velocities; lanes beyond n are left alone
TEST(ContactBatch, LanesFilledFromNodeRows)
{
  constexpr int NODES = 50;
  alignas(64) double rows[8 * NODES];
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double &v : rows) v = u(rng);
  std::uniform_int_distribution<int> pick(0, NODES - 1);
  for (int n = 0; n <= NCF::CONTACT_BATCH; n++)
    for (bool vel : {false, true}) {
      ContactBatch b;
      NCF::TangentialBatch t;
      for (auto &a : b.x)
        for (double &v : a) v = -7.0;
      for (auto &a : t.v)
        for (double &v : a) v = -7.0;
      int idx[NCF::CONTACT_BATCH][4];
      for (auto &lane : idx)
        for (int &k : lane) k = pick(rng);
      b.n = n;
      NCF::fill_lanes_from_rows(b, t, rows, idx, vel);
      for (int l = 0; l < NCF::CONTACT_BATCH; l++)
        for (int m = 0; m < 4; m++)
          for (int d = 0; d < 3; d++) {
            const double *r = rows + 8 * idx[l][m];
            EXPECT_EQ(b.x[3 * m + d][l], l < n ? r[d] : -7.0) << n << " " << l << " " << m;
            EXPECT_EQ(t.v[3 * m + d][l], l < n && vel ? r[4 + d] : -7.0)
                << n << " " << l << " " << m;
          }
    }
}
