// fix ncf/needles on 1, 2 and 4 MPI ranks: the same piercing trajectory to round-off, with a
// needle close to a periodic face (its image acts on chains across it).

#include "ncf_lammps_test.h"
#include "ncf_scenes.h"

#include <gtest/gtest.h>

using namespace ncftest;

TEST(FixNeedlesMPI, SamePiercingOn124Ranks)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto runs = mat_on_1_2_4_ranks(scratch_dir("mpi_needles"), 61, R"(
fix nve all nve
fix damp all viscous 2e-7
fix needles all ncf/needles diameter 0.3e-3 kn 2e9 chain 1 69e-6 at 0.7e-3 0.5e-3 at 1.95e-3 1.2e-3 target 0.7e-3 0.1e-3 20 tip 0.2e-3 length 1e-3
fix pbc ends ncf/pbc
timestep 8e-9
run 3000
)",
                                 "f_needles[2]");
  if (world_rank() == 0) EXPECT_NE(runs[0].value, 0.0);    // the needles push on the chains
  expect_same_on_ranks(runs, 1e-6, 1e-10 * MAT_LX, "needles");
}
