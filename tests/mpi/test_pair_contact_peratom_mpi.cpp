// Per-atom energy and virial of pair ncf/contact on 1, 2 and 4 MPI ranks (newton on, periodic in
// x and y, friction and dashpot): compute pe/atom and compute stress/atom sum to the contact
// energy and virial on every rank count (the shares of ghost nodes, owned by other ranks, summed
// back), and pair_modify nofdotr gives the f dot r virial; the sums agree across rank counts.

#include "mpi_layered_mat.h"
#include "ncf_lammps_test.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace ncftest;
using namespace contactscene;

namespace {

// evdwl, the sum of pe/atom, the pair pressure tensor times the volume (6), minus the sum of
// stress/atom (6), the same tensor with nofdotr (6), the contacts
struct Sums {
  double evdwl = 0.0, pesum = 0.0, contacts = 0.0;
  double pv[6] = {}, sa[6] = {}, pv_nofdotr[6] = {};
};

Sums run_on(MPI_Comm comm, bool nofdotr)
{
  Lammps l(comm);
  l.cmds(R"(
units si
atom_style bond
atom_modify map array
boundary p p f
bond_style ncf/chain
)");
  l.cmd("read_data " + mpimat::scene_data("contact_peratom_mpi"));
  l.cmds(R"(
bond_coeff 1 modulus 120e9 diameter 69e-6
pair_style ncf/contact
pair_coeff * * kn 1e8 mu 0.3 damp 20 diameter 69e-6
comm_modify vel yes
neighbor 2e-5 bin
timestep 2e-9
velocity all create 4e13 4928459 mom yes loop geom
fix nve all nve
compute pea all pe/atom pair
compute pesum all reduce sum c_pea
compute sa all stress/atom NULL pair
compute sasum all reduce sum c_sa[*]
compute pp all pressure NULL pair
compute pc all pair ncf/contact
thermo_style custom step evdwl c_pesum c_pp[*] c_sasum[*] c_pc[1] vol
thermo 10
)");
  if (nofdotr) l.cmd("pair_modify nofdotr");
  l.cmd("run 60");
  Sums s;
  s.evdwl = l.value("evdwl");
  s.pesum = l.value("c_pesum");
  s.contacts = l.value("c_pc[1]");
  const double vol = l.value("vol");
  for (int c = 0; c < 6; c++) {
    const std::string k = std::to_string(c + 1);
    (nofdotr ? s.pv_nofdotr : s.pv)[c] = l.value("c_pp[" + k + "]") * vol;
    s.sa[c] = -l.value("c_sasum[" + k + "]");
  }
  return s;
}

}    // namespace

TEST(PairContactPerAtomRanks, SumsOn1And2And4Ranks)
{
  ASSERT_GE(world_size(), 4);
  mpimat::scene_data("contact_peratom_mpi");    // collective: before the communicators split
  std::vector<Sums> fdotr, explicit_virial;
  for (int n : {1, 2, 4})
    on_ranks(n, [&](MPI_Comm comm) {
      const Sums a = run_on(comm, false), b = run_on(comm, true);
      int me;
      MPI_Comm_rank(comm, &me);
      if (me == 0 && world_rank() == 0) {
        fdotr.push_back(a);
        explicit_virial.push_back(b);
      }
    });
  if (world_rank() != 0) return;
  ASSERT_EQ(fdotr.size(), 3u);
  const Sums &ref = fdotr[0];
  ASSERT_GT(ref.contacts, 50.0);
  ASSERT_GT(ref.evdwl, 0.0);
  double vmax = 0.0;
  for (double v : ref.pv) vmax = std::max(vmax, std::fabs(v));
  ASSERT_GT(vmax, 0.0);
  for (size_t r = 0; r < fdotr.size(); r++) {
    const Sums &a = fdotr[r], &b = explicit_virial[r];
    const int nprocs = 1 << r;
    EXPECT_NEAR(a.pesum, a.evdwl, 1e-12 * a.evdwl) << nprocs << " ranks";
    EXPECT_NEAR(b.pesum, b.evdwl, 1e-12 * b.evdwl) << nprocs << " ranks";
    for (int c = 0; c < 6; c++) {
      EXPECT_NEAR(a.sa[c], a.pv[c], 1e-11 * vmax) << nprocs << " ranks, component " << c;
      EXPECT_NEAR(b.pv_nofdotr[c], a.pv[c], 1e-11 * vmax) << nprocs << " ranks, component " << c;
      EXPECT_NEAR(b.sa[c], b.pv_nofdotr[c], 1e-11 * vmax) << nprocs << " ranks, component " << c;
      // (the trajectories differ across rank counts by round-off only)
      EXPECT_NEAR(a.pv[c], ref.pv[c], 1e-6 * vmax) << nprocs << " ranks, component " << c;
    }
    EXPECT_NEAR(a.evdwl, ref.evdwl, 1e-6 * ref.evdwl) << nprocs << " ranks";
  }
}
