// Integration tests of fix ncf/plate through LAMMPS.

#include "ncf_lammps_test.h"
#include "ncf_scenes.h"

#include "fmt/format.h"
#include "lammps.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace ncftest;
using ::testing::HasSubstr;

namespace {

const double D = 69e-6, A = 2e-4, KN = 2e7;

// a straight chain of n nodes along x at height z, element length A, per-type mass m
std::string write_line(const std::string &dir, int n, double z, double m)
{
  const std::string path = dir + "/line.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "line\n\n%d atoms\n1 atom types\n%d bonds\n1 bond types\n\n", n, n - 1);
  fprintf(fp, "0 %.17g xlo xhi\n0 1e-3 ylo yhi\n-1e-3 2e-3 zlo zhi\n\n", (n + 2) * A);
  fprintf(fp, "Masses\n\n1 %.17g\n\nAtoms # bond\n\n", m);
  for (int i = 0; i < n; i++) fprintf(fp, "%d 1 1 %.17g 5e-4 %.17g\n", i + 1, (i + 1) * A, z);
  fprintf(fp, "\nBonds\n\n");
  for (int i = 1; i < n; i++) fprintf(fp, "%d 1 %d %d\n", i, i, i + 1);
  fclose(fp);
  return path;
}

const char *SETUP = R"(
units si
atom_style bond
atom_modify map array
boundary p p f
neighbor 1e-4 bin
comm_modify cutoff 6e-4
bond_style ncf/chain
)";

}    // namespace

TEST(FixPlate, NormalForceMatchesThePenaltyLaw)
{
  auto dir = scratch_dir("plate_force");
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + write_line(dir, 3, 30e-6, 1e-9));
  l.cmds(R"(
bond_coeff 1 modulus 120e9 diameter 69e-6
fix plate all ncf/plate kn 2e7 diameter 1 69e-6 lower z 0.0
run 0
)");
  // every node penetrates by r - z = 4.5 um; tributary lengths A/2, A, A/2: total 2 A
  const double g = 0.5 * D - 30e-6;
  EXPECT_NEAR(l.value("f_plate[3]"), KN * g * 2 * A, 1e-12);
  EXPECT_NEAR(l.value("f_plate[7]"), 3.0, 0.0);
  EXPECT_NEAR(l.value("f_plate[9]"), g, 1e-15);
  auto f = l.forces();
  EXPECT_NEAR(f[2], KN * g * 0.5 * A, 1e-13);
  EXPECT_NEAR(f[5], KN * g * A, 1e-13);
  // energy kn l g^2 / 2 summed, reported as the fix scalar
  EXPECT_NEAR(l.value("f_plate"), 0.5 * KN * 2 * A * g * g, 1e-20);
  // the pressure is the force over the box area (lower plate: vector element 6)
  EXPECT_NEAR(l.value("f_plate[6]"), KN * g * 2 * A / (5 * A * 1e-3), 1e-6);
}

// A chain's diameter is given once: without 'diameter' the plate takes pair ncf/contact's (the
// same force as with it given), and a different value given to the plate is refused
TEST(FixPlate, TakesTheDiameterOfThePairStyle)
{
  auto dir = scratch_dir("plate_pair_diameter");
  auto force_with = [&](const std::string &plate_diameter) {
    Lammps l;
    l.cmds(SETUP);
    l.cmd("read_data " + write_line(dir, 3, 30e-6, 1e-9));
    l.cmds(R"(
bond_coeff 1 modulus 120e9 diameter 69e-6
pair_style ncf/contact
pair_coeff * * kn 2e7 diameter 69e-6
)");
    l.cmd("fix plate all ncf/plate kn 2e7 " + plate_diameter + " lower z 0.0");
    l.cmd("run 0");
    return l.value("f_plate[3]");
  };
  const double given = force_with("diameter 1 69e-6");
  EXPECT_GT(given, 0.0);
  EXPECT_EQ(force_with(""), given);
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + write_line(dir, 3, 30e-6, 1e-9));
  l.cmds("bond_coeff 1 modulus 120e9 diameter 69e-6\npair_style ncf/contact\n"
         "pair_coeff * * kn 2e7 diameter 69e-6");
  EXPECT_THAT(error_of([&] { l.cmd("fix plate all ncf/plate kn 2e7 diameter 1 70e-6 lower z 0"); }),
              HasSubstr("fix ncf/plate: diameter 7e-05 of atom type 1 differs from pair "
                        "ncf/contact's diameter 6.9e-05: a chain's diameter is given once"));
}

TEST(FixPlate, TargetMotionStopsAtTheTarget)
{
  auto dir = scratch_dir("plate_target");
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + write_line(dir, 3, 1e-4, 1e-9));
  l.cmds(R"(
bond_coeff 1 ea 10
fix plate all ncf/plate kn 2e7 diameter 1 69e-6 lower z 0.0 upper target 1e-3 5e-4 10.0
fix nve all nve
timestep 1e-7
run 200
)");
  // 200 steps x 1e-7 s x 10 m/s = 2e-4 m
  EXPECT_NEAR(l.value("f_plate[2]"), 1e-3 - 2e-4, 1e-15);
  l.cmd("run 500");
  EXPECT_EQ(l.value("f_plate[2]"), 5e-4);
}

// The plate's velocity in target motion enters the dashpot: resting nodes under an upper plate
// that moves down onto them at 5 m/s carry kn l g + c l v, moving up kn l g - c l v, and once
// it has reached its target kn l g (c = damp, l the tributary lengths, 2 A in all)
TEST(FixPlate, TargetMotionVelocityEntersTheDashpot)
{
  auto dir = scratch_dir("plate_target_velocity");
  const double z = 1e-4, damp = 10.0, speed = 5.0;
  const double ztop = z + 0.5 * D - 5e-6;    // the upper plate starts 5 um into the nodes
  const std::string data = write_line(dir, 3, z, 1e-9);
  struct Case {
    double target, v;    // where the plate goes; its velocity along the approach
    int steps;
  } cases[] = {{0.0, speed, 1}, {1e-3, -speed, 1}, {ztop - 1e-9, 0.0, 3}};
  for (const Case &c : cases) {
    SCOPED_TRACE(fmt::format("target {}", c.target));
    Lammps l;
    l.cmds(SETUP);
    l.cmd("read_data " + data);
    l.cmd("bond_coeff 1 ea 10");
    // no integrator: the nodes stay where they are, at rest
    l.cmd(fmt::format("fix plate all ncf/plate kn {} damp {} diameter 1 69e-6 "
                      "upper target {:.17g} {:.17g} {}",
                      KN, damp, ztop, c.target, speed));
    l.cmd("timestep 1e-9");
    l.cmd(fmt::format("run {}", c.steps));
    const double zp = l.value("f_plate[2]");
    if (c.v == 0.0) EXPECT_EQ(zp, c.target);
    const double g = 0.5 * D - (zp - z);
    ASSERT_GT(g, 4e-6);
    EXPECT_NEAR(l.value("f_plate[4]"), (KN * g + damp * c.v) * 2 * A, 1e-9 * KN * g * 2 * A);
  }
}

TEST(FixPlate, CoulombFrictionSticksThenSlides)
{
  // a chain pressed on the lower plate by a constant force per node, pulled sideways
  auto dir = scratch_dir("plate_friction");
  const double m = 1e-9, press = 1e-4, mu = 0.3;
  for (double ratio : {0.5, 1.5}) {
    Lammps l;
    l.cmds(SETUP);
    l.cmd("read_data " + write_line(dir, 5, 34.4e-6, m));
    l.cmds(R"(
bond_coeff 1 modulus 120e9 diameter 69e-6
fix press all addforce 0 0 -1e-4
)");
    l.cmd(fmt::format("fix pull all addforce {} 0 0", ratio * mu * press));
    l.cmds(R"(
fix plate all ncf/plate kn 2e7 kt 1.0 mu 0.3 damp 20 diameter 1 69e-6 lower z 0.0
fix nve all nve
timestep 2e-8
variable vx equal vcm(all,x)
variable x0 equal xcm(all,x)
run 0
)");
    const double x0 = l.value("v_x0");
    l.cmd("run 20000");
    const double vx = l.value("v_vx"), dx = l.value("v_x0") - x0;
    const double ftx = l.value("f_plate[11]"), cap = mu * press * 5;
    if (ratio < 1.0) {
      // sticking: only the elastic slip spring moves, by about 2 P / (kt l) at most
      EXPECT_LT(std::fabs(dx), 1e-7) << "sticking chain moved by " << dx;
      EXPECT_LT(std::fabs(ftx), cap * (1 - 1e-6));    // below the Coulomb limit
    } else {
      // sliding: acceleration (ratio - 1) mu press / m per node over the sliding time
      const double t = 20000 * 2e-8, expect = (ratio - 1.0) * mu * press / m * t;
      EXPECT_NEAR(vx / expect, 1.0, 0.05) << "sliding velocity " << vx << " expected ~" << expect;
      EXPECT_NEAR(ftx / -cap, 1.0, 0.02);    // the plate holds back mu Fn
    }
  }
}

TEST(FixPlate, RestartContinuesTheSameTrajectory)
{
  auto dir = scratch_dir("plate_restart");
  auto mat = write_mat(dir, 3.0, 31);
  const char *fixes = R"(
fix plate all ncf/plate kn 2e7 kt 0.5 mu 0.3 diameter 1 69e-6 lower z 0.0 upper target 0.66e-3 3e-4 5
fix nve all nve
fix damp all viscous 1e-7
timestep 1e-8
)";
  std::vector<double> straight;
  {
    Lammps l;
    load_mat(l, mat);
    l.cmds(fixes);
    l.cmd("velocity all create 5e12 3 loop geom");
    l.cmd("fix touch all ave/time 1 1 1 f_plate[8] ave running");
    l.cmd("run 1500");
    l.cmd("write_restart " + dir + "/half.restart");
    l.cmd("run 1500");
    straight = l.positions();
    EXPECT_GT(l.value("f_touch"), 0.0);    // the upper plate did touch the mat
  }
  Lammps r;
  r.cmd("read_restart " + dir + "/half.restart");
  r.cmds("fix NCF_NODE all property/atom i_ncf_layer i_ncf_end\nfix MASS all property/atom rmass\n"
         "neighbor 1e-4 bin\ncomm_modify cutoff 6e-4");
  r.cmds(fixes);
  r.cmd("run 1500");
  EXPECT_EQ(max_abs_diff(r.positions(), straight), 0.0);
}

// the plate of a restart file with friction, defined again without it: no history is kept (the
// stored slip is dropped, no tangential force), the contact itself continues
TEST(FixPlate, RestartWithoutFrictionDropsTheHistory)
{
  auto dir = scratch_dir("plate_restart_mu0");
  auto mat = write_mat(dir, 3.0, 31);
  // pressed down on the plate and pulled sideways (the friction force of the slip springs)
  const char *setup = R"(
fix press all addforce 0 0 -1e-4
fix pull all addforce 1e-5 0 0
fix damp all viscous 1e-7
fix nve all nve
timestep 1e-8
)";
  {
    Lammps l;
    load_mat(l, mat);
    // the lowest chains (axes at z = 0.3 mm) on a lower plate, 0.1 um into it
    l.cmd("fix plate all ncf/plate kn 2e7 kt 0.5 mu 0.3 diameter 1 69e-6 lower z 0.2656e-3");
    l.cmds(setup);
    l.cmd("run 200");
    EXPECT_GT(l.value("f_plate[7]"), 0.0);
    EXPECT_NE(l.value("f_plate[11]"), 0.0);    // friction with a stored slip
    l.cmd("write_restart " + dir + "/fric.restart");
  }
  Lammps r;
  r.cmd("read_restart " + dir + "/fric.restart");
  r.cmds("fix NCF_NODE all property/atom i_ncf_layer i_ncf_end\nfix MASS all property/atom rmass\n"
         "neighbor 1e-4 bin\ncomm_modify cutoff 6e-4");
  r.cmd("fix plate all ncf/plate kn 2e7 diameter 1 69e-6 lower z 0.2656e-3");
  r.cmds(setup);
  r.cmd("run 100");
  EXPECT_GT(r.value("f_plate[7]"), 0.0);     // still in contact
  EXPECT_EQ(r.value("f_plate[11]"), 0.0);    // and frictionless
  EXPECT_EQ(r.value("f_plate[12]"), 0.0);
}

struct BadPlate {
  const char *args;
  const char *message;
};

class FixPlateErrors : public ::testing::TestWithParam<BadPlate> {};

TEST_P(FixPlateErrors, NameTheProblem)
{
  auto dir = scratch_dir("plate_errors");
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + write_line(dir, 3, 1e-4, 1e-9));
  l.cmd("bond_coeff 1 ea 10");
  l.cmd("variable zz atom z");
  auto msg = error_of([&] {
    l.cmd(std::string("fix p all ncf/plate ") + GetParam().args);
  });
  EXPECT_THAT(msg, HasSubstr(GetParam().message)) << GetParam().args;
}

INSTANTIATE_TEST_SUITE_P(
    Table, FixPlateErrors,
    ::testing::Values(
        BadPlate{"diameter 1 69e-6 lower z 0",
                 "fix ncf/plate: keyword 'kn' (normal stiffness, Pa) is required"},
        BadPlate{"kn 2e7 diameter 1 69e-6",
                 "fix ncf/plate: define at least one plate with 'lower' or 'upper'"},
        BadPlate{"kn 2e7 lower z 0",
                 "fix ncf/plate: no chain diameter: define pair_style ncf/contact with its "
                 "diameters before this fix, or give 'diameter TYPES D'"},
        BadPlate{"kn -1 diameter 1 69e-6 lower z 0", "fix ncf/plate: kn -1 must be > 0"},
        BadPlate{"kn abc diameter 1 69e-6 lower z 0",
                 "fix ncf/plate: value 'abc' of 'kn' is not a number"},
        BadPlate{"kn 2e7 mu -0.1 diameter 1 69e-6 lower z 0",
                 "fix ncf/plate: mu -0.1 must be >= 0"},
        BadPlate{"kn 2e7 kt 0 mu 0.3 diameter 1 69e-6 lower z 0",
                 "fix ncf/plate: friction (mu 0.3) needs a tangential stiffness 'kt' > 0"},
        BadPlate{"kn 2e7 diameter 1 lower z 0",
                 "fix ncf/plate: value 'lower' of 'diameter' is not a number"},
        BadPlate{"kn 2e7 diameter 2 69e-6 lower z 0", "Numeric index 2 is out of bounds (1-1)"},
        BadPlate{"kn 2e7 diameter 1 69e-6 lower", "fix ncf/plate: 'lower' needs a motion"},
        BadPlate{"kn 2e7 diameter 1 69e-6 lower fly 3",
                 "fix ncf/plate: 'lower': unknown motion 'fly' (z, move, target, v_NAME)"},
        BadPlate{"kn 2e7 diameter 1 69e-6 upper move 1e-3",
                 "fix ncf/plate: 'upper move' needs more values"},
        BadPlate{"kn 2e7 diameter 1 69e-6 upper target 1e-3 0 0",
                 "fix ncf/plate: 'upper target' needs a speed > 0"},
        BadPlate{"kn 2e7 diameter 1 69e-6 upper v_top",
                 "fix ncf/plate: 'upper': variable 'top' does not exist"},
        BadPlate{"kn 2e7 diameter 1 69e-6 upper v_zz",
                 "fix ncf/plate: 'upper': variable 'zz' is not equal-style"},
        // kt is a ratio of kn, as in pair_coeff; a stiffness in Pa (the meaning it had here
        // before) is refused, naming the change
        BadPlate{"kn 2e7 kt 2e7 diameter 1 69e-6 lower z 0",
                 "fix ncf/plate: kt 2e7 must be a ratio of kn in [0, 10]"},
        BadPlate{"kn 2e7 kt -1 diameter 1 69e-6 lower z 0", "fix ncf/plate: kt -1 must be >= 0"},
        BadPlate{"kn 2e7 kt", "fix ncf/plate: keyword 'kt' needs a value"},
        BadPlate{"kn 2e7 stiff 3 diameter 1 69e-6 lower z 0",
                 "fix ncf/plate: unknown keyword 'stiff'"}));

TEST(FixPlate, NodeWithoutChainBondIsAnError)
{
  auto dir = scratch_dir("plate_nobond");
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + write_line(dir, 3, 1e-4, 1e-9));
  l.cmds("bond_coeff 1 ea 10\ncreate_atoms 1 single 1e-4 5e-4 1e-4\nmass 1 1e-9");
  l.cmd("fix p all ncf/plate kn 2e7 diameter 1 69e-6 lower z 0");
  EXPECT_THAT(error_of([&] {
                l.cmd("run 0");
              }),
              HasSubstr("has no ncf/chain bond: no tributary length"));
}
