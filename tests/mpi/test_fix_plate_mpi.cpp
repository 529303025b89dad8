// fix ncf/plate (with friction) and fix ncf/pbc together on 1, 2 and 4 MPI ranks: the same
// compaction trajectory to round-off.

#include "ncf_lammps_test.h"
#include "ncf_scenes.h"

#include "comm.h"
#include "lammps.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace ncftest;

namespace {

struct Result {
  int nprocs = 0;
  double pressure = 0.0;
  std::vector<double> x0, x;
};

Result run_on(int nranks, const Mat &mat)
{
  Result res;
  MPI_Comm comm;
  MPI_Comm_split(MPI_COMM_WORLD, world_rank() < nranks ? 0 : MPI_UNDEFINED, world_rank(), &comm);
  if (comm != MPI_COMM_NULL) {
    {
      Lammps l(comm);
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
      res.nprocs = l.lmp->comm->nprocs;
      res.x0 = l.positions();
      l.cmds(R"(
variable isend atom i_ncf_end>0
group ends variable isend
velocity all create 5e12 5 loop geom
fix nve all nve
fix damp all viscous 2e-7
fix plate all ncf/plate kn 2e7 kt 2e7 mu 0.3 damp 10 diameter 1 69e-6 lower z 0 upper target 0.66e-3 0.4e-3 5
fix endsz ends setforce 0 0 NULL
fix pbc ends ncf/pbc faces x
timestep 1e-8
run 4000
)");
      res.x = l.positions();
      res.pressure = l.value("f_plate[5]");
    }
    MPI_Comm_free(&comm);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return res;
}

}    // namespace

TEST(FixPlateMPI, SameCompactionOn124Ranks)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto dir = scratch_dir("mpi_plate");
  Mat mat;
  if (world_rank() == 0) mat = write_mat(dir, 3.0, 41, false, 12, 3, 16);
  MPI_Barrier(MPI_COMM_WORLD);
  mat.path = dir + "/mat.data";
  mat.masses = dir + "/masses.in";

  Result r1 = run_on(1, mat), r2 = run_on(2, mat), r4 = run_on(4, mat);
  if (world_rank() != 0) return;
  EXPECT_EQ(r2.nprocs, 2);
  EXPECT_EQ(r4.nprocs, 4);
  EXPECT_GT(r1.pressure, 0.0);    // the upper plate is pressing
  const double d2 = max_abs_diff(r1.x, r2.x), d4 = max_abs_diff(r1.x, r4.x);
  std::printf("[measured] plate + pbc compaction: max |x1 - x2| = %.3g m, max |x1 - x4| = %.3g m, pressure %.4g Pa\n",
              d2, d4, r1.pressure);
  EXPECT_LE(d2, 1e-10 * MAT_LX);
  EXPECT_LE(d4, 1e-10 * MAT_LX);
}
