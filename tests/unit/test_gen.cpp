// Unit tests of the fabric generator ncf-gen (tools/ncf-gen, library ncf_gen_core), no LAMMPS.
// Numbers from the paper: Table 1 (fabrics), Table 3 (discretisation), Eq. 1 (t_L).

#include "ncf_gen.h"
#include "ncf_gen_geom.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <unistd.h>

using namespace NCFGEN;
using ::testing::HasSubstr;
using ::testing::Not;

namespace {

const std::string SRC = NCF_SOURCE_DIR;
const std::string MATERIALS = SRC + "/potentials/ncf.materials";

NCF::MaterialLibrary materials()
{
  return NCF::MaterialLibrary::read(MATERIALS);
}

// a card: the shared head, then the given layers and stitching lines
std::string card_text(const std::string &body, const std::string &head_extra = "")
{
  return "# test card\nname t\nmaterials " + MATERIALS +
      "\nseed 3\nchain_diameter 69 um\npacking 0.5\nfibre_mesh 0.2 mm\nyarn_mesh 0.1 mm\n" +
      head_extra + body;
}

const std::string STITCH_TRICOT_CHAIN =
    "pattern tricot-chain\ngauge 5\nstitch_length 2.8 mm\nyarn PES_7.6tex\n";
const std::string STITCH_TRICOT =
    "pattern tricot\ngauge 5\nstitch_length 2.2 mm\nyarn PES_5.0tex\n";

std::string layer(double angle, double aw_gsm, double sigma, const std::string &mat)
{
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "layer %g deg\n  areal_weight %g g/m^2\n  material %s\n  sigma %g deg\n", angle,
                aw_gsm, mat.c_str(), sigma);
  return buf;
}

const std::string CT24 = "SGL_Sigrafil_CT24-4.8/240", CT50 = "SGL_Sigrafil_CT50-4.4/255";

Fabric build(const std::string &text)
{
  return build_fabric(parse_card(text, SRC + "/examples/test.card"), materials());
}

Fabric example(const std::string &which, int rw, int rl)
{
  Card c = read_card(SRC + "/examples/" + which);
  c.r_w = rw;
  c.r_l = rl;
  return build_fabric(c, materials());
}

std::vector<Segment> segments(const Part &p, double lx)
{
  return part_segments(p, lx);
}

// atoms of a data file as written: wrapped x y z and image flags, by id; bonds as (i, j)
struct DataFile {
  double lx = 0, ly = 0;
  std::map<int, std::array<double, 3>> x;
  std::map<int, std::array<int, 3>> image;
  std::map<int, std::pair<int, int>> ends;    // id -> (layer, end)
  std::vector<std::pair<int, int>> bonds;
};

DataFile parse_data(const std::string &text)
{
  DataFile d;
  std::istringstream in(text);
  std::string line, section;
  while (std::getline(in, line)) {
    if (line.find("xlo xhi") != std::string::npos) {
      double a, b;
      std::sscanf(line.c_str(), "%lf %lf", &a, &b);
      d.lx = b - a;
    } else if (line.find("ylo yhi") != std::string::npos) {
      double a, b;
      std::sscanf(line.c_str(), "%lf %lf", &a, &b);
      d.ly = b - a;
    } else if (line.rfind("Atoms", 0) == 0 || line == "Bonds" || line == "NCF_NODE" ||
               line == "Masses" || line == "NCF_CHAIN_L0") {
      section = line.substr(0, 5);
    } else if (!line.empty()) {
      std::istringstream w(line);
      if (section == "Atoms") {
        int id, mol, type;
        std::array<double, 3> p;
        std::array<int, 3> im;
        w >> id >> mol >> type >> p[0] >> p[1] >> p[2] >> im[0] >> im[1] >> im[2];
        d.x[id] = p;
        d.image[id] = im;
      } else if (section == "Bonds") {
        int id, type, i, j;
        w >> id >> type >> i >> j;
        d.bonds.emplace_back(i, j);
      } else if (section == "NCF_N") {
        int id, l, e;
        w >> id >> l >> e;
        d.ends[id] = {l, e};
      }
    }
  }
  return d;
}

}    // namespace

// ------------------------------------------------------------------ lapping notation, RVE

TEST(GenLapping, NamedPatternsAndTheirRepeats)
{
  EXPECT_EQ(parse_lapping("pillar", "c").repeat, 1);
  EXPECT_EQ(parse_lapping("chain", "c").repeat, 1);
  EXPECT_EQ(parse_lapping("tricot", "c").repeat, 2);
  EXPECT_EQ(parse_lapping("tricot-chain", "c").repeat, 4);
  EXPECT_EQ(parse_lapping("tricot-chain", "c").needle, (std::vector<int>{0, 0, 1, 1}));
  EXPECT_EQ(parse_lapping("tricot", "c").needle, (std::vector<int>{0, 1}));
  // notation: open and closed pillar give the same idealised path
  EXPECT_EQ(parse_lapping("0-1/1-0//", "c").repeat, 1);
  EXPECT_EQ(parse_lapping("1-0//", "c").repeat, 1);
  // any other lapping with underlaps over at most one needle, e.g. atlas laps
  EXPECT_EQ(parse_lapping("1-0/1-2/2-3/2-1//", "c").repeat, 4);
  EXPECT_EQ(parse_lapping("0-1/2-1/2-3/1-2//", "c").needle, (std::vector<int>{0, 1, 2, 1}));
  EXPECT_EQ(parse_lapping("1-0/1-2/2-3/3-4/3-2/2-1", "c").needle,
            (std::vector<int>{0, 1, 2, 3, 2, 1}));
  // wide underlaps: cord (two needles), satin (three)
  EXPECT_EQ(parse_lapping("1-0/2-3//", "c").max_underlap, 2);
  EXPECT_EQ(parse_lapping("1-0/3-4//", "c").max_underlap, 3);
  EXPECT_EQ(parse_lapping("tricot", "c").max_underlap, 1);
}

TEST(GenLapping, MalformedNotationNamesTheValue)
{
  for (const char *bad : {"satin", "1-0/", "1-0/1-x//", "10//", "-1/0-1//", "1-3/2-1//", "2-2//"}) {
    try {
      parse_lapping(bad, "card:7");
      ADD_FAILURE() << bad << " accepted";
    } catch (InputError &e) {
      EXPECT_THAT(e.what(), HasSubstr("card:7: key 'pattern'")) << bad;
      EXPECT_THAT(e.what(), HasSubstr(bad));
    }
  }
}

TEST(GenRve, SizesPerPattern)
{
  struct Case {
    const char *pattern;
    int courses;
  } cases[] = {{"pillar", 1},    {"tricot", 2},   {"tricot-chain", 4}, {"1-0/1-2/2-3/2-1//", 4},
               {"1-0/2-3//", 2}, {"1-0/3-4//", 2}};
  for (auto &c : cases)
    for (int rw : {1, 2})
      for (int rl : {1, 3}) {
        const std::string text =
            card_text(layer(0, 150, 1, CT24) + "pattern " + c.pattern +
                          "\ngauge 5\nstitch_length 2.2 mm\nyarn PES_5.0tex\n",
                      "rve " + std::to_string(rw) + " " + std::to_string(rl) + "\n");
        Fabric f = build(text);
        EXPECT_NEAR(f.lx, rl * c.courses * 2.2e-3, 1e-15) << c.pattern;
        EXPECT_NEAR(f.ly, rw * 25.4e-3 / 5, 1e-15) << c.pattern;
        EXPECT_EQ(f.needles.size(), (std::size_t)(rw * rl * c.courses)) << c.pattern;
        EXPECT_EQ(f.yarn.yarns, rw);
      }
  // the paper's elementary RVEs: 0/90 tricot-chain 11.2 x 5.08 mm, +-45 tricot 4.4 x 5.08 mm
  Fabric a = example("gen-ncf090/ncf090.card", 1, 1), b = example("gen-ncf45/ncf45.card", 3, 3);
  EXPECT_NEAR(a.lx, 11.2e-3, 1e-15);
  EXPECT_NEAR(a.ly, 5.08e-3, 1e-15);
  EXPECT_NEAR(b.lx, 3 * 4.4e-3, 1e-15);
  EXPECT_NEAR(b.ly, 3 * 5.08e-3, 1e-15);
}

TEST(GenYarn, WideUnderlapsKeepClearOfEachOther)
{
  // cord (underlaps over 2 needles) and a 3-needle satin: the underlaps of neighbouring yarns
  // cover the same stretch. Knitted: they run hole to hole, a course apart, and pass no other
  // hole; running stitch: with the legs opened to k yarn diameters nothing overlaps
  for (const char *path : {"knit", "running"})
    for (const char *pattern : {"1-0/2-3//", "1-0/3-4//"})
      for (int rw : {1, 3}) {
        const std::string text =
            card_text(layer(45, 150, 2, CT24) + "pattern " + pattern +
                          "\ngauge 5\nstitch_length 2.2 mm\nyarn PES_7.6tex\n",
                      "rve " + std::to_string(rw) + " 1\nyarn_path " + path + "\n");
        Fabric f = build(text);    // throws if any two yarn segments overlap
        EXPECT_GE(f.yarn_gap, 0.0) << path << " " << pattern << " rw " << rw;
        if (std::string(path) == "running")
          EXPECT_GE(f.yarn.leg_offset, 0.5 * parse_lapping(pattern, "c").max_underlap * 87.9e-6);
      }
}

// ------------------------------------------------------------------ fibrous layers

TEST(GenLayers, ChainsPerWidthWithinOnePercentOfArealWeight)
{
  std::vector<Fabric> fabrics = {
      example("gen-ncf090/ncf090.card", 1, 1), example("gen-ncf090/ncf090.card", 2, 2),
      example("gen-ncf45/ncf45.card", 1, 1), example("gen-ncf45/ncf45.card", 3, 3),
      build(card_text(layer(30, 200, 2, CT24) + layer(-60, 120, 0, CT50) + layer(10, 80, 5, CT24) +
                      STITCH_TRICOT))};
  for (const Fabric &f : fabrics)
    for (const LayerInfo &L : f.layers) {
      const double target = L.spec.areal_weight / L.chain.mass_per_length;
      EXPECT_NEAR(L.chains_per_width_target, target, 1e-9 * target);
      EXPECT_NEAR(L.chains / L.width, target, 0.01 * target) << L.spec.angle;
      // and the fibre mass in the RVE is the areal weight times the area (to the rounding of
      // the chain count): every cross-section across the fibres cuts the same chains
      EXPECT_NEAR(L.node_mass * L.nodes, L.spec.areal_weight * f.lx * f.ly,
                  0.01 * L.spec.areal_weight * f.lx * f.ly);
    }
  // hand computation for the 0/90 NCF: 150 g/m^2 / (905 kg/m^3 * pi/4 * (69 um)^2) = 44.33 /mm
  EXPECT_NEAR(fabrics[0].layers[0].chains_per_width_target * 1e-3, 44.33, 0.01);
  EXPECT_EQ(fabrics[0].layers[0].chains, 225);    // 44.33 * 5.08
  EXPECT_EQ(fabrics[0].layers[1].chains, 496);    // 44.33 * 11.2
}

TEST(GenLayers, AngleSampleStdWithinFivePercentOfSigma)
{
  // 675 chains (0 deg, 3 RVE widths) and 993 chains (90 deg, 2 x 2 RVE of the 0/90 NCF)
  Fabric f = build(card_text(layer(0, 150, 3.0, CT24) + STITCH_TRICOT_CHAIN, "rve 3 1\n"));
  ASSERT_GE(f.layers[0].chains, 500);
  EXPECT_NEAR(f.layers[0].angle_std, 3.0, 0.05 * 3.0);
  EXPECT_NEAR(f.layers[0].angle_mean, 0.0, 0.05 * 3.0);
  Fabric g = example("gen-ncf090/ncf090.card", 2, 2);
  ASSERT_GE(g.layers[1].chains, 500);
  EXPECT_NEAR(g.layers[1].angle_std, 4.0, 0.05 * 4.0);
  // the sample is recomputed here from the chains' node positions
  const LayerInfo &L = f.layers[0];
  double sum = 0, sum2 = 0;
  int n = 0;
  std::map<int, std::pair<const Node *, const Node *>> ends;
  for (const Node &nd : f.fibres.nodes) {
    if (nd.end == XLO) ends[nd.chain].first = &nd;
    if (nd.end == XHI) ends[nd.chain].second = &nd;
  }
  for (auto &kv : ends) {
    const double a = std::atan2(kv.second.second->x[1] - kv.second.first->x[1],
                                kv.second.second->x[0] - kv.second.first->x[0]) *
        180.0 / M_PI;
    sum += a;
    sum2 += a * a;
    n++;
  }
  ASSERT_EQ(n, L.chains);
  const double std = std::sqrt((sum2 - sum * sum / n) / (n - 1));
  EXPECT_NEAR(std, L.angle_std, 1e-9);
  // plain iid sampling: unbiased on average over seeds
  double mean_std = 0;
  for (int seed = 1; seed <= 10; seed++) {
    Card c = parse_card(
        card_text(layer(0, 150, 3.0, CT24) + STITCH_TRICOT_CHAIN, "rve 3 1\nsampling random\n"),
        SRC + "/examples/test.card");
    c.seed = seed;
    mean_std += build_fabric(c, materials()).layers[0].angle_std / 10;
  }
  EXPECT_NEAR(mean_std, 3.0, 0.03 * 3.0);
}

TEST(GenLayers, NoPairOfChainsCloserThanTheContactDiameter)
{
  std::vector<Fabric> fabrics = {
      example("gen-ncf090/ncf090.card", 1, 1), example("gen-ncf090/ncf090.card", 2, 2),
      example("gen-ncf45/ncf45.card", 1, 1),
      build(card_text(
          layer(30, 150, 3, CT24) + layer(-75, 150, 0, CT24) + layer(0, 150, 0, CT24) +
              "pattern 1-0/1-2/2-3/2-1//\ngauge 7\nstitch_length 1.9 mm\nyarn PES_5.0tex\n",
          "rve 2 1\n"))};
  for (const Fabric &f : fabrics) {
    const Clearance c = min_clearance(segments(f.fibres, f.lx), f.lx, f.ly);
    EXPECT_GT(c.pairs, 1000);
    EXPECT_GE(c.gap, 0.0) << f.card.name << " segments " << c.s1 << " " << c.s2;
    EXPECT_LT(c.gap, 1e-3 * f.card.chain_diameter);    // the stack is tight somewhere
    // the stitching yarn keeps its diameter from itself and its neighbours
    const Clearance y = min_clearance(segments(f.stitch, f.lx), f.lx, f.ly);
    EXPECT_GE(y.gap, 0.0);
  }
}

// An inclined chain continues through the opposite face as its own periodic image, offset across
// its axis by its travel along the face less whole periods; near the angle where that offset
// vanishes (49.1 deg in a 4.4 x 5.08 mm RVE) the two would overlap at their end nodes, at the
// same height. The generator moves such ends further in: the promise of no overlap holds, with
// the mesh kept at least one diameter (the thick chains of an accuracy study met it at 45 +- 2 deg)
TEST(GenLayers, ChainsKeepClearOfTheirOwnPeriodicImage)
{
  const std::string stitch = "pattern tricot\ngauge 5\nstitch_length 2.2 mm\nyarn PES_5.0tex\n";
  for (double sigma : {0.0, 2.0}) {
    for (const char *d : {"69 um", "138 um"}) {
      const std::string text = "name t\nmaterials " + MATERIALS + "\nseed 1\nchain_diameter " + d +
          "\npacking 0.5\nfibre_mesh 0.2 mm\nyarn_mesh 0.1 mm\n" + layer(49, 154, sigma, CT50) +
          layer(-49, 154, sigma, CT50) + stitch;
      Fabric f = build(text);
      ASSERT_NEAR(f.lx, 4.4e-3, 1e-12);
      ASSERT_NEAR(f.ly, 5.08e-3, 1e-12);
      const Clearance c = min_clearance(segments(f.fibres, f.lx), f.lx, f.ly);
      EXPECT_GE(c.gap, 0.0) << "sigma " << sigma << ", d " << d;
      for (const Bond &b : f.fibres.bonds) EXPECT_GE(b.l0, f.card.chain_diameter * (1.0 - 1e-9));
    }
  }
}

TEST(GenLayers, ClearanceCheckerAgreesWithBruteForce)
{
  Fabric f = build(card_text(layer(20, 40, 6, CT24) + layer(-70, 40, 6, CT24) +
                             "pattern pillar\ngauge 10\nstitch_length 1.0 mm\nyarn PES_5.0tex\n"));
  auto segs = segments(f.fibres, f.lx);
  ASSERT_LT(segs.size(), 4000u);
  double best = 1e300;
  for (std::size_t i = 0; i < segs.size(); i++)
    for (std::size_t j = i + 1; j < segs.size(); j++) {
      const Segment &p = segs[i], &q = segs[j];
      if (p.na == q.na || p.na == q.nb || p.nb == q.na || p.nb == q.nb) continue;
      for (int ix = -2; ix <= 2; ix++)
        for (int iy = -3; iy <= 3; iy++) {
          double q0[3] = {q.a[0] + ix * f.lx, q.a[1] + iy * f.ly, q.a[2]};
          double q1[3] = {q.b[0] + ix * f.lx, q.b[1] + iy * f.ly, q.b[2]};
          best = std::min(best,
                          std::sqrt(segment_distance2<3>(p.a, p.b, q0, q1)) - p.radius - q.radius);
        }
    }
  EXPECT_NEAR(min_clearance(segs, f.lx, f.ly).gap, best, 1e-15);
}

TEST(GenLayers, EveryFaceCrossingContinuesAtTheMatchingPointOfTheOppositeFace)
{
  for (const Fabric &f :
       {example("gen-ncf45/ncf45.card", 1, 1), example("gen-ncf090/ncf090.card", 1, 1)}) {
    DataFile d = parse_data(layers_data(f));
    ASSERT_EQ(d.x.size(), f.fibres.nodes.size());
    const double L[2] = {d.lx, d.ly};
    int crossings = 0;
    std::map<int, std::vector<std::array<double, 3>>> dirs;
    for (auto &b : d.bonds) {
      const auto &p = d.x[b.first], &q = d.x[b.second];
      const auto &ip = d.image[b.first], &iq = d.image[b.second];
      // the bond vector from the unwrapped positions (image flags) and by minimum image agree
      std::array<double, 3> u;
      for (int k = 0; k < 3; k++) u[k] = q[k] - p[k] + (k < 2 ? (iq[k] - ip[k]) * L[k] : 0.0);
      for (int k = 0; k < 2; k++) {
        const double m = q[k] - p[k] - std::round((q[k] - p[k]) / L[k]) * L[k];
        EXPECT_NEAR(u[k], m, 1e-12);
      }
      for (int k = 0; k < 2; k++) {
        if (ip[k] == iq[k]) continue;
        crossings++;
        // the point where the bond leaves through face k (from p) and where it enters through
        // the opposite face (back from q): the same point shifted by one box length
        const double face = iq[k] > ip[k] ? L[k] : 0.0;
        const double t = (face - p[k]) / u[k];
        ASSERT_GE(t, 0.0);
        ASSERT_LE(t, 1.0);
        for (int c = 0; c < 3; c++) {
          const double leave = p[c] + t * u[c];
          const double enter =
              q[c] - (1.0 - t) * u[c] + (c == k ? (iq[k] > ip[k] ? L[k] : -L[k]) : 0.0);
          EXPECT_NEAR(leave, enter, 1e-12);
        }
      }
      // straight continuation: every bond of a chain has the same direction
      const double n = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
      dirs[f.fibres.nodes[b.first - 1].chain].push_back({u[0] / n, u[1] / n, u[2] / n});
    }
    EXPECT_GT(crossings, 0);
    for (auto &kv : dirs)
      for (auto &v : kv.second)
        for (int k = 0; k < 3; k++) EXPECT_NEAR(v[k], kv.second.front()[k], 1e-9);
    // each chain crosses once along its main direction: two end nodes, on the two faces
    std::map<int, std::vector<int>> ends;
    for (auto &kv : d.ends)
      if (kv.second.second) ends[f.fibres.nodes[kv.first - 1].chain].push_back(kv.second.second);
    int chains = 0;
    for (auto &L2 : f.layers) chains += L2.chains;
    ASSERT_EQ((int) ends.size(), chains);
    for (auto &kv : ends) {
      ASSERT_EQ(kv.second.size(), 2u);
      EXPECT_TRUE((kv.second[0] == XLO && kv.second[1] == XHI) ||
                  (kv.second[0] == YLO && kv.second[1] == YHI));
    }
  }
}

TEST(GenLayers, ThicknessFromEquationOneAndHomogeneousMatForSigmaZero)
{
  Fabric a = example("gen-ncf090/ncf090.card", 1, 1), b = example("gen-ncf45/ncf45.card", 1, 1);
  for (auto *f : {&a, &b})
    for (auto &L : f->layers)
      EXPECT_NEAR(L.t_l, L.spec.areal_weight / (0.20 * L.filament_density), 1e-15);
  EXPECT_NEAR(a.layers[0].t_l * 1e3, 0.41, 0.005);    // Table 3
  EXPECT_NEAR(b.layers[0].t_l * 1e3, 0.43, 0.005);
  // sigma = 0: chains straight at the nominal angle, the mat placed directly with thickness t_L
  Fabric h = build(card_text(layer(0, 150, 0, CT24) + layer(90, 150, 0, CT24) +
                                 layer(35, 150, 0, CT50) + STITCH_TRICOT_CHAIN,
                             "V_L 0.25\n"));
  double base = 0.0;
  for (const LayerInfo &L : h.layers) {
    EXPECT_TRUE(L.homogeneous);
    EXPECT_NEAR(L.t_l, L.spec.areal_weight / (0.25 * L.filament_density), 1e-15);
    EXPECT_NEAR(L.stack, L.t_l, 2e-6 * 69e-6);    // centres 1e-6 d_c/2 inside the mat
    EXPECT_NEAR(L.z_min, base + 0.5 * 69e-6, 1e-9);
    EXPECT_NEAR(L.angle_std, 0.0, 1e-12);
    base += L.t_l;
  }
  EXPECT_NEAR(h.stack_top, h.thickness, 1e-12);
  EXPECT_GE(min_clearance(segments(h.fibres, h.lx), h.lx, h.ly).gap, 0.0);
  // at 0 and 90 deg each chain's end continues as its own start through the opposite face
  for (std::size_t i = 0; i + 1 < h.fibres.nodes.size(); i++) {
    const Node &n = h.fibres.nodes[i];
    if (n.layer > 2 || n.end != XLO && n.end != YLO) continue;
    std::size_t j = i;
    while (h.fibres.nodes[j].end != XHI && h.fibres.nodes[j].end != YHI) j++;
    const Node &e = h.fibres.nodes[j];
    const double h0 =
        std::hypot(h.fibres.nodes[i + 1].x[0] - n.x[0], h.fibres.nodes[i + 1].x[1] - n.x[1]);
    const int k = n.end == XLO ? 0 : 1;
    EXPECT_NEAR(n.x[k] + (k ? h.ly : h.lx) - e.x[k], h0, 1e-12);
    EXPECT_NEAR(n.x[1 - k], e.x[1 - k], 1e-15);
    EXPECT_EQ(n.x[2], e.x[2]);
  }
}

// ------------------------------------------------------------------ stitching yarn

TEST(GenYarn, DiameterFromLinearDensityAndIdealisedPath)
{
  Fabric a = example("gen-ncf090/ncf090.card", 2, 2), b = example("gen-ncf45/ncf45.card", 1, 1);
  EXPECT_NEAR(a.yarn.chain.diameter * 1e6, 88.0, 0.5);
  EXPECT_NEAR(b.yarn.chain.diameter * 1e6, 71.0, 0.5);
  for (Fabric *f : {&a, &b}) {
    const YarnInfo &y = f->yarn;
    // each yarn is a closed loop once along the RVE: its bonds add up to (Lx, 0, 0)
    std::map<int, std::array<double, 3>> sum;
    std::map<int, int> nb;
    for (const Bond &bd : f->stitch.bonds) {
      const Node &p = f->stitch.nodes[bd.i], &q = f->stitch.nodes[bd.j];
      double dx = q.x[0] - p.x[0];
      if (dx < -0.5 * f->lx) dx += f->lx;
      sum[p.chain][0] += dx;
      sum[p.chain][1] += q.x[1] - p.x[1];
      sum[p.chain][2] += q.x[2] - p.x[2];
      nb[p.chain]++;
      EXPECT_LE(bd.l0, f->card.yarn_mesh * (1 + 1e-12));
    }
    ASSERT_EQ((int) sum.size(), y.yarns);
    for (auto &kv : sum) {
      EXPECT_NEAR(kv.second[0], f->lx, 1e-12);
      EXPECT_NEAR(kv.second[1], 0.0, 1e-12);
      EXPECT_NEAR(kv.second[2], 0.0, 1e-12);
    }
    // knit: nodes on the underlap face, on the loops between their two levels beyond the loop
    // face, or on legs; at each hole one leg down (x_c - e), one up (x_c + e), both at its y
    std::map<std::pair<long, long>, int> legs;
    const double zlo = std::min(y.z_loop, y.z_loop_out), zhi = std::max(y.z_loop, y.z_loop_out);
    for (const Node &n : f->stitch.nodes) {
      if (std::fabs(n.x[2] - y.z_under) < 1e-12) continue;    // underlap face
      const double xw = n.x[0] - f->lx * std::floor(n.x[0] / f->lx);
      const double yw = n.x[1] - f->ly * std::floor(n.x[1] / f->ly);
      if (n.x[2] >= zlo - 1e-12 && n.x[2] <= zhi + 1e-12) continue;    // on a loop
      const double hx = std::round(xw / f->course - 0.5),
                   hy = std::round(yw / f->needle_spacing - 0.5);
      const double off = xw - (hx + 0.5) * f->course;
      EXPECT_NEAR(std::fabs(off), y.leg_offset, 1e-12);
      EXPECT_NEAR(yw, (hy + 0.5) * f->needle_spacing, 1e-12);
      legs[{(long) hx * 2 + (off > 0), (long) hy}]++;
    }
    // every stitching point has two legs, the same number of inner nodes on each
    EXPECT_EQ(legs.size(), 2 * f->needles.size());
    for (auto &kv : legs) EXPECT_EQ(kv.second, legs.begin()->second);
    EXPECT_GE(std::fabs(y.z_under - y.z_loop), f->thickness + y.chain.diameter);
    EXPECT_GT(std::fabs(y.z_loop_out - y.z_under), std::fabs(y.z_loop - y.z_under));
    // the lumped masses add up to the yarn mass (the bonds' lengths times the mass per length)
    double length = 0.0;
    for (const Bond &bd : f->stitch.bonds) length += bd.l0;
    EXPECT_NEAR(y.node_mass * y.nodes, y.chain.mass_per_length * length,
                1e-12 * y.node_mass * y.nodes);
    EXPECT_NEAR(y.length_per_yarn * y.yarns, length, 1e-12 * length);
  }
}

TEST(GenYarn, PerYarnAndPerAreaValuesDoNotDependOnTheRveSize)
{
  Fabric a = example("gen-ncf090/ncf090.card", 1, 1), b = example("gen-ncf090/ncf090.card", 2, 3);
  EXPECT_EQ(b.yarn.yarns, 2);
  EXPECT_NEAR(b.yarn.length_per_yarn, 3 * a.yarn.length_per_yarn, 1e-12);
  EXPECT_NEAR(b.yarn.areal_weight, a.yarn.areal_weight, 1e-12 * a.yarn.areal_weight);
  EXPECT_NEAR(b.yarn.node_mass, a.yarn.node_mass, 1e-12 * a.yarn.node_mass);
  EXPECT_EQ(b.yarn.nodes, 6 * a.yarn.nodes);
  // 7.6 tex along the path in an 11.2 x 5.08 mm RVE
  EXPECT_NEAR(a.yarn.areal_weight, 7.6e-6 * a.yarn.length_per_yarn / (11.2e-3 * 5.08e-3), 1e-12);
  // the knitted path course by course (tricot-chain: needles 0, 0, 1, 1): two legs from the
  // underlap face to the loops' outer level, two cross pieces G, the outgoing side to the head
  // (course + h + e along x, rising dz), the head 2G, the return side (course + h - e), the
  // underlap (course - 2e along x, k needles along y)
  const YarnInfo &y = a.yarn;
  const double c = a.course, e = y.leg_offset, G = y.loop_half_width, h = y.head_offset;
  const double dz = std::fabs(y.z_loop - y.z_loop_out), leg = std::fabs(y.z_under - y.z_loop_out);
  double path = 0.0;
  const int needle[4] = {0, 0, 1, 1};
  for (int k = 0; k < 4; k++) {
    const int dk = needle[(k + 1) % 4] - needle[k];
    path += 2 * leg + 4 * G + std::hypot(c + h + e, dz) + std::hypot(c + h - e, dz) +
        std::hypot(c - 2 * e, dk * a.needle_spacing);
  }
  EXPECT_NEAR(y.length_per_yarn, path, 1e-12);
  // which makes the yarn's areal weight that of a real NCF's stitching (5-10 g/m^2 at gauge 5)
  std::printf("[measured] ncf090 knitted yarn: %.4f mm per RVE, %.3f g/m^2\n", path * 1e3,
              y.areal_weight * 1e3);
}

TEST(GenYarn, MassScalingMultipliesEveryMass)
{
  Fabric a = build(card_text(layer(0, 150, 1, CT24) + STITCH_TRICOT));
  Fabric b = build(card_text(layer(0, 150, 1, CT24) + STITCH_TRICOT, "mass_scaling 100\n"));
  EXPECT_NEAR(b.layers[0].node_mass, 100 * a.layers[0].node_mass, 1e-12 * b.layers[0].node_mass);
  EXPECT_NEAR(b.yarn.node_mass, 100 * a.yarn.node_mass, 1e-12 * b.yarn.node_mass);
  EXPECT_NEAR(b.layers[0].dt_crit, 10 * a.layers[0].dt_crit, 1e-12);
  // critical time step L0 sqrt(rho_c / E_c) of the shortest bond
  EXPECT_NEAR(a.layers[0].dt_crit, a.layers[0].min_l0 * std::sqrt(905.0 / 120e9), 1e-20);
}

TEST(GenYarn, PackingSetsTheContactDiameterNotTheAxialStiffnessOrMass)
{
  // the paper's hexagonal packing by default; a looser yarn is wider (d ~ 1/sqrt(packing)) but
  // carries the same filaments: E_c A and the mass per length do not change
  Fabric a = build(card_text(layer(0, 150, 1, CT24) + STITCH_TRICOT));
  Fabric b = build(card_text(layer(0, 150, 1, CT24) + STITCH_TRICOT, "yarn_packing 0.5\n"));
  EXPECT_NEAR(a.yarn.chain.packing, NCF::HEXAGONAL_PACKING, 1e-15);
  EXPECT_NEAR(b.yarn.chain.packing, 0.5, 1e-15);
  EXPECT_NEAR(b.yarn.chain.diameter / a.yarn.chain.diameter,
              std::sqrt(NCF::HEXAGONAL_PACKING / 0.5), 1e-12);
  EXPECT_NEAR(b.yarn.chain.diameter * 1e6, 96.0, 0.5);    // 5.0 tex of PES at packing 0.5
  EXPECT_NEAR(b.yarn.chain.ea, a.yarn.chain.ea, 1e-12 * a.yarn.chain.ea);
  EXPECT_NEAR(b.yarn.chain.mass_per_length, a.yarn.chain.mass_per_length,
              1e-12 * a.yarn.chain.mass_per_length);
  // the legs open with the diameter, and the summary names the packing
  EXPECT_NEAR(b.yarn.leg_offset / a.yarn.leg_offset, b.yarn.chain.diameter / a.yarn.chain.diameter,
              1e-12);
  const std::string text = summary_text(b);
  const auto at = text.find("chain diameter, packing");
  ASSERT_NE(at, std::string::npos) << text;
  const std::string line = text.substr(at, text.find('\n', at) - at);
  EXPECT_NE(line.find("um, 0.5000"), std::string::npos) << line;
}

// ------------------------------------------------------------------ outputs

TEST(GenOutputs, SameSeedSameBytesOtherSeedOtherBytes)
{
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("ncf_gen_seed_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string card = SRC + "/examples/gen-ncf45/ncf45.card";
  std::string err;
  ASSERT_TRUE(generate(card, (dir / "a").string(), err)) << err;
  ASSERT_TRUE(generate(card, (dir / "b").string(), err)) << err;
  auto slurp = [](const fs::path &p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  for (const char *suffix : {".layers.data", ".yarn.data", ".needles", ".summary", ".yarn.lmp"}) {
    const std::string a = slurp(dir / (std::string("a") + suffix)),
                      b = slurp(dir / (std::string("b") + suffix));
    EXPECT_FALSE(a.empty()) << suffix;
    EXPECT_EQ(a, b) << suffix;
  }
  Card c = read_card(card);
  c.seed = 2;
  EXPECT_NE(layers_data(build_fabric(c, materials())), slurp(dir / "a.layers.data"));
  fs::remove_all(dir);
}

TEST(GenOutputs, ManufacturingParametersReachTheSettings)
{
  // the card's needle diameter and pretension become variables of the stage scripts
  auto value_of = [](const std::string &text, const std::string &name) {
    const std::string key = "variable " + name + " equal ";
    const auto pos = text.find(key);
    if (pos == std::string::npos) return -1.0;
    return std::stod(text.substr(pos + key.size()));
  };
  const std::string body = layer(0, 150, 1, CT24) + STITCH_TRICOT;
  const std::string s0 =
      settings_text(build_fabric(parse_card(card_text(body), "t.card"), materials()), "t");
  EXPECT_NEAR(value_of(s0, "ncf_needle_d"), 0.6e-3, 1e-15);
  EXPECT_NEAR(value_of(s0, "ncf_pretension"), 0.16, 1e-15);
  const std::string s1 = settings_text(
      build_fabric(
          parse_card(card_text(body + "needle_diameter 0.45 mm\npretension 0.17\n"), "t.card"),
          materials()),
      "t");
  EXPECT_NEAR(value_of(s1, "ncf_needle_d"), 0.45e-3, 1e-15);
  EXPECT_NEAR(value_of(s1, "ncf_pretension"), 0.17, 1e-15);
}

TEST(GenOutputs, MalformedCardsNameTheLineAndWriteNothing)
{
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("ncf_gen_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string good = card_text(layer(0, 150, 1, CT24) + STITCH_TRICOT);
  // the good card: line 9 is "layer 0 deg", 10 areal_weight, 11 material, 12 sigma, 13 pattern,
  // 14 gauge, 15 stitch_length, 16 yarn
  struct Case {
    std::string from, to;
    int line;
    std::vector<std::string> words;
  } cases[] = {
      {"packing 0.5\n", "packing 0.5\nwarp_speed 3\n", 7, {"unknown key 'warp_speed'"}},
      {"seed 3\n", "seed\n", 4, {"key 'seed' has no value"}},
      {"chain_diameter 69 um\n",
       "chain_diameter -69 um\n",
       5,
       {"key 'chain_diameter'", "'-69'", "> 0"}},
      {"sigma 1 deg\n", "sigma -1 deg\n", 12, {"key 'sigma'", "'-1'", ">= 0"}},
      {"material SGL_Sigrafil_CT24-4.8/240\n",
       "material Unobtainium\n",
       11,
       {"key 'material'", "'Unobtainium'", "unknown material"}},
      {"pattern tricot\n", "pattern 1-0/1-x//\n", 13, {"key 'pattern'", "'1-0/1-x//'"}},
      {"pattern tricot\n", "pattern satin\n", 13, {"key 'pattern'", "'satin'"}},
      {"yarn PES_5.0tex\n", "yarn PES_99tex\n", 16, {"key 'yarn'", "'PES_99tex'"}},
      {"areal_weight 150 g/m^2\n", "areal_weight 150 furlongs\n", 10, {"unknown unit 'furlongs'"}},
      {"gauge 5\n", "gauge 5\ngauge 7\n", 15, {"given twice"}},
      {"fibre_mesh 0.2 mm\n",
       "fibre_mesh 0.05 mm\n",
       7,
       {"key 'fibre_mesh'", "shorter than the chain diameter"}},
      {"yarn_mesh 0.1 mm\n",
       "yarn_mesh 0.05 mm\n",
       8,
       {"key 'yarn_mesh'", "shorter than the yarn diameter"}},
      {"yarn_mesh 0.1 mm\n", "yarn_mesh 0.1 mm\nsigma 2\n", 9, {"outside a layer block"}},
      {"yarn PES_5.0tex\n",
       "yarn PES_5.0tex\npretension 1.2\n",
       17,
       {"key 'pretension'", "'1.2'", "in [0, 1)"}},
      {"stitch_length 2.2 mm\n",
       "stitch_length 1e-9 mm\n",
       15,
       {"key 'stitch_length'", "shorter than two fibre elements"}},
      {"seed 3\n", "seed 3\nrve 1000 1000\n", 5, {"fibre nodes", "more than the limit", "'rve'"}},
      {"yarn PES_5.0tex\n",
       "yarn PES_5.0tex\nneedle_diameter 0 mm\n",
       17,
       {"key 'needle_diameter'", "'0'", "> 0"}},
  };
  for (auto &c : cases) {
    std::string text = good;
    const auto pos = text.find(c.from);
    ASSERT_NE(pos, std::string::npos) << c.from;
    text.replace(pos, c.from.size(), c.to);
    const fs::path card = dir / "bad.card";
    {
      std::ofstream o(card);
      o << text;
    }
    std::string err;
    EXPECT_FALSE(generate(card.string(), (dir / "out").string(), err)) << c.to;
    EXPECT_THAT(err, HasSubstr(card.string() + ":" + std::to_string(c.line) + ":")) << err;
    for (auto &w : c.words) EXPECT_THAT(err, HasSubstr(w)) << err;
    int files = 0;
    for (auto &e : fs::directory_iterator(dir)) files += e.path().filename() != "bad.card";
    EXPECT_EQ(files, 0) << c.to;
  }
  fs::remove_all(dir);
}

TEST(GenOutputs, SigmaThatTurnsAChainAcrossItsAxisIsAnError)
{
  const std::string text = card_text(layer(40, 150, 19, CT24) + STITCH_TRICOT, "rve 2 2\n");
  try {
    build(text);
    ADD_FAILURE() << "accepted";
  } catch (InputError &e) {
    EXPECT_THAT(e.what(), HasSubstr("test.card:10: key 'sigma'"));
    EXPECT_THAT(e.what(), HasSubstr("reduce sigma"));
  }
}

// ------------------------------------------------------------------ quality presets

namespace {

// the value of "variable NAME STYLE VALUE" in a settings file, as text ("" if absent)
std::string settings_value(const std::string &text, const std::string &name)
{
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream w(line);
    std::string cmd, n, style, value;
    w >> cmd >> n >> style >> value;
    if (cmd == "variable" && n == name) return value;
  }
  return "";
}

// a card without chain_diameter, fibre_mesh and yarn_mesh (they come from the preset), with
// the given extra head lines
std::string preset_card(const std::string &extra)
{
  return "name t\nmaterials " + MATERIALS + "\nseed 3\nrve 1 1\n" + extra + layer(0, 150, 1, CT24) +
      layer(90, 150, 1, CT24) + STITCH_TRICOT_CHAIN;
}

}    // namespace

TEST(GenQuality, EachPresetSetsItsResolutionAndRunParameters)
{
  // the values doc/ncf-gen.md documents ("Quality presets"); standard = the paper's Table 3
  struct Expect {
    std::string name;
    double dc, fmesh, ymesh, dtfrac, pdyn, tau;
  } expected[] = {
      {"draft", 98e-6, 0.4e-3, 0.2e-3, 0.7, 4e4, 1000},
      {"standard", 69e-6, 0.2e-3, 0.1e-3, 0.5, 1e4, 2000},
      {"fine", 49e-6, 0.1e-3, 0.05e-3, 0.4, 5e3, 2000},
  };
  ASSERT_EQ(quality_presets().size(), 3u);
  for (const auto &e : expected) {
    SCOPED_TRACE(e.name);
    const Card c = parse_card(preset_card("quality " + e.name + "\n"), "t.card");
    EXPECT_EQ(c.quality, e.name);
    EXPECT_DOUBLE_EQ(c.chain_diameter, e.dc);
    EXPECT_DOUBLE_EQ(c.fibre_mesh, e.fmesh);
    EXPECT_DOUBLE_EQ(c.yarn_mesh, e.ymesh);
    EXPECT_DOUBLE_EQ(c.dtfrac, e.dtfrac);
    EXPECT_DOUBLE_EQ(c.pdyn, e.pdyn);
    EXPECT_DOUBLE_EQ(c.tau, e.tau);
    for (const char *k : {"chain_diameter", "fibre_mesh", "yarn_mesh"})
      EXPECT_FALSE(c.from_card(k));

    // the model follows: chain diameter, element lengths, critical step
    const Fabric f = build_fabric(c, materials());
    EXPECT_DOUBLE_EQ(f.layers[0].chain.diameter, e.dc);
    EXPECT_LE(f.layers[0].max_l0, e.fmesh * 1.5);
    EXPECT_GE(f.layers[0].min_l0, e.dc * (1 - 1e-12));
    const double dy = f.yarn.chain.diameter;    // 87.9 um: fine's 0.05 mm is raised to it
    EXPECT_DOUBLE_EQ(f.card.yarn_mesh, std::max(e.ymesh, dy));
    EXPECT_EQ(f.yarn_mesh_preset_raised > 0.0, e.ymesh < dy);
    // (elements of at most yarn_mesh but never shorter than d_y: below 2 d_y when raised)
    for (const Bond &b : f.stitch.bonds)
      EXPECT_LE(b.l0, std::max(f.card.yarn_mesh, 2 * dy) * (1 + 1e-12));

    // the run parameters reach the stage scripts through the settings, read back exactly
    const std::string s = settings_text(f, "t");
    EXPECT_EQ(settings_value(s, "ncf_quality"), e.name);
    EXPECT_EQ(std::stod(settings_value(s, "ncf_dtfrac")), e.dtfrac);
    EXPECT_EQ(std::stod(settings_value(s, "ncf_pdyn")), e.pdyn);
    EXPECT_EQ(std::stod(settings_value(s, "ncf_tau")), e.tau);
    EXPECT_THAT(s, HasSubstr("variable ncf_dtfrac index "));    // -var dtfrac still wins
    const std::string sum = summary_text(f);
    EXPECT_THAT(sum, HasSubstr("quality " + e.name + "\n"));
    EXPECT_THAT(sum, ::testing::ContainsRegex("chain_diameter +[0-9.]+ um  \\(quality " + e.name));
    EXPECT_THAT(sum, HasSubstr(e.ymesh < dy ? "raised to the yarn diameter" : "yarn_mesh"));
  }
  // the three presets are three different models: coarser to finer
  const Fabric d = build_fabric(parse_card(preset_card("quality draft\n"), "t.card"), materials());
  const Fabric s = build_fabric(parse_card(preset_card(""), "t.card"), materials());
  const Fabric f = build_fabric(parse_card(preset_card("quality fine\n"), "t.card"), materials());
  EXPECT_LT(d.fibres.nodes.size() * 3, s.fibres.nodes.size());
  EXPECT_LT(s.fibres.nodes.size() * 3, f.fibres.nodes.size());
}

TEST(GenQuality, KeysOnTheCardWinOverThePreset)
{
  const Card c =
      parse_card(preset_card("chain_diameter 69 um\nquality fine\nyarn_mesh 0.2 mm\n"), "t.card");
  EXPECT_EQ(c.quality, "fine");
  EXPECT_DOUBLE_EQ(c.chain_diameter, 69e-6);    // the card's, before or after the quality line
  EXPECT_DOUBLE_EQ(c.yarn_mesh, 0.2e-3);
  EXPECT_DOUBLE_EQ(c.fibre_mesh, 0.1e-3);    // the preset's
  EXPECT_DOUBLE_EQ(c.dtfrac, 0.4);
  EXPECT_TRUE(c.from_card("chain_diameter"));
  EXPECT_TRUE(c.from_card("yarn_mesh"));
  EXPECT_FALSE(c.from_card("fibre_mesh"));
  const Fabric f = build_fabric(c, materials());
  EXPECT_DOUBLE_EQ(f.layers[0].chain.diameter, 69e-6);
  EXPECT_EQ(f.yarn_mesh_preset_raised, 0.0);
  // the summary says where each value came from
  const std::string sum = summary_text(f);
  EXPECT_THAT(sum, ::testing::ContainsRegex("chain_diameter +69 um  \\(card\\)"));
  EXPECT_THAT(sum, ::testing::ContainsRegex("fibre_mesh +0.1 mm  \\(quality fine\\)"));
  EXPECT_THAT(sum, ::testing::ContainsRegex("yarn_mesh +0.2 mm  \\(card\\)"));
  EXPECT_THAT(sum, ::testing::ContainsRegex("dtfrac .* 0.4  \\(quality fine"));

  // a preset mesh shorter than a thicker chain given on the card is raised to its diameter (the
  // finest allowed) and the summary says so; a mesh given on the card is never changed
  const Fabric g = build_fabric(
      parse_card(preset_card("quality fine\nchain_diameter 138 um\n"), "t.card"), materials());
  EXPECT_DOUBLE_EQ(g.card.fibre_mesh, 138e-6);
  EXPECT_DOUBLE_EQ(g.fibre_mesh_preset_raised, 0.1e-3);
  EXPECT_THAT(summary_text(g), HasSubstr("the preset's 0.1 mm raised to the chain diameter"));
  EXPECT_THROW(build_fabric(parse_card(preset_card("quality fine\nchain_diameter 138 um\n"
                                                   "fibre_mesh 0.1 mm\n"),
                                       "t.card"),
                            materials()),
               InputError);
}

TEST(GenQuality, StandardAndNoQualityKeyGiveTheSameFiles)
{
  // every output file byte for byte, for the paper's +-45 card as it is, with 'quality standard'
  // added, and (which must differ) with 'quality draft'; written from the same card path, since
  // the path is part of the files
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("ncf_gen_quality_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto slurp = [](const fs::path &p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  std::string text = slurp(SRC + "/examples/gen-ncf45/ncf45.card");
  ASSERT_THAT(text, HasSubstr("name            ncf45"));
  ASSERT_EQ(text.find("quality"), std::string::npos);
  const std::string materials_line = "materials       ../../potentials/ncf.materials";
  ASSERT_NE(text.find(materials_line), std::string::npos);
  text.replace(text.find(materials_line), materials_line.size(), "materials " + MATERIALS);
  // the card without its resolution keys: then they come from the preset as well
  std::string bare = text;
  for (const char *key : {"chain_diameter", "fibre_mesh", "yarn_mesh"}) {
    const auto pos = bare.find(std::string("\n") + key);
    ASSERT_NE(pos, std::string::npos) << key;
    bare.erase(pos, bare.find('\n', pos + 1) - pos);
  }
  const fs::path card = dir / "q.card";
  auto run = [&](const std::string &card_text, const std::string &prefix) {
    {
      std::ofstream o(card);
      o << card_text;
    }
    // (the prefix is part of the settings: the same name in a folder of its own)
    fs::create_directories(dir / prefix);
    std::string err;
    EXPECT_TRUE(generate(card.string(), (dir / prefix / "q").string(), err)) << err;
  };
  run(text, "none");
  run(text + "quality standard\n", "standard");
  run("quality standard\n" + text, "first");
  run(bare, "bare");
  run(bare + "quality standard\n", "bare_standard");
  run(bare + "quality draft\n", "bare_draft");
  for (const char *suffix :
       {".layers.data", ".yarn.data", ".needles", ".settings.lmp", ".yarn.lmp", ".summary"}) {
    SCOPED_TRACE(suffix);
    const std::string none = slurp(dir / "none" / (std::string("q") + suffix));
    ASSERT_FALSE(none.empty());
    EXPECT_EQ(none, slurp(dir / "standard" / (std::string("q") + suffix)));
    EXPECT_EQ(none, slurp(dir / "first" / (std::string("q") + suffix)));
    const std::string bare_none = slurp(dir / "bare" / (std::string("q") + suffix));
    EXPECT_EQ(bare_none, slurp(dir / "bare_standard" / (std::string("q") + suffix)));
    // the model itself does not depend on where the standard values came from
    if (std::string(suffix) != ".summary") EXPECT_EQ(none, bare_none);
    if (std::string(suffix) != ".needles" && std::string(suffix) != ".yarn.lmp")
      EXPECT_NE(bare_none, slurp(dir / "bare_draft" / (std::string("q") + suffix)));
  }
  fs::remove_all(dir);
}

// ------------------------------------------------------------------ warp knit

// The knitted loops interlock along the wale: the two legs of the next course at the same hole
// column pass through each loop, inside its outline in the plane and across its levels in z,
// and the loop's head lies beyond them; the underlaps run from a course's hole to the next
// course's hole on the pattern's needle (diagonal in tricot). Nothing overlaps (the generator
// throws otherwise), for every named lapping.
TEST(GenKnit, LoopsInterlockAlongTheWaleAndUnderlapsGoHoleToHole)
{
  for (const char *pattern :
       {"pillar", "chain", "tricot", "tricot-chain", "1-0/2-3//", "1-0/3-4//"}) {
    const std::string text =
        card_text(layer(0, 150, 1, CT24) + layer(90, 150, 1, CT24) + "pattern " +
                  std::string(pattern) + "\ngauge 5\nstitch_length 2.2 mm\nyarn PES_5.0tex\n");
    Fabric f = build(text);
    const YarnInfo &y = f.yarn;
    EXPECT_GE(f.yarn_gap, 0.0) << pattern;
    ASSERT_GT(y.loop_half_width, 0.0);
    const Lapping lap = parse_lapping(pattern, "c");
    // the nodes of each yarn in path order, unwrapped (a closed loop once along x)
    const int n = (int) f.stitch.nodes.size();
    std::vector<std::array<double, 3>> p(n);
    for (int i = 0; i < n; i++)
      for (int d = 0; d < 3; d++) p[i][d] = f.stitch.nodes[i].x[d];
    // loops: maximal runs of nodes beyond the loop face
    const double out = y.z_loop_out < y.z_loop ? -1.0 : 1.0;
    int loops = 0;
    for (int i = 0; i < n; i++) {
      const bool beyond = out * (p[i][2] - y.z_loop) >= -1e-12;
      const bool prev = out * (p[(i + n - 1) % n][2] - y.z_loop) >= -1e-12;
      if (!beyond || prev) continue;
      int j = i;
      while (out * (p[(j + 1) % n][2] - y.z_loop) >= -1e-12) j = (j + 1) % n;
      loops++;
      // the hole of this loop: its first node (bottom of the down-leg) and last (the up-leg)
      const auto &a = p[i], &b = p[j];
      EXPECT_NEAR(a[1], b[1], 1e-12);
      const double xh = 0.5 * (a[0] + b[0]), yh = a[1];
      EXPECT_NEAR(b[0] - a[0], 2 * y.leg_offset, 1e-12) << pattern;
      // head: the loop's farthest x, beyond the next course's up-leg by more than d_y
      double xmax = -1e300, zmax_head = 0.0;
      for (int k = i; k != (j + 1) % n; k = (k + 1) % n)
        if (p[k][0] > xmax) xmax = p[k][0], zmax_head = p[k][2];
      EXPECT_NEAR(xmax - xh, f.course + y.head_offset, 1e-12) << pattern;
      EXPECT_GT(xmax - (xh + f.course + y.leg_offset), y.chain.diameter) << pattern;
      // the next course's legs at this hole column (x_h + course, y_h +- 0) pass through the
      // loop: inside its sides (|dy| < G) and from the underlap face to beyond the loop's level
      // there (the loop at x_h + course lies between z_loop and z_loop_out)
      EXPECT_LT(y.chain.diameter, y.loop_half_width) << pattern;
      EXPECT_GT(out * (y.z_loop_out - y.z_loop), y.chain.diameter) << pattern;
      EXPECT_NEAR(zmax_head, y.z_loop, 1e-12) << pattern;
      (void) yh;
    }
    EXPECT_EQ(loops, (int) f.needles.size()) << pattern;
    // underlaps: from (x_c + e, y_c) on the underlap face to (x_{c+1} - e, y_{c+1})
    const int courses = f.courses;
    for (int c = 0; c < courses; c++) {
      const int k = lap.needle[(c + 1) % lap.repeat] - lap.needle[c % lap.repeat];
      bool found = false;
      for (int i = 0; i < n && !found; i++) {
        const auto &a = p[i];
        if (std::fabs(a[2] - y.z_under) > 1e-12) continue;
        const double xa = a[0] - f.lx * std::floor(a[0] / f.lx);
        if (std::fabs(xa - ((c + 0.5) * f.course + y.leg_offset)) > 1e-12) continue;
        // walk along the underlap to its far end on the underlap face
        int j = i;
        while (std::fabs(p[(j + 1) % n][2] - y.z_under) < 1e-12 && j - i < n) j++;
        auto b = p[j % n];
        double dx = b[0] - a[0];
        if (dx < 0) dx += f.lx;
        EXPECT_NEAR(dx, f.course - 2 * y.leg_offset, 1e-9) << pattern << " course " << c;
        double dyy = b[1] - a[1];
        dyy -= f.ly * std::round((dyy - k * f.needle_spacing) / f.ly);
        EXPECT_NEAR(dyy, k * f.needle_spacing, 1e-9) << pattern << " course " << c;
        found = true;
      }
      EXPECT_TRUE(found) << pattern << " course " << c;
    }
  }
}

// yarn_path running keeps the path of a running stitch (hole to hole on the loop face), for
// comparison; the card key refuses other words
TEST(GenKnit, RunningStitchOnRequestAndBadPathRefused)
{
  const std::string base = layer(0, 150, 1, CT24) + layer(90, 150, 1, CT24) + STITCH_TRICOT;
  Fabric k = build(card_text(base)), r = build(card_text(base, "yarn_path running\n"));
  EXPECT_TRUE(k.card.knit);
  EXPECT_FALSE(r.card.knit);
  EXPECT_EQ(r.yarn.z_loop_out, r.yarn.z_loop);
  EXPECT_GT(k.yarn.length_per_yarn, r.yarn.length_per_yarn);    // loops out and back
  try {
    build(card_text(base, "yarn_path lock\n"));
    ADD_FAILURE() << "yarn_path lock accepted";
  } catch (InputError &e) {
    EXPECT_THAT(e.what(), HasSubstr("key 'yarn_path': value 'lock' must be 'knit' or 'running'"));
  }
}

// ------------------------------------------------------------------ bending (opt-in)

// 'bending bundle': one angle per pair of consecutive bonds of every fibre chain (none for the
// yarn), angle_style cosine with K = EI / l0_mean per layer, EI = n_f E_f pi d_f^4 / 64 of the
// chain's unbonded filaments, computed here from the materials file and the card's values
TEST(GenBending, AnglesPerChainAndStiffnessFromTheCardsMaterials)
{
  const std::string body = layer(0, 150, 1, CT24) + layer(90, 120, 2, CT50) + STITCH_TRICOT;
  const Fabric f = build(card_text(body + "bending bundle\n"));
  const NCF::MaterialLibrary lib = materials();
  ASSERT_EQ(f.layers.size(), 2u);
  const double pi = 3.14159265358979323846, dc = 69e-6, phi = 0.5;
  // the chain each node belongs to and the bonds of the part, to check every angle
  std::map<std::pair<int, int>, int> bond_type;
  for (const Bond &b : f.fibres.bonds) bond_type[{std::min(b.i, b.j), std::max(b.i, b.j)}] = b.type;
  std::map<int, int> angles_of_type;
  for (const Angle &a : f.fibres.angles) {
    angles_of_type[a.type]++;
    const auto b1 = bond_type.find({std::min(a.i, a.j), std::max(a.i, a.j)});
    const auto b2 = bond_type.find({std::min(a.j, a.k), std::max(a.j, a.k)});
    ASSERT_TRUE(b1 != bond_type.end() && b2 != bond_type.end())
        << "angle " << a.i << "-" << a.j << "-" << a.k << " is not two bonds of a chain";
    EXPECT_EQ(b1->second, a.type);
    EXPECT_EQ(b2->second, a.type);
    EXPECT_NE(a.i, a.k);
    EXPECT_EQ(f.fibres.nodes[a.i].chain, f.fibres.nodes[a.k].chain);
  }
  EXPECT_TRUE(f.stitch.angles.empty()) << "the stitching yarn gets no angles";
  std::size_t total = 0;
  for (std::size_t i = 0; i < f.layers.size(); i++) {
    const LayerInfo &L = f.layers[i];
    const int type = (int) i + 1;
    // counts: a chain of n nodes has n - 1 bonds and n - 2 angles
    EXPECT_EQ(angles_of_type[type], L.bonds - L.chains) << "layer " << type;
    EXPECT_EQ(L.bending_angles, L.bonds - L.chains);
    total += L.bonds - L.chains;
    // K from the material, independently of the generator's chain properties
    const NCF::Material &m = lib.get(L.spec.material);
    const double nf = phi * dc * dc / (m.filament_diameter * m.filament_diameter);
    const double ei = nf * m.modulus * pi * std::pow(m.filament_diameter, 4) / 64.0;
    double sum = 0.0;
    int nb = 0;
    for (const Bond &b : f.fibres.bonds)
      if (b.type == type) {
        sum += b.l0;
        nb++;
      }
    ASSERT_EQ(nb, L.bonds);
    EXPECT_NEAR(L.chain.bundle_ei / ei, 1.0, 1e-12) << "layer " << type;
    EXPECT_NEAR(L.bending_k / (ei / (sum / nb)), 1.0, 1e-12) << "layer " << type;
  }
  EXPECT_EQ(f.fibres.angles.size(), total);
  // the issue's number: 49 filaments of 7 um at 255 GPa give 1.46e-9 N m^2
  EXPECT_NEAR(f.layers[1].chain.bundle_ei, 1.46e-9, 0.005e-9);
  EXPECT_GT(f.layers[0].chain.bundle_ei, 0.0);
  EXPECT_NE(f.layers[0].bending_k, f.layers[1].bending_k) << "each layer its own material";

  // the files: atom_style angle with an Angles section, angle_style cosine with K per layer
  const std::string data = layers_data(f);
  EXPECT_THAT(data, HasSubstr("\n" + std::to_string(total) + " angles\n2 angle types\n"));
  EXPECT_THAT(data, HasSubstr("Atoms # angle\n"));
  const auto at_angles = data.find("\nAngles\n\n");
  ASSERT_NE(at_angles, std::string::npos);
  std::istringstream in(data.substr(at_angles + 9));
  std::string row;
  std::size_t rows = 0;
  while (std::getline(in, row) && !row.empty()) rows++;
  EXPECT_EQ(rows, total);
  EXPECT_THAT(yarn_data(f), Not(HasSubstr("angle")));
  const std::string settings = settings_text(f, "t");
  EXPECT_THAT(settings, HasSubstr("angle_style cosine\n"));
  for (int type = 1; type <= 2; type++) {
    const std::string key = "angle_coeff " + std::to_string(type) + " ";
    const auto pos = settings.find(key);
    ASSERT_NE(pos, std::string::npos);
    EXPECT_NEAR(std::stod(settings.substr(pos + key.size())) / f.layers[type - 1].bending_k, 1.0,
                1e-15);
  }
  const std::string summary = summary_text(f);
  EXPECT_THAT(summary, HasSubstr("bundle: EI 1.46e-09 N m^2"));
}

TEST(GenBending, NoneIsTheDefaultAndChangesNoFile)
{
  const std::string body = layer(0, 150, 1, CT24) + STITCH_TRICOT;
  const Fabric f0 = build(card_text(body));
  const Fabric f1 = build(card_text(body + "bending none\n"));
  EXPECT_FALSE(f0.card.bending);
  EXPECT_TRUE(f0.fibres.angles.empty());
  EXPECT_EQ(f0.layers[0].bending_angles, 0);
  EXPECT_EQ(layers_data(f0), layers_data(f1));
  EXPECT_EQ(settings_text(f0, "t"), settings_text(f1, "t"));
  EXPECT_THAT(layers_data(f0), Not(HasSubstr("ngle")));
  EXPECT_THAT(layers_data(f0), HasSubstr("Atoms # bond\n"));
  EXPECT_THAT(settings_text(f0, "t"), Not(HasSubstr("angle_")));
  EXPECT_THAT(summary_text(f0), HasSubstr("none (stretch-only chains)"));
  // bundle changes the layers' file, not the yarn's nor the positions
  const Fabric f2 = build(card_text(body + "bending bundle\n"));
  EXPECT_EQ(yarn_data(f0), yarn_data(f2));
  ASSERT_EQ(f0.fibres.nodes.size(), f2.fibres.nodes.size());
  for (std::size_t i = 0; i < f0.fibres.nodes.size(); i++)
    for (int d = 0; d < 3; d++) ASSERT_EQ(f0.fibres.nodes[i].x[d], f2.fibres.nodes[i].x[d]);
}

TEST(GenBending, BadValuesNameTheKeyAndTheValue)
{
  const std::string body = layer(0, 150, 1, CT24) + STITCH_TRICOT;
  for (const char *bad : {"yes", "Bundle", "1"}) {
    try {
      build(card_text(body + "bending " + bad + "\n"));
      ADD_FAILURE() << "bending " << bad << " was accepted";
    } catch (const InputError &e) {
      EXPECT_THAT(e.what(), HasSubstr("key 'bending': value '" + std::string(bad) + "'"));
      EXPECT_THAT(e.what(), HasSubstr("'none'"));
      EXPECT_THAT(e.what(), HasSubstr("'bundle'"));
    }
  }
}
