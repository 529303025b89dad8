// Integration tests of pair_style ncf/contact through LAMMPS (plugin auto-loaded): balance and
// outputs, exactly-once counting across periodic boundaries, parallel contact independent of the
// mesh, friction at mu F_n while sliding over many nodes, Coulomb stick/slide, frictionless
// energy conservation, dissipation and momentum with friction, restart with history, no
// pass-through under a fast press, mu = 0 without history, error messages.

#include "ncf_lammps_test.h"
#include "ncf_passthrough.h"
#include "test_pair_contact_scene.h"

#include "atom.h"
#include "comm.h"
#include "fix.h"
#include "fmt/format.h"
#include "force.h"
#include "lammps.h"
#include "modify.h"
#include "pair.h"

#include "ncf_contact.h"
#include "pair_ncf_contact.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>

using namespace ncftest;
using namespace contactscene;
using ::testing::HasSubstr;

namespace {

const double KN = 1e8;
const double MESH = 1e-4;
const double NODE_MASS = RHO_A * MESH;

std::string setup(const std::string &data, const std::string &boundary = "f f f",
                  const std::string &coeff = "pair_coeff * * kn 1e8 diameter 69e-6",
                  const std::string &style = "pair_style ncf/contact")
{
  return "units si\natom_style bond\natom_modify map array sort 0 0\nboundary " + boundary +
      "\nbond_style ncf/chain\nread_data " + data +
      "\nbond_coeff 1 modulus 120e9 diameter 69e-6\n" + style + "\n" + coeff +
      "\ncomm_modify vel yes\ntimestep 1e-9\nneighbor 2e-5 bin\nneigh_modify every 1 delay 0 check "
      "yes\n"
      "compute pc all pair ncf/contact\nthermo_style custom step pe ke evdwl c_pc[1] c_pc[2] "
      "c_pc[3]\n";
}

std::vector<Chain> crossed(double gap, std::array<double, 3> shift = {0, 0, 0})
{
  const double h = 5 * MESH;
  auto a = straight({-h + shift[0], shift[1], shift[2]}, {h + shift[0], shift[1], shift[2]}, 10);
  auto b = straight({0.013e-3 + shift[0], -h + shift[1], gap + shift[2]},
                    {0.013e-3 + shift[0], h + shift[1], gap + shift[2]}, 10);
  return {a, b};
}

double sum_over(const std::vector<double> &v, int first, int last, int dim)
{
  double s = 0.0;
  for (int i = first; i <= last; i++) s += v[3 * (i - 1) + dim];
  return s;
}

// run 0, then: the forces on the atoms ids are -d(pe)/dx by central differences (to 1e-5 of
// the largest force), and the forces on atoms 1..natoms sum to zero
void expect_forces_are_energy_gradient(Lammps &l, std::initializer_list<int> ids, int natoms)
{
  l.cmd("run 0");
  const auto f = l.forces();
  const auto x0 = l.positions();
  double fmax = 0.0;
  for (double v : f) fmax = std::max(fmax, std::fabs(v));
  for (int d = 0; d < 3; d++) EXPECT_NEAR(sum_over(f, 1, natoms, d), 0.0, 1e-9 * fmax) << d;
  const double h = 1e-10;
  for (int id : ids)
    for (int d = 0; d < 3; d++)
      EXPECT_NEAR(f[3 * (id - 1) + d], -l.energy_derivative("pe", id, d, x0[3 * (id - 1) + d], h),
                  1e-5 * fmax)
          << id << " " << d;
}

}    // namespace

TEST(PairContact, CrossedChainsBalanceAndOutputs)
{
  auto dir = scratch_dir("contact_crossed");
  const double gap = 0.9 * DIAM;
  Lammps l;
  l.cmds(setup(write_data(dir + "/c.data", crossed(gap), Box(), NODE_MASS)));
  l.cmd("run 0");
  auto f = l.forces();
  // chain 1 = atoms 1..11 pushed down, chain 2 = 12..22 pushed up, equal and opposite
  const double fz1 = sum_over(f, 1, 11, 2), fz2 = sum_over(f, 12, 22, 2);
  EXPECT_LT(fz1, 0.0);
  EXPECT_NEAR(fz1, -fz2, 1e-12 * std::fabs(fz1));
  for (int d = 0; d < 2; d++) EXPECT_NEAR(sum_over(f, 1, 11, d), 0.0, 1e-9 * std::fabs(fz1));
  EXPECT_GT(l.value("evdwl"), 0.0);
  // the crossing sits on a node of chain 1: two segments of each chain touch -> 4 pairs
  EXPECT_EQ(l.value("c_pc[1]"), 4.0);
  EXPECT_NEAR(l.value("c_pc[3]"), DIAM - gap, 1e-12);
  const double dx = 0.013e-3;    // chain 2 runs 13 um beside the node of chain 1
  EXPECT_NEAR(l.value("c_pc[2]"), 2 * (DIAM - gap) + 2 * (DIAM - std::sqrt(gap * gap + dx * dx)),
              1e-12);
}

TEST(PairContact, EnergyGradientThroughLammps)
{
  auto dir = scratch_dir("contact_fd");
  Lammps l;
  auto chains = crossed(0.85 * DIAM);
  chains[1].x[5][2] -= 3e-6;    // kink the upper chain near the crossing
  chains[1].x[6][0] += 2e-5;
  l.cmds(setup(write_data(dir + "/c.data", chains, Box(), NODE_MASS)));
  expect_forces_are_energy_gradient(l, {5, 6, 7, 16, 17, 18}, 22);
}

// Two chains crossing beyond their free ends, inside the end caps only (0.2 D beyond one end,
// 0.25 D beyond the other): the forces, which the style puts on the extended ends and maps back
// onto the end nodes and their neighbours, are -dE/dx there and balance
TEST(PairContact, EnergyGradientAtFreeChainEnds)
{
  auto dir = scratch_dir("contact_fd_ends");
  const double h = 5 * MESH, gap = 0.85 * DIAM;
  const double xc = h + 0.2 * DIAM, yend = -0.25 * DIAM;
  auto a = straight({-h, 0.0, 0.0}, {h, 0.0, 0.0}, 10);
  auto b = straight({xc, yend - 2 * h, gap}, {xc, yend, gap}, 10);
  b.x[9][0] += 3e-6;    // the last segment of b a little askew
  Lammps l;
  l.cmds(setup(write_data(dir + "/e.data", {a, b}, Box(), NODE_MASS)));
  l.cmd("run 0");
  ASSERT_GE(l.value("c_pc[1]"), 1.0);
  ASSERT_GT(l.value("evdwl"), 0.0);
  expect_forces_are_energy_gradient(l, {10, 11, 21, 22}, 22);
}

// Coefficients of two types not given for the pair 1 2 are mixed: kn as two springs in series,
// 2 kn1 kn2 / (kn1 + kn2); the forces are those of that kn given explicitly
TEST(PairContact, MixedStiffnessIsTwoSpringsInSeries)
{
  auto dir = scratch_dir("contact_mix");
  auto chains = crossed(0.9 * DIAM);
  chains[1].type = 2;
  const std::string data = write_data(dir + "/m.data", chains, Box(), NODE_MASS, 2);
  const std::string own =
      "pair_coeff 1 1 kn 1e8 diameter 69e-6\npair_coeff 2 2 kn 4e8 diameter 69e-6";
  std::vector<double> f[2];
  for (int k = 0; k < 2; k++) {
    Lammps l;
    l.cmds(setup(data, "f f f", k ? own + "\npair_coeff 1 2 kn 1.6e8 diameter 69e-6" : own));
    l.cmd("run 0");
    ASSERT_EQ(l.value("c_pc[1]"), 4.0);
    f[k] = l.forces();
  }
  double fmax = 0.0;
  for (double v : f[1]) fmax = std::max(fmax, std::fabs(v));
  EXPECT_GT(fmax, 0.0);
  EXPECT_LT(max_abs_diff(f[0], f[1]), 1e-12 * fmax);
}

// The critical time step of the contacts, sqrt(2 m / (kn L)) with L the node's two half
// segments: a time step 1 % above it stops the run with both numbers, 1 % below runs
TEST(PairContact, TimestepAboveTheContactCriticalStepIsRefused)
{
  auto dir = scratch_dir("contact_dt");
  const std::string data = write_data(dir + "/c.data", crossed(0.9 * DIAM), Box(), NODE_MASS);
  const double dtc = std::sqrt(2.0 * NODE_MASS / (KN * MESH));
  for (double ratio : {1.01, 0.99}) {
    Lammps l;
    l.cmds(setup(data));
    l.cmd("bond_coeff 1 ea 1e-3");    // (soft bonds: the bonds' own critical step is far above)
    l.cmd(fmt::format("timestep {:.17g}", ratio * dtc));
    const std::string err = error_of([&] {
      l.cmd("run 1");
    });
    if (ratio > 1.0) {
      EXPECT_THAT(err, HasSubstr(fmt::format("is above the critical time step {:.6g}", dtc)));
    } else {
      EXPECT_EQ(err, "");
    }
  }
}

// The lists hold while no node has moved more than half the skin since their build: with
// reneighbouring only every 1000 steps, a chain moved (fix move) by 0.45 skin in 100 steps runs,
// by 0.75 skin stops with the advice
TEST(PairContact, NodeMovingMoreThanHalfTheSkinBetweenBuildsStops)
{
  auto dir = scratch_dir("contact_skin");
  const std::string data = write_data(dir + "/c.data", crossed(0.9 * DIAM), Box(), NODE_MASS);
  const double skin = 2e-5, dt = 1e-9;
  for (double frac : {0.45, 0.75}) {
    Lammps l;
    l.cmds(setup(data));
    l.cmd("neigh_modify every 1000 delay 0 check no");
    l.cmd("group moving molecule 2");
    l.cmd(fmt::format("fix mv moving move linear {:.17g} 0 0", frac * skin / (100 * dt)));
    l.cmd(fmt::format("timestep {}", dt));
    const std::string err = error_of([&] {
      l.cmd("run 100");
    });
    if (frac < 0.5)
      EXPECT_EQ(err, "");
    else
      EXPECT_THAT(err, HasSubstr("more than half the neighbour skin"));
  }
}

// A pair of segments enters the lists at a build when its gap could close before the next one
// (nodes move at most skin/2 each): two chains crossing 0.9 skin apart, moved towards each other
// by 0.475 skin each in 99 steps (fix move, no reneighbouring in between), are in contact at the
// end, as the brute-force law says
TEST(PairContact, PairsThatCanCloseWithinTheSkinAreListed)
{
  auto dir = scratch_dir("contact_closing");
  const double skin = 2e-5, dt = 1e-9, v = 0.48 * skin / (100 * dt);
  const auto chains = crossed(DIAM + 0.9 * skin);
  Lammps l;
  l.cmds(setup(write_data(dir + "/c.data", chains, Box(), NODE_MASS)));
  l.cmd("neigh_modify every 1000 delay 0 check no");
  l.cmd("group lower molecule 1");
  l.cmd("group upper molecule 2");
  l.cmd(fmt::format("fix up lower move linear 0 0 {:.17g}", v));
  l.cmd(fmt::format("fix down upper move linear 0 0 {:.17g}", -v));
  l.cmd(fmt::format("timestep {}", dt));
  l.cmd("run 0");
  EXPECT_EQ(l.value("c_pc[1]"), 0.0);
  l.cmd("run 99");
  const Brute ref = brute_force(chains, l.positions(), 1e300, KN);
  ASSERT_GT(ref.contacts, 0);
  EXPECT_EQ(l.value("c_pc[1]"), ref.contacts);
}

TEST(PairContact, SameForcesAcrossPeriodicBoundary)
{
  // the crossing scene in the middle of a periodic box and shifted so that the crossing and
  // both chains straddle the periodic faces: the same forces, counted once
  auto dir = scratch_dir("contact_pbc");
  Box box;
  for (int d = 0; d < 3; d++) box.lo[d] = -1.5e-3, box.hi[d] = 1.5e-3;
  std::vector<double> ref;
  double nref = 0.0;
  for (int k = 0; k < 2; k++) {
    const std::array<double, 3> shift = k == 0
        ? std::array<double, 3>{0, 0, 0}
        : std::array<double, 3>{1.5e-3, 1.5e-3, 1.5e-3 - 3e-5};
    Lammps l;
    l.cmds(setup(write_data(dir + "/c" + std::to_string(k) + ".data", crossed(0.9 * DIAM, shift),
                            box, NODE_MASS),
                 "p p p"));
    l.cmd("run 0");
    auto f = l.forces();
    if (k == 0) {
      ref = f;
      nref = l.value("c_pc[1]");
      EXPECT_EQ(nref, 4.0);
    } else {
      EXPECT_EQ(l.value("c_pc[1]"), nref);
      double fmax = 0.0;
      for (double v : ref) fmax = std::max(fmax, std::fabs(v));
      EXPECT_LT(max_abs_diff(f, ref), 1e-9 * fmax);
    }
  }
}

TEST(PairContact, ParallelContactSameForMeshes)
{
  // chain 2 lies on chain 1 over 1 mm: the contact force is kn h (gap/D) l_c for mesh 0.2, 0.1,
  // 0.05 mm (within 2 %), and the force on chain 2 is a pure normal force (no torque). l_c is
  // the chain's length plus its two end caps (default endcap 0.5 D at each free end)
  auto dir = scratch_dir("contact_parallel");
  const double gap = 0.97 * DIAM, l = 1.0e-3;
  const double hpen = (DIAM * DIAM - gap * gap) / (2 * DIAM);
  const double expect = KN * hpen * gap / DIAM * (l + 2.0 * 0.5 * DIAM);
  for (double mesh : {0.2e-3, 0.1e-3, 0.05e-3}) {
    std::vector<Chain> chains = {
        straight({-1.5e-3, 0, 0}, {1.5e-3, 0, 0}, (int) std::lround(3e-3 / mesh)),
        straight({-0.5e-3 + 0.0137e-3, 0, gap}, {0.5e-3 + 0.0137e-3, 0, gap},
                 (int) std::lround(l / mesh))};
    Box box;
    box.lo[0] = -2e-3;
    box.hi[0] = 2e-3;
    Lammps lmp;
    lmp.cmds(setup(write_data(dir + "/p.data", chains, box, RHO_A * mesh)));
    lmp.cmd("run 0");
    auto f = lmp.forces();
    const int n1 = (int) chains[0].x.size(), n2 = (int) chains[1].x.size();
    const double fz = sum_over(f, n1 + 1, n1 + n2, 2);
    EXPECT_NEAR(fz, expect, 0.02 * expect) << "mesh " << mesh;
    // moment about the centre of chain 2 (y component: tilting)
    auto x = lmp.positions();
    double my = 0.0, cx = 0.0137e-3;
    for (int i = n1 + 1; i <= n1 + n2; i++) my += (x[3 * (i - 1)] - cx) * f[3 * (i - 1) + 2];
    EXPECT_LT(std::fabs(my), 1e-6 * expect * l) << "mesh " << mesh;
  }
}

namespace {
// a short chain (one segment across, or two along x) pressed with load `load` on a long fixed chain
// along x (mesh 0.05 mm: many element boundaries), dragged along x at speed v; returns the
// ratios |F_x| / F_z measured on the fixed chain every `every` steps once sliding. dir = -1: the
// mirrored scene, dragged towards -x; slider_first: the slider's tags before the fixed chain's
// (the contact then moves along the second segment of the pairs, not the first)
std::vector<double> slide_ratios(const std::string &dir, bool parallel, double mu, int nsteps,
                                 int every, double sense = 1.0, bool slider_first = false)
{
  const double mesh = 0.05e-3, heavy = 100.0;    // node masses x100 (mass scaling)
  std::vector<Chain> chains = {straight({-1.2e-3, 0, 0}, {1.2e-3, 0, 0}, 48)};
  const double z = 0.95 * DIAM, s = sense;
  if (parallel)
    chains.push_back(
        straight({s * (-0.9e-3 + 0.0111e-3), 0, z}, {s * (-0.7e-3 + 0.0111e-3), 0, z}, 2));
  else
    chains.push_back(straight({-s * 0.8e-3, -1e-4, z}, {-s * 0.8e-3, 1e-4, z}, 1));    // one
        // segment: a chain of several would drape over B
  if (slider_first) std::swap(chains[0], chains[1]);
  Box box;
  box.lo[0] = -1.5e-3;
  box.hi[0] = 1.5e-3;
  Lammps l;
  l.cmds(setup(write_data(dir + "/s.data", chains, box, heavy * RHO_A * mesh), "f f f",
               fmt::format("pair_coeff * * kn 1e8 mu {} kt 1.0 diameter 69e-6", mu)));
  l.cmd(fmt::format("group fixed molecule {}", slider_first ? 2 : 1));
  l.cmd(fmt::format("group slider molecule {}", slider_first ? 1 : 2));
  l.cmd(fmt::format("fix drag slider move linear {} NULL NULL", 2.0 * s));
  l.cmds(R"(
fix load slider addforce 0.0 0.0 -0.02
fix damp slider viscous 1e-6
compute fb fixed reduce sum fx fy fz
timestep 1e-8
thermo 0
)");
  l.cmd("run 2000");    // settle and start sliding
  std::vector<double> ratios;
  for (int k = 0; k < nsteps / every; k++) {
    l.cmd(fmt::format("run {} pre no post no", every));
    // friction along the fixed chain (x), normal force perpendicular to it (y, z)
    const double fx = l.value("c_fb[1]"), fy = l.value("c_fb[2]"), fz = l.value("c_fb[3]");
    ratios.push_back(std::fabs(fx) / std::sqrt(fy * fy + fz * fz));
  }
  return ratios;
}
}    // namespace

TEST(PairContact, SlidingFrictionStaysAtMuFnOverManyNodes)
{
  // 10000 steps at 2 m/s and dt 1e-8: 0.2 mm, across 4 elements of the fixed chain, sampled
  // every 20 steps (several samples per element, at and between nodes); towards both ends of the
  // fixed chain, with its tags before and after the slider's (the slip taken over past each of
  // the four nodes of a pair)
  auto dir = scratch_dir("contact_slide");
  const double mu = 0.3;
  for (bool parallel : {false, true})
    for (double sense : {1.0, -1.0})
      for (bool slider_first : {false, true}) {
        SCOPED_TRACE(fmt::format("{}, towards {}x, {} first", parallel ? "parallel" : "crossing",
                                 sense > 0 ? "+" : "-", slider_first ? "slider" : "fixed chain"));
        auto r = slide_ratios(dir, parallel, mu, 10000, 20, sense, slider_first);
        double lo = 1e9, hi = 0.0;
        for (double v : r) {
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
        std::printf("[measured] %s: ratio / mu in [%.5f, %.5f]\n",
                    parallel ? "parallel" : "crossing", lo / mu, hi / mu);
        EXPECT_GT(lo, 0.98 * mu) << "dip";
        EXPECT_LT(hi, 1.02 * mu) << "spike";
      }
}

TEST(PairContact, CoulombStickBelowAndSlideAtMuFn)
{
  auto dir = scratch_dir("contact_coulomb");
  const double mu = 0.3, load = 0.02;
  auto moved = [&](double pull) {
    std::vector<Chain> chains = {
        straight({-1e-3, 0, 0}, {1e-3, 0, 0}, 20),
        straight({0.0123e-3, -1e-4, 0.95 * DIAM}, {0.0123e-3, 1e-4, 0.95 * DIAM}, 1)};
    Lammps l;
    l.cmds(setup(write_data(dir + "/k.data", chains, Box(), 100 * NODE_MASS), "f f f",
                 "pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6"));
    l.cmds(fmt::format(R"(
group slider molecule 2
fix nve slider nve
fix load slider addforce {} 0.0 {}
fix damp slider viscous 5e-3
variable dx equal xcm(slider,x)
timestep 1e-8
thermo 0
)",
                       pull / 2.0, -load / 2.0));
    l.cmd("run 4000");
    const double x1 = l.value("v_dx");
    l.cmd("run 6000");
    return l.value("v_dx") - x1;
  };
  const double stick = moved(0.8 * mu * load), slide = moved(1.5 * mu * load);
  EXPECT_LT(std::fabs(stick), 1e-7) << "sticks below mu F_n";
  EXPECT_GT(slide, 1e-5) << "slides above mu F_n";
}

namespace {
// four chains in two crossing pairs flying into each other; all free, no fixes but nve
std::vector<Chain> collision_scene()
{
  return {straight({-4e-4, 0, 0}, {4e-4, 0, 0}, 8),
          straight({0.05e-3, -4e-4, 1.05 * DIAM}, {0.05e-3, 4e-4, 1.05 * DIAM}, 8),
          straight({-4e-4, 0.2e-3, 2.1 * DIAM}, {4e-4, 0.3e-3, 2.1 * DIAM}, 8),
          straight({-0.1e-3, -4e-4, 3.15 * DIAM}, {0.1e-3, 4e-4, 3.15 * DIAM}, 8)};
}
}    // namespace

TEST(PairContact, FrictionlessNveConservesEnergy)
{
  auto dir = scratch_dir("contact_nve");
  Lammps l;
  l.cmds(setup(write_data(dir + "/n.data", collision_scene(), Box(), NODE_MASS)));
  l.cmds(R"(
velocity all set 0 0 0
group c1 molecule 1 3
group c2 molecule 2 4
velocity c1 set 0.0 0.0 0.5
velocity c2 set 0.0 0.0 -0.5
fix nve all nve
variable etot equal pe+ke
timestep 2e-9
thermo 0
)");
  l.cmd("run 0");
  const double e0 = l.value("v_etot");
  double worst = 0.0, maxcontacts = 0.0;
  for (int k = 0; k < 100; k++) {
    l.cmd("run 100 pre no post no");
    worst = std::max(worst, std::fabs(l.value("v_etot") - e0) / e0);
    maxcontacts = std::max(maxcontacts, l.value("c_pc[1]"));
  }
  EXPECT_GE(maxcontacts, 2.0) << "the chains must actually collide";
  EXPECT_LT(worst, 1e-5);
  printf("[ pair ncf/contact ] frictionless NVE, 1e4 steps: max |E - E0| / E0 = %.3g, up to %g "
         "contacts\n",
         worst, maxcontacts);
}

TEST(PairContact, FrictionDissipatesAndConservesMomentum)
{
  auto dir = scratch_dir("contact_dissipation");
  Lammps l;
  l.cmds(setup(write_data(dir + "/d.data", collision_scene(), Box(), NODE_MASS), "f f f",
               "pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6"));
  l.cmds(R"(
group c1 molecule 1 3
group c2 molecule 2 4
velocity c1 set 0.3 0.0 0.5
velocity c2 set -0.2 0.1 -0.5
fix nve all nve
variable etot equal pe+ke
variable px equal vcm(all,x)*mass(all)
variable py equal vcm(all,y)*mass(all)
variable pz equal vcm(all,z)*mass(all)
timestep 2e-9
thermo 0
)");
  l.cmd("run 0");
  const double e0 = l.value("v_etot");
  const double p0[3] = {l.value("v_px"), l.value("v_py"), l.value("v_pz")};
  const double pscale = l.value("mass(all)") * 0.5;
  double prev_diss = 0.0, min_step = 0.0, total = 0.0;
  for (int k = 0; k < 100; k++) {
    l.cmd("run 100 pre no post no");
    const double diss = e0 - l.value("v_etot");
    min_step = std::min(min_step, diss - prev_diss);
    prev_diss = diss;
    total = diss;
    EXPECT_GE(diss, -1e-6 * e0) << "dissipated energy negative at block " << k;
    EXPECT_NEAR(l.value("v_px"), p0[0], 1e-12 * pscale);
    EXPECT_NEAR(l.value("v_py"), p0[1], 1e-12 * pscale);
    EXPECT_NEAR(l.value("v_pz"), p0[2], 1e-12 * pscale);
  }
  EXPECT_GT(total, 1e-3 * e0) << "friction must dissipate something in this scene";
  printf("[ pair ncf/contact ] friction: dissipated %.3g of E0, smallest step of dissipation %.3g "
         "E0\n",
         total / e0, min_step / e0);
  EXPECT_GE(min_step, -1e-6 * e0);
}

TEST(PairContact, RestartKeepsFrictionHistory)
{
  auto dir = scratch_dir("contact_restart");
  Box box;
  box.lo[0] = box.lo[1] = 0.0;
  box.hi[0] = box.hi[1] = 1.2e-3;
  const std::string data =
      write_data(dir + "/r.data", random_mat(12, 12, 1.2e-3, 1e-4, 0.9 * DIAM, 5), box, NODE_MASS);
  const std::string coeff = "pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6";
  const char *fixes = R"(
fix nve all nve
fix visc all viscous 1e-7
timestep 5e-9
thermo 0
)";
  std::vector<double> ref;
  {
    Lammps l;
    l.cmds(setup(data, "p p f", coeff));
    l.cmd("velocity all create 1e12 4 mom yes rot no dist gaussian");    // ~m/s at these masses
    l.cmds(fixes);
    l.cmd("run 100");
    EXPECT_GT(l.value("c_pc[1]"), 0.0) << "the history must matter: contacts at the restart";
    l.cmd("write_restart " + dir + "/mid.restart");
    l.cmd("run 500");
    ref = l.positions();
  }
  auto resumed = [&](bool drop_history) {
    Lammps l;
    l.cmd("read_restart " + dir + "/mid.restart");
    l.cmd("bond_coeff 1 modulus 120e9 diameter 69e-6");
    l.cmd("comm_modify vel yes");
    l.cmd("neighbor 2e-5 bin");
    l.cmd("neigh_modify every 1 delay 0 check yes");
    l.cmd("compute pc all pair ncf/contact");
    if (drop_history) {    // negative control: the test must see a lost history
      l.cmd("run 0");
      l.cmd("unfix NCF_CONTACT_HISTORY");    // (the pair style creates it again, empty)
    }
    l.cmds(fixes);
    l.cmd("run 500");
    return l.positions();
  };
  double scale = 0.0;
  for (double v : ref) scale = std::max(scale, std::fabs(v));
  EXPECT_LT(max_abs_diff(resumed(false), ref), 1e-10 * scale);
  EXPECT_GT(max_abs_diff(resumed(true), ref), 1e-9 * scale);
}

namespace {
std::string fmt_lmax(double lmax)
{
  char buf[64];
  snprintf(buf, sizeof buf, "pair_style ncf/contact lmax %.9g", lmax);
  return buf;
}

// node indices of the segments of a list of chains (nodes numbered chain after chain)
std::vector<std::pair<int, int>> segments_of(const std::vector<Chain> &chains)
{
  std::vector<std::pair<int, int>> segs;
  int id = 0;
  for (const auto &c : chains) {
    for (size_t k = 0; k + 1 < c.x.size(); k++) segs.emplace_back(id + (int) k, id + (int) k + 1);
    id += (int) c.x.size();
  }
  return segs;
}
}    // namespace

namespace {
// 4 layers of 6 chains (0.8 mm, mesh 0.1 mm, 1.3 D apart) pressed by a wall at `speed` until
// the top layer is 3 D above the bottom one, then held; returns the checker after 3000 steps
PassThroughChecker press(const std::string &dir, double kn, double speed, double &maxpen,
                         double &maxcontacts)
{
  const double side = 1.0e-3, dz = 1.3 * DIAM;
  auto chains = layered_mat(4, 6, side, 1e-4, dz, 23);
  Box box;
  box.lo[0] = box.lo[1] = 0.0;
  box.hi[0] = box.hi[1] = side;
  box.lo[2] = -0.5 * DIAM;
  box.hi[2] = 4 * dz;
  const double travel = box.hi[2] - 0.5 * DIAM - 3.0 * DIAM;
  Lammps l;
  l.cmds(setup(write_data(dir + "/m.data", chains, box, NODE_MASS), "p p f",
               fmt::format("pair_coeff * * kn {} mu 0.3 kt 1.0 diameter 69e-6", kn)));
  l.cmd(fmt::format("variable ztop equal \"zhi - {0}*time*({0}*time<{1}) - {1}*({0}*time>={1})\"",
                    speed, travel));
  l.cmds(R"(
fix wtop all wall/harmonic zhi v_ztop 1e4 0.0 3.45e-5
fix wbot all wall/harmonic zlo EDGE 1e4 0.0 3.45e-5
fix nve all nve
fix visc all viscous 2e-5
timestep 5e-9
thermo 0
)");
  PassThroughChecker checker(segments_of(chains), side, side, 2e-4);
  l.cmd("run 0");
  checker.check(l.positions());
  maxpen = maxcontacts = 0.0;
  for (int k = 0; k < 600; k++) {
    l.cmd("run 5 pre no post no");
    checker.check(l.positions());
    maxpen = std::max(maxpen, l.value("c_pc[3]"));
    maxcontacts = std::max(maxcontacts, l.value("c_pc[1]"));
  }
  return checker;
}
}    // namespace

TEST(PairContact, NoPassThroughInAFastPress)
{
  // wall at 20 m/s, dt 5e-9 s, kn 1e10 Pa: 0.0014 D per step, inside the documented bound (v dt <= 0.05 D,
  // kinetic energy of a chain below the crossing barrier (2/15) kn D^3)
  auto dir = scratch_dir("contact_press");
  double maxpen, maxcontacts;
  auto checker = press(dir, 1e10, 20.0, maxpen, maxcontacts);
  EXPECT_GT(maxcontacts, 20.0);
  EXPECT_EQ(checker.flips, 0) << "a chain passed through another";
  // chains without bending stiffness fold at their nodes under the press; the node caps cover the
  // convex side of such kinks (without them penetrations reached 0.7 D here)
  EXPECT_GT(checker.closest, 0.5 * DIAM) << "axes came closer than half a diameter";
  printf(
      "[ pair ncf/contact ] press: max penetration %.3g D, closest axes %.3g D, %g contacts max\n",
      maxpen / DIAM, checker.closest / DIAM, maxcontacts);
  // negative control: the checker sees chains pass through each other with a far too soft
  // contact (kn 1e3 Pa)
  auto soft = press(dir, 1e3, 20.0, maxpen, maxcontacts);
  EXPECT_GT(soft.flips, 0) << "the checker must detect a pass-through";
}

TEST(PairContact, NoHistoryWithoutFriction)
{
  auto dir = scratch_dir("contact_nohist");
  for (double mu : {0.0, 0.3}) {
    Lammps l;
    l.cmds(setup(write_data(dir + "/h.data", crossed(0.9 * DIAM), Box(), NODE_MASS), "f f f",
                 fmt::format("pair_coeff * * kn 1e8 mu {} diameter 69e-6", mu)));
    l.cmd("run 0");
    // the store of fix ncf/contact/history has slots (and memory) only with friction
    auto *fix = l.lmp->modify->get_fix_by_id("NCF_CONTACT_HISTORY");
    ASSERT_NE(fix, nullptr);
    int dim = -1;
    const int slots = *static_cast<int *>(fix->extract("slots", dim));
    EXPECT_EQ(slots > 0, mu > 0.0);
    EXPECT_EQ(fix->memory_usage() > 0.0, mu > 0.0);
    EXPECT_EQ(l.lmp->force->pair->comm_forward > 0, mu > 0.0);
  }
}

// fatom yes: the magnitude of every node's contact force (d_ncf_fcontact) is that of the force on
// it (the bonds are at their reference lengths), in a closed box and with the crossing moved
// across the periodic faces (contacts with ghost images, whose forces go back to their owners)
TEST(PairContact, PerAtomContactForceForDumps)
{
  auto dir = scratch_dir("contact_fatom");
  Box box;
  for (int d = 0; d < 3; d++) box.lo[d] = -1.5e-3, box.hi[d] = 1.5e-3;
  const std::array<double, 3> across{1.5e-3, 1.5e-3, 0.0};
  for (int periodic = 0; periodic < 2; periodic++) {
    SCOPED_TRACE(periodic ? "across the periodic faces" : "closed box");
    Lammps l;
    const auto chains = periodic ? crossed(0.9 * DIAM, across) : crossed(0.9 * DIAM);
    l.cmds(
        setup(write_data(dir + "/a" + std::to_string(periodic) + ".data", chains, box, NODE_MASS),
              periodic ? "p p f" : "f f f", "pair_coeff * * kn 1e8 diameter 69e-6",
              "pair_style ncf/contact fatom yes"));
    l.cmd("run 0");
    ASSERT_EQ(l.value("c_pc[1]"), 4.0);
    const auto f = l.forces();
    LAMMPS_NS::Atom *atom = l.lmp->atom;
    int flag = -1, cols = -1;
    const int idx = atom->find_custom("ncf_fcontact", flag, cols);
    ASSERT_GE(idx, 0);
    std::vector<double> fc(f.size() / 3, -1.0);
    for (int i = 0; i < atom->nlocal; i++) fc[atom->tag[i] - 1] = atom->dvector[idx][i];
    int touched = 0;
    for (size_t i = 0; i < fc.size(); i++) {
      const double mag = std::sqrt(f[3 * i] * f[3 * i] + f[3 * i + 1] * f[3 * i + 1] +
                                   f[3 * i + 2] * f[3 * i + 2]);
      EXPECT_NEAR(fc[i], mag, 1e-12 * std::fabs(f[3 * 5 + 2])) << "atom " << i + 1;
      touched += mag > 0.0;
    }
    EXPECT_GE(touched, 4);
  }
}

// work yes: d_ncf_work, the node's share of the work, set at every list build: 1 for a node that
// owns no list entry, 1 + WORK_NEAR per owned entry in reach (through the law) + WORK_FAR per
// other entry + WORK_CAP per node cap. Crossing chains far apart, touching, then apart again
// (within the skin: listed, not in reach); kept through a restart; absent with work no.
TEST(PairContact, WorkEstimatePerNodeForBalancing)
{
  using LAMMPS_NS::PairNCFContact;
  auto dir = scratch_dir("contact_work");
  auto work = [](Lammps &l) {
    LAMMPS_NS::Atom *atom = l.lmp->atom;
    int flag = -1, cols = -1;
    const int idx = atom->find_custom("ncf_work", flag, cols);
    std::vector<double> w;
    if (idx < 0) return w;
    w.assign(atom->natoms, -1.0);
    for (int i = 0; i < atom->nlocal; i++) w[atom->tag[i] - 1] = atom->dvector[idx][i];
    return w;
  };
  auto sum_extra = [](const std::vector<double> &w) {
    double s = 0.0;
    for (double v : w) s += v - 1.0;
    return s;
  };
  auto define = [&](Lammps &l, double gap, const std::string &style) {
    l.cmds(setup(write_data(dir + "/w.data", crossed(gap), Box(), NODE_MASS), "f f f",
                 "pair_coeff * * kn 1e8 diameter 69e-6", style));
    l.cmd("run 0");
  };
  std::vector<double> apart, touching, lifted;
  {
    SCOPED_TRACE("far apart");
    Lammps l;
    define(l, 20 * DIAM, "pair_style ncf/contact work yes");
    apart = work(l);
    ASSERT_EQ(apart.size(), 22u);    // two chains of 11 nodes
    // (segments of one chain two apart are listed too, out of reach)
    for (double v : apart) {
      EXPECT_GE(v, 1.0);
      EXPECT_LT(v, 1.0 + PairNCFContact::WORK_NEAR) << "no entry in reach";
    }
  }
  {
    Lammps l;
    define(l, 0.9 * DIAM, "pair_style ncf/contact work yes");
    const double contacts = l.value("c_pc[1]");
    ASSERT_GT(contacts, 0.0);
    touching = work(l);
    int busy = 0;
    for (double v : touching) busy += v >= 1.0 + PairNCFContact::WORK_NEAR;
    EXPECT_GE(busy, 1) << "a node owns an entry in contact";
    // every pair in contact is an entry in reach, counted once, on its owner node
    EXPECT_GE(sum_extra(touching) - sum_extra(apart),
              contacts * PairNCFContact::WORK_NEAR * (1.0 - 1e-12));
    // the upper chain lifted to 1.15 D (out of reach, most entries still listed within the
    // skin): the next build counts those at WORK_FAR
    l.cmd("group upper molecule 2");
    l.cmd(fmt::format("displace_atoms upper move 0 0 {}", 0.25 * DIAM));
    l.cmd("run 0");
    EXPECT_EQ(l.value("c_pc[1]"), 0.0);
    lifted = work(l);
    EXPECT_GT(sum_extra(lifted), sum_extra(apart)) << "the entries within the skin are listed";
    // (and a few entries of the touching state are no longer listed at all)
    EXPECT_GE(sum_extra(touching) - sum_extra(lifted),
              contacts * (PairNCFContact::WORK_NEAR - PairNCFContact::WORK_FAR) * (1.0 - 1e-12));
    l.cmd("write_restart " + dir + "/w.restart");
  }
  {
    // through a restart: the keyword is kept, the estimate set again at the first build
    Lammps r;
    r.cmd("read_restart " + dir + "/w.restart");
    r.cmd("bond_coeff 1 modulus 120e9 diameter 69e-6");
    r.cmd("comm_modify vel yes");
    r.cmd("neighbor 2e-5 bin");
    r.cmd("run 0");
    EXPECT_EQ(work(r), lifted);
  }
  // work no (the default): no per-node estimate
  Lammps n;
  define(n, 0.9 * DIAM, "pair_style ncf/contact");
  EXPECT_TRUE(work(n).empty());
}

// fatom N: the per-node contact force is computed on every N-th step, at the setup and on the last
// step of a run, and kept as it was on the steps between (which skip its accumulation and reverse
// communication); the values it has are those of fatom yes on the same step. A crossing pressed
// together so that the force changes every step; the largest node force recorded each step.
TEST(PairContact, PerAtomContactForceEveryNSteps)
{
  auto dir = scratch_dir("contact_fatom_every");
  const std::string data = write_data(dir + "/e.data", crossed(0.9 * DIAM), Box(), NODE_MASS);
  auto record = [&](const std::string &every) {
    Lammps l;
    l.cmds(setup(data, "f f f", "pair_coeff * * kn 1e8 diameter 69e-6",
                 "pair_style ncf/contact fatom " + every));
    l.cmds(R"(
group c2 molecule 2
velocity c2 set 0.0 0.0 -2.0
fix nve all nve
variable fc atom d_ncf_fcontact
compute fmax all reduce max v_fc
fix rec all vector 1 c_fmax
thermo 0
run 9
)");
    std::vector<double> v;
    for (int k = 1; k <= 10; k++) v.push_back(l.value(fmt::format("f_rec[{}]", k)));
    return v;
  };
  const auto all = record("yes"), every4 = record("4");
  // (the test can fail: the force grows every step)
  for (int k = 1; k < 10; k++) ASSERT_GT(all[k], all[k - 1]) << "step " << k;
  const std::vector<int> from = {0, 0, 0, 0, 4, 4, 4, 4, 8, 9};    // the step each value is of
  for (int k = 0; k < 10; k++) EXPECT_EQ(every4[k], all[from[k]]) << "step " << k;
  // fatom 0 is fatom no: no per-node force, no reverse communication
  Lammps l;
  l.cmds(setup(data, "f f f", "pair_coeff * * kn 1e8 diameter 69e-6",
               "pair_style ncf/contact fatom 0"));
  l.cmd("run 0");
  EXPECT_EQ(l.lmp->force->pair->comm_reverse, 0) << "fatom 0 is fatom no";
}

// The communication cutoff is the user's (comm_modify cutoff) raised to what the style needs: one
// segment length more with friction (the history of the neighbouring segments), so it shrinks
// again when friction is switched off, in the same process and after a restart from a run with
// friction (LAMMPS's restart header holds the raised value); a larger cutoff the user gives stays.
TEST(PairContact, GhostCutoffShrinksWhenFrictionIsSwitchedOff)
{
  auto dir = scratch_dir("contact_ghost_cutoff");
  const std::string data = write_data(dir + "/g.data", crossed(0.9 * DIAM), Box(), NODE_MASS);
  const std::string with = "pair_coeff * * kn 1e8 mu 0.3 diameter 69e-6";
  const std::string without = "pair_coeff * * kn 1e8 mu 0 diameter 69e-6";
  double cut_mu, cut_nomu, lmax;
  {
    Lammps l;
    l.cmds(setup(data, "f f f", with));
    l.cmd("run 0");
    cut_mu = l.lmp->comm->cutghostuser;
    lmax = static_cast<LAMMPS_NS::PairNCFContact *>(l.lmp->force->pair)->max_segment_length();
    l.cmd("write_restart " + dir + "/mu.restart");
    l.cmd(without);
    l.cmd("run 0");
    cut_nomu = l.lmp->comm->cutghostuser;
    EXPECT_NEAR(cut_mu - cut_nomu, lmax, 1e-12 * cut_mu) << "in the same process";
    l.cmd("comm_modify cutoff 5e-3");
    l.cmd("run 0");
    EXPECT_EQ(l.lmp->comm->cutghostuser, 5e-3) << "the user's larger cutoff stays";
    l.cmd("comm_modify cutoff 0");
    l.cmd(with);
    l.cmd("run 0");
    EXPECT_EQ(l.lmp->comm->cutghostuser, cut_mu);
  }
  auto after_restart = [&](const std::string &coeff, const std::string &extra) {
    Lammps l;
    l.cmd("read_restart " + dir + "/mu.restart");
    l.cmds("bond_coeff 1 modulus 120e9 diameter 69e-6\npair_style ncf/contact\n" + coeff +
           "\ncomm_modify vel yes\nneighbor 2e-5 bin\n" + extra);
    l.cmd("run 0");
    return l.lmp->comm->cutghostuser;
  };
  EXPECT_EQ(after_restart(without, ""), cut_nomu) << "after a restart from a run with friction";
  EXPECT_EQ(after_restart(with, ""), cut_mu);
  EXPECT_EQ(after_restart(without, "comm_modify cutoff 4e-3"), 4e-3);
}

// fix ncf/contact/history (created by the pair style) writes the friction history into the
// per-atom store before atoms migrate; a fix that migrates atoms in its own pre_exchange must come
// after it. pair_style given after the box: created then, before fix balance, fine. pair_style
// given before the box: created at the first run, after fix balance: a clear error.
TEST(PairContact, HistoryFixBeforeFixesThatMigrateAtoms)
{
  auto dir = scratch_dir("contact_history_fix");
  const std::string data = write_data(dir + "/h.data", crossed(0.9 * DIAM), Box(), NODE_MASS);
  const std::string coeff = "pair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6";
  EXPECT_EQ(error_of([&] {
              Lammps l;
              l.cmds(setup(data, "f f f", coeff));
              l.cmd("fix bal all balance 10 1.1 shift x 5 1.1");
              l.cmd("run 20");
            }),
            "");
  const std::string err = error_of([&] {
    Lammps l;
    l.cmds("units si\natom_style bond\natom_modify map array sort 0 0\nboundary f f f\n"
           "bond_style ncf/chain\npair_style ncf/contact\nread_data " +
           data + "\nbond_coeff 1 modulus 120e9 diameter 69e-6\n" + coeff +
           "\ncomm_modify vel yes\ntimestep 1e-9\nneighbor 2e-5 bin\n"
           "fix bal all balance 10 1.1 shift x 5 1.1");
    l.cmd("run 0");
  });
  EXPECT_THAT(err, HasSubstr("fix bal (balance) migrates atoms"));
  EXPECT_THAT(err, HasSubstr("define pair_style ncf/contact"));
}

// A segment that grows longer than the lmax the ghost shell was sized for during a run stops the
// run (the style checks the lengths one by one only when the longest segment at the last list
// build plus the displacements since could exceed lmax)
TEST(PairContact, SegmentGrowingPastLmaxStops)
{
  auto dir = scratch_dir("contact_lmax");
  const std::string data = write_data(dir + "/l.data", crossed(0.9 * DIAM), Box(), NODE_MASS);
  const double seg = 10.0 * MESH / 9.0;    // the segments of crossed()
  auto run = [&](double vend) {
    return error_of([&] {
      Lammps l;
      l.cmds(setup(data, "f f f", "pair_coeff * * kn 1e8 diameter 69e-6", fmt_lmax(1.02 * seg)));
      l.cmd("group tip id 10");
      l.cmd("velocity tip set " + std::to_string(vend) + " 0 0");
      l.cmd("fix nve all nve");
      l.cmd("run 200");
    });
  };
  EXPECT_EQ(run(0.0), "");
  EXPECT_THAT(run(3000.0), HasSubstr("longer than lmax"));
}

TEST(PairContact, ErrorsNameStyleKeywordAndValue)
{
  auto dir = scratch_dir("contact_errors");
  const std::string data = write_data(dir + "/e.data", crossed(0.9 * DIAM), Box(), NODE_MASS);
  auto err = [&](const std::string &style, const std::string &coeff,
                 const std::string &extra = "") {
    return error_of([&] {
      Lammps l;
      l.cmds(setup(data, "f f f", coeff, style));
      if (!extra.empty()) l.cmds(extra);
      l.cmd("run 0");
    });
  };
  EXPECT_THAT(err("pair_style ncf/contact ramp 2", "pair_coeff * * kn 1e8 diameter 69e-6"),
              HasSubstr("ramp 2"));
  EXPECT_THAT(err("pair_style ncf/contact bogus 1", "pair_coeff * * kn 1e8 diameter 69e-6"),
              HasSubstr("unknown keyword 'bogus'"));
  EXPECT_THAT(err("pair_style ncf/contact", "pair_coeff * * kn -1 diameter 69e-6"),
              HasSubstr("kn -1"));
  EXPECT_THAT(err("pair_style ncf/contact", "pair_coeff * * kn 1e8 mu -0.1 diameter 69e-6"),
              HasSubstr("mu -0.1"));
  EXPECT_THAT(err("pair_style ncf/contact", "pair_coeff * * kn 1e8"), HasSubstr("no diameter"));
  EXPECT_THAT(err("pair_style ncf/contact", "pair_coeff * * kn 1e8 mu 0.3 diameter 69e-6",
                  "comm_modify vel no"),
              HasSubstr("comm_modify vel yes"));
  EXPECT_THAT(
      err("pair_style ncf/contact", "pair_coeff * * kn 1e8 diameter 69e-6", "newton off on"),
      HasSubstr("newton pair on"));
  EXPECT_THAT(err("pair_style ncf/contact lmax 1e-5", "pair_coeff * * kn 1e8 diameter 69e-6"),
              HasSubstr("exceeds lmax"));
  EXPECT_THAT(err("pair_style ncf/contact dtcheck maybe", "pair_coeff * * kn 1e8 diameter 69e-6"),
              HasSubstr("dtcheck maybe"));
  // time step above the critical one of the contacts: a clear error (sqrt(2 m / (kn L)) is
  // 2.6e-7 s here), or a warning with dtcheck warn
  EXPECT_THAT(
      err("pair_style ncf/contact", "pair_coeff * * kn 1e8 diameter 69e-6", "timestep 1e-6"),
      HasSubstr("above the critical time step"));
  EXPECT_EQ(err("pair_style ncf/contact dtcheck warn", "pair_coeff * * kn 1e8 diameter 69e-6",
                "timestep 1e-6\nbond_style ncf/chain dtcheck no\nbond_coeff 1 modulus 120e9 "
                "diameter 69e-6"),
            "");
}
