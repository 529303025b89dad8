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

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <vector>

using namespace ncftest;
using ::testing::HasSubstr;

namespace {

// A data file with n atoms in a straight chain along x, spacing a, reference lengths l0
// (NCF_CHAIN_L0 section: with the lower tag of each bond, or with the higher one if on_upper)
// and the given box.
std::string write_chain_data(const std::string &dir, int n, double a, double l0, double mass,
                             bool with_l0 = true, double box = 0.0, bool on_upper = false)
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
    for (int i = 1; i <= n; i++)
      if (on_upper)
        fprintf(fp, "%d %d 0 %.17g 0\n", i, i > 1 ? -1 : 0, i > 1 ? l0 : 0.0);
      else
        fprintf(fp, "%d %d 0 %.17g 0\n", i, i < n ? 1 : 0, i < n ? l0 : 0.0);
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

// (the L0 of a bond stored with either of its atoms)
TEST(BondChain, AnalyticForceAndEnergy)
{
  for (bool on_upper : {false, true}) {
    SCOPED_TRACE(on_upper ? "L0 with the higher tag" : "L0 with the lower tag");
    auto dir = scratch_dir("bond_analytic");
    const double a = 2.1e-4, l0 = 2.0e-4, ea = 448.7;
    auto data = write_chain_data(dir, 2, a, l0, 1e-9, true, 0.0, on_upper);
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
      const double fd = -l.energy_derivative("ebond", i, d, x0[3 * (i - 1) + d], h);
      EXPECT_NEAR(f[3 * (i - 1) + d], fd, 1e-5 * std::fabs(fd) + 1e-6)
          << "atom " << i << " dim " << d;
    }
}

TEST(BondChain, AxialWaveSpeedIsSqrtEOverRho)
{
  // a long chain with lumped masses; node 1 is driven at constant speed v0: the front (half
  // of v0) travels at c = sqrt(E/rho) in the continuum limit
  const double E = 120e9, rho = 905.0, d = 69e-6, a = 2e-4;
  const double A = M_PI * 0.25 * d * d, m = rho * A * a;
  const int n = 600;
  const double c = std::sqrt(E / rho), dtc = a / c;
  auto dir = scratch_dir("bond_wave");
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + write_chain_data(dir, n, a, a, m) + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  l.cmd(fmt::format("bond_coeff 1 modulus {} diameter {}", E, d));
  l.cmds(R"(
group driven id 1
group free subtract all driven
fix move driven move linear 1.0 0 0
fix nve free nve
)");
  l.cmd(fmt::format("timestep {}", 0.5 * dtc));
  // the front after t covers c t; take t so that it stays well inside the chain
  const int steps = 800;    // front at ~400 elements
  l.cmd(fmt::format("run {}", steps));
  auto v = l.velocities();
  // locate the front: first node (from the far end) whose speed exceeds v0/2
  int front = -1;
  for (int i = n - 1; i >= 0; i--)
    if (v[3 * i] > 0.5) {
      front = i;
      break;
    }
  ASSERT_GT(front, 0);
  const double t = steps * 0.5 * dtc;
  const double measured = front * a / t;
  EXPECT_NEAR(measured / c, 1.0, 0.02) << "front at node " << front << ", c = " << c;
  std::printf("[measured] wave speed %.6g m/s, sqrt(E/rho) %.6g m/s, ratio %.5f\n", measured, c,
              measured / c);
}

TEST(BondChain, UndampedVibrationConservesEnergy)
{
  // free chain, first axial mode excited; velocity Verlet at half the critical time step
  const double E = 120e9, rho = 905.0, d = 69e-6, a = 2e-4;
  const double A = M_PI * 0.25 * d * d;
  const int n = 50;
  auto dir = scratch_dir("bond_energy");
  // end nodes carry half the mass of interior nodes (lumped masses): per-atom masses
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + write_chain_data(dir, n, a, a, rho * A * a) +
        " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  l.cmd(fmt::format("bond_coeff 1 modulus {} diameter {}", E, d));
  const double L = (n - 1) * a;
  for (int i = 0; i < n; i++)
    l.cmd(fmt::format("set atom {} x {:.17g} y {:.17g}", i + 1,
                      i * a + 1e-3 * a * std::cos(M_PI * i * a / L),
                      1e-4 * a * std::sin(2 * M_PI * i / (n - 1))));
  l.cmds(R"(
fix nve all nve
variable etot equal pe+ke
thermo_style custom step pe ke v_etot
)");
  const double dtc = a / std::sqrt(E / rho);
  l.cmd(fmt::format("timestep {}", 0.5 * dtc));
  l.cmd("fix log all print 10 \"${etot}\" file " + dir + "/etot.txt screen no");
  l.cmd("run 10000");
  std::ifstream in(dir + "/etot.txt");
  std::string line;
  std::vector<double> e;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') e.push_back(std::stod(line));
  ASSERT_GE(e.size(), 1000u);
  // drift: mean over the first and the last tenth of the run (the Verlet energy oscillates
  // around a conserved shadow value; a drift moves the mean)
  const std::size_t w = e.size() / 10;
  double first = 0, last = 0;
  for (std::size_t i = 0; i < w; i++) {
    first += e[i] / w;
    last += e[e.size() - w + i] / w;
  }
  EXPECT_GT(first, 0.0);
  EXPECT_LT(std::fabs(last - first) / first, 1e-6) << "first " << first << " last " << last;
  std::printf("[measured] relative energy drift over 1e4 steps at dt_c/2: %.3g\n",
              std::fabs(last - first) / first);
}

namespace {
std::map<std::pair<long, long>, double> random_chain_setup(Lammps &l, const std::string &dir,
                                                           int seed)
{
  // chain with irregular reference lengths (no two alike) to see any rounding
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.9, 1.1);
  const int n = 12;
  const std::string path = dir + "/irregular.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "irregular\n\n%d atoms\n2 atom types\n%d bonds\n2 bond types\n\n", n, n - 1);
  fprintf(fp,
          "0 4e-3 xlo xhi\n-1e-3 1e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\nMasses\n\n1 1e-9\n2 "
          "2e-9\n\nAtoms # bond\n\n");
  double x = 1e-4;
  std::vector<double> l0(n);
  for (int i = 0; i < n; i++) {
    fprintf(fp, "%d %d %d %.17g %.17g 0\n", i + 1, i / 6 + 1, 1 + i % 2, x, 1e-5 * u(rng));
    l0[i] = 2e-4 * u(rng) / 3.0;    // irrational-looking lengths
    x += 2.5e-4;
  }
  fprintf(fp, "\nBonds\n\n");
  for (int i = 1; i < n; i++) fprintf(fp, "%d %d %d %d\n", i, 1 + i % 2, i, i + 1);
  fprintf(fp, "\nNCF_CHAIN_L0\n\n");
  for (int i = 1; i <= n; i++)
    fprintf(fp, "%d %d 0 %.17g 0\n", i, i < n ? 1 : 0, i < n ? l0[i - 1] : 0.0);
  fclose(fp);
  l.cmds(SETUP);
  l.cmd("read_data " + path + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  l.cmd("bond_coeff 1 ea 448.7 shrink 0.05");
  l.cmd("bond_coeff 2 ea 1.1e1 compression 0.25");
  std::map<std::pair<long, long>, double> expect;
  for (int i = 1; i < n; i++) expect[{i, i + 1}] = l0[i - 1];
  return expect;
}
}    // namespace

TEST(BondChain, ReferenceLengthsSurviveRestartBitForBit)
{
  auto dir = scratch_dir("bond_restart");
  std::map<std::pair<long, long>, double> expect;
  {
    Lammps l;
    expect = random_chain_setup(l, dir, 3);
    EXPECT_EQ(l.reference_lengths(), expect);
    l.cmds("fix nve all nve\ntimestep 1e-9\nrun 10");
    l.cmd("write_restart " + dir + "/chain.restart");
  }
  Lammps r;
  r.cmd("read_restart " + dir + "/chain.restart");
  r.cmd("run 0");
  auto got = r.reference_lengths();
  ASSERT_EQ(got.size(), expect.size());
  for (auto &kv : expect)
    EXPECT_EQ(got.at(kv.first), kv.second) << kv.first.first << "-" << kv.first.second;
  // coefficients come back too
  auto *bond = r.lmp->force->bond;
  int dim;
  EXPECT_EQ(static_cast<double *>(bond->extract("shrink", dim))[1], 0.05);
  EXPECT_EQ(static_cast<double *>(bond->extract("compression", dim))[2], 0.25);
}

TEST(BondChain, RestartContinuesTheSameTrajectory)
{
  auto dir = scratch_dir("bond_restart_run");
  std::vector<double> straight;
  {
    Lammps l;
    random_chain_setup(l, dir, 5);
    l.cmds("velocity all create 1e-10 4 loop geom\nfix nve all nve\ntimestep 2e-9\nrun 200");
    l.cmd("write_restart " + dir + "/half.restart");
    l.cmd("run 200");
    straight = l.positions();
  }
  Lammps r;
  r.cmd("read_restart " + dir + "/half.restart");
  r.cmds("fix nve all nve\ntimestep 2e-9\nrun 200");
  EXPECT_EQ(max_abs_diff(r.positions(), straight), 0.0);
}

TEST(BondChain, ReferenceLengthsSurviveWriteDataReadData)
{
  auto dir = scratch_dir("bond_data");
  std::map<std::pair<long, long>, double> expect;
  {
    Lammps l;
    expect = random_chain_setup(l, dir, 11);
    l.cmd("run 0");
    l.cmd("write_data " + dir + "/out.data");
  }
  Lammps r;
  r.cmds(SETUP);
  r.cmd("read_data " + dir + "/out.data fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  EXPECT_EQ(r.reference_lengths(), expect);
  r.cmd("run 0");
  int dim;
  auto *bond = r.lmp->force->bond;
  EXPECT_EQ(static_cast<double *>(bond->extract("ea", dim))[1], 448.7);
  EXPECT_EQ(static_cast<double *>(bond->extract("shrink", dim))[1], 0.05);
  EXPECT_EQ(static_cast<double *>(bond->extract("ea", dim))[2], 1.1e1);
  // the second round trip gives the same file
  r.cmd("write_data " + dir + "/out2.data");
  std::ifstream a(dir + "/out.data"), b(dir + "/out2.data");
  std::string la, lb;
  std::getline(a, la);    // the first line carries the time stamp
  std::getline(b, lb);
  std::stringstream sa, sb;
  sa << a.rdbuf();
  sb << b.rdbuf();
  EXPECT_EQ(sa.str(), sb.str());
}

// LAMMPS's force-style harness writes its data files with `nofix` (tests/harness): fix sections,
// NCF_CHAIN_L0 among them, are left out, so a bond read from such a file has no reference length
// and takes its current one at the next run (no force). The harness scene therefore sets L0
// after read_data (tests/harness/in.ncf-chain).
TEST(BondChain, NofixDataFileLosesTheReferenceLengths)
{
  auto dir = scratch_dir("bond_data_nofix");
  auto data = write_chain_data(dir, 5, 2.3e-4, 2.0e-4, 1e-9);
  {
    Lammps l;
    l.cmds(SETUP);
    l.cmd("read_data " + data + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
    l.cmd("bond_coeff 1 ea 10.0");
    l.cmd("run 0");
    EXPECT_GT(l.value("ebond"), 0.0);
    l.cmd("write_data " + dir + "/nofix.data nofix");
  }
  Lammps r(MPI_COMM_WORLD, dir + "/log.lammps");
  r.cmds(SETUP);
  r.cmd("read_data " + dir + "/nofix.data fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  EXPECT_TRUE(r.reference_lengths().empty());
  r.cmd("run 0");
  EXPECT_EQ(r.value("ebond"), 0.0);
  for (auto &kv : r.reference_lengths()) EXPECT_NEAR(kv.second, 2.3e-4, 1e-18);
  std::ifstream in(dir + "/log.lammps");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("taken from the current geometry for 4 bond(s)"));
}

// single(), which compute bond/local uses, gives the force and energy of the force loop for
// per-bond reference lengths (two separate bonds of different L0, stretched and compressed)
TEST(BondChain, SingleMatchesTheForceLoop)
{
  auto dir = scratch_dir("bond_single");
  const std::string path = dir + "/two.data";
  FILE *fp = fopen(path.c_str(), "w");
  fprintf(fp, "two bonds\n\n4 atoms\n1 atom types\n2 bonds\n2 bond types\n\n");
  fprintf(fp, "-1e-3 1e-3 xlo xhi\n-1e-3 1e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\n");
  fprintf(fp, "Masses\n\n1 1e-9\n\nAtoms # bond\n\n");
  fprintf(fp, "1 1 1 0 0 0\n2 1 1 1.7e-4 0.6e-4 -0.3e-4\n");
  fprintf(fp, "3 2 1 0 3e-4 0\n4 2 1 -1.1e-4 3.2e-4 0.4e-4\n");
  fprintf(fp, "\nBonds\n\n1 1 1 2\n2 2 3 4\n");
  fprintf(fp,
          "\nNCF_CHAIN_L0\n\n1 1 0 1.7e-4 0\n2 -1 0 1.7e-4 0\n3 1 0 1.3e-4 0\n4 -1 0 1.3e-4 0\n");
  fclose(fp);
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + path + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  l.cmd("bond_coeff 1 ea 10.0 compression 0.5");
  l.cmd("bond_coeff 2 ea 20.0 shrink 0.01");
  l.cmd("run 0");
  auto *atom = l.lmp->atom;
  auto *bond = l.lmp->force->bond;
  double esum = 0.0;
  for (int b = 0; b < 2; b++) {
    const int i = atom->map(1 + 2 * b), j = atom->map(2 + 2 * b);
    double del[3], rsq = 0.0;
    for (int d = 0; d < 3; d++) {
      del[d] = atom->x[i][d] - atom->x[j][d];
      rsq += del[d] * del[d];
    }
    double fforce = 0.0;
    esum += bond->single(b + 1, rsq, i, j, fforce);
    EXPECT_NE(fforce, 0.0);
    for (int d = 0; d < 3; d++) {
      EXPECT_NEAR(atom->f[i][d], fforce * del[d], 1e-12 * std::fabs(fforce * 1e-4)) << b << d;
      EXPECT_NEAR(atom->f[j][d], -fforce * del[d], 1e-12 * std::fabs(fforce * 1e-4)) << b << d;
    }
  }
  EXPECT_NEAR(esum, l.value("ebond"), 1e-12 * std::fabs(esum));
}

TEST(BondChain, AppendedDataKeepsItsReferenceLengths)
{
  // read_data ... add append shifts the tags of the second file: relative tags keep L0 attached
  auto dir = scratch_dir("bond_append");
  auto data = write_chain_data(dir, 5, 2e-4, 1.9e-4, 1e-9, true, 2e-3);
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + data +
        " extra/bond/per/atom 2 extra/special/per/atom 4 fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  l.cmd("read_data " + data + " add append shift 0 5e-4 0 fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  l.cmd("bond_coeff 1 ea 1.0");
  auto got = l.reference_lengths();
  ASSERT_EQ(got.size(), 8u);
  for (auto &kv : got) EXPECT_EQ(kv.second, 1.9e-4);
  EXPECT_EQ(got.count({6, 7}), 1u);
  EXPECT_EQ(got.count({5, 6}), 0u);
}

TEST(BondChain, MissingReferenceLengthsAreCapturedFromTheGeometry)
{
  auto dir = scratch_dir("bond_capture");
  auto data = write_chain_data(dir, 6, 2.3e-4, 0.0, 1e-9, false);
  auto got = std::map<std::pair<long, long>, double>();
  {
    Lammps l(MPI_COMM_WORLD, dir + "/log.lammps");
    l.cmds(SETUP);
    l.cmd("read_data " + data);
    l.cmd("bond_coeff 1 ea 10.0");
    l.cmd("run 0");
    got = l.reference_lengths();
    EXPECT_NEAR(l.value("ebond"), 0.0, 1e-30);
    // the largest L0 is reported for the communication cutoff check
    EXPECT_NEAR(l.lmp->force->bond->equilibrium_distance(1), 2.3e-4, 1e-18);
  }
  // the log counts the bonds it captured (it said 0 when the owned atoms had captured them all)
  std::ifstream in(dir + "/log.lammps");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("taken from the current geometry for 5 bond(s)"));
  ASSERT_EQ(got.size(), 5u);
  for (auto &kv : got) EXPECT_NEAR(kv.second, 2.3e-4, 1e-18);
}

// The reference lengths are looked up in the order of LAMMPS's bond list, which changes when the
// atoms are sorted or migrate: a chain of alternating element lengths (0.1 and 0.3 mm, captured
// from its geometry) translated rigidly through the periodic x face, its atoms (listed in reverse
// in the data file) sorted into 10 um bins every 5 steps and the lists rebuilt every step, keeps
// every bond at its own reference length (a length looked up for another bond strains it by 200 %)
TEST(BondChain, ReferenceLengthsFollowTheBondListWhenTheAtomsAreReordered)
{
  auto dir = scratch_dir("bond_reorder");
  const std::string path = dir + "/zigzag.data";
  const int n = 12;
  {
    FILE *fp = fopen(path.c_str(), "w");
    fprintf(fp, "chain\n\n%d atoms\n1 atom types\n%d bonds\n1 bond types\n\n", n, n - 1);
    fprintf(fp, "0 3e-3 xlo xhi\n-1e-3 1e-3 ylo yhi\n-1e-3 1e-3 zlo zhi\n\n");
    fprintf(fp, "Masses\n\n1 1e-9\n\nAtoms # bond\n\n");
    double x = 0.1e-3;
    std::vector<double> xs;
    for (int i = 0; i < n; i++) {
      xs.push_back(x);
      x += (i % 2 ? 0.3e-3 : 0.1e-3);
    }
    for (int i = n - 1; i >= 0; i--) fprintf(fp, "%d 1 1 %.17g 0 0\n", i + 1, xs[i]);
    fprintf(fp, "\nBonds\n\n");
    for (int i = 1; i < n; i++) fprintf(fp, "%d 1 %d %d\n", i, i, i + 1);
    fclose(fp);
  }
  Lammps l;
  l.cmds("units si\natom_style bond\natom_modify map array sort 5 1e-5\nboundary p p p\n"
         "bond_style ncf/chain");
  l.cmd("read_data " + path);
  l.cmds(R"(
bond_coeff 1 ea 10.0
neighbor 1e-5 bin
neigh_modify every 1 delay 0 check no
comm_modify cutoff 6e-4
velocity all set 500 0 0
fix nve all nve
timestep 1e-8
thermo_style custom step ebond
thermo 0
run 0
)");
  EXPECT_NEAR(l.value("ebond"), 0.0, 1e-30);
  std::vector<long> first;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) first.push_back((long) l.lmp->atom->tag[i]);
  double emax = 0.0;
  for (int k = 0; k < 60; k++) {
    l.cmd("run 5 pre no");
    emax = std::max(emax, std::fabs(l.value("ebond")));
  }
  std::vector<long> last;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) last.push_back((long) l.lmp->atom->tag[i]);
  EXPECT_NE(first, last) << "the atoms must have been reordered";
  // (1.5 mm travelled, through the x face; energy of a strain of 1e-12 in every bond: 5e-28 J)
  EXPECT_LT(emax, 1e-24) << "largest bond energy along the way [J]";
}

TEST(BondChain, ShrinkByFixAdaptPullsTheChainTogether)
{
  // two nodes, damped: the distance settles at L0 (1 - s)
  auto dir = scratch_dir("bond_shrink");
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + write_chain_data(dir, 2, 2e-4, 2e-4, 1e-9) +
        " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  l.cmds(R"(
bond_coeff 1 ea 10.0
variable s equal ramp(0.0,0.16)
fix adapt all adapt 1 bond ncf/chain shrink 1 v_s
fix nve all nve
fix damp all viscous 2e-4
timestep 1e-7
run 2000
variable s delete
unfix adapt
run 3000
)");
  auto x = l.positions();
  EXPECT_NEAR(x[3] - x[0], 0.84 * 2e-4, 1e-9);
}

TEST(BondChain, TimestepAboveCriticalIsRefusedWithTheNumbers)
{
  auto dir = scratch_dir("bond_dt");
  const double E = 120e9, rho = 905.0, d = 69e-6, a = 2e-4, A = M_PI * 0.25 * d * d;
  const double dtc = a / std::sqrt(E / rho);
  auto data = write_chain_data(dir, 10, a, a, rho * A * a);
  {
    Lammps l;
    l.cmds(SETUP);
    l.cmd("read_data " + data + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
    l.cmd(fmt::format("bond_coeff 1 modulus {} diameter {}", E, d));
    l.cmd("fix nve all nve");
    l.cmd(fmt::format("timestep {}", 1.05 * dtc));
    auto msg = error_of([&] {
      l.cmd("run 10");
    });
    EXPECT_THAT(msg, HasSubstr("bond ncf/chain: timestep"));
    EXPECT_THAT(msg, HasSubstr("is above the critical time step"));
    EXPECT_THAT(msg, HasSubstr(fmt::format("{:.6g}", dtc)));
    // just below the critical step the chain stays bounded and finite
    l.cmd(fmt::format("timestep {}", 0.98 * dtc));
    l.cmd("velocity all create 1e-6 1 loop geom");
    l.cmd("run 5000");
    for (double xi : l.positions()) ASSERT_TRUE(std::isfinite(xi));
    EXPECT_LT(l.value("ke"), 1e3);    // bounded
  }
  {
    // with dtcheck warn the user takes responsibility: it runs (and blows up, without crashing)
    Lammps l;
    l.cmds(SETUP);
    l.cmd("bond_style ncf/chain dtcheck warn");
    l.cmd("read_data " + data + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
    l.cmd(fmt::format("bond_coeff 1 modulus {} diameter {}", E, d));
    l.cmd("fix nve all nve");
    l.cmd(fmt::format("timestep {}", 1.05 * dtc));
    EXPECT_EQ(error_of([&] {
                l.cmd("run 1");
              }),
              "");
  }
}

TEST(BondChain, CompressionRatioScalesTheCompressiveForce)
{
  auto dir = scratch_dir("bond_compression");
  auto data = write_chain_data(dir, 2, 1.8e-4, 2e-4, 1e-9);
  for (double c : {1.0, 0.3, 0.0}) {
    Lammps l;
    l.cmds(SETUP);
    l.cmd("read_data " + data + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
    l.cmd(fmt::format("bond_coeff 1 ea 100.0 compression {}", c));
    l.cmd("run 0");
    auto f = l.forces();
    EXPECT_NEAR(f[0], -c * 100.0 * 0.1, 1e-12) << "c = " << c;    // pushed apart
  }
}

struct BadLine {
  const char *command;
  const char *message;
};

class BondChainErrors : public ::testing::TestWithParam<BadLine> {};

TEST_P(BondChainErrors, NameTheProblem)
{
  auto dir = scratch_dir("bond_errors");
  auto data = write_chain_data(dir, 3, 2e-4, 2e-4, 1e-9);
  Lammps l;
  l.cmds(SETUP);
  l.cmd("read_data " + data + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
  auto msg = error_of([&] {
    l.cmd(GetParam().command);
  });
  EXPECT_THAT(msg, HasSubstr(GetParam().message)) << "command: " << GetParam().command;
}

INSTANTIATE_TEST_SUITE_P(
    Table, BondChainErrors,
    ::testing::Values(
        BadLine{"bond_style ncf/chain dtcheck",
                "bond_style ncf/chain: keyword 'dtcheck' needs a value"},
        BadLine{"bond_style ncf/chain dtcheck maybe",
                "bond_style ncf/chain: dtcheck 'maybe' is not one of error, warn, no"},
        BadLine{"bond_style ncf/chain stiff 3", "bond_style ncf/chain: unknown keyword 'stiff'"},
        BadLine{"bond_coeff 1",
                "bond_coeff ncf/chain: expected 'N ea EA' or 'N modulus E diameter d'"},
        BadLine{"bond_coeff 1 ea", "bond_coeff ncf/chain: expected"},
        BadLine{"bond_coeff 1 ea 10 shrink",
                "bond_coeff ncf/chain: keyword 'shrink' needs a value"},
        BadLine{"bond_coeff 1 ea -10", "bond_coeff ncf/chain: ea must be > 0, got -10"},
        BadLine{"bond_coeff 1 ea abc", "bond_coeff ncf/chain: value 'abc' of 'ea' is not a number"},
        BadLine{"bond_coeff 1 ea 10 shrink 1.0",
                "bond_coeff ncf/chain: shrink must be in [0, 1), got 1.0"},
        BadLine{"bond_coeff 1 ea 10 shrink -0.1",
                "bond_coeff ncf/chain: shrink must be in [0, 1), got -0.1"},
        BadLine{"bond_coeff 1 ea 10 compression 2",
                "bond_coeff ncf/chain: compression must be in [0, 1], got 2"},
        BadLine{"bond_coeff 1 ea 10 colour red", "bond_coeff ncf/chain: unknown keyword 'colour'"},
        BadLine{"bond_coeff 1 modulus 1e9", "give 'ea' or both 'modulus' and 'diameter'"},
        BadLine{
            "bond_coeff 1 modulus 1e9 shrink 0.1",
            "no axial stiffness for bond type(s) 1: give 'ea' or both 'modulus' and 'diameter'"},
        BadLine{"bond_coeff 1 modulus 0 diameter 1e-5",
                "bond_coeff ncf/chain: modulus must be > 0, got 0"},
        BadLine{"bond_coeff 1 modulus 1e9 diameter -1",
                "bond_coeff ncf/chain: diameter must be > 0, got -1"},
        BadLine{"bond_coeff 1 ea 5 modulus 1e9 diameter 1e-5",
                "give either 'ea' or 'modulus' with 'diameter', not both"},
        BadLine{"bond_coeff 2 ea 5", "Numeric index 2 is out of bounds (1-1)"},
        BadLine{"run 0", "Bond coeffs are not set"}));

TEST(BondChain, AutoLoadedPluginSurvivesClear)
{
  Lammps l;
  l.cmds(SETUP);
  l.cmd("clear");
  // after clear, LAMMPS_PLUGIN_PATH auto-loads the plugin again: the style is still known
  l.cmds("units si\natom_style bond");
  EXPECT_EQ(error_of([&] {
              l.cmd("bond_style ncf/chain");
            }),
            "");
}

TEST(BondChain, UnknownStyleWithoutPluginIsAnError)
{
  // the harness really depends on the plugin: unloading it makes the style unknown
  Lammps l;
  l.cmd("plugin unload bond ncf/chain");
  l.cmds("units si\natom_style bond");
  EXPECT_THAT(error_of([&] {
                l.cmd("bond_style ncf/chain");
              }),
              HasSubstr("Unrecognized bond style 'ncf/chain'"));
}
