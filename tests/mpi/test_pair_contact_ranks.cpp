// pair ncf/contact on 1, 2 and 4 MPI ranks (newton on, periodic in x and y, friction history):
// a 50-chain mat compacted by a moving wall for 2000 steps ends in the same positions to 1e-10
// (relative to the box), with the contacts of the serial brute-force reference on every rank count; a run restarted in the middle on another number of ranks too, and a run
// whose sub-domains fix balance moves every 100 steps (the friction history migrates with the
// atoms through the per-atom rows that fix ncf/contact/history writes before they move), also
// when fix balance weighs the atoms by the style's work estimate (work yes, d_ncf_work).

#include "mpi_layered_mat.h"
#include "ncf_lammps_test.h"

#include "atom.h"
#include "comm.h"
#include "lammps.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ncftest;
using namespace contactscene;

namespace {

using mpimat::SIDE;

std::string scene_data()
{
  return mpimat::scene_data("contact_ranks");
}

const char *PRESS = R"(
variable ztop equal zhi-10.0*time
fix wtop all wall/harmonic zhi v_ztop 1e4 0.0 3.45e-5
fix wbot all wall/harmonic zlo EDGE 1e4 0.0 3.45e-5
fix nve all nve
fix visc all viscous 1e-4
timestep 5e-9
thermo 0
)";

void define(Lammps &l)
{
  l.cmds(R"(
units si
atom_style bond
atom_modify map array sort 0 0
boundary p p f
bond_style ncf/chain
)");
  l.cmd("read_data " + scene_data());
  l.cmds(R"(
bond_coeff 1 modulus 120e9 diameter 69e-6
pair_style ncf/contact
pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6
comm_modify vel yes
neighbor 2e-5 bin
neigh_modify every 1 delay 0 check yes
velocity all set 0 0 0
timestep 5e-9
)");
}

// runs f on the first n ranks of MPI_COMM_WORLD; returns the positions on world rank 0
std::vector<double> positions_on_ranks(int n, const std::function<std::vector<double>(MPI_Comm)> &f)
{
  std::vector<double> out;
  on_ranks(n, [&](MPI_Comm comm) {
    out = f(comm);
  });
  return out;
}

double rel_diff(const std::vector<double> &a, const std::vector<double> &b)
{
  if (a.size() != b.size() || a.empty()) return 1e300;
  return max_abs_diff(a, b) / SIDE;
}

}    // namespace

TEST(PairContactRanks, SameTrajectoryOn1And2And4Ranks)
{
  ASSERT_GE(world_size(), 4);
  scene_data();    // collective: written before the communicators are split
  const auto chains = mpimat::chains();
  double contacts = 0.0;
  auto run = [&](MPI_Comm comm) {
    Lammps l(comm);
    define(l);
    l.cmds(PRESS);
    l.cmd("compute pc all pair ncf/contact");
    l.cmd("thermo_style custom step pe c_pc[1] c_pc[2] c_pc[4]");
    l.cmd("run 2000");
    contacts = l.value("c_pc[1]");
    // against the serial brute-force reference of the contact law (every pair of the system, no
    // list, no ranks) at the final positions: the same contacts, caps and penetrations, so that
    // a fault common to every rank count (a pair listed twice, one missed) shows too
    const std::vector<double> x = l.positions();
    const double caps = l.value("c_pc[4]"), pensum = l.value("c_pc[2]");
    const int n = l.lmp->comm->nprocs;
    if (world_rank() == 0) {
      const Brute ref = brute_force(chains, x, SIDE, 1e8);
      EXPECT_EQ(contacts, ref.contacts) << n << " ranks";
      EXPECT_EQ(caps, ref.caps) << n << " ranks";
      EXPECT_NEAR(pensum, ref.pensum, 1e-9 * ref.pensum) << n << " ranks";
    }
    return x;
  };
  auto p1 = positions_on_ranks(1, run);
  auto p2 = positions_on_ranks(2, run);
  auto p4 = positions_on_ranks(4, run);
  if (world_rank() == 0) {
    EXPECT_GT(contacts, 50.0) << "the mat must be in contact";
    EXPECT_LT(rel_diff(p1, p2), 1e-10);
    EXPECT_LT(rel_diff(p1, p4), 1e-10);
    printf(
        "[ pair ncf/contact ] %g contacts; max |dx| / box: 1 vs 2 ranks %.3g, 1 vs 4 ranks %.3g\n",
        contacts, rel_diff(p1, p2), rel_diff(p1, p4));
    // and the compaction moved the chains (the comparison is not trivial)
    std::vector<double> p0;
    {
      Lammps l(MPI_COMM_SELF);
      define(l);
      l.cmd("run 0");
      p0 = l.positions();
    }
    EXPECT_GT(rel_diff(p1, p0), 1e-4);
  }
}

TEST(PairContactRanks, RestartInTheMiddleOnOtherRankCounts)
{
  ASSERT_GE(world_size(), 4);
  scene_data();
  const std::string restart = scratch_dir("contact_ranks_restart") + "/mid.restart";
  auto straight = positions_on_ranks(1, [&](MPI_Comm comm) {
    Lammps l(comm);
    define(l);
    l.cmds(PRESS);
    l.cmd("run 1000");
    l.cmd("run 1000");
    return l.positions();
  });
  positions_on_ranks(4, [&](MPI_Comm comm) {
    Lammps l(comm);
    define(l);
    l.cmds(PRESS);
    l.cmd("run 1000");
    l.cmd("write_restart " + restart);
    return std::vector<double>();
  });
  auto resumed = positions_on_ranks(2, [&](MPI_Comm comm) {
    Lammps l(comm);
    l.cmd("read_restart " + restart);
    l.cmds(R"(
bond_coeff 1 modulus 120e9 diameter 69e-6
comm_modify vel yes
neighbor 2e-5 bin
neigh_modify every 1 delay 0 check yes
)");
    l.cmds(PRESS);
    l.cmd("run 1000");
    return l.positions();
  });
  if (world_rank() == 0) {
    EXPECT_LT(rel_diff(straight, resumed), 1e-10);
    printf("[ pair ncf/contact ] restart 4 -> 2 ranks vs straight run on 1 rank: max |dx| / box "
           "%.3g\n",
           rel_diff(straight, resumed));
  }
}

TEST(PairContactRanks, BalancingMovesTheHistoryWithTheAtoms)
{
  ASSERT_GE(world_size(), 4);
  scene_data();
  auto run = [&](bool balance) {
    return [balance](MPI_Comm comm) {
      Lammps l(comm);
      define(l);
      if (balance) l.cmd("fix bal all balance 100 1.0 shift xy 10 1.0");
      l.cmds(PRESS);
      l.cmd("run 2000");
      return l.positions();
    };
  };
  auto straight = positions_on_ranks(1, run(false));
  auto balanced = positions_on_ranks(4, run(true));
  if (world_rank() == 0) {
    EXPECT_LT(rel_diff(straight, balanced), 1e-10);
    printf("[ pair ncf/contact ] 4 balanced ranks vs 1 rank: max |dx| / box %.3g\n",
           rel_diff(straight, balanced));
  }
}

// work yes: fix balance weighing every node by d_ncf_work. The ranks' shares of the estimated work
// end closer to equal than with every node weighing the same (the mat's contacts are uneven: more
// of them near the lower plate), and the trajectory is that of one rank.
TEST(PairContactRanks, BalancingByTheWorkEstimate)
{
  ASSERT_GE(world_size(), 4);
  scene_data();
  double imbalance[2] = {0.0, 0.0};    // largest rank's share of the work / the mean, at the end
  auto run = [&](int weighted) {
    return [&imbalance, weighted](MPI_Comm comm) {
      Lammps l(comm);
      define(l);
      l.cmd("pair_style ncf/contact work yes");
      l.cmd("pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6");
      l.cmd("variable w atom d_ncf_work");
      l.cmd(std::string("fix bal all balance 100 1.0 shift xy 10 1.0") +
            (weighted ? " weight var w" : ""));
      l.cmds(PRESS);
      l.cmd("run 2000");
      // (the estimate of the last list build, the cuts of the last balancing before it)
      LAMMPS_NS::Atom *atom = l.lmp->atom;
      int flag = -1, cols = -1;
      const int idx = atom->find_custom("ncf_work", flag, cols);
      double mine = 0.0, most = 0.0, all = 0.0;
      for (int i = 0; i < atom->nlocal; i++) mine += atom->dvector[idx][i];
      MPI_Allreduce(&mine, &most, 1, MPI_DOUBLE, MPI_MAX, comm);
      MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, comm);
      imbalance[weighted] = most / (all / l.lmp->comm->nprocs);
      return l.positions();
    };
  };
  auto straight = positions_on_ranks(1, run(0));
  auto by_nodes = positions_on_ranks(4, run(0));
  auto by_work = positions_on_ranks(4, run(1));
  if (world_rank() == 0) {
    EXPECT_LT(rel_diff(straight, by_work), 1e-10);
    EXPECT_LT(rel_diff(straight, by_nodes), 1e-10);
    EXPECT_LT(imbalance[1], imbalance[0]) << "weighing by the work estimate balances it better";
    printf("[ pair ncf/contact ] 4 ranks balanced by d_ncf_work vs 1 rank: max |dx| / box %.3g; "
           "largest share of the estimated work / mean: %.4f by nodes, %.4f by d_ncf_work\n",
           rel_diff(straight, by_work), imbalance[0], imbalance[1]);
  }
}
