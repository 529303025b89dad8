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
  on_ranks(nranks, [&](MPI_Comm comm) {
    Lammps l(comm);
    load_mat(l, mat);
    res.nprocs = l.lmp->comm->nprocs;
    res.x0 = l.positions();
    l.cmds(R"(
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
  });
  return res;
}

}    // namespace

TEST(FixPlateMPI, SameCompactionOn124Ranks)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto dir = scratch_dir("mpi_plate");
  if (world_rank() == 0) write_mat(dir, 3.0, 41, false, 12, 3, 16);
  MPI_Barrier(MPI_COMM_WORLD);
  const Mat mat = mat_files(dir);

  Result r1 = run_on(1, mat), r2 = run_on(2, mat), r4 = run_on(4, mat);
  if (world_rank() != 0) return;
  EXPECT_EQ(r2.nprocs, 2);
  EXPECT_EQ(r4.nprocs, 4);
  EXPECT_GT(r1.pressure, 0.0);    // the upper plate is pressing
  const double d2 = max_abs_diff(r1.x, r2.x), d4 = max_abs_diff(r1.x, r4.x);
  std::printf("[measured] plate + pbc compaction: max |x1 - x2| = %.3g m, max |x1 - x4| = %.3g m, "
              "pressure %.4g Pa\n",
              d2, d4, r1.pressure);
  EXPECT_LE(d2, 1e-10 * MAT_LX);
  EXPECT_LE(d4, 1e-10 * MAT_LX);
}
