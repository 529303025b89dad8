// Integration tests of fix ncf/shrink (pretension of the stitching yarn by a negative thermal load).

#include "ncf_lammps_test.h"

#include "fmt/format.h"
#include "lammps.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace ncftest;
using ::testing::HasSubstr;

namespace {

// two bond types: a chain of n nodes of type-1 bonds and one type-2 bond at its end
std::string write_pair(const std::string &dir, int n = 4)
{
  const std::string path = dir + "/pair.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "pair\n\n%d atoms\n1 atom types\n%d bonds\n2 bond types\n\n", n, n - 1);
  fprintf(fp, "0 %.17g xlo xhi\n-1e-3 1e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\n", (n + 1) * 2e-4);
  fprintf(fp, "Masses\n\n1 1e-9\n\nAtoms # bond\n\n");
  for (int i = 0; i < n; i++) fprintf(fp, "%d 1 1 %.17g 0 0\n", i + 1, (i + 0.5) * 2e-4);
  fprintf(fp, "\nBonds\n\n");
  for (int i = 1; i < n; i++) fprintf(fp, "%d %d %d %d\n", i, i < n - 1 ? 1 : 2, i, i + 1);
  fclose(fp);
  return path;
}

void load(Lammps &l, const std::string &data)
{
  l.cmds(R"(
units si
atom_style bond
atom_modify map array
boundary f f f
bond_style ncf/chain
)");
  l.cmd("read_data " + data);
  l.cmd("bond_coeff 1 ea 100");
  l.cmd("bond_coeff 2 ea 10");
}

}    // namespace

TEST(FixShrink, CosineAndLinearRamps)
{
  auto dir = scratch_dir("shrink_ramp");
  Lammps l;
  load(l, write_pair(dir));
  l.cmd("fix s all ncf/shrink btype 2 strain 0.16 steps 100");
  l.cmd("run 0");
  EXPECT_EQ(l.value("f_s"), 0.0);
  l.cmd("run 50");
  EXPECT_NEAR(l.value("f_s"), 0.08, 1e-15);    // cosine ramp at half time: half
  l.cmd("run 25");
  EXPECT_NEAR(l.value("f_s"), 0.16 * 0.5 * (1 - std::cos(0.75 * M_PI)), 1e-15);
  l.cmd("run 100");
  EXPECT_EQ(l.value("f_s"), 0.16);    // held at the target
  EXPECT_EQ(l.value("f_s[2]"), 1.0);
  // a new fix ramps linearly from the current value
  l.cmd("unfix s");
  l.cmd("fix s all ncf/shrink btype 2 strain 0.0 steps 40 ramp linear");
  l.cmd("run 10");
  EXPECT_NEAR(l.value("f_s"), 0.16 * 0.75, 1e-15);
}

TEST(FixShrink, ThermalLoadGivesTheYarnTension)
{
  // nodes held in place: the shrunk bond pulls with N = EA s (stiffness EA / L0 kept)
  auto dir = scratch_dir("shrink_thermal");
  Lammps l;
  load(l, write_pair(dir));
  l.cmd("fix s all ncf/shrink btype 2 thermal 1e-4 -1700 steps 10");
  l.cmd("run 10");
  EXPECT_NEAR(l.value("f_s"), 0.17, 1e-15);
  auto f = l.forces();
  EXPECT_NEAR(f[3 * 2 + 0], 10 * 0.17, 1e-12);     // node 3 pulled towards node 4 (+x)
  EXPECT_NEAR(f[3 * 3 + 0], -10 * 0.17, 1e-12);    // node 4 towards node 3
}

TEST(FixShrink, RestartContinuesTheRamp)
{
  auto dir = scratch_dir("shrink_restart");
  const char *fixes = "fix s all ncf/shrink btype 2 strain 0.16 steps 300\nfix nve all nve\ntimestep 2e-8";
  std::vector<double> straight;
  double s_end = 0.0;
  {
    Lammps l;
    load(l, write_pair(dir));
    l.cmds(fixes);
    l.cmd("run 150");
    l.cmd("write_restart " + dir + "/half.restart");
    l.cmd("run 150");
    straight = l.positions();
    s_end = l.value("f_s");
  }
  Lammps r;
  r.cmd("read_restart " + dir + "/half.restart");
  r.cmds(fixes);
  r.cmd("run 150");
  EXPECT_EQ(r.value("f_s"), s_end);
  EXPECT_EQ(max_abs_diff(r.positions(), straight), 0.0);
}

struct BadShrink {
  const char *args;
  const char *message;
};

class FixShrinkErrors : public ::testing::TestWithParam<BadShrink> {};

TEST_P(FixShrinkErrors, NameTheProblem)
{
  auto dir = scratch_dir("shrink_errors");
  Lammps l;
  load(l, write_pair(dir));
  auto msg = error_of([&] { l.cmd(std::string("fix s all ncf/shrink ") + GetParam().args); });
  EXPECT_THAT(msg, HasSubstr(GetParam().message)) << GetParam().args;
}

INSTANTIATE_TEST_SUITE_P(
    Table, FixShrinkErrors,
    ::testing::Values(
        BadShrink{"strain 0.1 steps 10", "fix ncf/shrink: keyword 'btype' is required"},
        BadShrink{"btype 3 strain 0.1 steps 10", "fix ncf/shrink: btype 3 is not a bond type (1-2)"},
        BadShrink{"btype 2 steps 10", "fix ncf/shrink: give the target with 'strain S' or 'thermal ALPHA DT'"},
        BadShrink{"btype 2 strain 0.1", "fix ncf/shrink: keyword 'steps' is required"},
        BadShrink{"btype 2 strain 1.2 steps 10", "fix ncf/shrink: strain 1.2 must be in [0, 1)"},
        BadShrink{"btype 2 thermal 1e-4 1000 steps 10", "fix ncf/shrink: thermal load alpha 0.0001 x dT 1000 gives a shrink -0.1"},
        BadShrink{"btype 2 thermal 1e-4 steps 10", "fix ncf/shrink: value 'steps' of 'thermal' is not a number"},
        BadShrink{"btype 2 thermal 1e-4", "fix ncf/shrink: keyword 'thermal' needs 2 values"},
        BadShrink{"btype 2 strain 0.1 steps 0", "fix ncf/shrink: steps 0 must be >= 1"},
        BadShrink{"btype 2 strain 0.1 steps 10 ramp smooth", "fix ncf/shrink: ramp 'smooth' is not one of cosine, linear"},
        BadShrink{"btype 2 strain 0.1 steps 10 speed 3", "fix ncf/shrink: unknown keyword 'speed'"}));
