// Unit tests of the quasi-static criterion of fix ncf/settle (ncf_settle.h): every criterion must
// hold at the check, a steady one over the last `window` checks; the kinetic energy is judged
// against the largest reference energy since the reset; a steady value by the drift of its window's half means
// against its largest magnitude (noise averages out, a creep does not); a damped oscillation
// settles where its envelope says; a value that is not finite never holds; reset forgets; bad
// set-ups are refused.

#include "ncf_input_error.h"
#include "ncf_settle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using NCF::Settle;
using S = NCF::Settle::Sample;

TEST(Settle, KineticEnergyAtTheCheckSteadyOverTheWindow)
{
  Settle s(3);
  s.add(Settle::KE_RATIO, "KE / max v_w", 1e-3);
  EXPECT_TRUE(s.check({{1e-4, 1.0}}));    // alone, the kinetic energy holds at its check
  EXPECT_FALSE(s.check({{2e-3, 1.0}}));
  EXPECT_TRUE(s.check({{1e-3, 1.0}}));    // at the tolerance holds
  s.add(Settle::STEADY, "v_p", 1e-2);     // with a steady criterion: `window` checks first
  s.reset();
  EXPECT_FALSE(s.check({{1e-4, 1.0}, {5.0}}));
  EXPECT_FALSE(s.check({{1e-4, 1.0}, {5.0}}));
  EXPECT_TRUE(s.check({{1e-4, 1.0}, {5.0}}));
  EXPECT_FALSE(s.check({{2e-3, 1.0}, {5.0}}));    // steady, but moving
  EXPECT_TRUE(s.check({{1e-4, 1.0}, {5.0}}));
  EXPECT_FALSE(s.check({{1e-4, 1.0}, {6.0}}));    // at rest, but the value jumped
  EXPECT_EQ(s.checks(), 6);
}

TEST(Settle, KineticEnergyAgainstTheLargestReference)
{
  // a relaxation: the stored energy falls from 1 to 1e-3 while the kinetic energy decays; KE is
  // compared with the largest energy of the run, not with what is left
  Settle s(2);
  s.add(Settle::KE_RATIO, "KE / max v_pe", 1e-2);
  EXPECT_FALSE(s.check({{0.5, 1.0}}));
  EXPECT_FALSE(s.check({{2e-2, 0.01}}));    // 2e-2 against max 1.0
  EXPECT_TRUE(s.check({{5e-3, 1e-3}}));     // 5e-3 against max 1.0, not against 1e-3
  EXPECT_DOUBLE_EQ(s.measure(0), 5e-3);
  s.reset();    // a new run: its own scale
  EXPECT_FALSE(s.check({{5e-3, 1e-3}}));
  EXPECT_DOUBLE_EQ(s.measure(0), 5.0);
}

TEST(Settle, AllCriteriaTogether)
{
  Settle s(2);
  s.add(Settle::KE_RATIO, "KE / max v_w", 1e-3);
  s.add(Settle::AT_MOST, "fmax", 0.5);
  EXPECT_FALSE(s.check({{1e-4, 1.0}, {1.0}}));    // KE holds, the force does not
  EXPECT_TRUE(s.held(0));
  EXPECT_FALSE(s.held(1));
  EXPECT_FALSE(s.check({{2e-3, 1.0}, {0.4}}));    // the force holds, KE does not
  EXPECT_TRUE(s.check({{1e-4, 1.0}, {0.4}}));
}

TEST(Settle, SteadyIsTheDriftOfTheWindowNotItsNoise)
{
  // a pressure of 1 with a scatter of +-2 % from check to check and no drift: settles with a
  // tolerance of 1 % over 10 checks (the halves' means scatter by ~0.9 % at most here)
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  Settle noisy(10);
  noisy.add(Settle::STEADY, "v_p", 0.01);
  bool settled = false;
  for (int k = 0; k < 30 && !settled; k++) settled = noisy.check({{1.0 + u(rng)}});
  EXPECT_TRUE(settled);
  // the same scatter on a creep of 1 % per check (5 % between the halves' means, against a
  // scatter of their difference of ~0.7 %): never
  Settle creep(10);
  creep.add(Settle::STEADY, "v_p", 0.01);
  for (int k = 0; k < 30; k++) EXPECT_FALSE(creep.check({{1.0 + 0.01 * k + u(rng)}})) << k;
  // the drift exactly: halves of 1, 2 | 3 (dropped) | 4, 5 of a window of 5: (4.5 - 1.5) / 5
  Settle five(5);
  five.add(Settle::STEADY, "v_x", 1.0);
  for (double x : {1.0, 2.0, 3.0, 4.0, 5.0}) five.check({{x}});
  EXPECT_DOUBLE_EQ(five.measure(0), 3.0 / 5.0);
  // against the largest magnitude since the reset: a quantity relaxing from 10 to noise near 0
  Settle relax(4);
  relax.add(Settle::STEADY, "v_p", 0.01);
  relax.check({{10.0}});
  for (double x : {0.05, -0.04, 0.06, -0.05}) relax.check({{x}});
  EXPECT_TRUE(relax.held(0));    // the noise of 0.05 is 0.5 % of 10
  // all zero is steady
  Settle zero(2);
  zero.add(Settle::STEADY, "v_t", 0.0);
  zero.check({{0.0}});
  EXPECT_TRUE(zero.check({{0.0}}));
}

TEST(Settle, DampedOscillationSettlesWhereTheEnvelopeSays)
{
  // x(t) = 1 + A exp(-t/tau) cos(w t), checked every dt, window W checks over more than a period.
  // The halves' means differ by at most 2 E (E: the envelope at the window's start) and, for an
  // oscillation, by at least a fraction of the envelope at its end; so the check settles after
  // the envelope fell below ~tol/2 and not long before it fell below ~tol
  const double A = 0.2, tau = 2000.0, w = 2.0 * M_PI / 700.0, dt = 100.0, tol = 1e-3;
  const int W = 10;
  Settle s(W);
  s.add(Settle::STEADY, "v_x", tol);
  int at = -1;
  for (int k = 0; k < 400 && at < 0; k++) {
    const double t = k * dt;
    if (s.check({{1.0 + A * std::exp(-t / tau) * std::cos(w * t)}})) at = k;
  }
  ASSERT_GT(at, 0);
  const double t_at = at * dt;
  const double scale = 1.0 + A;    // the largest value: the first check
  // sufficient: 2 E(t_at - (W-1) dt) <= tol * scale
  const double t_sufficient = tau * std::log(2.0 * A / (tol * scale)) + (W - 1) * dt;
  EXPECT_LE(t_at, t_sufficient + dt);
  // not settled while the envelope at the window's end exceeds 10 tol
  const double t_early = tau * std::log(A / (10.0 * tol * scale));
  EXPECT_GE(t_at, t_early);
}

TEST(Settle, NotFiniteNeverHoldsAndResetForgets)
{
  Settle s(2);
  s.add(Settle::STEADY, "v_p", 1.0);
  s.check({{1.0}});
  EXPECT_FALSE(s.check({{NAN}}));
  EXPECT_FALSE(s.check({{1.0}}));    // NaN still in the window
  EXPECT_TRUE(s.check({{1.0}}));
  EXPECT_FALSE(s.check({{INFINITY}}));    // not finite: fails while in the window
  EXPECT_FALSE(s.check({{1.0}}));
  EXPECT_TRUE(s.check({{1.0}}));
  s.reset();
  EXPECT_EQ(s.checks(), 0);
  EXPECT_FALSE(s.check({{1.0}}));
  EXPECT_NE(s.report().find("1 of the window's 2 checks"), std::string::npos) << s.report();
  EXPECT_TRUE(s.check({{1.0}}));
  Settle k(2);
  k.add(Settle::KE_RATIO, "KE / max v_w", 1.0);
  EXPECT_FALSE(k.check({{NAN, 1.0}}));
  EXPECT_TRUE(k.check({{0.0, 1.0}}));
  EXPECT_FALSE(k.check({{0.0, NAN}}));    // a reference that is not finite fails
  EXPECT_TRUE(k.check({{0.0, 1.0}}));
  // a reference of zero: KE / 0 holds only for KE 0
  Settle z(1);
  z.add(Settle::KE_RATIO, "KE / max v_w", 1e-3);
  EXPECT_TRUE(z.check({{0.0, 0.0}}));
  EXPECT_FALSE(z.check({{1e-30, 0.0}}));
}

TEST(Settle, ReportNamesEachCriterion)
{
  Settle s(2);
  s.add(Settle::KE_RATIO, "KE / max v_work", 1e-3);
  s.add(Settle::STEADY, "v_p", 0.002);
  s.check({{5e-4, 1.0}, {100.0}});
  s.check({{2e-3, 1.0}, {100.1}});
  const std::string r = s.report();
  EXPECT_NE(r.find("KE / max v_work 0.002 > 0.001"), std::string::npos) << r;
  EXPECT_NE(r.find("v_p drifted 0.0999 % <= 0.2 % over 2 checks"), std::string::npos) << r;
}

TEST(Settle, BadSetUpsAreRefused)
{
  EXPECT_THROW(Settle(0), NCF::InputError);
  Settle one(1);
  EXPECT_THROW(one.add(Settle::STEADY, "v_p", 0.01), NCF::InputError);    // no drift in 1 check
  Settle s(3);
  EXPECT_THROW(s.add(Settle::KE_RATIO, "KE", -1.0), NCF::InputError);
  EXPECT_THROW(s.add(Settle::AT_MOST, "fmax", NAN), NCF::InputError);
  EXPECT_THROW(s.check({{1.0}}), NCF::InputError);    // no criterion: one sample too many
  Settle none(2);
  EXPECT_FALSE(none.check({}));    // nothing to hold: never settled
}
