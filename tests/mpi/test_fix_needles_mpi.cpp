// fix ncf/needles on 1, 2 and 4 MPI ranks: the same piercing trajectory to round-off, with a
// needle close to a periodic face (its image acts on chains across it).

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
  double fz = 0.0;
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
fix nve all nve
fix damp all viscous 2e-7
fix needles all ncf/needles diameter 0.3e-3 kn 2e9 chain 1 69e-6 at 0.7e-3 0.5e-3 at 1.95e-3 1.2e-3 target 0.7e-3 0.1e-3 20 tip 0.2e-3 length 1e-3
fix pbc ends ncf/pbc
timestep 8e-9
run 3000
)");
    res.x = l.positions();
    res.fz = l.value("f_needles[2]");
  });
  return res;
}

}    // namespace

TEST(FixNeedlesMPI, SamePiercingOn124Ranks)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto dir = scratch_dir("mpi_needles");
  if (world_rank() == 0) write_mat(dir, 3.0, 61, false, 12, 3, 16);
  MPI_Barrier(MPI_COMM_WORLD);
  const Mat mat = mat_files(dir);

  Result r1 = run_on(1, mat), r2 = run_on(2, mat), r4 = run_on(4, mat);
  if (world_rank() != 0) return;
  EXPECT_EQ(r2.nprocs, 2);
  EXPECT_EQ(r4.nprocs, 4);
  EXPECT_GT(max_abs_diff(r1.x, r1.x0), 1e-6);    // the needles pushed chains
  const double d2 = max_abs_diff(r1.x, r2.x), d4 = max_abs_diff(r1.x, r4.x);
  std::printf(
      "[measured] needles: max |x1 - x2| = %.3g m, max |x1 - x4| = %.3g m, needle force %.4g N\n",
      d2, d4, r1.fz);
  EXPECT_LE(d2, 1e-10 * MAT_LX);
  EXPECT_LE(d4, 1e-10 * MAT_LX);
}
