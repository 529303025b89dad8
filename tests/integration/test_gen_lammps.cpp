// Integration tests of the fabric generator: the ncf-gen tool writes the paper's two fabrics
// (and one pattern / angle set that no example uses), LAMMPS with the plugin loads them, and the
// loaded state is checked (counts, per-bond reference lengths, node properties, no penetration).
//
// The contact pair style is not part of this test: "zero penetration at the first step" is
// checked geometrically on the positions LAMMPS holds after "run 0" (closest distance of all
// segment pairs, periodic images included) with the generator's header-only checker.

#include "ncf_lammps_test.h"
#include "ncf_scenes.h"

#include "../../tools/ncf-gen/ncf_gen_geom.h"

#include "lammps.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

using namespace ncftest;

namespace {

// segments of the bonds of a data file from the positions LAMMPS holds (unwrapped, by tag)
std::vector<NCFGEN::Segment> segments(const Data &d, long offset, const std::vector<double> &x,
                                      const std::map<int, double> &diameter, double lx)
{
  std::vector<NCFGEN::Segment> out;
  for (auto &b : d.bond) {
    NCFGEN::Segment s;
    const long i = b.first + offset, j = b.second + offset;
    for (int k = 0; k < 3; k++) {
      s.a[k] = x[3 * (i - 1) + k];
      s.b[k] = x[3 * (j - 1) + k];
    }
    if (s.b[0] < s.a[0] - 0.5 * lx) s.b[0] += lx;    // the closing bond of a yarn loop
    s.chain = 0;
    s.na = (int) i;
    s.nb = (int) j;
    s.radius = 0.5 * diameter.at(d.type.at(b.first));
    out.push_back(s);
  }
  return out;
}

void load_and_check(const std::string &card, const std::string &name)
{
  const std::string dir = scratch_dir("gen_" + name);
  const std::string prefix = generate(card, dir + "/" + name);
  const Data layers = read_data_file(prefix + ".layers.data");
  const Data yarn = read_data_file(prefix + ".yarn.data");
  ASSERT_GT(layers.atoms, 0);
  ASSERT_GT(yarn.atoms, 0);

  auto lp = std::make_unique<Lammps>();
  Lammps &l = *lp;
  l.cmds(GENERATED_SETUP);
  l.cmd("read_data " + prefix + ".layers.data" + GENERATED_READ_FIXES);
  l.cmd("include " + prefix + ".settings.lmp");
  EXPECT_EQ((long) l.value("atoms"), layers.atoms);
  EXPECT_EQ((long) l.value("bonds"), layers.bonds);
  EXPECT_EQ((long) l.value("count(ncf_ends)"), layers.ends);
  const int nlayers = (int) l.value("v_ncf_nlayers");
  const int ytype = (int) l.value("v_ncf_yarn_type");
  EXPECT_EQ(ytype, nlayers + 1);
  // node properties: layer index and end face as written
  for (int face = 1; face <= 4; face++) {
    l.cmd("variable f" + std::to_string(face) + " atom i_ncf_end==" + std::to_string(face));
    l.cmd("group f" + std::to_string(face) + " variable f" + std::to_string(face));
    long expect = 0;
    for (auto &kv : layers.end) expect += kv.second == face;
    EXPECT_EQ((long) l.value("count(f" + std::to_string(face) + ")"), expect) << face;
  }
  for (int t = 1; t <= nlayers; t++) {
    l.cmd("variable ly" + std::to_string(t) + " atom i_ncf_layer==" + std::to_string(t));
    l.cmd("group ly" + std::to_string(t) + " variable ly" + std::to_string(t));
    EXPECT_EQ(l.value("count(ly" + std::to_string(t) + ")"),
              l.value("count(ncf_layer" + std::to_string(t) + ")"));
  }

  // the stitching yarn, appended as a later stage does
  l.cmd("read_data " + prefix + ".yarn.data add append" + GENERATED_READ_FIXES);
  l.cmd("include " + prefix + ".yarn.lmp");
  EXPECT_EQ((long) l.value("atoms"), layers.atoms + yarn.atoms);
  EXPECT_EQ((long) l.value("bonds"), layers.bonds + yarn.bonds);
  EXPECT_EQ((long) l.value("count(ncf_yarn)"), yarn.atoms);
  l.cmd("variable yl atom i_ncf_layer==0");
  l.cmd("group yl variable yl");
  EXPECT_EQ((long) l.value("count(yl)"), yarn.atoms);

  l.cmd("variable dt equal 0.5*v_ncf_dt_crit");
  l.cmd("timestep ${dt}");
  l.cmd("thermo_style custom step ebond");
  l.cmd("run 0");
  // every bond starts at its reference length: no bond energy
  EXPECT_LT(std::fabs(l.value("ebond")), 1e-18);
  auto ref = l.reference_lengths();
  EXPECT_EQ((long) ref.size(), layers.bonds + yarn.bonds);
  for (std::size_t b = 0; b < layers.bond.size(); b += 97) {
    const std::pair<long, long> key = std::minmax(layers.bond[b].first, layers.bond[b].second);
    ASSERT_TRUE(ref.count(key));
    EXPECT_EQ(ref[key], layers.l0[b]);
  }
  for (std::size_t b = 0; b < yarn.bond.size(); b += 7) {
    const long i = yarn.bond[b].first + layers.atoms, j = yarn.bond[b].second + layers.atoms;
    const std::pair<long, long> key(std::min(i, j), std::max(i, j));
    ASSERT_TRUE(ref.count(key));
    EXPECT_EQ(ref[key], yarn.l0[b]);
  }

  // zero penetration at the first step: layers among themselves, the yarn with itself (the yarn
  // wraps the compacted mat and meets the layers only after compaction)
  const auto x = l.positions();
  const double lx = l.value("lx"), ly = l.value("ly");
  std::map<int, double> dia;
  for (int t = 1; t <= ytype; t++) dia[t] = l.value("v_ncf_d_" + std::to_string(t));
  const auto cl = NCFGEN::min_clearance(segments(layers, 0, x, dia, lx), lx, ly);
  EXPECT_GT(cl.pairs, 0);
  EXPECT_GE(cl.gap, 0.0) << name;
  const auto cy = NCFGEN::min_clearance(segments(yarn, layers.atoms, x, dia, lx), lx, ly);
  EXPECT_GE(cy.gap, 0.0) << name;

  // a few steps at half the critical time step: nothing moves, nothing is lost
  l.cmd("fix nve all nve");
  l.cmd("run 20");
  EXPECT_LT(std::fabs(l.value("ebond")), 1e-18);
  EXPECT_EQ((long) l.value("atoms"), layers.atoms + yarn.atoms);
  EXPECT_LT(max_abs_diff(l.positions(), x), 1e-12);

  // the same through LAMMPS's own contact evaluation (pair ncf/contact): the layers alone and the
  // yarn alone have no penetration at the first step (one LAMMPS instance at a time: plugins are
  // registered per process)
  lp.reset();
  for (const std::string part : {"layers", "yarn"}) {
    Lammps p;
    p.cmds(GENERATED_SETUP);
    p.cmd("read_data " + prefix + "." + part + ".data" + GENERATED_READ_FIXES);
    p.cmd("include " + prefix + ".settings.lmp");
    p.cmds("pair_style ncf/contact\npair_coeff * * kn 1e8 diameter ${ncf_d_fibre}\n"
           "pair_coeff ${ncf_yarn_type} ${ncf_yarn_type} diameter ${ncf_d_yarn}\n"
           "compute pc all pair ncf/contact\nthermo_style custom step c_pc[1] c_pc[3]\nrun 0");
    EXPECT_EQ(p.value("c_pc[3]"), 0.0) << name << " " << part;
  }

}

}    // namespace

TEST(GenLammps, PaperFabric090TricotChainLoads)
{
  load_and_check(source_path("examples/gen-ncf090/ncf090.card"), "ncf090");
}

TEST(GenLammps, PaperFabric45TricotLoads)
{
  load_and_check(source_path("examples/gen-ncf45/ncf45.card"), "ncf45");
}

TEST(GenLammps, PatternAndAnglesNoExampleUsesLoad)
{
  // three layers at 30 / -60 / 0 deg, one of them homogeneous (sigma = 0), an atlas lapping,
  // gauge 7, a 2 x 1 RVE, loops on top
  const std::string dir = scratch_dir("gen_odd_card");
  const std::string card = dir + "/odd.card";
  std::ofstream(card)
      << "name odd\nmaterials " << source_path("potentials/ncf.materials")
      << "\nseed 11\nrve 2 1\nchain_diameter 80 um\npacking 0.6\n"
         "fibre_mesh 0.25 mm\nyarn_mesh 0.12 mm\nV_L 0.25\nmass_scaling 10\n"
         "layer 30\n areal_weight 0.1\n material SGL_Sigrafil_CT24-4.8/240\n sigma 2.5\n"
         "layer -60\n areal_weight 120 g/m^2\n material SGL_Sigrafil_CT50-4.4/255\n sigma 1\n"
         "layer 0\n areal_weight 100 g/m^2\n material SGL_Sigrafil_CT50-4.4/255\n sigma 0\n"
         "pattern 1-0/1-2/2-3/2-1//\ngauge 7\nstitch_length 1.9 mm\nyarn PES_5.0tex\n"
         "loops top\n";
  load_and_check(card, "odd");
}
