// pair_style ncf/contact keeps its candidate segment pairs and node caps in lists that are only
// rebuilt when LAMMPS reneighbours. These tests compare the style with a brute-force evaluation
// of the same contact law over all segment pairs and all (segment, node) caps of the system
// (contactscene::brute_force: every periodic image, no list, no cutoff), step after step through a press of a random mat
// during which LAMMPS reneighbours many times: the number of contacts, of active caps and the
// contact energy must agree to round-off at every check, so a contact the lists dropped (a stale
// list, a pair missed at a build, a wrong image) would show.

#include "ncf_lammps_test.h"
#include "test_pair_contact_scene.h"

#include "lammps.h"
#include "neighbor.h"

#include "ncf_contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace ncftest;
using namespace contactscene;

namespace {
// a random mat (4 layers of 6 parallel chains at a random angle per layer, 1.3 diameters apart)
// pressed by a moving wall until the layers touch and beyond, then held, while the two middle
// layers slide against each other at 10 m/s in x; frictionless (the contact energy is then the
// sum of the law over the pairs). Contacts form, slide from segment to segment and end all
// through the run.
const double SIDE = 1.0e-3, KN = 1e10;
std::vector<Chain> press_scene(Lammps &l, const std::string &neighbor)
{
  auto dir = scratch_dir("contact_list");
  const double dz = 1.3 * DIAM;
  auto chains = layered_mat(4, 6, SIDE, 1e-4, dz, 5);
  Box box;
  box.lo[0] = box.lo[1] = 0.0;
  box.hi[0] = box.hi[1] = SIDE;
  box.lo[2] = -0.5 * DIAM;
  box.hi[2] = 4 * dz;
  l.cmds("units si\natom_style bond\natom_modify map array sort 0 0\nboundary p p f\n"
         "bond_style ncf/chain\nread_data " +
         write_data(dir + "/m.data", chains, box, RHO_A * 1e-4) +
         "\nbond_coeff 1 modulus 120e9 diameter 69e-6\npair_style ncf/contact\n"
         "pair_coeff * * kn 1e10 diameter 69e-6\n" +
         neighbor +
         "\ncompute pc all pair ncf/contact\nthermo_style custom step pe evdwl c_pc[1] c_pc[4]\n");
  l.cmds(R"cmd(
variable ztop equal "zhi - 20*time*(20*time<1.5e-4) - 1.5e-4*(20*time>=1.5e-4)"
group mid1 molecule 7:12
group mid2 molecule 13:18
velocity mid1 set 10 0 0
velocity mid2 set -10 0 0
fix wtop all wall/harmonic zhi v_ztop 1e4 0.0 3.45e-5
fix wbot all wall/harmonic zlo EDGE 1e4 0.0 3.45e-5
fix nve all nve
fix visc all viscous 2e-5
timestep 5e-9
thermo 0
)cmd");
  return chains;
}
}    // namespace

TEST(PairContactList, SameContactsAsBruteForceThroughAPressWithReneighbouring)
{
  // the press scene with a large skin (60 um), so that a list that ignored the motion since its
  // build would miss contacts
  Lammps l;
  auto chains = press_scene(l, "neighbor 6e-5 bin\nneigh_modify every 1 delay 0 check yes");
  l.cmd("run 0");
  int checks = 0, bad = 0, maxcontacts = 0, maxcaps = 0;
  long builds = 0, steps = 0;
  for (int k = 0; k < 300; k++) {
    l.cmd("run 10 pre no post no");
    steps += 10;
    builds = (long) l.lmp->neighbor->ncalls;
    const Brute ref = brute_force(chains, l.positions(), SIDE, KN);
    const double contacts = l.value("c_pc[1]"), caps = l.value("c_pc[4]");
    const double energy = l.value("evdwl");
    checks++;
    maxcontacts = std::max(maxcontacts, ref.contacts);
    maxcaps = std::max(maxcaps, ref.caps);
    EXPECT_EQ(contacts, ref.contacts) << "step " << steps;
    EXPECT_EQ(caps, ref.caps) << "step " << steps;
    EXPECT_NEAR(energy, ref.energy, 1e-9 * ref.energy) << "step " << steps;
    if (contacts != ref.contacts || caps != ref.caps) bad++;
    if (bad > 5) break;
  }
  // the comparison is not trivial: many contacts and caps, LAMMPS reneighboured many times, and
  // the lists were reused in between
  EXPECT_GT(maxcontacts, 25);
  EXPECT_GT(maxcaps, 0);
  EXPECT_GT(builds, 10);
  EXPECT_LT(builds, steps / 2);
  printf("[ pair ncf/contact ] lists vs brute force: %d checks, up to %d contacts and %d caps, "
         "%ld neighbour builds in %ld steps\n",
         checks, maxcontacts, maxcaps, builds, steps);
}

TEST(PairContactList, StopsWhenNodesMoveMoreThanHalfTheSkinBetweenBuilds)
{
  // reneighbouring only every 1000 steps without the distance check: the sliding layers move
  // more than skin/2 (10 um) in between, the lists could miss contacts, the style stops
  const std::string err = error_of([&] {
    Lammps l;
    press_scene(l, "neighbor 2e-5 bin\nneigh_modify every 1000 delay 0 check no");
    l.cmd("run 1000");
  });
  EXPECT_NE(err.find("more than half the neighbour skin"), std::string::npos) << err;
  EXPECT_NE(err.find("neigh_modify every 1 delay 0 check yes"), std::string::npos) << err;
}
