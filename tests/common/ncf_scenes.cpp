/* ----------------------------------------------------------------------
   USER-NCF test scenes (see ncf_scenes.h)
------------------------------------------------------------------------- */

#include "ncf_scenes.h"

#include "ncf_lammps_test.h"

#include "comm.h"
#include "lammps.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

namespace ncftest {

Mat write_mat(const std::string &dir, double sigma_deg, unsigned seed, bool ring, int ny, int nz,
              int nel)
{
  Mat mat;
  mat.nchain = ny * nz;
  mat.nper = ring ? nel : nel + 1;
  std::mt19937 rng(seed);
  std::normal_distribution<double> angle(0.0, sigma_deg * M_PI / 180.0);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  mat.path = dir + (ring ? "/ring.data" : "/mat.data");
  FILE *fp = fopen(mat.path.c_str(), "w");
  const int natoms = mat.nchain * mat.nper;
  const int nbonds = mat.nchain * nel;
  fprintf(fp, "mat\n\n%d atoms\n1 atom types\n%d bonds\n1 bond types\n\n", natoms, nbonds);
  fprintf(fp, "0 %.17g xlo xhi\n0 %.17g ylo yhi\n0 %.17g zlo zhi\n\n", MAT_LX, MAT_LY, MAT_LZ);
  const double a = MAT_LX / nel, mass = 905.0 * M_PI / 4 * 69e-6 * 69e-6 * a;
  fprintf(fp, "Atoms # bond\n\n");
  std::vector<int> code;
  std::vector<double> m;
  int id = 0;
  for (int c = 0; c < mat.nchain; c++) {
    const double th = sigma_deg > 0 ? angle(rng) : 0.0;
    const double y0 =
        (c % ny + 0.5) * MAT_LY / ny + (sigma_deg > 0 ? 0.2 * MAT_LY / ny * jitter(rng) : 0.0);
    const double z0 = 0.3e-3 + (c / ny) * 0.15e-3;
    for (int j = 0; j < mat.nper; j++) {
      double x = j * a, y = y0 + j * a * std::tan(th);
      int ix = 0, iy = 0;
      // keep the coordinates inside the box with image flags (end node j = nel sits on xhi)
      while (x >= MAT_LX) x -= MAT_LX, ix++;
      while (y >= MAT_LY) y -= MAT_LY, iy++;
      while (y < 0) y += MAT_LY, iy--;
      fprintf(fp, "%d %d 1 %.17g %.17g %.17g %d %d 0\n", ++id, c + 1, x, y, z0, ix, iy);
      code.push_back(ring ? 0 : (j == 0 ? 1 : (j == nel ? 2 : 0)));
      // lumped masses: the two end nodes of an open chain carry half an element each
      m.push_back((!ring && (j == 0 || j == nel)) ? 0.5 * mass : mass);
    }
  }
  fprintf(fp, "\nBonds\n\n");
  int b = 0;
  for (int c = 0; c < mat.nchain; c++)
    for (int j = 0; j < nel; j++) {
      const int i1 = c * mat.nper + j + 1, i2 = c * mat.nper + (j + 1) % mat.nper + 1;
      fprintf(fp, "%d 1 %d %d\n", ++b, i1, i2);
    }
  fprintf(fp, "\nNCF_NODE\n\n");
  for (int i = 0; i < natoms; i++) fprintf(fp, "%d 1 %d\n", i + 1, code[i]);
  fclose(fp);
  // per-atom masses for the lumped end nodes
  mat.masses = dir + (ring ? "/ring_masses.in" : "/masses.in");
  FILE *fm = fopen(mat.masses.c_str(), "w");
  fprintf(fm, "set group all mass %.17g\n", mass);
  for (int i = 0; i < natoms; i++)
    if (m[i] != mass) fprintf(fm, "set atom %d mass %.17g\n", i + 1, m[i]);
  fclose(fm);
  return mat;
}

std::vector<int> face_codes(const Mat &mat, bool ring)
{
  std::vector<int> code;
  for (int c = 0; c < mat.nchain; c++)
    for (int j = 0; j < mat.nper; j++)
      code.push_back(ring ? 0 : (j == 0 ? 1 : (j == mat.nper - 1 ? 2 : 0)));
  return code;
}

void load_mat(Lammps &l, const Mat &mat)
{
  l.cmds(R"(
units si
atom_style bond
atom_modify map array
boundary p p f
newton on
neighbor 1e-4 bin
comm_modify cutoff 6e-4
bond_style ncf/chain
fix NCF_NODE all property/atom i_ncf_layer i_ncf_end
fix MASS all property/atom rmass
)");
  l.cmd("read_data " + mat.path + " fix NCF_NODE NULL NCF_NODE");
  l.cmd("bond_coeff 1 modulus 120e9 diameter 69e-6");
  l.cmd("include " + mat.masses);
  l.cmd("variable isend atom i_ncf_end>0");
  l.cmd("group ends variable isend");
}

Mat mat_files(const std::string &dir, bool ring)
{
  Mat mat;
  mat.path = dir + (ring ? "/ring.data" : "/mat.data");
  mat.masses = dir + (ring ? "/ring_masses.in" : "/masses.in");
  return mat;
}

std::vector<RankRun> mat_on_1_2_4_ranks(const std::string &dir, unsigned seed,
                                        const std::string &commands, const std::string &expression)
{
  if (world_rank() == 0) write_mat(dir, 3.0, seed, false, 12, 3, 16);
  MPI_Barrier(MPI_COMM_WORLD);
  const Mat mat = mat_files(dir);
  std::vector<RankRun> runs;
  for (int n : {1, 2, 4}) {
    RankRun r;
    on_ranks(n, [&](MPI_Comm comm) {
      Lammps l(comm);
      load_mat(l, mat);
      r.nprocs = l.lmp->comm->nprocs;
      r.x0 = l.positions();
      l.cmds(commands);
      r.x = l.positions();
      if (!expression.empty()) r.value = l.value(expression);
    });
    runs.push_back(r);
  }
  return runs;
}

void expect_same_on_ranks(const std::vector<RankRun> &r, double moved, double tol, const char *what)
{
  if (world_rank() != 0) return;
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].nprocs, 1);
  EXPECT_EQ(r[1].nprocs, 2);
  EXPECT_EQ(r[2].nprocs, 4);
  EXPECT_GT(max_abs_diff(r[0].x, r[0].x0), moved) << what << ": the scene must move";
  const double d2 = max_abs_diff(r[0].x, r[1].x), d4 = max_abs_diff(r[0].x, r[2].x);
  std::printf("[measured] %s: max |x1 - x2| = %.3g m, max |x1 - x4| = %.3g m\n", what, d2, d4);
  EXPECT_LE(d2, tol) << what;
  EXPECT_LE(d4, tol) << what;
}

Data read_data_file(const std::string &path)
{
  Data d;
  std::ifstream in(path);
  std::string line, section;
  std::map<long, std::array<long, 2>> dt;
  std::map<long, std::array<double, 2>> l0;
  while (std::getline(in, line)) {
    if (line.find(" atoms") != std::string::npos && section.empty())
      d.atoms = std::atol(line.c_str());
    if (line.find(" bonds") != std::string::npos && section.empty())
      d.bonds = std::atol(line.c_str());
    // (the Angles of a 'bending bundle' card are a section of their own, not read here)
    if (line.rfind("Atoms", 0) == 0 || line == "Bonds" || line == "NCF_NODE" || line == "Masses" ||
        line == "NCF_CHAIN_L0" || line == "Angles") {
      section = line.substr(0, 5);
      continue;
    }
    if (line.empty()) continue;
    std::istringstream w(line);
    if (section == "Atoms") {
      long id, mol;
      int type;
      w >> id >> mol >> type;
      d.type[id] = type;
    } else if (section == "Bonds") {
      long id, i, j;
      int type;
      w >> id >> type >> i >> j;
      d.bond.emplace_back(i, j);
    } else if (section == "NCF_C") {
      long id;
      w >> id >> dt[id][0] >> dt[id][1] >> l0[id][0] >> l0[id][1];
    } else if (section == "NCF_N") {
      long id;
      int l, e;
      w >> id >> l >> e;
      d.layer[id] = l;
      d.end[id] = e;
      d.ends += e != 0;
    }
  }
  for (auto &b : d.bond) {
    double v = -1;
    for (int k = 0; k < 2; k++)
      if (dt[b.first][k] == b.second - b.first) v = l0[b.first][k];
    d.l0.push_back(v);
  }
  return d;
}

std::string generate(const std::string &card, const std::string &prefix)
{
  const char *build = std::getenv("NCF_BUILD");
  const std::string tool = std::string(build ? build : ".") + "/ncf-gen";
  const std::string cmd = tool + " " + card + " -o " + prefix + " -q";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return prefix;
}

const char *const GENERATED_SETUP = R"(
units si
atom_style bond
atom_modify map array
boundary p p f
bond_style ncf/chain
fix NCF_NODE all property/atom i_ncf_layer i_ncf_end ghost yes
)";
const char *const GENERATED_READ_FIXES =
    " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0 fix NCF_NODE NULL NCF_NODE";

}    // namespace ncftest
