// Integration tests of the per-atom outputs and the explicit virial of pair_style ncf/contact
// (plugin auto-loaded): compute pe/atom sums to the contact energy and compute stress/atom to
// the contact virial on a periodic mat with friction, dashpots, node caps and free chain ends
// (contacts across the periodic faces, so ghost shares are summed back); `pair_modify nofdotr`
// gives the f dot r virial; asking for any of them leaves the trajectory unchanged bit for bit.
// (LAMMPS's own harness checks the same on a small scene: tests/harness.)

#include "ncf_lammps_test.h"
#include "test_pair_contact_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace ncftest;
using namespace contactscene;

namespace {

const double MESH = 1e-4;

// three layers of parallel chains pressed slightly into each other (layer spacing 0.9 D),
// periodic in x and y, chains 0.8 mm long in a 1 mm box (free ends inside the box, chains across
// the periodic faces), random node velocities of ~1 m/s (friction and dashpots from the start)
std::string mat_scene(const std::string &dir)
{
  Box box;
  box.lo[0] = box.lo[1] = 0.0;
  box.hi[0] = box.hi[1] = 1e-3;
  box.lo[2] = -2e-4;
  box.hi[2] = 4e-4;
  const auto chains = layered_mat(3, 5, 1e-3, MESH, 0.9 * DIAM, 20261125);
  const std::string data = write_data(dir + "/mat.data", chains, box, RHO_A * MESH);
  return "units si\natom_style bond\natom_modify map array\nboundary p p f\n"
         "bond_style ncf/chain\nread_data " +
      data +
      "\nbond_coeff 1 modulus 120e9 diameter 69e-6\n"
      "pair_style ncf/contact\npair_coeff * * kn 1e8 mu 0.3 damp 20 diameter 69e-6\n"
      "comm_modify vel yes\ntimestep 2e-9\nneighbor 2e-5 bin\n"
      "velocity all create 4e13 4928459 mom yes loop geom\nfix 1 all nve\n";
}

// the computes of the per-atom outputs and the pair's global ones, in thermo every step
const char *PERATOM = R"(
compute pea all pe/atom pair
compute pesum all reduce sum c_pea
compute sa all stress/atom NULL pair
compute sasum all reduce sum c_sa[1] c_sa[2] c_sa[3] c_sa[4] c_sa[5] c_sa[6]
compute csa all centroid/stress/atom NULL pair
compute csasum all reduce sum c_csa[*]
compute pp all pressure NULL pair
compute pc all pair ncf/contact
thermo_style custom step evdwl c_pesum c_pp[*] c_sasum[*] c_csasum[*] c_pc[1] c_pc[4] vol
thermo 1
)";

const char *GLOBAL = R"(
compute pp all pressure NULL pair
thermo_style custom step evdwl c_pp[*] vol
thermo 1
)";

}    // namespace

TEST(PairContactPerAtom, EnergyAndVirialSumToTheTotals)
{
  auto dir = scratch_dir("pair_peratom_sums");
  Lammps l;
  l.cmds(mat_scene(dir));
  l.cmds(PERATOM);
  for (int run = 0; run < 3; run++) {
    l.cmd("run 40");
    // a scene with contacts, caps, friction
    ASSERT_GT(l.value("c_pc[1]"), 10.0);
    ASSERT_GT(l.value("c_pc[4]"), 0.0);
    const double e = l.value("evdwl");
    ASSERT_GT(e, 0.0);
    EXPECT_NEAR(l.value("c_pesum"), e, 1e-12 * e);
    // stress/atom is -(virial) per atom (pressure x volume; SI: nktv2p = 1), the pressure
    // virial / V
    const double vol = l.value("vol");
    double pmax = 0.0;
    for (int c = 1; c <= 6; c++)
      pmax = std::max(pmax, std::fabs(l.value("c_pp[" + std::to_string(c) + "]")));
    ASSERT_GT(pmax, 0.0);
    for (int c = 1; c <= 6; c++) {
      const double p = l.value("c_pp[" + std::to_string(c) + "]");
      EXPECT_NEAR(-l.value("c_sasum[" + std::to_string(c) + "]") / vol, p, 1e-11 * pmax)
          << "run " << run << " component " << c;
      // the centroid form: the same sums
      EXPECT_NEAR(-l.value("c_csasum[" + std::to_string(c) + "]") / vol, p, 1e-11 * pmax)
          << "run " << run << " component " << c;
    }
    // (yx zx zy differ from xy xz yz: the friction forces of a contact act one contact distance
    // apart, a couple that makes the virial asymmetric, by the order of mu)
  }
}

// the explicit virial (pair_modify nofdotr) against f dot r, and the trajectory with per-atom
// outputs, without, and with nofdotr: the same bits
TEST(PairContactPerAtom, NofdotrVirialAndUnchangedTrajectory)
{
  auto dir = scratch_dir("pair_peratom_nofdotr");
  struct Result {
    std::vector<double> x, v, p;
  };
  auto run = [&](const char *outputs, bool nofdotr) {
    Result r;
    Lammps l;
    l.cmds(mat_scene(dir));
    if (nofdotr) l.cmd("pair_modify nofdotr");
    l.cmds(outputs);
    for (int k = 0; k < 3; k++) {
      l.cmd("run 30");
      for (int c = 1; c <= 6; c++) r.p.push_back(l.value("c_pp[" + std::to_string(c) + "]"));
    }
    r.x = l.positions();
    r.v = l.velocities();
    return r;
  };
  const Result plain = run(GLOBAL, false);
  const Result peratom = run(PERATOM, false);
  const Result explicit_virial = run(GLOBAL, true);
  const Result both = run(PERATOM, true);
  for (const Result *r : {&peratom, &explicit_virial, &both}) {
    EXPECT_EQ(r->x, plain.x);
    EXPECT_EQ(r->v, plain.v);
  }
  EXPECT_EQ(peratom.p, plain.p);
  double pmax = 0.0;
  for (double p : plain.p) pmax = std::max(pmax, std::fabs(p));
  ASSERT_GT(pmax, 0.0);
  for (size_t k = 0; k < plain.p.size(); k++) {
    EXPECT_NE(explicit_virial.p[k], 0.0) << k;
    EXPECT_NEAR(explicit_virial.p[k], plain.p[k], 1e-12 * pmax) << k;
    EXPECT_EQ(both.p[k], explicit_virial.p[k]) << k;
  }
}
