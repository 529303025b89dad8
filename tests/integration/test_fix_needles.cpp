// Integration tests of fix ncf/needles: segment-based needle contact (kernel ncf_needle.h).

#include "ncf_needle.h"
#include "ncf_lammps_test.h"

#include "fmt/format.h"
#include "lammps.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>
#include <cstdio>

using namespace ncftest;
using ::testing::HasSubstr;

namespace {

const double DC = 69e-6, DN = 0.5e-3, KN = 1e8;

// one chain along x at y = y0, z = 0 with n nodes of spacing a, periodic box [0, n a) in x
std::string write_chain(const std::string &dir, int n, double a, double y0)
{
  const std::string path = dir + "/chain.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "chain\n\n%d atoms\n1 atom types\n%d bonds\n1 bond types\n\n", n, n);
  fprintf(fp, "0 %.17g xlo xhi\n-2e-3 2e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\nMasses\n\n1 1e-9\n\n", n * a);
  fprintf(fp, "Atoms # bond\n\n");
  for (int i = 0; i < n; i++) fprintf(fp, "%d 1 1 %.17g %.17g 0\n", i + 1, (i + 0.5) * a, y0);
  fprintf(fp, "\nBonds\n\n");
  for (int i = 0; i < n; i++) fprintf(fp, "%d 1 %d %d\n", i + 1, i + 1, (i + 1) % n + 1);    // a ring
  fclose(fp);
  return path;
}

void load(Lammps &l, const std::string &data)
{
  l.cmds(R"(
units si
atom_style bond
atom_modify map array
boundary p p f
comm_modify cutoff 2e-3
bond_style ncf/chain
)");
  l.cmd("read_data " + data);
  l.cmd("bond_coeff 1 ea 100");
}

// independent sum of the kernel over the ring's segments against one needle (point down); the
// contact energy summed into *energy if given
NCF::Vec3 kernel_force_on_needle(int n, double a, double y0, double nxp, double nyp, double ztip,
                                 double len, double tip, double *energy = nullptr)
{
  NCF::Vec3 fsum;
  for (int i = 0; i < n; i++) {
    NCF::Vec3 a0{(i + 0.5) * a, y0, 0}, a1{(i + 1.5) * a, y0, 0};
    // the needle's image nearest to this segment (box length n a in x)
    const double mid = (i + 1.0) * a, L = n * a;
    double dx = mid - nxp;
    dx -= L * std::round(dx / L);
    NCF::Needle nd;
    nd.x = mid - dx;
    nd.y = nyp;
    nd.zapex = ztip;
    nd.direction = -1;
    nd.radius = 0.5 * DN;
    nd.tip = tip;
    nd.length = len;
    auto c = NCF::needle_contact(a0, a1, 0.5 * DC, nd, KN);
    fsum += c.fneedle;
    if (energy && c.active) *energy += c.energy;
  }
  return fsum;
}

}    // namespace

TEST(FixNeedles, ForceMatchesTheKernelAndBalances)
{
  // a needle pierces a chain midway between two nodes (elements 1 mm long), offset 0.2 mm
  auto dir = scratch_dir("needles_kernel");
  const int n = 4;
  const double a = 1e-3, y0 = 0.0, off = 0.2e-3;
  Lammps l;
  load(l, write_chain(dir, n, a, y0));
  l.cmd(fmt::format("fix nd all ncf/needles diameter {} kn {} chain 1 {} at {} {} move -1e-4 0 length 1.5e-3 tip 1e-4",
                    DN, KN, DC, 2.0e-3, y0 + off));
  l.cmd("run 0");
  double energy = 0.0;
  auto expect = kernel_force_on_needle(n, a, y0, 2.0e-3, y0 + off, -1e-4, 1.5e-3, 1e-4, &energy);
  ASSERT_GT(std::fabs(expect.y), 1e-6);    // the needle really touches the segment between nodes
  EXPECT_NEAR(l.value("f_nd[1][2]"), expect.y, 1e-9 * std::fabs(expect.y));
  EXPECT_NEAR(l.value("f_nd[1][1]"), expect.x, 1e-9 * std::fabs(expect.y));
  // Newton's third law: the forces on the chain's nodes balance the needle's
  auto f = l.forces();
  double fy = 0;
  for (int i = 0; i < n; i++) fy += f[3 * i + 1];
  EXPECT_NEAR(fy, -expect.y, 1e-9 * std::fabs(expect.y));
  EXPECT_LT(fy, 0.0);                    // the chain is pushed away from the needle (at +y)
  EXPECT_EQ(l.value("f_nd[3]"), 1.0);    // one segment, touched between its nodes
  // the fix's energy (its scalar) is the kernel's, and its gradient the force on the nodes
  ASSERT_GT(energy, 0.0);
  EXPECT_NEAR(l.value("f_nd"), energy, 1e-9 * energy);
  const auto x0 = l.positions();
  for (int id : {2, 3})
    EXPECT_NEAR(f[3 * (id - 1) + 1],
                -l.energy_derivative("f_nd", id, 1, x0[3 * (id - 1) + 1], 1e-9),
                1e-5 * std::fabs(expect.y))
        << "atom " << id;
}

TEST(FixNeedles, NeedleAcrossThePeriodicBoundary)
{
  // the same needle shifted by one box length: same force (closest image)
  auto dir = scratch_dir("needles_pbc");
  const int n = 4;
  const double a = 1e-3, off = 0.2e-3;
  double f1 = 0, f2 = 0;
  for (double xn : {1.5e-3, 1.5e-3 + 4e-3}) {
    Lammps l;
    load(l, write_chain(dir, n, a, 0.0));
    l.cmd(fmt::format("fix nd all ncf/needles diameter {} kn {} chain 1 {} at {} {} move -5e-4 0 length 1.5e-3",
                      DN, KN, DC, xn, off));
    l.cmd("run 0");
    (xn < 3e-3 ? f1 : f2) = l.value("f_nd[1][2]");
  }
  EXPECT_NE(f1, 0.0);
  EXPECT_NEAR(f2, f1, 1e-12 * std::fabs(f1));
}

// many needles, binned in the plane (cells of ~ a needle diameter): every needle still gets the
// force of every segment it touches, also across the periodic faces (x: the ring's box; y: the
// needles at the lower face touch the chain through its image at the upper face)
TEST(FixNeedles, ManyNeedlesEachTheKernelForce)
{
  auto dir = scratch_dir("needles_many");
  const int n = 4;
  const double a = 1e-3, y0 = 1.9e-3;
  Lammps l;
  load(l, write_chain(dir, n, a, y0));
  std::string at;
  std::vector<std::array<double, 2>> pos;
  // (rows 0.22 mm on either side of the chain, staggered by half the 0.55 mm pitch, so that no two
  // needles overlap, also through the faces: the fix refuses overlapping needles)
  for (int i = 0; i < 7; i++)
    for (int row = 0; row < 3; row++) {
      const double yn = row == 0 ? y0 + 0.22e-3 - 4e-3 : row == 1 ? y0 - 0.22e-3 : 0.0;
      pos.push_back({(row == 1 ? 0.325e-3 : 0.05e-3) + i * 0.55e-3, yn});
      at += fmt::format(" at {} {}", pos.back()[0], yn);
    }
  l.cmd(fmt::format("fix nd all ncf/needles diameter {} kn {} chain 1 {}{} move -1e-4 0 length 1.5e-3 tip 1e-4",
                    DN, KN, DC, at));
  l.cmd("run 0");
  int touching = 0;
  for (std::size_t k = 0; k < pos.size(); k++) {
    // the needle at its image nearest to the chain in y (the kernel helper wraps x only)
    double yk = pos[k][1];
    if (yk < y0 - 2e-3) yk += 4e-3;
    auto expect = kernel_force_on_needle(n, a, y0, pos[k][0], yk, -1e-4, 1.5e-3, 1e-4);
    touching += std::fabs(expect.y) > 0.0;
    for (int d = 0; d < 2; d++) {
      const double want = d ? expect.y : expect.x;
      EXPECT_NEAR(l.value(fmt::format("f_nd[{}][{}]", k + 1, d + 1)), want, 1e-9 * std::fabs(expect.y) + 1e-15)
          << "needle " << k + 1 << " at " << pos[k][0] << " " << pos[k][1];
    }
  }
  EXPECT_GE(touching, 12);
}

// segments much shorter than the needle is wide, as in a fabric (0.1 mm against 0.5 mm): the
// segments whose midpoints lie within the needle's radius and more of its axis (the cells the
// fix flags as near a needle) get the kernel's force, at several distances from the axis
TEST(FixNeedles, ShortSegmentsAroundANeedleEachTheKernelForce)
{
  auto dir = scratch_dir("needles_short");
  const int n = 40;
  const double a = 1e-4;
  for (double y0 : {0.05e-3, 0.2e-3, 0.27e-3, -0.27e-3}) {
    SCOPED_TRACE(y0);
    Lammps l;
    load(l, write_chain(dir, n, a, y0));
    l.cmd(fmt::format("fix nd all ncf/needles diameter {} kn {} chain 1 {} at 2e-3 0 move -1e-4 0 "
                      "length 1.5e-3 tip 1e-4",
                      DN, KN, DC));
    l.cmd("run 0");
    const auto expect = kernel_force_on_needle(n, a, y0, 2e-3, 0.0, -1e-4, 1.5e-3, 1e-4);
    ASSERT_GT(std::fabs(expect.y), 0.0) << "the chain touches the needle";
    EXPECT_NEAR(l.value("f_nd[1][2]"), expect.y, 1e-9 * std::fabs(expect.y));
    EXPECT_NEAR(l.value("f_nd[1][1]"), expect.x, 1e-9 * std::fabs(expect.y));
  }
}

TEST(FixNeedles, PointUpMirrorsPointDown)
{
  // a needle coming up from below (direction up) meets the chain as its mirror image coming down
  auto dir = scratch_dir("needles_up");
  double fy[2], fz[2];
  for (int k = 0; k < 2; k++) {
    Lammps l;
    load(l, write_chain(dir, 4, 1e-3, 0.0));
    l.cmd(fmt::format("fix nd all ncf/needles diameter {} kn {} chain 1 {} at 2e-3 1e-4 move {} 0 length 1.5e-3 tip 2e-4 direction {}",
                      DN, KN, DC, k == 0 ? -1.5e-4 : 1.5e-4, k == 0 ? "down" : "up"));
    l.cmd("run 0");
    fy[k] = l.value("f_nd[1][2]");
    fz[k] = l.value("f_nd[1][3]");
  }
  EXPECT_GT(fy[0], 0.0);     // the chain (at y = 0) pushes the needle (at y = 0.1 mm) to +y
  EXPECT_GT(fz[0], 0.0);     // the point pushes the chain down, so the chain pushes it up
  EXPECT_NEAR(fy[1], fy[0], 1e-12 * fy[0]);
  EXPECT_NEAR(fz[1], -fz[0], 1e-12 * std::fabs(fz[0]));
}

TEST(FixNeedles, TipAboveTheChainTouchesNothingThenPiercing)
{
  auto dir = scratch_dir("needles_motion");
  Lammps l;
  load(l, write_chain(dir, 4, 1e-3, 0.0));
  // tip starts 0.6 mm above the chain and moves down at 100 m/s (no integrator: the chain stays)
  l.cmd(fmt::format("fix nd all ncf/needles diameter {} kn {} chain 1 {} at 2e-3 2e-4 target 6e-4 -6e-4 100 length 2e-3",
                    DN, KN, DC));
  l.cmd("timestep 1e-8");
  l.cmd("run 100");    // tip at 0.5 mm: above the chain
  EXPECT_NEAR(l.value("f_nd[1]"), 5e-4, 1e-15);
  EXPECT_EQ(l.value("f_nd[3]"), 0.0);
  l.cmd("run 900");    // tip at -0.4 mm: through the chain
  EXPECT_NEAR(l.value("f_nd[1]"), -4e-4, 1e-15);
  EXPECT_EQ(l.value("f_nd[3]"), 1.0);
  l.cmd("run 1000");
  EXPECT_EQ(l.value("f_nd[1]"), -6e-4);    // stopped at the target
}

// needles out of reach cost nothing per segment: output 6 counts the segment visits (a node and
// one of its bond partners) of the last step; with the needles' body above every node by more
// than the margin of a segment (its radius and the point's cone) there are none at all
TEST(FixNeedles, OutOfReachVisitsNoSegment)
{
  auto dir = scratch_dir("needles_reach");
  Lammps l;
  load(l, write_chain(dir, 4, 1e-3, 0.0));
  const double tip = 0.3e-3, margin = 0.5 * DC * (1.0 + tip / (0.5 * DN));
  // tip just beyond the margin above the chain axis, then just within it, then through the chain
  l.cmd(fmt::format("variable zt equal {}", 1.01 * margin));
  l.cmd(fmt::format("fix nd all ncf/needles diameter {} kn {} chain 1 {} at 2e-3 2e-4 v_zt tip {} length 2e-3",
                    DN, KN, DC, tip));
  l.cmd("run 0");
  EXPECT_EQ(l.value("f_nd[6]"), 0.0);
  EXPECT_EQ(l.value("f_nd[3]"), 0.0);
  l.cmd(fmt::format("variable zt equal {}", 0.99 * margin));
  l.cmd("run 0");
  EXPECT_EQ(l.value("f_nd[6]"), 8.0);    // 4 nodes, 2 bond partners each
  l.cmd("variable zt equal -4e-4");
  l.cmd("run 0");
  EXPECT_EQ(l.value("f_nd[6]"), 8.0);
  EXPECT_EQ(l.value("f_nd[3]"), 1.0);
}

struct BadNeedle {
  const char *args;
  const char *message;
};

class FixNeedlesErrors : public ::testing::TestWithParam<BadNeedle> {};

TEST_P(FixNeedlesErrors, NameTheProblem)
{
  auto dir = scratch_dir("needles_errors");
  Lammps l;
  load(l, write_chain(dir, 4, 1e-3, 0.0));
  FILE *fp = fopen((dir + "/bad.needles").c_str(), "w");
  fprintf(fp, "# x y\n1e-3 2e-3\n1e-3\n");
  fclose(fp);
  std::string args = GetParam().args;
  const auto pos = args.find("DIR");
  if (pos != std::string::npos) args.replace(pos, 3, dir);
  EXPECT_THAT(error_of([&] { l.cmd("fix nd all ncf/needles " + args); }), HasSubstr(GetParam().message)) << args;
}

INSTANTIATE_TEST_SUITE_P(
    Table, FixNeedlesErrors,
    ::testing::Values(
        BadNeedle{"kn 1e8 chain 1 69e-6 at 0 0 move 0 0", "fix ncf/needles: keyword 'diameter' (of the needles) is required"},
        BadNeedle{"diameter 5e-4 chain 1 69e-6 at 0 0 move 0 0", "fix ncf/needles: keyword 'kn' (contact stiffness, Pa) is required"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 move 0 0", "fix ncf/needles: no needle: give 'file FILE' or 'at X Y'"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 at 0 0", "fix ncf/needles: give the motion of the tips"},
        BadNeedle{"diameter 5e-4 kn 1e8 at 0 0 move 0 0", "fix ncf/needles: no chain diameter: define pair_style ncf/contact"},
        BadNeedle{"diameter 5e-4 kn 1e8 mu 0.3 chain 1 69e-6 at 0 0 move 0 0", "fix ncf/needles: contact keyword 'mu' is not one of this style's (kn)"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 at 0 0 move 0 0", "fix ncf/needles: value 'at' of 'chain' is not a number"},
        BadNeedle{"diameter -5e-4 kn 1e8 chain 1 69e-6 at 0 0 move 0 0", "fix ncf/needles: diameter -5e-4 must be > 0"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 at 0 move 0 0", "fix ncf/needles: value 'move' of 'at' is not a number"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 at 0 0 move 0", "fix ncf/needles: 'tips move' needs more values"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 at 0 0 target 0 1 0", "fix ncf/needles: 'tips target' needs a speed > 0"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 file DIR/none move 0 0", "fix ncf/needles: cannot open needle file"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 file DIR/bad.needles move 0 0", "bad.needles:3: expected 'x y', got '1e-3'"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 at 0 0 move 0 0 direction left", "fix ncf/needles: direction 'left' is not one of down, up"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 at 0 0 v_nothing", "fix ncf/needles: 'tips': variable 'nothing' does not exist"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 at 0 0 move 0 0 sharp yes", "fix ncf/needles: unknown keyword 'sharp'"},
        BadNeedle{"diameter 5e-4 kn 1e8 chain 1 69e-6 at 0 0 move 0 0 tip 1e-3 length 2e-3", "fix ncf/needles: length 0.002 must be at least 2.2 times tip 0.001"}));
