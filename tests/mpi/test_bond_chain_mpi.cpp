// bond_style ncf/chain on 1, 2 and 4 MPI ranks: the same trajectory to round-off.
// Run by ctest under mpirun -np 4; each scene runs on sub-communicators of 1, 2 and 4 ranks.

#include "ncf_lammps_test.h"

#include "comm.h"
#include "lammps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

using namespace ncftest;

namespace {

// nchain ring chains along x, closed across the periodic boundary (the last node bonds to the
// first through the box face), wiggled in y and z; two bond types; with or without stored L0
std::string write_network(const std::string &dir, bool with_l0)
{
  const int nchain = 24, nper = 40;
  const double a = 2e-4, lx = nper * a, ly = 2.4e-3, lz = 1.2e-3;
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::string path = dir + (with_l0 ? "/network_l0.data" : "/network.data");
  FILE *fp = fopen(path.c_str(), "w");
  const int n = nchain * nper;
  fprintf(fp, "ring chains\n\n%d atoms\n2 atom types\n%d bonds\n2 bond types\n\n", n, n);
  fprintf(fp, "0 %.17g xlo xhi\n0 %.17g ylo yhi\n0 %.17g zlo zhi\n\n", lx, ly, lz);
  fprintf(fp, "Masses\n\n1 3.4e-10\n2 1.2e-10\n\nAtoms # bond\n\n");
  for (int c = 0; c < nchain; c++) {
    const double y0 = (c % 6 + 0.5) * ly / 6, z0 = (c / 6 + 0.5) * lz / 4;
    for (int k = 0; k < nper; k++) {
      const int id = c * nper + k + 1;
      fprintf(fp, "%d %d %d %.17g %.17g %.17g\n", id, c + 1, 1 + c % 2, (k + 0.3 * u(rng)) * a,
              y0 + 2e-5 * u(rng), z0 + 2e-5 * u(rng));
    }
  }
  fprintf(fp, "\nBonds\n\n");
  int b = 0;
  for (int c = 0; c < nchain; c++)
    for (int k = 0; k < nper; k++) {
      const int i = c * nper + k + 1, j = c * nper + (k + 1) % nper + 1;
      fprintf(fp, "%d %d %d %d\n", ++b, 1 + c % 2, i, j);
    }
  if (with_l0) {
    fprintf(fp, "\nNCF_CHAIN_L0\n\n");
    for (int c = 0; c < nchain; c++)
      for (int k = 0; k < nper; k++) {
        const int id = c * nper + k + 1;
        // node k bonds to k+1; the first node also to the last (ring)
        const double l1 = a * (1.0 + 0.05 * u(rng));
        if (k == 0)
          fprintf(fp, "%d 1 %d %.17g %.17g\n", id, nper - 1, l1, a * (1.0 + 0.05 * u(rng)));
        else if (k < nper - 1)
          fprintf(fp, "%d 1 0 %.17g 0\n", id, l1);
        else
          fprintf(fp, "%d 0 0 0 0\n", id);
      }
  }
  fclose(fp);
  return path;
}

struct Result {
  int nprocs = 0;
  std::vector<double> x0, x;
  std::map<std::pair<long, long>, double> l0;
  double slots = 0.0;    // filled L0 slots of all atoms
};

Result run_on(int nranks, const std::string &data)
{
  Result res;
  on_ranks(nranks, [&](MPI_Comm comm) {
    Lammps l(comm);
    l.cmds(R"(
units si
atom_style bond
newton on
boundary p p p
comm_modify cutoff 6e-4
bond_style ncf/chain
)");
    l.cmd("read_data " + data + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
    res.nprocs = l.lmp->comm->nprocs;
    res.x0 = l.positions();
    l.cmds(R"(
bond_coeff 1 modulus 120e9 diameter 69e-6
bond_coeff 2 modulus 1.81e9 diameter 88e-6 shrink 0.02
velocity all create 1e-3 7 loop geom
fix nve all nve
timestep 5e-9
run 1000
)");
    res.x = l.positions();
    res.l0 = l.reference_lengths();
    // filled L0 slots of all atoms
    l.cmd("variable nslot atom (i2_ncf_dtag[1]!=0)+(i2_ncf_dtag[2]!=0)");
    l.cmd("compute nslot all reduce sum v_nslot");
    l.cmd("run 0");
    res.slots = l.value("c_nslot");
  });
  return res;
}

void compare_ranks(bool with_l0)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto dir = scratch_dir(with_l0 ? "mpi_bond_l0" : "mpi_bond_capture");
  std::string data;
  if (world_rank() == 0) data = write_network(dir, with_l0);
  // every rank needs the path
  char buf[4096] = {0};
  if (world_rank() == 0) snprintf(buf, sizeof(buf), "%s", data.c_str());
  MPI_Bcast(buf, sizeof(buf), MPI_CHAR, 0, MPI_COMM_WORLD);
  data = buf;

  Result r1 = run_on(1, data), r2 = run_on(2, data), r4 = run_on(4, data);
  if (world_rank() != 0) return;
  ASSERT_FALSE(r1.x.empty());
  EXPECT_EQ(r1.nprocs, 1);
  EXPECT_EQ(r2.nprocs, 2);
  EXPECT_EQ(r4.nprocs, 4);
  // the trajectory really moved, so that equality is not trivial
  EXPECT_GT(max_abs_diff(r1.x, r1.x0), 1e-6);
  const double lbox = 8e-3;    // largest box length
  EXPECT_LE(max_abs_diff(r1.x, r2.x), 1e-12 * lbox);
  EXPECT_LE(max_abs_diff(r1.x, r4.x), 1e-12 * lbox);
  std::printf("[measured] max |x1 - x2| = %.3g m, max |x1 - x4| = %.3g m (box 8e-3 m)\n",
              max_abs_diff(r1.x, r2.x), max_abs_diff(r1.x, r4.x));
  EXPECT_EQ(r1.l0.size(), 24u * 40u);
  // captured L0: both atoms of every bond hold it, also where the bond was captured on a ghost copy
  // of one of them (the data file of the stored case gives it to the lower tag only)
  if (!with_l0)
    for (const Result *r : {&r1, &r2, &r4})
      EXPECT_EQ(r->slots, 2.0 * 24 * 40) << r->nprocs << " ranks";
  EXPECT_EQ(r1.l0, r2.l0);
  EXPECT_EQ(r1.l0, r4.l0);
}

}    // namespace

TEST(BondChainMPI, SameTrajectoryOn124RanksWithStoredL0)
{
  compare_ranks(true);
}

TEST(BondChainMPI, SameTrajectoryOn124RanksWithCapturedL0)
{
  compare_ranks(false);
}

// A restart file read on 4 ranks without bond_coeff: every rank has the coefficients of the file
// (ea, shrink, compression, read by rank 0 and broadcast), so the forces and the energy after
// read_restart are those before write_restart
TEST(BondChainMPI, RestartGivesEveryRankTheCoefficients)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto dir = scratch_dir("mpi_bond_restart");
  char buf[4096] = {0};
  if (world_rank() == 0) snprintf(buf, sizeof(buf), "%s", write_network(dir, true).c_str());
  MPI_Bcast(buf, sizeof(buf), MPI_CHAR, 0, MPI_COMM_WORLD);
  const std::string data = buf, restart = dir + "/coeffs.restart";
  std::vector<double> f[2];
  double pe[2] = {0.0, 0.0};
  on_ranks(4, [&](MPI_Comm comm) {
    Lammps l(comm);
    l.cmds("units si\natom_style bond\nnewton on\nboundary p p p\ncomm_modify cutoff 6e-4\n"
           "bond_style ncf/chain");
    l.cmd("read_data " + data + " fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0");
    l.cmd("bond_coeff 1 modulus 120e9 diameter 69e-6 compression 0.5");
    l.cmd("bond_coeff 2 modulus 1.81e9 diameter 88e-6 shrink 0.02");
    l.cmd("run 0");
    f[0] = l.forces();
    pe[0] = l.value("pe");
    l.cmd("write_restart " + restart);
  });
  on_ranks(4, [&](MPI_Comm comm) {
    Lammps l(comm);
    l.cmd("read_restart " + restart);
    l.cmd("comm_modify cutoff 6e-4");
    l.cmd("run 0");
    f[1] = l.forces();
    pe[1] = l.value("pe");
  });
  if (world_rank() != 0) return;
  double fmax = 0.0;
  for (double v : f[0]) fmax = std::max(fmax, std::fabs(v));
  EXPECT_GT(pe[0], 0.0);
  EXPECT_NEAR(pe[1], pe[0], 1e-12 * pe[0]);
  EXPECT_LT(max_abs_diff(f[1], f[0]), 1e-12 * fmax);
}
