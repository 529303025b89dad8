// fix ncf/pbc on 1, 2 and 4 MPI ranks: the same trajectory to round-off, with a box deformation.

#include "ncf_lammps_test.h"
#include "ncf_scenes.h"

#include <gtest/gtest.h>

using namespace ncftest;

TEST(FixPBCMPI, SameTrajectoryOn124Ranks)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto runs = mat_on_1_2_4_ranks(scratch_dir("mpi_pbc"), 21, R"(
change_box all triclinic
velocity all create 5e12 5 loop geom
fix nve all nve
fix deform all deform 1 x erate 500 xy erate 1000 remap x
fix pbc ends ncf/pbc faces x
timestep 5e-9
run 2000
)",
                                 "");
  expect_same_on_ranks(runs, 1e-7, 1e-12 * MAT_LX, "fix ncf/pbc with box deformation");
}

TEST(FixPBCMPI, NormalHoldSameTrajectoryOn124Ranks)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto runs = mat_on_1_2_4_ranks(scratch_dir("mpi_pbc_hold"), 22, R"(
change_box all triclinic
velocity all create 5e12 5 loop geom
fix nve all nve
fix deform all deform 1 x erate 500 xy erate 1000 remap x
fix pbc ends ncf/pbc faces x normal hold
timestep 5e-9
run 2000
)",
                                 "");
  expect_same_on_ranks(runs, 1e-7, 1e-12 * MAT_LX, "fix ncf/pbc normal hold with box deformation");
}
