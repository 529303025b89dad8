// Split-run invariance of pair ncf/contact with friction on 2 and 4 MPI ranks: `run 20` against
// `run 7` + `run 13`, two `run 0` in between, and `run 7` + write_restart / read_restart (same
// rank count) + `run 13`, bit for bit on each rank count (the friction history migrating with
// the atoms, take-overs of slips owned by other ranks). LAMMPS reneighbours every step here, so
// that its own work at a cut (atoms moved to other ranks, wrapped, re-sorted at the setup) is the
// same as in the uncut run; see tests/integration/test_split_runs.cpp for the one-rank scenes.

#include "mpi_layered_mat.h"
#include "ncf_lammps_test.h"

#include "fmt/format.h"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

using namespace ncftest;
using namespace contactscene;

namespace {

using mpimat::SIDE;

std::string scene_data()
{
  return mpimat::scene_data("split_ranks");
}

const char *RUN = R"(
comm_modify vel yes
neighbor 2e-5 bin
neigh_modify every 1 delay 0 check no
compute pc all pair ncf/contact
thermo_style custom step pe c_pc[1]
thermo 0
fix nve all nve
timestep 5e-9
)";

void define(Lammps &l)
{
  l.cmds("units si\natom_style bond\natom_modify map array sort 0 0\nboundary p p f\n"
         "bond_style ncf/chain");
  l.cmd("read_data " + scene_data());
  l.cmds(R"(
bond_coeff 1 modulus 120e9 diameter 69e-6
pair_style ncf/contact
pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6
velocity all create 1e12 4 mom yes rot no dist gaussian
)");
  l.cmds(RUN);
}

struct State {
  std::vector<double> x, v, f;
  double contacts = 0.0;
};

State state(Lammps &l)
{
  State s{l.positions(), l.velocities(), l.forces(), 0.0};
  s.contacts = l.value("c_pc[1]");
  return s;
}

void expect_same(const State &a, const State &b, const std::string &what)
{
  EXPECT_EQ(max_abs_diff(a.x, b.x), 0.0) << what << ": positions";
  EXPECT_EQ(max_abs_diff(a.v, b.v), 0.0) << what << ": velocities";
  EXPECT_EQ(max_abs_diff(a.f, b.f), 0.0) << what << ": forces";
  EXPECT_EQ(a.x.size(), b.x.size()) << what;
}

}    // namespace

TEST(SplitRunsRanks, PairContactFrictionOn2And4Ranks)
{
  ASSERT_GE(world_size(), 4);
  scene_data();    // collective: written before the communicators are split
  const std::string restart = scratch_dir("split_ranks_restart") + "/cut.restart";
  for (int n : {2, 4}) {
    State whole, cut, zero, viafile;
    on_ranks(n, [&](MPI_Comm comm) {
      {
        Lammps l(comm);
        define(l);
        l.cmd("run 20");
        whole = state(l);
      }
      {
        Lammps l(comm);
        define(l);
        l.cmd("run 7");
        l.cmd("run 13");
        cut = state(l);
      }
      {
        Lammps l(comm);
        define(l);
        l.cmd("run 7");
        l.cmd("run 0");
        l.cmd("run 0");
        l.cmd("run 13");
        zero = state(l);
      }
      {
        auto l = std::make_unique<Lammps>(comm);
        define(*l);
        l->cmd("run 7");
        l->cmd("write_restart " + restart);
        l.reset();
        l = std::make_unique<Lammps>(comm);
        l->cmd("read_restart " + restart);
        l->cmd("bond_coeff 1 modulus 120e9 diameter 69e-6");
        l->cmds(RUN);
        l->cmd("run 13");
        viafile = state(*l);
      }
    });
    if (world_rank() == 0) {
      EXPECT_GT(whole.contacts, 50.0) << "the mat must be in contact";
      expect_same(cut, whole, fmt::format("{} ranks: run 7 + run 13 vs run 20", n));
      expect_same(zero, whole, fmt::format("{} ranks: run 7 + run 0 + run 0 + run 13", n));
      expect_same(viafile, whole, fmt::format("{} ranks: run 7 + restart + run 13", n));
    }
  }
}
