// Integration test of compute ncf/orient: known chain angles in two layers.

#include "ncf_lammps_test.h"

#include "lammps.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

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
