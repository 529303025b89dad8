// Integration test of compute ncf/orient: known chain angles in two layers.

#include "ncf_lammps_test.h"

#include "fmt/format.h"
#include "lammps.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace ncftest;
using ::testing::HasSubstr;

namespace {

// layer 1: four chains along x at -2, 0, 2, 4 deg; layer 2: three chains along y at 89, 90, 94
std::string write_angles(const std::string &dir)
{
  const std::string path = dir + "/angles.data";
  struct Chain {
    int layer;
    double angle, x0, y0;
  } chains[] = {{1, -2, 0, 1e-3}, {1, 0, 0, 2e-3}, {1, 2, 0, 3e-3}, {1, 4, 0, 4e-3},
                {2, 89, 1e-3, 0}, {2, 90, 2e-3, 0}, {2, 94, 3e-3, 0}};
  const int nel = 10, nper = nel + 1, nc = 7;
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "angles\n\n%d atoms\n2 atom types\n%d bonds\n1 bond types\n\n", nc * nper, nc * nel);
  fprintf(fp, "-1e-3 6e-3 xlo xhi\n-1e-3 6e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\nMasses\n\n1 1e-9\n2 1e-9\n\n");
  fprintf(fp, "Atoms # bond\n\n");
  int id = 0;
  for (int c = 0; c < nc; c++)
    for (int j = 0; j < nper; j++) {
      const double t = chains[c].angle * M_PI / 180, s = j * 2e-4 * (c % 2 ? 1.0 : 1.5);
      fprintf(fp, "%d %d %d %.17g %.17g %.17g\n", ++id, c + 1, chains[c].layer,
              chains[c].x0 + s * std::cos(t), chains[c].y0 + s * std::sin(t), 1e-4 * chains[c].layer);
    }
  fprintf(fp, "\nBonds\n\n");
  int b = 0;
  for (int c = 0; c < nc; c++)
    for (int j = 0; j < nel; j++) fprintf(fp, "%d 1 %d %d\n", ++b, c * nper + j + 1, c * nper + j + 2);
  fprintf(fp, "\nNCF_NODE\n\n");
  for (int c = 0; c < nc; c++)
    for (int j = 0; j < nper; j++) fprintf(fp, "%d %d 0\n", c * nper + j + 1, chains[c].layer);
  fclose(fp);
  return path;
}

void load(Lammps &l, const std::string &data)
{
  l.cmds(R"(
units si
atom_style bond
boundary f f f
bond_style ncf/chain
fix NCF_NODE all property/atom i_ncf_layer i_ncf_end
)");
  l.cmd("read_data " + data + " fix NCF_NODE NULL NCF_NODE");
  l.cmd("bond_coeff 1 ea 10");
}

}    // namespace

TEST(ComputeOrient, MeanAndStdOfKnownAngles)
{
  auto dir = scratch_dir("orient_known");
  Lammps l;
  load(l, write_angles(dir));
  // chains 1 and 3 (even index) have longer elements (1.5x): the statistics weigh by length
  l.cmd("compute o all ncf/orient layer 1 0 layer 2 90 bins 20 range 10");
  l.cmd("run 0");
  const double w[4] = {1.5, 1.0, 1.5, 1.0}, a[4] = {-2, 0, 2, 4};
  double sw = 0, m = 0, m2 = 0;
  for (int k = 0; k < 4; k++) sw += w[k], m += w[k] * a[k], m2 += w[k] * a[k] * a[k];
  m /= sw;
  const double sd = std::sqrt(m2 / sw - m * m);
  EXPECT_NEAR(l.value("c_o[1]"), m, 1e-9);
  EXPECT_NEAR(l.value("c_o[2]"), sd, 1e-9);
  // layer 2 at 89, 90, 94 deg (chains 5, 6, 7: element lengths 1.5, 1, 1.5)
  const double m2l = (-1.0 * 1.5 + 0.0 * 1.0 + 4.0 * 1.5) / 4.0;
  EXPECT_NEAR(l.value("c_o[7]"), m2l, 1e-9);
  EXPECT_NEAR(l.value("c_o[9]"), 90.0 + m2l, 0.3);    // principal axis of layer 2
  // histogram: bin of 0 deg (width 1 deg: [-1, 0) is bin 9, [0, 1) bin 10) holds chain 2
  EXPECT_NEAR(l.value("c_o[11][1]"), 0.5, 1e-12);           // bin centre
  EXPECT_NEAR(l.value("c_o[11][2]"), 1.0 / sw, 1e-9);       // density 1/deg of chain 2's weight
}

TEST(ComputeOrient, ErrorsNameTheProblem)
{
  auto dir = scratch_dir("orient_errors");
  Lammps l;
  load(l, write_angles(dir));
  EXPECT_THAT(error_of([&] { l.cmd("compute o all ncf/orient"); }),
              HasSubstr("compute ncf/orient: name at least one layer: 'layer L ANGLE'"));
  EXPECT_THAT(error_of([&] { l.cmd("compute o all ncf/orient layer 1"); }),
              HasSubstr("compute ncf/orient: keyword 'layer' needs a layer index and its angle"));
  EXPECT_THAT(error_of([&] { l.cmd("compute o all ncf/orient layer 1 0 layer 1 90"); }),
              HasSubstr("compute ncf/orient: layer 1 given twice"));
  EXPECT_THAT(error_of([&] { l.cmd("compute o all ncf/orient layer 1 0 bins 0"); }),
              HasSubstr("compute ncf/orient: bins 0 must be in [1, 100000]"));
  EXPECT_THAT(error_of([&] { l.cmd("compute o all ncf/orient layer 1 0 range 120"); }),
              HasSubstr("compute ncf/orient: range 120 must be in (0, 90] degrees"));
  EXPECT_THAT(error_of([&] { l.cmd("compute o all ncf/orient layer 1 0 colour red"); }),
              HasSubstr("compute ncf/orient: unknown keyword 'colour'"));
  l.cmd("compute o all ncf/orient layer 1 0 property i_nothing");
  EXPECT_THAT(error_of([&] { l.cmd("run 0"); }), HasSubstr("compute ncf/orient: no per-atom integer i_nothing"));
}

namespace {

// chains of PNEL elements of length `seg` at `angle` (deg) from (x0, y0), in layer `layer`
// (z = 1e-4 layer); reverse: the nodes numbered from the other end (the bonds point backwards)
struct OrientChain {
  int layer;
  double angle, x0, y0, seg;
  bool reverse;
};

// periodic box [0, 2 mm) in x and y: the chains cross the x and y faces (positions wrapped into
// the box, image flags in the data file)
const double PSIDE = 2e-3;
const int PNEL = 8;

std::string write_periodic(const std::string &dir, const std::vector<OrientChain> &chains)
{
  const std::string path = dir + "/periodic.data";
  const int nper = PNEL + 1, nc = (int) chains.size();
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "periodic angles\n\n%d atoms\n2 atom types\n%d bonds\n1 bond types\n\n", nc * nper,
          nc * PNEL);
  fprintf(fp,
          "0 %.17g xlo xhi\n0 %.17g ylo yhi\n-1e-3 1e-3 zlo zhi\n\nMasses\n\n1 1e-9\n2 1e-9\n\n",
          PSIDE, PSIDE);
  fprintf(fp, "Atoms # bond\n\n");
  int id = 0;
  for (int c = 0; c < nc; c++)
    for (int j = 0; j < nper; j++) {
      const OrientChain &ch = chains[c];
      const int k = ch.reverse ? PNEL - j : j;
      const double t = ch.angle * M_PI / 180;
      double p[2] = {ch.x0 + k * ch.seg * std::cos(t), ch.y0 + k * ch.seg * std::sin(t)};
      int img[2];
      for (int d = 0; d < 2; d++) {
        img[d] = (int) std::floor(p[d] / PSIDE);
        p[d] -= img[d] * PSIDE;
      }
      fprintf(fp, "%d %d %d %.17g %.17g %.17g %d %d 0\n", ++id, c + 1, ch.layer, p[0], p[1],
              1e-4 * ch.layer, img[0], img[1]);
    }
  fprintf(fp, "\nBonds\n\n");
  int b = 0;
  for (int c = 0; c < nc; c++)
    for (int j = 0; j < PNEL; j++)
      fprintf(fp, "%d 1 %d %d\n", ++b, c * nper + j + 1, c * nper + j + 2);
  fprintf(fp, "\nNCF_NODE\n\n");
  for (int c = 0; c < nc; c++)
    for (int j = 0; j < nper; j++) fprintf(fp, "%d %d 0\n", c * nper + j + 1, chains[c].layer);
  fclose(fp);
  return path;
}

// the six outputs of one layer computed directly from the chains: mean and std of the
// deviation from the nominal angle (axes: folded into [-90, 90] by std::remainder), principal
// axis and value of the length-weighted orientation tensor, share of the length outside the
// range, in-plane length
std::array<double, 6> expected_outputs(const std::vector<OrientChain> &chains, int layer,
                                       double nominal, double range)
{
  double w = 0, m = 0, m2 = 0, out = 0, a = 0, b = 0, c = 0;
  for (const auto &ch : chains) {
    if (ch.layer != layer) continue;
    const double l = PNEL * ch.seg, d = std::remainder(ch.angle - nominal, 180.0);
    const double t = ch.angle * M_PI / 180;
    w += l;
    m += l * d;
    m2 += l * d * d;
    if (std::fabs(d) > range) out += l;
    a += l * std::cos(t) * std::cos(t);
    b += l * std::sin(t) * std::sin(t);
    c += l * std::cos(t) * std::sin(t);
  }
  m /= w;
  double ang = 0.5 * std::atan2(2 * c, a - b) * 180 / M_PI;
  if (ang < 0) ang += 180;
  const double lam = 0.5 * (a + b) + std::sqrt(0.25 * (a - b) * (a - b) + c * c);
  return {m, std::sqrt(m2 / w - m * m), ang, lam / w, out / w, w};
}

}    // namespace

// The deviation of an axis folds past +-90 deg from the nominal angle (a chain at 93 deg in a
// 0 deg layer, at -89 deg in a 90 deg layer), chains numbered backwards, bonds across the
// periodic faces, newton_bond on and off (every bond counted once): all six outputs per layer
// against a direct evaluation
TEST(ComputeOrient, FoldedAnglesPeriodicBondsAndNewtonOff)
{
  auto dir = scratch_dir("orient_periodic");
  const std::vector<OrientChain> chains = {
      {1, -3, 1.8e-3, 0.4e-3, 1.5e-4, false}, {1, 1, 1.5e-3, 0.9e-3, 1.0e-4, true},
      {1, 178, 0.3e-3, 1.4e-3, 1.2e-4, true}, {1, 93, 0.2e-3, 1.7e-3, 1.0e-4, false},
      {2, 93, 0.5e-3, 1.8e-3, 1.5e-4, false}, {2, -89, 1.2e-3, 0.3e-3, 1.0e-4, true},
      {2, 88, 1.7e-3, 1.6e-3, 1.2e-4, true},  {2, 271, 0.9e-3, 0.6e-3, 1.1e-4, false}};
  const std::string data = write_periodic(dir, chains);
  const double range = 10.0;
  const auto e1 = expected_outputs(chains, 1, 0.0, range),
             e2 = expected_outputs(chains, 2, 90.0, range);
  ASSERT_GT(e1[4], 0.0);    // the 93 deg chain of layer 1 lies outside the range
  for (const char *newton : {"on", "on off"}) {
    SCOPED_TRACE(std::string("newton ") + newton);
    Lammps l;
    l.cmds(std::string("units si\natom_style bond\nnewton ") + newton +
           "\nboundary p p f\ncomm_modify cutoff 6e-4\nbond_style ncf/chain\n"
           "fix NCF_NODE all property/atom i_ncf_layer i_ncf_end\n");
    l.cmd("read_data " + data + " fix NCF_NODE NULL NCF_NODE");
    l.cmd("bond_coeff 1 ea 10");
    l.cmd("compute o all ncf/orient layer 1 0 layer 2 90 bins 20 range 10");
    l.cmd("run 0");
    for (int k = 0; k < 6; k++) {
      const double tol = k == 2 ? 1e-7 : 1e-9 * std::max(1.0, std::fabs(e1[k]));
      EXPECT_NEAR(l.value(fmt::format("c_o[{}]", k + 1)), e1[k], tol)
          << "layer 1, output " << k + 1;
      EXPECT_NEAR(l.value(fmt::format("c_o[{}]", k + 7)), e2[k],
                  k == 2 ? 1e-7 : 1e-9 * std::max(1.0, std::fabs(e2[k])))
          << "layer 2, output " << k + 1;
    }
  }
}
