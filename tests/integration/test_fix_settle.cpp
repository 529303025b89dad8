// Integration tests of fix ncf/settle: a damped chain that was kicked settles and the run ends
// early (the step after the check is the run's last one: thermo prints it, the next run is not
// stopped); a criterion that cannot hold runs to the cap; inactive it checks nothing; bad input
// names the style, the keyword and the value.

#include "ncf_lammps_test.h"

#include "lammps.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>

using namespace ncftest;
using ::testing::HasSubstr;

namespace {

// a chain of n nodes along x, its nodes kicked in y (a damped transverse and axial vibration
// of a chain whose ends are held)
std::string write_chain(const std::string &dir, int n = 6)
{
  const std::string path = dir + "/chain.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "chain\n\n%d atoms\n1 atom types\n%d bonds\n1 bond types\n\n", n, n - 1);
  fprintf(fp, "0 %.17g xlo xhi\n-1e-3 1e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\n", (n + 1) * 2e-4);
  fprintf(fp, "Masses\n\n1 1e-9\n\nAtoms # bond\n\n");
  for (int i = 0; i < n; i++) fprintf(fp, "%d 1 1 %.17g 0 0\n", i + 1, (i + 0.5) * 2e-4);
  fprintf(fp, "\nVelocities\n\n");
  for (int i = 0; i < n; i++) fprintf(fp, "%d 0.1 %g 0\n", i + 1, (i % 2 ? 1.0 : -1.0));
  fprintf(fp, "\nBonds\n\n");
  for (int i = 1; i < n; i++) fprintf(fp, "%d 1 %d %d\n", i, i, i + 1);
  fclose(fp);
  return path;
}

void load(Lammps &l, const std::string &dir)
{
  l.cmds(R"(
units si
atom_style bond
atom_modify map array
boundary f f f
bond_style ncf/chain
)");
  l.cmd("read_data " + write_chain(dir));
  l.cmds(R"(
bond_coeff 1 ea 100
group ends id 1 6
fix nve all nve
fix damp all viscous 2.5e-4
fix hold ends setforce 0 0 0
velocity ends set 0 0 0
timestep 2e-8
variable ekin0 equal 1e-9*(6*0.01+4*1.0)/2
variable xs equal xcm(all,x)
)");
}

std::string read_text(const std::string &path)
{
  std::string text;
  FILE *fp = fopen(path.c_str(), "r");
  if (!fp) return text;
  char buf[4096];
  while (fgets(buf, sizeof(buf), fp)) text += buf;
  fclose(fp);
  return text;
}

}    // namespace

TEST(FixSettle, EndsTheRunWhenQuasiStatic)
{
  auto dir = scratch_dir("settle_ends");
  Lammps l(MPI_COMM_WORLD, dir + "/log.lammps");
  load(l, dir);
  l.cmd("fix s all ncf/settle 10 window 6 ke v_ekin0 1e-6 steady v_xs 1e-9");
  l.cmd("thermo 1000000");
  l.cmd("run 100000");
  const double steps = l.value("f_s[2]");
  EXPECT_EQ(l.value("f_s[1]"), 1.0);
  EXPECT_GT(steps, 60.0);
  EXPECT_LT(steps, 100000.0);
  // the run ended on the step after the check that settled (a multiple of 10, plus one)
  EXPECT_EQ(l.value("step"), steps);
  EXPECT_EQ((long) steps % 10, 1);
  // that step is the run's last one to LAMMPS: thermo (every 1e6 steps) printed it
  l.cmd("log none");
  EXPECT_THAT(read_text(dir + "/log.lammps"),
              testing::ContainsRegex("\n +" + std::to_string((long) steps) + " +[-0-9]"));
  // and it is quasi-static there: KE within the tolerance of the initial kinetic energy
  EXPECT_LE(l.value("ke"), 1e-6 * l.value("v_ekin0") * 1.01);
  // the next run, without checks, is not stopped by the timer that ended the last one
  l.cmd("fix_modify s active no");
  l.cmd("run 50");
  EXPECT_EQ(l.value("step"), steps + 50);
  EXPECT_EQ(l.value("f_s[1]"), 0.0);
}

TEST(FixSettle, RunsToTheCapAndSaysSo)
{
  auto dir = scratch_dir("settle_cap");
  Lammps l(MPI_COMM_WORLD, dir + "/log.lammps");
  load(l, dir);
  // a tolerance of zero kinetic energy never holds in 200 steps
  l.cmd("fix s all ncf/settle 10 ke v_ekin0 0.0");
  l.cmd("run 200");
  EXPECT_EQ(l.value("step"), 200.0);
  EXPECT_EQ(l.value("f_s[1]"), 0.0);
  EXPECT_EQ(l.value("f_s[2]"), 200.0);
  EXPECT_GT(l.value("f_s[3]"), 0.0);    // KE / max v_ekin0 at the last check
  l.cmd("log none");
  EXPECT_THAT(read_text(dir + "/log.lammps"),
              HasSubstr("fix ncf/settle s: not quasi-static at the end of the run (its cap "
                        "of 200 steps): KE / max v_ekin0"));
}

TEST(FixSettle, InactiveChecksNothing)
{
  auto dir = scratch_dir("settle_inactive");
  Lammps l;
  load(l, dir);
  // (a steady potential energy: the checks need it tallied on their steps)
  l.cmd("variable e equal pe+1e-9");
  l.cmd("fix s all ncf/settle 10 window 2 ke v_ekin0 1.0 steady v_e 1e9 active no");
  l.cmd("run 100");
  EXPECT_EQ(l.value("step"), 100.0);
  l.cmd("fix_modify s active yes");
  // a run that goes on with `pre no` (no setup): its own checks, counted from its first step
  l.cmd("run 100 pre no");
  EXPECT_EQ(l.value("step"), 121.0);    // checks at 110 and 120 fill the window: settled
  EXPECT_EQ(l.value("f_s[2]"), 21.0);
  l.cmd("run 100 pre no");
  EXPECT_EQ(l.value("step"), 141.0);    // the next one again (130, 140), not stopped at once
  EXPECT_EQ(l.value("f_s[2]"), 20.0);
}

TEST(FixSettle, BadInputNamesStyleKeywordAndValue)
{
  auto dir = scratch_dir("settle_bad");
  auto run = [&](const std::string &fix, bool run_it = false) {
    return error_of([&] {
      Lammps l;
      load(l, dir);
      l.cmd(fix);
      if (run_it) l.cmd("run 10");
    });
  };
  EXPECT_THAT(run("fix s all ncf/settle"), HasSubstr("fix ncf/settle: needs the check interval N"));
  EXPECT_THAT(run("fix s all ncf/settle 0 ke v_ekin0 1"),
              HasSubstr("fix ncf/settle: value '0' of 'N' must be an integer in [1, 1000000000]"));
  EXPECT_THAT(run("fix s all ncf/settle 10"), HasSubstr("give at least one criterion"));
  EXPECT_THAT(run("fix s all ncf/settle 10 ke ekin0 1"),
              HasSubstr("fix ncf/settle: ke 'ekin0' is not a variable v_NAME"));
  EXPECT_THAT(
      run("fix s all ncf/settle 10 ke v_ekin0"),
      HasSubstr("fix ncf/settle: keyword 'ke' needs a reference energy v_REF and a tolerance"));
  EXPECT_THAT(run("fix s all ncf/settle 10 ke v_ekin0 -1"),
              HasSubstr("fix ncf/settle: ke tolerance -1 must be >= 0"));
  EXPECT_THAT(run("fix s all ncf/settle 10 fmax 0"),
              HasSubstr("fix ncf/settle: fmax 0 must be > 0"));
  EXPECT_THAT(run("fix s all ncf/settle 10 steady v_xs 0.1 window 1"),
              HasSubstr("needs a window of >= 2 checks"));
  EXPECT_THAT(run("fix s all ncf/settle 10 fmax 1 window 2 window 3"),
              HasSubstr("fix ncf/settle: keyword 'window' given twice"));
  EXPECT_THAT(run("fix s all ncf/settle 10 fmax 1 speed 3"),
              HasSubstr("fix ncf/settle: unknown keyword 'speed'"));
  EXPECT_THAT(run("fix s all ncf/settle 10 steady v_nothing 0.1", true),
              HasSubstr("fix ncf/settle: variable 'nothing' does not exist"));
  EXPECT_THAT(run("fix s all ncf/settle 10 fmax 1 active maybe"),
              HasSubstr("fix ncf/settle: value 'maybe' of 'active' is not one of yes, no"));
}
