// Integration tests of fix ncf/pbc (averaged periodic boundary conditions) through LAMMPS.

#include "ncf_lammps_test.h"
#include "ncf_pbc.h"
#include "ncf_scenes.h"

#include "atom.h"
#include "domain.h"
#include "fix.h"
#include "lammps.h"
#include "modify.h"
#include "neighbor.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

using namespace ncftest;
using ::testing::HasSubstr;

namespace {

const double LX = MAT_LX;

// independent evaluation of the averaged constraint from the gathered positions: groups from the
// kernel with the reference positions, then sum_i w_i X_i - F D_g for every group
double constraint_error(const std::vector<double> &xref, const std::vector<double> &x,
                        const std::vector<int> &code, const double *href, const double *h)
{
  std::vector<NCF::FaceNode> fn;
  std::vector<int> idx;
  for (std::size_t i = 0; i < code.size(); i++)
    if (code[i] == 1 || code[i] == 2) {
      fn.push_back({code[i] == 1 ? -1 : 1, xref[3 * i + 1], xref[3 * i + 2]});
      idx.push_back((int) i);
    }
  auto mesh = NCF::auto_face_mesh(fn, href[1]);
  int ng = 0;
  auto g = NCF::face_groups(mesh, fn, ng);
  auto w = NCF::face_weights(fn, g, ng);
  std::vector<double> c(3 * ng, 0.0), d(3 * ng, 0.0);
  for (std::size_t k = 0; k < fn.size(); k++)
    for (int dim = 0; dim < 3; dim++) {
      c[3 * g[k] + dim] += w[k] * x[3 * idx[k] + dim];
      d[3 * g[k] + dim] += w[k] * xref[3 * idx[k] + dim];
    }
  // F = h href^-1 in the plane (x, y), identity in z
  const double F00 = h[0] / href[0], F01 = (h[5] - h[0] * href[5] / href[0]) / href[1],
               F11 = h[1] / href[1];
  double err = 0.0;
  for (int k = 0; k < ng; k++) {
    const double t[3] = {F00 * d[3 * k] + F01 * d[3 * k + 1], F11 * d[3 * k + 1], d[3 * k + 2]};
    for (int dim = 0; dim < 3; dim++) err = std::max(err, std::fabs(c[3 * k + dim] - t[dim]));
  }
  return err;
}

// normal hold: largest |x - xlo - xy/ly (y - ylo) - lx s_ref| over the end nodes (codes 1, 2), with
// s_ref the node's reduced x in the (orthogonal) reference box; the hold keeps it at round-off
double normal_hold_error(const std::vector<double> &xref, const std::vector<double> &x,
                         const std::vector<int> &code, const double *href, const double *h,
                         const double *lo)
{
  double err = 0.0;
  for (std::size_t i = 0; i < code.size(); i++) {
    if (code[i] != 1 && code[i] != 2) continue;
    const double s = xref[3 * i] / href[0];    // (the mat's box starts at 0)
    const double along = x[3 * i] - lo[0] - h[5] / h[1] * (x[3 * i + 1] - lo[1]);
    err = std::max(err, std::fabs(along - h[0] * s));
  }
  return err;
}

void box_lo(Lammps &l, double *lo)
{
  for (int k = 0; k < 3; k++) lo[k] = l.lmp->domain->boxlo[k];
}

void box_h(Lammps &l, double *h)
{
  for (int k = 0; k < 6; k++) h[k] = l.lmp->domain->h[k];
}

// after read_restart of the mat: what a restart file does not keep, defined again as when it was
// written (the fix ncf/pbc restores its state from the file), then n steps
void resume(Lammps &r, int n, const std::string &pbc_keywords = "")
{
  r.cmds(R"(
fix NCF_NODE all property/atom i_ncf_layer i_ncf_end
fix MASS all property/atom rmass
neighbor 1e-4 bin
comm_modify cutoff 6e-4
fix nve all nve
)");
  r.cmd("fix pbc ends ncf/pbc faces x " + pbc_keywords);
  r.cmd("timestep 5e-9");
  r.cmd("run " + std::to_string(n));
}

}    // namespace

TEST(FixPBC, AveragedConstraintHoldsOver10kSteps)
{
  auto dir = scratch_dir("pbc_hold");
  auto mat = write_mat(dir, 3.0, 11);
  Lammps l;
  load_mat(l, mat);
  auto xref = l.positions();
  double href[6], h[6];
  box_h(l, href);
  l.cmds(R"(
velocity all create 5e12 5 loop geom
fix nve all nve
fix pbc ends ncf/pbc faces x
timestep 5e-9
thermo_style custom step pe ke f_pbc
)");
  l.cmd("run 10000");
  auto x = l.positions();
  box_h(l, h);
  const double err = constraint_error(xref, x, face_codes(mat), href, h);
  std::printf("[measured] averaged PBC error after 1e4 steps: %.3g m (%.3g of the box)\n", err,
              err / LX);
  EXPECT_LT(err, 1e-10 * LX);
  // the fix reports the same order of magnitude
  EXPECT_LT(l.value("f_pbc"), 1e-10 * LX);
  // and the chains did move (the constraint is not trivially satisfied)
  EXPECT_GT(max_abs_diff(x, xref), 1e-7);
}

// The fix finds its own end nodes again whenever LAMMPS may have moved atoms in memory: also at
// the setup of a run after one without any list build (LAMMPS counts the builds from zero in
// every run, and sorts the atoms at every setup). A rigid shift between the runs (which the
// constraint does not see) puts the atoms into other sort bins.
TEST(FixPBC, OwnEndNodesFoundAgainWhenAtomsAreReordered)
{
  auto dir = scratch_dir("pbc_reorder");
  auto mat = write_mat(dir, 3.0, 11);
  Lammps l;
  load_mat(l, mat);
  auto xref = l.positions();
  double href[6], h[6];
  box_h(l, href);
  l.cmds(R"(
atom_modify sort 1000 5e-5
velocity all create 5e12 5 loop geom
fix nve all nve
fix pbc ends ncf/pbc faces x
timestep 5e-9
thermo_style custom step pe ke f_pbc
run 50
)");
  ASSERT_EQ(l.lmp->neighbor->ncalls, 0) << "the case: a run without list builds";
  const auto before = l.positions();
  std::vector<int> order(l.lmp->atom->tag, l.lmp->atom->tag + l.lmp->atom->nlocal);
  l.cmd("displace_atoms all move 3.1e-4 1.7e-4 0.0");
  l.cmd("run 50");
  ASSERT_NE(order, std::vector<int>(l.lmp->atom->tag, l.lmp->atom->tag + l.lmp->atom->nlocal))
      << "the case: the atoms sorted anew at the setup of the second run";
  // (the positions unwrapped, the shift taken off again)
  auto x = l.positions();
  for (std::size_t i = 0; i < x.size(); i += 3) x[i] -= 3.1e-4, x[i + 1] -= 1.7e-4;
  box_h(l, h);
  const double err = constraint_error(xref, x, face_codes(mat), href, h);
  EXPECT_LT(err, 1e-10 * LX);
  // and the constraint forces went to the end nodes: nothing jumped (thermal motion over 50 steps
  // is a few um; forces on the wrong nodes move them by up to the box)
  EXPECT_LT(max_abs_diff(x, before), 1e-5);
}

// with normal hold also every end node keeps its reduced coordinate along the (tilted) face
// normal: the hold is affine with the box
TEST(FixPBC, ConstraintFollowsABoxDeformation)
{
  auto dir = scratch_dir("pbc_deform");
  auto mat = write_mat(dir, 3.0, 12);
  for (const std::string mode : {"free", "hold"}) {
    Lammps l;
    load_mat(l, mat);
    l.cmd("change_box all triclinic");
    auto xref = l.positions();
    double href[6], h[6], lo[3];
    box_h(l, href);
    l.cmds(R"(
velocity all create 5e12 5 loop geom
fix nve all nve
fix deform all deform 1 x erate 1000 xy erate 2000 remap x
)");
    l.cmd("fix pbc ends ncf/pbc faces x normal " + mode);
    l.cmds("timestep 1e-9\nrun 10000");
    auto x = l.positions();
    box_h(l, h);
    box_lo(l, lo);
    EXPECT_NEAR(h[0], LX * 1.01, 1e-12);    // 1 % stretch happened
    EXPECT_GT(std::fabs(h[5]), 1e-5);       // and a shear
    const double err = constraint_error(xref, x, face_codes(mat), href, h);
    const double normal = normal_hold_error(xref, x, face_codes(mat), href, h, lo);
    std::printf("[measured] normal %s with box deformation: averaged PBC error %.3g m (%.3g of the "
                "box), end nodes off their faces by %.3g m\n",
                mode.c_str(), err, err / LX, normal);
    EXPECT_LT(err, 1e-10 * LX);
    if (mode == "hold") EXPECT_LT(normal, 1e-10 * LX);
  }
}

TEST(FixPBC, ConservesMomentum)
{
  auto dir = scratch_dir("pbc_momentum");
  auto mat = write_mat(dir, 3.0, 13);
  Lammps l;
  load_mat(l, mat);
  l.cmds(R"(
velocity all create 5e12 5 loop geom mom yes
fix nve all nve
fix pbc ends ncf/pbc faces x
variable px equal mass(all)*vcm(all,x)
variable py equal mass(all)*vcm(all,y)
variable pz equal mass(all)*vcm(all,z)
variable pscale equal sqrt(2*ke*mass(all))
timestep 5e-9
run 2000
)");
  const double scale = l.value("v_pscale");
  EXPECT_LT(std::fabs(l.value("v_px")), 1e-12 * scale);
  EXPECT_LT(std::fabs(l.value("v_py")), 1e-12 * scale);
  EXPECT_LT(std::fabs(l.value("v_pz")), 1e-12 * scale);
}

TEST(FixPBC, WithoutVariabilityItIsOrdinaryPeriodicity)
{
  // sigma = 0: open chains with end nodes on the faces + fix ncf/pbc against the same chains
  // closed across the boundary: the interior nodes follow the same trajectory
  auto dir = scratch_dir("pbc_sigma0");
  auto open = write_mat(dir, 0.0, 1, false);
  auto ring = write_mat(dir, 0.0, 1, true);
  // a smooth initial deformation, identical in both (the ring has no node j = nel)
  auto perturb = [&](Lammps &l, const Mat &mat) {
    for (int c = 0; c < mat.nchain; c++)
      for (int j = 0; j < mat.nper; j++) {
        const int id = c * mat.nper + j + 1;
        const double s = std::sin(2 * M_PI * j / 10.0 + c);
        l.cmd(fmt::format("set atom {} vx {:.17g} vy {:.17g} vz {:.17g}", id, 0.3 * s, 0.5 * s,
                          0.2 * std::cos(c + 2 * M_PI * j / 10.0)));
      }
  };
  std::vector<double> xo, xr, xr0;
  {
    Lammps l;
    load_mat(l, open);
    perturb(l, open);
    l.cmds("fix nve all nve\nfix pbc ends ncf/pbc faces x\ntimestep 5e-9\nrun 3000");
    xo = l.positions();
  }
  {
    Lammps l;
    load_mat(l, ring);
    perturb(l, ring);
    xr0 = l.positions();
    l.cmds("fix nve all nve\ntimestep 5e-9\nrun 3000");
    xr = l.positions();
  }
  // compare node j of chain c (j < nel) in both; the open chain's node nel is the image of node 0
  double diff = 0.0;
  for (int c = 0; c < open.nchain; c++)
    for (int j = 0; j < ring.nper; j++)
      for (int d = 0; d < 3; d++) {
        const double a = xo[3 * (c * open.nper + j) + d], b = xr[3 * (c * ring.nper + j) + d];
        diff = std::max(diff, std::fabs(a - b));
      }
  std::printf("[measured] sigma = 0: max |x_open - x_ring| = %.3g m\n", diff);

  EXPECT_LT(diff, 1e-10 * LX);
  EXPECT_GT(max_abs_diff(xr, xr0), 1e-7);    // the chains moved
}

// (with normal hold too: the node holds' multipliers of the last step come from the file)
TEST(FixPBC, RestartContinuesTheSameTrajectory)
{
  auto dir = scratch_dir("pbc_restart");
  auto mat = write_mat(dir, 3.0, 14);
  for (const std::string normal : {"free", "hold"}) {
    std::vector<double> straight;
    {
      Lammps l;
      load_mat(l, mat);
      l.cmds("velocity all create 5e12 5 loop geom\nfix nve all nve");
      l.cmd("fix pbc ends ncf/pbc faces x normal " + normal);
      l.cmds("timestep 5e-9\nrun 500");
      l.cmd("write_restart " + dir + "/half.restart");
      l.cmd("run 500");
      straight = l.positions();
    }
    Lammps r;
    r.cmd("read_restart " + dir + "/half.restart");
    resume(r, 500, "normal " + normal);
    EXPECT_EQ(max_abs_diff(r.positions(), straight), 0.0) << normal;
  }
}

// A fix defined after fix ncf/pbc in the same process (an indenter, a second plate) is moved
// behind it by a copy that takes its state ('from'), the original then removed: the run goes on
// as if nothing had happened, bit for bit; capturing a new reference instead does not
TEST(FixPBC, MovedByFromContinuesTheSameTrajectory)
{
  auto dir = scratch_dir("pbc_from");
  auto mat = write_mat(dir, 3.0, 14);
  for (const std::string normal : {"free", "hold"}) {
    auto start = [&](Lammps &l) {
      load_mat(l, mat);
      l.cmds("velocity all create 5e12 5 loop geom\nfix nve all nve");
      l.cmd("fix pbc ends ncf/pbc faces x normal " + normal);
      l.cmds("timestep 5e-9\nrun 500");
    };
    std::vector<double> straight, moved, recaptured;
    {
      Lammps l;
      start(l);
      l.cmd("run 500");
      straight = l.positions();
    }
    {
      Lammps l;
      start(l);
      // (the copies keep the original's normal mode without the keyword)
      l.cmds("fix later all addforce 0 0 0\nfix pbc_moving ends ncf/pbc from pbc\nunfix pbc");
      l.cmds("fix pbc ends ncf/pbc from pbc_moving\nunfix pbc_moving\nrun 500");
      // the copy is the last fix that changes forces
      auto fixes = l.lmp->modify->get_fix_list();
      EXPECT_STREQ(fixes.back()->id, "pbc");
      moved = l.positions();
    }
    {
      Lammps l;
      start(l);
      l.cmd("unfix pbc");
      l.cmd("fix pbc ends ncf/pbc faces x normal " + normal);
      l.cmd("run 500");
      recaptured = l.positions();
    }
    EXPECT_EQ(max_abs_diff(moved, straight), 0.0) << normal;
    EXPECT_GT(max_abs_diff(recaptured, straight), 0.0) << normal;
    std::printf("[measured] normal %s: moved by 'from': %.3g m; captured again: %.3g m\n",
                normal.c_str(), max_abs_diff(moved, straight), max_abs_diff(recaptured, straight));
  }
}

// A restart file written after a box deformation (stretch and shear): the fix, defined again in
// the tilted box, takes its reference from the file, and the constraint keeps its targets F D_g
// with F relative to the reference box of the start (not the box of the restart): the same
// trajectory
TEST(FixPBC, RestartAfterABoxDeformation)
{
  auto dir = scratch_dir("pbc_restart_deform");
  auto mat = write_mat(dir, 3.0, 15);
  std::vector<double> straight, xref;
  double href[6], h[6];
  {
    Lammps l;
    load_mat(l, mat);
    l.cmd("change_box all triclinic");
    xref = l.positions();
    box_h(l, href);
    l.cmds(R"(
velocity all create 5e12 5 loop geom
fix nve all nve
fix deform all deform 1 x erate 2000 xy erate 4000 remap x
fix pbc ends ncf/pbc faces x
timestep 5e-9
run 500
unfix deform
)");
    l.cmd("write_restart " + dir + "/deformed.restart");
    l.cmd("run 300");
    straight = l.positions();
    box_h(l, h);
  }
  EXPECT_GT(h[0], LX * 1.004);    // the box was stretched and sheared before the restart
  EXPECT_GT(std::fabs(h[5]), 1e-6);
  Lammps r;
  r.cmd("read_restart " + dir + "/deformed.restart");
  resume(r, 300);
  // (to round-off: LAMMPS wraps the atoms of a tilted box through its lamda coordinates at the
  // setup of the resumed run, which changes the last bits of their positions)
  const auto x = r.positions();
  EXPECT_LT(max_abs_diff(x, straight), 1e-12 * LX);
  EXPECT_LT(constraint_error(xref, x, face_codes(mat), href, h), 1e-10 * LX);
  // a new fix in the tilted box has no reference to start from
  r.cmd("unfix pbc");
  r.cmd("fix pbc2 ends ncf/pbc faces x");
  EXPECT_THAT(error_of([&] {
                r.cmd("run 0");
              }),
              HasSubstr("fix ncf/pbc: the box must be orthogonal when the fix is defined"));
}

TEST(FixPBC, MinimizationKeepsTheConstraint)
{
  auto dir = scratch_dir("pbc_min");
  auto mat = write_mat(dir, 3.0, 15);
  Lammps l;
  load_mat(l, mat);
  auto xref = l.positions();
  double href[6];
  box_h(l, href);
  // pull every bond by a shrink factor so that the chains want to contract
  l.cmds(R"(
bond_coeff 1 modulus 120e9 diameter 69e-6 shrink 0.01
fix pbc ends ncf/pbc faces x
min_style cg
min_modify dmax 1e-5
minimize 0 1e-12 2000 20000
)");
  auto x = l.positions();
  const double err = constraint_error(xref, x, face_codes(mat), href, href);
  EXPECT_LT(err, 1e-10 * LX);
  EXPECT_GT(max_abs_diff(x, xref), 1e-7);    // it did relax
}

struct BadPbc {
  const char *command;
  const char *message;
};

class FixPBCErrors : public ::testing::TestWithParam<BadPbc> {};

TEST_P(FixPBCErrors, NameTheProblem)
{
  auto dir = scratch_dir("pbc_errors");
  auto mat = write_mat(dir, 3.0, 16);
  Lammps l;
  load_mat(l, mat);
  auto msg = error_of([&] {
    l.cmds(GetParam().command);
  });
  EXPECT_THAT(msg, HasSubstr(GetParam().message)) << GetParam().command;
}

INSTANTIATE_TEST_SUITE_P(
    Table, FixPBCErrors,
    ::testing::Values(
        BadPbc{"fix p ends ncf/pbc faces z", "fix ncf/pbc: faces 'z' is not one of auto, x, y, xy"},
        BadPbc{"fix p ends ncf/pbc faces", "fix ncf/pbc: keyword 'faces' needs a value"},
        BadPbc{"fix p ends ncf/pbc endface ncf_end",
               "fix ncf/pbc: endface 'ncf_end' must be 'auto' or a per-atom integer i_NAME"},
        BadPbc{"fix p ends ncf/pbc endface i_nothing",
               "fix ncf/pbc: no per-atom integer i_nothing"},
        BadPbc{"fix p ends ncf/pbc xcells 0 2", "fix ncf/pbc: xcells values must be >= 1, got 0"},
        BadPbc{"fix p ends ncf/pbc xcells 4", "fix ncf/pbc: keyword 'xcells' needs 2 values"},
        BadPbc{"fix p ends ncf/pbc xcells 100000 100000",
               "fix ncf/pbc: xcells 100000 100000 gives 1e+10 cells for the"},
        BadPbc{"fix p ends ncf/pbc stiffness 3", "fix ncf/pbc: unknown keyword 'stiffness'"},
        BadPbc{"fix p ends ncf/pbc faces y",
               "fix ncf/pbc: no end node of group ends lies on the y faces"},
        BadPbc{"fix p ends ncf/pbc faces xy",
               "fix ncf/pbc: no end node of group ends lies on the y faces"},
        BadPbc{"fix p all ncf/pbc endface i_ncf_layer",
               "fix ncf/pbc: x faces: averaged periodic boundary: no end node on the upper face"},
        BadPbc{"fix p ends ncf/pbc normal", "fix ncf/pbc: keyword 'normal' needs a value"},
        BadPbc{"fix p ends ncf/pbc normal fixed",
               "fix ncf/pbc: normal 'fixed' is not one of hold, free"},
        BadPbc{"fix p ends ncf/pbc from", "fix ncf/pbc: keyword 'from' needs a value"},
        BadPbc{"fix p ends ncf/pbc from nothing",
               "fix ncf/pbc: from 'nothing': no fix with this ID"},
        BadPbc{"fix n all nve\nfix p ends ncf/pbc from n",
               "fix ncf/pbc: from 'n': fix n is nve, not another fix ncf/pbc"},
        BadPbc{"fix p ends ncf/pbc faces x\nfix q ends ncf/pbc from p faces x",
               "fix ncf/pbc: keyword 'faces' cannot be combined with 'from p'"},
        BadPbc{"fix p ends ncf/pbc faces x\ngroup two id 1 2\nfix q two ncf/pbc from p",
               "fix ncf/pbc: from 'p': its group is ends, this fix's is two"}));

TEST(FixPBC, AutoFacesTieOnlyThePairsWithEndNodes)
{
  // the mat's chains all cross along x: faces auto (default) ties the x faces only
  auto dir = scratch_dir("pbc_auto");
  auto mat = write_mat(dir, 3.0, 19);
  Lammps l;
  load_mat(l, mat);
  l.cmd("fix pbc ends ncf/pbc");
  l.cmd("run 0");
  EXPECT_EQ(l.value("f_pbc[2]"), 2.0 * mat.nchain);    // both ends of every chain
  // no end node anywhere: an error
  l.cmd("group inner subtract all ends");
  EXPECT_THAT(error_of([&] {
                l.cmd("fix p2 inner ncf/pbc");
              }),
              HasSubstr("fix ncf/pbc: no end node of group inner lies on a periodic face"));
}

TEST(FixPBC, NonPeriodicDirectionIsRefused)
{
  auto dir = scratch_dir("pbc_nonperiodic");
  auto mat = write_mat(dir, 3.0, 17);
  Lammps l;
  load_mat(l, mat);
  l.cmd("change_box all boundary f p f");
  EXPECT_THAT(error_of([&] {
                l.cmd("fix p ends ncf/pbc faces x");
              }),
              HasSubstr("fix ncf/pbc: faces x need a periodic box in x"));
}

TEST(FixPBC, LaterFixChangingForcesIsReported)
{
  auto dir = scratch_dir("pbc_order");
  auto mat = write_mat(dir, 3.0, 18);
  Lammps l(MPI_COMM_WORLD, dir + "/log.lammps");
  load_mat(l, mat);
  l.cmd(std::string("variable pbcline string \"") +
        (getenv("NCFPBC") ? getenv("NCFPBC") : "fix pbc ends ncf/pbc faces x normal hold") + "\"");
  l.cmds("fix nve all nve\nfix pbc ends ncf/pbc faces x\nfix sf ends setforce 0 0 NULL\ntimestep "
         "5e-9\nrun 0");
  l.cmd("log none");
  std::ifstream in(dir + "/log.lammps");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_THAT(text.str(),
              HasSubstr("fix ncf/pbc: fix sf (setforce) changes forces after fix ncf/pbc"));
}

// keyword normal hold (the paper's walls at the RVE faces with Eq. 2): every end node stays on
// its face while the group constraint keeps holding in the face's plane and in z
TEST(FixPBCNormalHold, KeepsEveryEndOnItsFace)
{
  auto dir = scratch_dir("pbc_normal_hold");
  auto mat = write_mat(dir, 3.0, 31);
  for (const std::string mode : {"hold", "free"}) {
    Lammps l;
    load_mat(l, mat);
    auto xref = l.positions();
    double href[6], h[6], lo[3];
    box_h(l, href);
    l.cmds(R"(
velocity all create 5e12 5 loop geom
fix nve all nve
timestep 5e-9
)");
    l.cmd("fix pbc ends ncf/pbc faces x normal " + mode);
    l.cmd("run 5000");
    auto x = l.positions();
    box_h(l, h);
    box_lo(l, lo);
    const double normal = normal_hold_error(xref, x, face_codes(mat), href, h, lo);
    const double group = constraint_error(xref, x, face_codes(mat), href, h);
    std::printf("[measured] normal %s: end nodes off their faces by up to %.3g m, group "
                "constraint %.3g m\n",
                mode.c_str(), normal, group);
    EXPECT_LT(group, 1e-10 * LX) << mode;
    if (mode == "hold") {
      EXPECT_LT(normal, 1e-10 * LX);
      EXPECT_LT(l.value("f_pbc"), 1e-10 * LX);    // the fix's own residual includes the holds
    } else {
      EXPECT_GT(normal, 1e-7);    // free: the ends do move through the faces
    }
    EXPECT_GT(max_abs_diff(x, xref), 1e-7);
  }
}

// A chain deflected between held ends: the mat without orientation variability (chains along x,
// each chain's two ends one group), a force P across one chain's middle node and -P/2 on each of
// its end nodes (the supports' reactions, so that nothing drives a translation). Between held ends its length between the faces is fixed, so it stretches into a
// triangle, a string without pretension: T = EA (sqrt(1 + (2w/L)^2) - 1), P = 2 T sin(theta),
// tan(theta) = 2w/L. Relaxed under damping (about critical for the string's mode), the deflection is that of the string; the load taken
// away, it springs back (slowly: a string without pretension has no linear stiffness, its
// restoring force falls as w^3).
TEST(FixPBCNormalHold, ChainDeflectedBetweenHeldEndsSpringsBack)
{
  auto dir = scratch_dir("pbc_normal_spring");
  auto mat = write_mat(dir, 0.0, 34);
  const double EA = 120e9 * M_PI / 4 * 69e-6 * 69e-6, L = LX, P = 2e-4;
  // the string's deflection under P: solve P = 2 EA (sqrt(1 + t^2) - 1) t / sqrt(1 + t^2), t = 2w/L
  auto load = [&](double t) {
    const double r = std::sqrt(1 + t * t);
    return 2 * EA * (r - 1) * t / r;
  };
  double t0 = 0.0, t1 = 1.0, t = 0.5;
  for (int it = 0; it < 200; it++) {    // (bisection: the load grows monotonically with t)
    t = 0.5 * (t0 + t1);
    (load(t) < P ? t0 : t1) = t;
  }
  const double w_string = 0.5 * L * t;
  const int mid = 6, last = mat.nper;    // chain 1: nodes 1 .. nper, its middle node
  Lammps l;
  load_mat(l, mat);
  auto xref = l.positions();
  l.cmds(fmt::format(R"(
group mid id {}
group pins id 1 {}
fix nve all nve
fix damp all viscous 2e-4
fix push mid addforce 0 {} 0
fix pull pins addforce 0 {} 0
fix pbc ends ncf/pbc faces x normal hold
timestep 5e-9
run 20000
)",
                     mid, last, P, -0.5 * P));
  // deflection: the middle node from the line between the chain's ends
  auto deflection = [&](const std::vector<double> &p) {
    return p[3 * (mid - 1) + 1] - 0.5 * (p[1] + p[3 * (last - 1) + 1]);
  };
  auto x = l.positions();
  const double w = deflection(x) - deflection(xref);
  l.cmds("unfix push\nunfix pull\nrun 100000");
  const double back = deflection(l.positions()) - deflection(xref);
  std::printf("[measured] chain between held ends under %.3g N: deflection %.5g um (string: %.5g "
              "um), %.3g um after the load is taken away\n",
              P, 1e6 * w, 1e6 * w_string, 1e6 * back);
  EXPECT_NEAR(w, w_string, 1e-3 * w_string);
  EXPECT_LT(std::fabs(back), 0.15 * w_string);
  // and the end nodes stayed on their faces
  double href[6], lo[3];
  box_h(l, href);
  box_lo(l, lo);
  EXPECT_LT(normal_hold_error(xref, x, face_codes(mat), href, href, lo), 1e-10 * LX);
}

// The stress of the periodic fabric is the virial of its bonds (and contacts): straight chains
// along x, their ends on the x faces, stretched by 0.1 % with the box and at rest, carry a tension
// T each (from their bond lengths, EA (l - l0)/l0), and the virial of the whole system is
// -sum T lx. The constraint forces add nothing: counted with the end nodes at their unwrapped
// places they would cancel it exactly (a tensioned fabric without stress).
TEST(FixPBC, VirialIsThePeriodicStressOfTensionedChains)
{
  auto dir = scratch_dir("pbc_virial");
  auto mat = write_mat(dir, 0.0, 3);
  const double EA = 120e9 * M_PI / 4 * 69e-6 * 69e-6;
  for (const std::string mode : {"free", "hold"}) {
    Lammps l;
    load_mat(l, mat);
    l.cmds(R"(
fix nve all nve
fix damp all viscous 2e-4
fix stretch all deform 1 x scale 1.001 remap x
)");
    l.cmd("fix pbc ends ncf/pbc faces x normal " + mode);
    l.cmds(R"(
timestep 5e-9
run 5000
unfix stretch
run 20000
compute vir all pressure NULL virial
thermo_style custom step c_vir[1] vol
run 0
)");
    // the tension of each chain from its bonds (straight and uniform at rest)
    const double lx = l.value("lx"), pxxV = l.value("c_vir[1]") * l.value("vol");
    const double l0 = MAT_LX / 10, lbar = lx / 10;    // 10 elements per chain, straight along x
    const double T = EA * (lbar - l0) / l0;
    const double expect = -mat.nchain * T * lx;
    std::printf("[measured] normal %s: chains stretched 0.1 %%, tension %.5g N each; virial xx "
                "%.6g N m, expected -n T lx = %.6g N m\n",
                mode.c_str(), T, pxxV, expect);
    EXPECT_GT(T, 0.5 * EA * 1e-3);
    EXPECT_NEAR(pxxV, expect, 1e-3 * std::fabs(expect));
  }
}

// The work of a box deformation computed from the virial, -int W : L dt with L = dh/dt h^-1, is
// the energy the fabric stores: chains at sigma = 3 deg, no damping, stretched by 1 % and sheared
// by fix deform while they vibrate, under both normal modes. This is what the virtual shear test
// measures its force with; a constraint virial breaks it (counted with the + face nodes at their
// partners' places, the in-face offsets of the end nodes times their multipliers: 3.3e-4 here,
// 20x the stored energy on a stitched +-45 fabric; at their unwrapped places: no stress at all).
TEST(FixPBC, WorkOfTheBoxFromTheVirialIsTheEnergyStored)
{
  auto dir = scratch_dir("pbc_work");
  auto mat = write_mat(dir, 3.0, 21);
  for (const std::string mode : {"free", "hold"}) {
    Lammps l;
    load_mat(l, mat);
    l.cmd("change_box all triclinic");
    l.cmds(R"(
fix nve all nve
fix deform all deform 1 x erate 1000 xy erate 2000 remap x
)");
    l.cmd("fix pbc ends ncf/pbc faces x normal " + mode);
    l.cmds(R"(
compute vir all pressure NULL virial
compute pe all pe
compute ke all ke
thermo_style custom step c_vir[1] c_vir[2] c_vir[4] vol c_pe c_ke lx ly xy
thermo 10
timestep 1e-9
run 0
)");
    struct State {
      double lx, ly, xy, wxx, wyy, wxy, e;
    };
    auto state = [&]() {
      const double vol = l.value("vol");
      return State{l.value("lx"),
                   l.value("ly"),
                   l.value("xy"),
                   l.value("c_vir[1]") * vol,
                   l.value("c_vir[2]") * vol,
                   l.value("c_vir[4]") * vol,
                   l.value("c_pe") + l.value("c_ke")};
    };
    State a = state();
    const double e0 = a.e;
    double work = 0.0;
    for (int k = 0; k < 1000; k++) {
      l.cmd("run 10 post no");
      const State b = state();
      // midpoint rule: L dt = dh h^-1 at the mean box, the mean virial
      const double mlx = 0.5 * (a.lx + b.lx), mly = 0.5 * (a.ly + b.ly), mxy = 0.5 * (a.xy + b.xy);
      const double Lxx = (b.lx - a.lx) / mlx, Lyy = (b.ly - a.ly) / mly,
                   Lxy = (b.xy - a.xy) / mly - (b.lx - a.lx) * mxy / (mlx * mly);
      work -= 0.5 * ((a.wxx + b.wxx) * Lxx + (a.wyy + b.wyy) * Lyy + (a.wxy + b.wxy) * Lxy);
      a = b;
    }
    const double stored = a.e - e0;
    std::printf("[measured] normal %s: work of the box from the virial %.6g J, energy stored "
                "%.6g J (relative difference %.2g)\n",
                mode.c_str(), work, stored, (work - stored) / stored);
    EXPECT_GT(a.lx, 1.009 * MAT_LX);    // the deformation happened
    EXPECT_GT(stored, 0.0);
    EXPECT_NEAR(work, stored, 5e-5 * stored);    // (time discretisation: 1.7e-5 measured)
  }
}
