// fix ncf/pbc on 1, 2 and 4 MPI ranks: the same trajectory to round-off, with a box deformation.

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
  std::vector<double> x0, x;
};

Result run_on(int nranks, const Mat &mat)
{
  Result res;
  on_ranks(nranks, [&](MPI_Comm comm) {
    Lammps l(comm);
    load_mat(l, mat);
    res.nprocs = l.lmp->comm->nprocs;
    res.x0 = l.positions();
    l.cmds(R"(
change_box all triclinic
velocity all create 5e12 5 loop geom
fix nve all nve
fix deform all deform 1 x erate 500 xy erate 1000 remap x
fix pbc ends ncf/pbc faces x
timestep 5e-9
run 2000
)");
    res.x = l.positions();
  });
  return res;
}

}    // namespace

TEST(FixPBCMPI, SameTrajectoryOn124Ranks)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto dir = scratch_dir("mpi_pbc");
  if (world_rank() == 0) write_mat(dir, 3.0, 21, false, 12, 3, 16);
  MPI_Barrier(MPI_COMM_WORLD);
  const Mat mat = mat_files(dir);

  Result r1 = run_on(1, mat), r2 = run_on(2, mat), r4 = run_on(4, mat);
  if (world_rank() != 0) return;
  EXPECT_EQ(r1.nprocs, 1);
  EXPECT_EQ(r2.nprocs, 2);
  EXPECT_EQ(r4.nprocs, 4);
  EXPECT_GT(max_abs_diff(r1.x, r1.x0), 1e-7);
  const double d2 = max_abs_diff(r1.x, r2.x), d4 = max_abs_diff(r1.x, r4.x);
  std::printf(
      "[measured] fix ncf/pbc: max |x1 - x2| = %.3g m, max |x1 - x4| = %.3g m (box 2e-3 m)\n", d2,
      d4);
  EXPECT_LE(d2, 1e-12 * MAT_LX);
  EXPECT_LE(d4, 1e-12 * MAT_LX);
}
