// fix ncf/pbc on 1, 2 and 4 MPI ranks: the same trajectory to round-off, with a box deformation.

#include "ncf_lammps_test.h"
#include "ncf_scenes.h"

#include <gtest/gtest.h>

#include <string>

using namespace ncftest;

namespace {
void same_on_ranks(const char *dir, unsigned seed, const std::string &keywords, const char *what)
{
  ASSERT_GE(world_size(), 4) << "run this test with mpirun -np 4";
  auto runs = mat_on_1_2_4_ranks(scratch_dir(dir), seed,
                                 R"(
change_box all triclinic
velocity all create 5e12 5 loop geom
fix nve all nve
fix deform all deform 1 x erate 500 xy erate 1000 remap x
fix pbc ends ncf/pbc faces x )" + keywords +
                                     R"(
timestep 5e-9
run 2000
)",
                                 "");
  expect_same_on_ranks(runs, 1e-7, 1e-12 * MAT_LX, what);
}
}    // namespace

TEST(FixPBCMPI, SameTrajectoryOn124Ranks)
{
  same_on_ranks("mpi_pbc", 21, "", "fix ncf/pbc with box deformation");
}

TEST(FixPBCMPI, NormalHoldSameTrajectoryOn124Ranks)
{
  same_on_ranks("mpi_pbc_hold", 22, "normal hold", "fix ncf/pbc normal hold with box deformation");
}
