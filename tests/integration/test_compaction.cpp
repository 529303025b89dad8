// Stage 1 (compaction) end to end: a generated two-layer fabric with sigma = 3 deg
// (examples/needles/mini.card: 0/90 deg, pillar, 771 nodes) is compacted to the layer thickness
// t_L by the shipped stage script examples/manufacturing/in.compact (plates, averaged PBC, chain
// ends moving vertically only, its pass-through guard), with a trajectory dump every 50 steps.
// Every snapshot goes through a side-flip pass-through checker (periodic in x and y): no chain
// may pass through another, axes never come closer than half a diameter, and no node leaves the
// space between the two plates.

#include "ncf_lammps_test.h"
#include "ncf_passthrough.h"
#include "ncf_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

using namespace ncftest;

namespace {

// snapshots of a LAMMPS text dump "id x y z" sorted by id: calls f(step, positions)
template <class F> int read_dump(const std::string &path, long natoms, F f)
{
  std::ifstream in(path);
  std::string line;
  int snapshots = 0;
  while (std::getline(in, line)) {
    if (line.rfind("ITEM: TIMESTEP", 0) != 0) continue;
    long step = 0, n = 0;
    std::getline(in, line);
    step = std::atol(line.c_str());
    std::getline(in, line);    // ITEM: NUMBER OF ATOMS
    std::getline(in, line);
    n = std::atol(line.c_str());
    EXPECT_EQ(n, natoms);
    for (int k = 0; k < 5; k++) std::getline(in, line);    // box bounds (4 lines), ITEM: ATOMS
    std::vector<double> x(3 * (size_t) n);
    for (long i = 0; i < n; i++) {
      std::getline(in, line);
      std::istringstream w(line);
      long id;
      w >> id;
      EXPECT_EQ(id, i + 1);
      w >> x[3 * i] >> x[3 * i + 1] >> x[3 * i + 2];
    }
    f(step, x);
    snapshots++;
  }
  return snapshots;
}

// stage 1 (examples/manufacturing/in.compact) on DIR/mini.*, run from DIR as run.sh runs it, with
// index variables given first as on the command line ("NAME VALUE")
void compact(Lammps &l, const std::string &dir, const std::vector<std::string> &vars)
{
  std::filesystem::current_path(dir);
  l.cmd("variable prefix index mini");
  for (const auto &v : vars)
    l.cmd("variable " + v.substr(0, v.find(' ')) + " index " + v.substr(v.find(' ') + 1));
  l.cmd("variable here index " + source_path("examples/manufacturing"));
  l.cmd("include " + source_path("examples/manufacturing/in.compact"));
}

}    // namespace

TEST(Compaction, Sigma3MatReachesTLWithoutPassThrough)
{
  const std::string dir = scratch_dir("compaction_sigma3");
  const std::string prefix = generate(source_path("examples/needles/mini.card"), dir + "/mini");
  const Data layers = read_data_file(prefix + ".layers.data");
  ASSERT_GT(layers.bonds, 500);

  // the stage script reads PREFIX.* and writes OUT/PREFIX.*, as run.sh calls it from the output
  // folder
  Lammps l;
  compact(l, dir, {"dumpevery 50", "hold 1000"});

  const double d = l.value("v_ncf_d_fibre"), tl = l.value("v_ncf_thickness");
  const double lx = l.value("lx"), ly = l.value("ly");
  // the upper plate reached t_L and stays there
  EXPECT_NEAR(l.value("v_gap"), tl, 1e-9 * tl);
  EXPECT_GT(l.value("f_plates[5]"), 0.0) << "the plates carry a load at t_L";

  // upper plate position at a step of the stroke: from the stack top down at constant speed
  const double ztop0 = l.value("v_ztop0"), speed = l.value("v_speed"), dt = l.value("v_dt");
  auto z_upper = [&](long step) {
    return std::max(tl, ztop0 - speed * dt * (double) step);
  };

  std::vector<std::pair<int, int>> segs;
  for (const auto &b : layers.bond) segs.emplace_back((int) b.first - 1, (int) b.second - 1);
  PassThroughChecker checker(segs, lx, ly, 3e-4);
  double zlow = 1e300, zover = -1e300;
  const int snapshots = read_dump(prefix + ".compact.traj.dump", layers.atoms,
                                  [&](long step, const std::vector<double> &x) {
                                    checker.check(x);
                                    for (size_t i = 2; i < x.size(); i += 3) {
                                      zlow = std::min(zlow, x[i]);
                                      zover = std::max(zover, x[i] - z_upper(step));
                                    }
                                  });
  printf("[ compaction ] sigma 3 deg mat: %d snapshots, %ld crossing pairs compared, closest axes "
         "%.3f d, lowest node %.3f d above the lower plate, highest %.3f d below the upper one\n",
         snapshots, checker.pairs_seen, checker.closest / d, zlow / d, -zover / d);
  EXPECT_GT(snapshots, 100);
  EXPECT_GT(checker.pairs_seen, 10000) << "the check must see many crossings";
  EXPECT_EQ(checker.flips, 0) << "a chain passed through another";
  EXPECT_GT(checker.closest, 0.5 * d) << "axes came closer than half a diameter";
  // no node passes through a plate: every centre stays between the two plates
  EXPECT_GT(zlow, 0.0);
  EXPECT_LT(zover, 0.0);
}

TEST(Compaction, QualityPresetGivesTheRunParametersAndTheCommandLineWins)
{
  // mini.card with 'quality draft': the stage script takes pdyn and tau from the settings the
  // generator wrote (ncf_pdyn, ncf_tau), while dtfrac given before the script (as -var does)
  // wins over the preset's ncf_dtfrac
  const std::string dir = scratch_dir("compaction_quality");
  std::string text;
  {
    std::ifstream in(source_path("examples/needles/mini.card"));
    std::stringstream s;
    s << in.rdbuf();
    text = s.str();
  }
  const std::string materials_line = "materials       ../../potentials/ncf.materials";
  ASSERT_NE(text.find(materials_line), std::string::npos);
  text.replace(text.find(materials_line), materials_line.size(),
               "materials " + source_path("potentials/ncf.materials"));
  {
    std::ofstream out(dir + "/draft.card");
    out << text << "quality draft\n";
  }
  generate(dir + "/draft.card", dir + "/mini");

  Lammps l;
  compact(l, dir, {"hold 0", "dtfrac 0.3"});

  EXPECT_EQ(l.value("v_ncf_dtfrac"), 0.7);    // the draft preset in the settings
  EXPECT_EQ(l.value("v_dtfrac"), 0.3);        // the command line's
  EXPECT_DOUBLE_EQ(l.value("dt"), 0.3 * l.value("v_ncf_dt_crit"));
  EXPECT_EQ(l.value("v_pdyn"), 4e4);    // the draft preset's
  EXPECT_EQ(l.value("v_tau"), 1000.0);
  // (the script substitutes the speed as text, with 15 digits)
  const double v = std::sqrt(4e4 / l.value("v_rho_mat"));
  EXPECT_NEAR(l.value("v_speed"), v, 1e-13 * v);
  // the plate reached t_L with the preset's speed
  EXPECT_NEAR(l.value("v_gap"), l.value("v_ncf_thickness"), 1e-9 * l.value("v_ncf_thickness"));
}

TEST(Compaction, EndsFaceLetTheEndsSlideAlongTheirFaceOnly)
{
  // -var ends face: the end nodes keep their coordinate normal to their RVE face (x for the ends
  // on the x faces, y for those on the y faces) and move in the other two; with the default
  // (vertical, the paper's) they keep both in-plane coordinates
  const std::string dir = scratch_dir("compaction_ends_face");
  const std::string prefix = generate(source_path("examples/needles/mini.card"), dir + "/mini");
  const Data layers = read_data_file(prefix + ".layers.data");
  std::vector<double> x0;
  {
    Lammps g;
    g.cmds(GENERATED_SETUP);
    g.cmd("read_data " + prefix + ".layers.data" + GENERATED_READ_FIXES);
    x0 = g.positions();
  }
  for (const std::string ends : {"face", "vertical"}) {
    Lammps l;
    compact(l, dir, {"ends " + ends, "hold 200"});
    const auto x = l.positions();
    double normal = 0.0, along = 0.0;    // largest moves normal to the face and along it
    int xface = 0, yface = 0;
    for (const auto &[tag, code] : layers.end) {
      if (code == 0) continue;
      const size_t i = 3 * (size_t) (tag - 1);
      const int n = code <= 2 ? 0 : 1;    // XLO, XHI: x; YLO, YHI: y
      (n == 0 ? xface : yface)++;
      normal = std::max(normal, std::fabs(x[i + n] - x0[i + n]));
      along = std::max(along, std::fabs(x[i + 1 - n] - x0[i + 1 - n]));
    }
    printf("[ compaction ] ends %s: %d x-face and %d y-face end nodes, largest move normal to "
           "the face %.3g m, along it %.3g m; pressure at t_L %.4g Pa\n",
           ends.c_str(), xface, yface, normal, along, l.value("f_plates[5]"));
    EXPECT_GT(xface, 0);
    EXPECT_GT(yface, 0);
    EXPECT_EQ(normal, 0.0) << ends;
    if (ends == "face")
      EXPECT_GT(along, 1e-6) << "the ends did not slide along their faces";
    else
      EXPECT_EQ(along, 0.0);
  }
}
