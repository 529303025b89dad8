// fix ncf/plate (with friction) and fix ncf/pbc together on 1, 2 and 4 MPI ranks: the same
// compaction trajectory to round-off, and the same largest penetration.

#include "ncf_lammps_test.h"
#include "ncf_scenes.h"

#include <gtest/gtest.h>

using namespace ncftest;

TEST(FixPlateMPI, SameCompactionOn124Ranks)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto runs = mat_on_1_2_4_ranks(scratch_dir("mpi_plate"), 41, R"(
velocity all create 5e12 5 loop geom
fix nve all nve
fix damp all viscous 2e-7
fix plate all ncf/plate kn 2e7 kt 1.0 mu 0.3 damp 10 diameter 1 69e-6 lower z 0 upper target 0.66e-3 0.4e-3 5
fix endsz ends setforce 0 0 NULL
fix pbc ends ncf/pbc faces x
timestep 1e-8
run 4000
)",
                                 "f_plate[10]");
  expect_same_on_ranks(runs, 1e-7, 1e-10 * MAT_LX, "plate + pbc compaction");
  // the upper plate presses, and its largest penetration (a maximum over the ranks) is the same
  if (world_rank() == 0) {
    EXPECT_GT(runs[0].value, 0.0);
    for (int k = 1; k < 3; k++) EXPECT_NEAR(runs[k].value, runs[0].value, 1e-6 * runs[0].value);
  }
}
