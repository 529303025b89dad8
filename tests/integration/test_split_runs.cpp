// Split-run invariance: a run cut into pieces (`run 7` as `run 3` + `run 4`, `run 1` + `run 1` +
// `run 5`, `run 0` in between, write_restart / read_restart into a new LAMMPS instance at a cut,
// a restart file written during a run by the restart command)
// gives the same positions, velocities and forces bit for bit as the uncut run, for every style
// that keeps state from step to step: the friction history of pair ncf/contact, the motion of
// fix ncf/plate (and its friction history) and fix ncf/needles, the ramp of fix ncf/shrink and
// the reference state of fix ncf/pbc. Also: two `run 0` in a row give the forces of the step
// before them.
//
// The damping is fix ncf/damp (its own scene): LAMMPS evaluates the forces of a run's setup with
// the full-step velocities, where the steps use the half-step ones, so that a velocity-dependent
// force that keeps no state (fix viscous, a dashpot) is not split-invariant; fix ncf/damp applies
// at the setup the drag of the step before it (doc/fix_ncf_damp.md). The other scenes have no
// velocity-dependent force. Atom sorting is off and no node crosses a periodic boundary within the
// runs: LAMMPS sorts the atoms and wraps positions at every setup.

#include "ncf_lammps_test.h"
#include "ncf_scenes.h"
#include "test_pair_contact_scene.h"

#include "fmt/format.h"
#include "lammps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

using namespace ncftest;

namespace {

struct Snapshot {
  std::vector<double> x, v, f;
  std::vector<double> values;    // the scene's global outputs (Scene::outputs)
};

// A scene: define() sets it up in an empty instance; resume() continues it in an empty instance
// from a restart file written by it (what restart files do not keep given again)
struct Scene {
  std::function<void(Lammps &)> define;
  std::function<void(Lammps &, const std::string &)> resume;
  std::vector<std::string> outputs;    // state of the styles compared too (e.g. a tool's height)
};

Snapshot snapshot(Lammps &l, const Scene &s)
{
  Snapshot snap{l.positions(), l.velocities(), l.forces(), {}};
  for (const std::string &e : s.outputs) snap.values.push_back(l.value(e));
  return snap;
}

// Runs the pieces (run lengths; 0 is `run 0`); after piece restart_after (-1: none) the state
// goes through write_restart and read_restart into a new instance
Snapshot run_pieces(const Scene &s, const std::vector<int> &pieces, int restart_after,
                    const std::string &dir)
{
  auto l = std::make_unique<Lammps>();
  s.define(*l);
  for (size_t k = 0; k < pieces.size(); k++) {
    l->cmd(fmt::format("run {}", pieces[k]));
    if ((int) k == restart_after) {
      const std::string file = dir + "/cut.restart";
      l->cmd("write_restart " + file);
      l.reset();    // one LAMMPS instance at a time (plugin styles)
      l = std::make_unique<Lammps>();
      s.resume(*l, file);
    }
  }
  return snapshot(*l, s);
}

std::string describe(const std::vector<int> &pieces, int restart_after)
{
  std::string s;
  for (size_t k = 0; k < pieces.size(); k++) {
    s += (k ? " + " : "") + fmt::format("run {}", pieces[k]);
    if ((int) k == restart_after) s += " + restart";
  }
  return s;
}

// bitwise equality of two arrays, reporting the first difference
void expect_same_bits(const std::vector<double> &a, const std::vector<double> &b,
                      const std::string &what)
{
  ASSERT_EQ(a.size(), b.size()) << what;
  size_t ndiff = 0, first = a.size();
  for (size_t i = 0; i < a.size(); i++)
    if (!(a[i] == b[i]) && !(std::isnan(a[i]) && std::isnan(b[i]))) {
      if (!ndiff) first = i;
      ndiff++;
    }
  EXPECT_EQ(ndiff, 0u) << what << ": " << ndiff << " of " << a.size()
                       << " values differ; first: atom " << first / 3 + 1 << " dim " << first % 3
                       << ": " << fmt::format("{:.17g} vs {:.17g}", a[first], b[first]);
}

void expect_same(const Snapshot &cut, const Snapshot &ref, const std::string &what)
{
  expect_same_bits(cut.x, ref.x, what + ", positions");
  expect_same_bits(cut.v, ref.v, what + ", velocities");
  expect_same_bits(cut.f, ref.f, what + ", forces");
  for (size_t k = 0; k < cut.values.size(); k++)
    EXPECT_EQ(fmt::format("{:.17g}", cut.values[k]), fmt::format("{:.17g}", ref.values[k]))
        << what << ", "
        << "output " << k + 1;
}

// a restart file written during a run (`restart 3`: steps 3 and 6), read into a new instance at
// step 3 and run on to step 7, against that run (LAMMPS reneighbours on the steps that write a
// restart file: both runs write them on the same steps)
void check_restart_command(const Scene &s, const std::string &dir)
{
  Snapshot ref;
  {
    Lammps l;
    s.define(l);
    l.cmd("restart 3 " + dir + "/during.*");
    l.cmd("run 7");
    ref = snapshot(l, s);
  }
  Lammps r;
  s.resume(r, dir + "/during.3");
  r.cmd("restart 3 " + dir + "/after.*");
  r.cmd("run 4");
  expect_same(snapshot(r, s), ref, "run 7 with restart 3, read at step 3 + run 4");
}

// run 7 uncut against the same 7 steps cut unevenly and at several places, with and without a
// restart at a cut; the scene must have moved (not a trivially equal state)
void check_cuts(const Scene &s, const std::string &dir)
{
  const Snapshot ref = run_pieces(s, {7}, -1, dir);
  const Snapshot start = run_pieces(s, {0}, -1, dir);
  EXPECT_GT(max_abs_diff(ref.x, start.x), 0.0) << "the scene must move";
  struct Cut {
    std::vector<int> pieces;
    int restart_after;
  };
  const Cut cuts[] = {{{3, 4}, -1},   {{1, 1, 5}, -1}, {{2, 0, 0, 5}, -1},
                      {{6, 1}, -1},   {{3, 4}, 0},     {{1, 5, 1}, 1},
                      {{2, 3, 2}, 0}, {{0, 7}, 0},     {{1, 0, 6}, 1}};
  for (const Cut &c : cuts) {
    const std::string what = describe(c.pieces, c.restart_after) + " vs run 7";
    expect_same(run_pieces(s, c.pieces, c.restart_after, dir), ref, what);
  }
  check_restart_command(s, dir);
}

// forces of two `run 0` in a row after a run: those of the run's last step, both times
void check_run0(const Scene &s)
{
  std::vector<double> x7;
  {
    Lammps l;
    s.define(l);
    l.cmd("run 4");
    const std::vector<double> f4 = l.forces();
    l.cmd("run 0");
    const std::vector<double> fa = l.forces();
    l.cmd("run 0");
    const std::vector<double> fb = l.forces();
    expect_same_bits(fa, f4, "forces of run 0 after run 4 vs those of step 4");
    expect_same_bits(fb, fa, "forces of a second run 0 vs the first");
    l.cmd("run 3");
    x7 = l.positions();
  }
  Lammps r;    // (one LAMMPS instance at a time)
  s.define(r);
  r.cmd("run 7");
  expect_same_bits(x7, r.positions(), "positions of run 4 + run 0 + run 0 + run 3 vs run 7");
}

// ---------------------------------------------------------------- pair ncf/contact, friction

const double MESH = 1e-4;

std::string contact_data(const std::string &dir)
{
  using namespace contactscene;
  Box box;
  box.lo[0] = box.lo[1] = 0.0;
  box.hi[0] = box.hi[1] = 1.2e-3;
  return write_data(dir + "/contact.data", random_mat(12, 12, 1.2e-3, MESH, 0.9 * DIAM, 5), box,
                    RHO_A * MESH);
}

const char *CONTACT_RUN = R"(
comm_modify vel yes
neighbor 2e-5 bin
neigh_modify every 1 delay 0 check yes
compute pc all pair ncf/contact
thermo_style custom step pe ke evdwl c_pc[1]
thermo 0
fix nve all nve
timestep 5e-9
)";

Scene contact_scene(const std::string &data, const std::string &coeff,
                    const std::string &boundary = "p p f")
{
  Scene s;
  s.define = [=](Lammps &l) {
    l.cmds("units si\natom_style bond\natom_modify map array sort 0 0");
    l.cmd("boundary " + boundary);
    l.cmd("bond_style ncf/chain");
    l.cmd("read_data " + data);
    l.cmd("bond_coeff 1 modulus 120e9 diameter 69e-6");
    l.cmd("pair_style ncf/contact");
    l.cmd(coeff);
    l.cmd("velocity all create 1e12 4 mom yes rot no dist gaussian");
    l.cmds(CONTACT_RUN);
  };
  s.resume = [](Lammps &l, const std::string &file) {
    l.cmd("read_restart " + file);
    l.cmd("bond_coeff 1 modulus 120e9 diameter 69e-6");
    l.cmds(CONTACT_RUN);
  };
  return s;
}

}    // namespace

TEST(SplitRuns, PairContactFrictionHistory)
{
  auto dir = scratch_dir("split_contact");
  const Scene s =
      contact_scene(contact_data(dir), "pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6");
  {
    // the history must matter: contacts that slide at the start
    Lammps l;
    s.define(l);
    l.cmd("run 0");
    EXPECT_GT(l.value("c_pc[1]"), 10.0);
  }
  check_cuts(s, dir);
  check_run0(s);
}

// a longer run, the lists rebuilt every few steps (skin 0.2 um), cut where the uncut run does not
// rebuild them; in a closed box (no node crosses a periodic boundary: LAMMPS wraps them at a cut)
TEST(SplitRuns, PairContactLongRunManyListBuilds)
{
  auto dir = scratch_dir("split_contact_long");
  using namespace contactscene;
  Box box;
  box.lo[0] = box.lo[1] = -1e-3;
  box.hi[0] = box.hi[1] = 2.2e-3;
  const std::string data = write_data(
      dir + "/f.data", random_mat(24, 12, 1.2e-3, MESH, 0.9 * DIAM, 5), box, RHO_A * MESH);
  Scene s = contact_scene(data, "pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6", "f f f");
  const auto define = s.define;
  s.define = [=](Lammps &l) {
    define(l);
    l.cmd("neighbor 2e-7 bin");
  };
  s.outputs = {"c_pc[1]"};
  const Snapshot ref = run_pieces(s, {600}, -1, dir);
  EXPECT_GT(ref.values[0], 0.0) << "contacts at the end";
  for (int c : {173, 311, 450})
    expect_same(run_pieces(s, {c, 600 - c}, -1, dir), ref,
                fmt::format("run {} + run {}", c, 600 - c));
}

TEST(SplitRuns, PairContactWithoutFriction)
{
  auto dir = scratch_dir("split_contact_mu0");
  check_cuts(contact_scene(contact_data(dir), "pair_coeff * * kn 1e8 diameter 69e-6"), dir);
}

// ---------------------------------------------------------------- fixes on a mat (ncf_scenes)

namespace {

// the mat of ncf_scenes moved by a quarter element along x (its chain ends lie on the x faces,
// where LAMMPS would wrap them at a cut), `prepare` run once (not again after a restart),
// velocities, `fixes`
Scene mat_scene(const Mat &mat, const std::string &fixes, const std::string &prepare = "")
{
  Scene s;
  s.define = [=](Lammps &l) {
    load_mat(l, mat);
    l.cmd("atom_modify sort 0 0");
    l.cmd("displace_atoms all move 5e-5 0 0");
    l.cmds(prepare);
    l.cmd("velocity all create 5e12 3 loop geom");
    l.cmds(fixes);
    l.cmds("fix nve all nve\ntimestep 1e-8\nthermo 0");
  };
  s.resume = [=](Lammps &l, const std::string &file) {
    l.cmd("read_restart " + file);
    l.cmds("fix NCF_NODE all property/atom i_ncf_layer i_ncf_end\nfix MASS all property/atom "
           "rmass\nneighbor 1e-4 bin\ncomm_modify cutoff 6e-4\natom_modify sort 0 0");
    l.cmd("variable isend atom i_ncf_end>0");
    l.cmd("group ends variable isend");
    l.cmds(fixes);
    l.cmds("fix nve all nve\ntimestep 1e-8\nthermo 0");
  };
  return s;
}

void mat_z_range(const Mat &mat, double &zlo, double &zhi)
{
  Lammps l;
  load_mat(l, mat);
  const auto x = l.positions();
  zlo = 1e300;
  zhi = -1e300;
  for (size_t i = 2; i < x.size(); i += 3) {
    zlo = std::min(zlo, x[i]);
    zhi = std::max(zhi, x[i]);
  }
}

}    // namespace

TEST(SplitRuns, FixPlateMotionAndFriction)
{
  auto dir = scratch_dir("split_plate");
  const Mat mat = write_mat(dir, 3.0, 31);
  double zlo, zhi;
  mat_z_range(mat, zlo, zhi);
  // the mat moved so that its lowest node is 9.5 um into the lower plate, which starts at z = 0
  // and moves up (so that the last bit of the time since the start shows in its height); the
  // upper plate pressing the top nodes by 10 um; with friction
  const double lift = 0.5 * 69e-6 - 9.5e-6 - zlo;
  const std::string plate = fmt::format(
      "fix plate all ncf/plate kn 2e7 kt 0.5 mu 0.3 diameter 1 69e-6 lower move 0 1.0 upper z "
      "{:.17g}",
      zhi + lift + 0.5 * 69e-6 - 10e-6);
  Scene s = mat_scene(mat, plate, fmt::format("displace_atoms all move 0 0 {:.17g}", lift));
  s.outputs = {"f_plate[1]"};    // the lower plate's height
  {
    Lammps l;
    s.define(l);
    l.cmd("run 0");
    EXPECT_GT(l.value("f_plate[7]"), 0.0) << "contacts with the lower plate";
    EXPECT_GT(l.value("f_plate[8]"), 0.0) << "contacts with the upper plate";
  }
  check_cuts(s, dir);
  check_run0(s);
}

TEST(SplitRuns, FixPBCReferenceState)
{
  auto dir = scratch_dir("split_pbc");
  const Mat mat = write_mat(dir, 3.0, 14);
  const Scene s = mat_scene(mat, "fix pbc ends ncf/pbc faces x");
  check_cuts(s, dir);
  check_run0(s);
}

// ---------------------------------------------------------------- fix ncf/needles

namespace {

// a ring chain along x at y = 0, z = 0.2 mm (4 nodes, 1 mm apart) and a needle at (2, 0.2) mm
// whose tip, below the chain, moves down from z = 0 (so that the last bit of the time since the
// start shows in the tip's height): its conical point presses the chain sideways
Scene needle_scene(const std::string &dir)
{
  const std::string path = dir + "/chain.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "chain\n\n4 atoms\n1 atom types\n4 bonds\n1 bond types\n\n");
  fprintf(fp, "0 4e-3 xlo xhi\n-2e-3 2e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\nMasses\n\n1 1e-9\n\n");
  fprintf(fp, "Atoms # bond\n\n");
  for (int i = 0; i < 4; i++) fprintf(fp, "%d 1 1 %.17g 0 2e-4\n", i + 1, (i + 0.5) * 1e-3);
  fprintf(fp, "\nBonds\n\n");
  for (int i = 0; i < 4; i++) fprintf(fp, "%d 1 %d %d\n", i + 1, i + 1, (i + 1) % 4 + 1);
  fclose(fp);
  const std::string fixes = R"(
fix nd all ncf/needles diameter 0.5e-3 kn 1e8 chain 1 69e-6 at 2e-3 2e-4 move 0 -3.0 length 2e-3
fix nve all nve
timestep 1e-8
thermo 0
)";
  const char *setup = R"(
comm_modify cutoff 2e-3
atom_modify sort 0 0
)";
  Scene s;
  s.define = [=](Lammps &l) {
    l.cmds("units si\natom_style bond\natom_modify map array sort 0 0\nboundary p p f");
    l.cmds(setup);
    l.cmd("bond_style ncf/chain");
    l.cmd("read_data " + path);
    l.cmd("bond_coeff 1 ea 100");
    l.cmds(fixes);
  };
  s.resume = [=](Lammps &l, const std::string &file) {
    l.cmd("read_restart " + file);
    l.cmds(setup);
    l.cmd("bond_coeff 1 ea 100");
    l.cmds(fixes);
  };
  s.outputs = {"f_nd[1]"};    // the tip's height
  return s;
}

}    // namespace

TEST(SplitRuns, FixNeedlesMotion)
{
  auto dir = scratch_dir("split_needles");
  const Scene s = needle_scene(dir);
  {
    Lammps l;
    s.define(l);
    l.cmd("run 0");
    EXPECT_EQ(l.value("f_nd[3]"), 1.0) << "the needle touches the chain";
  }
  check_cuts(s, dir);
  check_run0(s);
}

// ---------------------------------------------------------------- fix ncf/shrink

namespace {

// a chain of 5 nodes with bonds of type 1 and a type-2 bond at its end, shrunk over 5 steps
Scene shrink_scene(const std::string &dir)
{
  const std::string path = dir + "/pair.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "pair\n\n5 atoms\n1 atom types\n4 bonds\n2 bond types\n\n");
  fprintf(fp, "0 1.2e-3 xlo xhi\n-1e-3 1e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\n");
  fprintf(fp, "Masses\n\n1 1e-9\n\nAtoms # bond\n\n");
  for (int i = 0; i < 5; i++) fprintf(fp, "%d 1 1 %.17g 0 0\n", i + 1, (i + 0.5) * 2e-4);
  fprintf(fp, "\nBonds\n\n");
  for (int i = 1; i < 5; i++) fprintf(fp, "%d %d %d %d\n", i, i < 4 ? 1 : 2, i, i + 1);
  fclose(fp);
  const char *fixes = R"(
fix s all ncf/shrink btype 2 strain 0.16 steps 5
fix nve all nve
timestep 1e-8
thermo 0
)";
  Scene s;
  s.define = [=](Lammps &l) {
    l.cmds("units si\natom_style bond\natom_modify map array sort 0 0\nboundary f f f");
    l.cmd("bond_style ncf/chain");
    l.cmd("read_data " + path);
    l.cmd("bond_coeff 1 ea 100");
    l.cmd("bond_coeff 2 ea 10");
    l.cmds(fixes);
  };
  s.resume = [=](Lammps &l, const std::string &file) {
    l.cmd("read_restart " + file);
    l.cmd("atom_modify sort 0 0");
    l.cmd("bond_coeff 1 ea 100");
    l.cmd("bond_coeff 2 ea 10");
    l.cmds(fixes);
  };
  return s;
}

}    // namespace

TEST(SplitRuns, FixShrinkRamp)
{
  auto dir = scratch_dir("split_shrink");
  check_cuts(shrink_scene(dir), dir);
  check_run0(shrink_scene(dir));
}

// ---------------------------------------------------------------- fix ncf/damp

namespace {

// the sliding contacts of the friction scene, damped over ~100 steps by `style` (ncf/damp or
// LAMMPS's viscous: the same drag F = -gamma v at every step)
Scene damped_scene(const std::string &dir, const std::string &style)
{
  const Scene base =
      contact_scene(contact_data(dir), "pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6");
  const std::string damp =
      "variable g equal mass(all)/count(all)/(100*dt)\nfix damp all " + style + " $(v_g:%.17g)";
  Scene s;
  s.define = [=](Lammps &l) {
    base.define(l);
    l.cmds(damp);
  };
  s.resume = [=](Lammps &l, const std::string &file) {
    base.resume(l, file);
    l.cmds(damp);
  };
  return s;
}

}    // namespace

// uncut, fix ncf/damp is fix viscous: the same drag at every step and at the first setup
TEST(SplitRuns, FixDampIsFixViscousInAnUncutRun)
{
  auto dir = scratch_dir("split_damp_ref");
  const Snapshot ref = run_pieces(damped_scene(dir, "viscous"), {7}, -1, dir);
  const Snapshot undamped = run_pieces(contact_scene(contact_data(dir),
                                                     "pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter "
                                                     "69e-6"),
                                       {7}, -1, dir);
  const std::vector<double> none(undamped.v.size(), 0.0);
  EXPECT_GT(max_abs_diff(ref.v, undamped.v), 1e-3 * max_abs_diff(undamped.v, none))
      << "the damping must change the velocities";
  expect_same(run_pieces(damped_scene(dir, "ncf/damp"), {7}, -1, dir), ref,
              "ncf/damp vs viscous, run 7");
}

// cut, in the same run or through a restart file: the drag of the setup is the last step's
TEST(SplitRuns, FixDampKeepsTheDragOfTheLastStep)
{
  auto dir = scratch_dir("split_damp");
  const Scene s = damped_scene(dir, "ncf/damp");
  check_cuts(s, dir);
  check_run0(s);
}

// the reason for fix ncf/damp: fix viscous evaluates the setup's drag with the full-step
// velocities, so that the same cut changes the run (the check above can fail)
TEST(SplitRuns, FixViscousDependsOnTheCut)
{
  auto dir = scratch_dir("split_viscous");
  const Scene s = damped_scene(dir, "viscous");
  const Snapshot ref = run_pieces(s, {7}, -1, dir);
  const Snapshot cut = run_pieces(s, {3, 4}, -1, dir);
  EXPECT_GT(max_abs_diff(cut.v, ref.v), 0.0) << "fix viscous, run 3 + run 4 vs run 7";
}

// a restart file from fix viscous (or none) read into fix ncf/damp: no kept drag, the setup
// takes the full-step velocities as fix viscous does
TEST(SplitRuns, FixDampWithoutKeptDragStartsAsViscous)
{
  auto dir = scratch_dir("split_damp_from_viscous");
  const Scene visc = damped_scene(dir, "viscous");
  Scene mixed = visc;
  const Scene damp = damped_scene(dir, "ncf/damp");
  mixed.resume = damp.resume;
  expect_same(run_pieces(mixed, {3, 4}, 0, dir), run_pieces(visc, {3, 4}, 0, dir),
              "viscous + restart + ncf/damp vs viscous + restart + viscous");
}

// fix_modify ID gamma: the coefficient changed in the same process, what the fix kept kept; the
// same as the new coefficient given to the fix defined again after a restart file (straight.lmp
// against the stages from their restart files)
TEST(SplitRuns, FixDampGammaChangedInPlaceIsTheRestartedRun)
{
  auto dir = scratch_dir("split_damp_modify");
  const Scene s = damped_scene(dir, "ncf/damp");
  Snapshot in_place;
  {
    Lammps l;
    s.define(l);
    l.cmd("run 3");
    l.cmd("fix_modify damp gamma $(2*v_g:%.17g)");
    l.cmd("run 4");
    in_place = snapshot(l, s);
  }
  Snapshot restarted;
  {
    auto l = std::make_unique<Lammps>();
    s.define(*l);
    l->cmd("run 3");
    l->cmd("write_restart " + dir + "/g.restart");
    l.reset();
    l = std::make_unique<Lammps>();
    s.resume(*l, dir + "/g.restart");
    l->cmd("fix_modify damp gamma $(2*v_g:%.17g)");
    l->cmd("run 4");
    restarted = snapshot(*l, s);
  }
  expect_same(in_place, restarted, "fix_modify gamma in place vs after a restart");
  const Snapshot same_gamma = run_pieces(s, {3, 4}, -1, dir);
  EXPECT_GT(max_abs_diff(in_place.v, same_gamma.v), 0.0) << "the new gamma must act";
}
