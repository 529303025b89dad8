// Integration tests of bond_style ncf/chain through LAMMPS (plugin auto-loaded).

#include "ncf_lammps_test.h"

#include "atom.h"
#include "bond.h"
#include "force.h"
#include "lammps.h"
#include "plugin.h"
#include "update.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

using namespace ncftest;
using ::testing::HasSubstr;

namespace {

// A data file with n atoms in a straight chain along x, spacing a, reference lengths l0
// (NCF_CHAIN_L0 section) and the given box.
std::string write_chain_data(const std::string &dir, int n, double a, double l0, double mass,
                             bool with_l0 = true, double box = 0.0)
{
  const std::string path = dir + "/chain.data";
  FILE *fp = fopen(path.c_str(), "w");
  const double len = box > 0.0 ? box : (n + 1) * a;
  fprintf(fp, "chain\n\n%d atoms\n1 atom types\n%d bonds\n1 bond types\n\n", n, n - 1);
  fprintf(fp, "%.17g %.17g xlo xhi\n-1e-3 1e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\n", -a, len - a);
  fprintf(fp, "Masses\n\n1 %.17g\n\nAtoms # bond\n\n", mass);
  for (int i = 0; i < n; i++) fprintf(fp, "%d 1 1 %.17g 0 0\n", i + 1, i * a);
  fprintf(fp, "\nBonds\n\n");
  for (int i = 1; i < n; i++) fprintf(fp, "%d 1 %d %d\n", i, i, i + 1);
  if (with_l0) {
    fprintf(fp, "\nNCF_CHAIN_L0\n\n");
    for (int i = 1; i <= n; i++) fprintf(fp, "%d %d 0 %.17g 0\n", i, i < n ? 1 : 0, i < n ? l0 : 0.0);
  }
  fclose(fp);
  return path;
}

const char *SETUP = R"(
units si
atom_style bond
atom_modify map array sort 0 0
boundary f p p
bond_style ncf/chain
)";

}    // namespace

TEST(BondChain, PluginIsListedWithVersionAndRevision)
{
  Lammps l;
  bool found = false;
  for (int i = 0; i < LAMMPS_NS::plugin_get_num_plugins(); i++) {
    const lammpsplugin_t *p = LAMMPS_NS::plugin_get_info(i);
    if (std::string(p->style) == "bond" && std::string(p->name) == "ncf/chain") {
      found = true;
      EXPECT_THAT(p->info, HasSubstr("USER-NCF"));
      EXPECT_THAT(p->info, HasSubstr("git "));
    }
  }
  EXPECT_TRUE(found) << "bond ncf/chain not registered by the auto-loaded plugin";
}

TEST(BondChain, AnalyticForceAndEnergy)
{
  auto dir = scratch_dir("bond_analytic");
  const double a = 2.1e-4, l0 = 2.0e-4, ea = 448.7;
  auto data = write_chain_data(dir, 2, a, l0, 1e-9);
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + data + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  l.cmd("bond_coeff 1 ea 448.7");
  l.cmd("run 0");
  auto f = l.forces();
  const double axial = ea * (a - l0) / l0;
  EXPECT_NEAR(f[0], axial, 1e-9 * axial);    // node 1 pulled towards node 2 (+x)
  EXPECT_NEAR(f[3], -axial, 1e-9 * axial);
  EXPECT_NEAR(l.value("ebond"), 0.5 * ea / l0 * (a - l0) * (a - l0), 1e-12 * axial * a);
}

TEST(BondChain, FiniteDifferenceForce)
{
  auto dir = scratch_dir("bond_fd");
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + write_chain_data(dir, 4, 2e-4, 2.05e-4, 1e-9) +
        " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  l.cmd("bond_coeff 1 modulus 120e9 diameter 69e-6 shrink 0.1 compression 0.5");
  // perturb the chain so that some bonds are in tension and some in compression
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3e-5, 3e-5);
  for (int i = 1; i <= 4; i++)
    l.cmd(fmt::format("set atom {} x {} y {} z {}", i, (i - 1) * 2e-4 + u(rng), u(rng), u(rng)));
  l.cmd("run 0");
  auto f = l.forces();
  auto x0 = l.positions();
  const double h = 1e-9;
  for (int i = 1; i <= 4; i++)
    for (int d = 0; d < 3; d++) {
      const double xi = x0[3 * (i - 1) + d];
      l.cmd(fmt::format("set atom {} {:c} {:.17g}", i, "xyz"[d], xi + h));
      l.cmd("run 0");
      const double ep = l.value("ebond");
      l.cmd(fmt::format("set atom {} {:c} {:.17g}", i, "xyz"[d], xi - h));
      l.cmd("run 0");
      const double em = l.value("ebond");
      l.cmd(fmt::format("set atom {} {:c} {:.17g}", i, "xyz"[d], xi));
      const double fd = -(ep - em) / (2 * h);
      EXPECT_NEAR(f[3 * (i - 1) + d], fd, 1e-5 * std::fabs(fd) + 1e-6) << "atom " << i << " dim " << d;
    }
}
