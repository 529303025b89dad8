// pair ncf/contact on 1, 2 and 4 MPI ranks: the friction history store grows beyond maxcontacts
// on every rank together (the wrapped scene of test_pair_contact_wrapped.h: a thin chain wrapped
// around a thick one pulled through it, up to 60 contacts owned by one node), with the same forces
// and the same width on any number of ranks; a restart file written on 2 ranks before the growth
// resumed on 4 and on 1; the comb numbered thin chains first on 2 and 4 ranks as numbered thick
// chain first on 1.

#include "../integration/test_pair_contact_wrapped.h"
#include "ncf_lammps_test.h"

#include "fmt/format.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <numeric>

using namespace ncftest;
using namespace wrappedscene;

namespace {

struct Out {
  std::vector<double> f;
  int slots = -1;
};

// runs f on the first n ranks of MPI_COMM_WORLD; the result of world rank 0
Out on(int n, const std::function<Out(MPI_Comm)> &f)
{
  Out out;
  on_ranks(n, [&](MPI_Comm comm) {
    Out o = f(comm);
    if (world_rank() == 0) out = o;
  });
  return out;
}

// the data file of a numbering, written by world rank 0 before the communicators are split (its
// own folder: scratch_dir empties it)
std::string data_file(const std::string &name, const std::vector<int> &ids = {},
                      double x0 = -1.6e-3)
{
  const std::string path = scratch_dir("contact_growth_mpi_" + name) + "/w.data";
  if (world_rank() == 0) scene(path, ids, x0);
  MPI_Barrier(MPI_COMM_WORLD);
  return path;
}

// the same for the comb
std::string comb_file(const std::string &name, const std::vector<int> &ids = {})
{
  const std::string path = scratch_dir("contact_growth_mpi_comb_" + name) + "/c.data";
  if (world_rank() == 0) comb_scene(path, ids);
  MPI_Barrier(MPI_COMM_WORLD);
  return path;
}

}    // namespace

TEST(PairContactGrowthRanks, SameGrowthAndForcesOn1And2And4Ranks)
{
  ASSERT_GE(world_size(), 4);
  // the thick chain 0.5 mm further on: from step 300 its second node passes under the helix, so
  // that contacts go over from one of its segments to the next, and the owner of the contact they
  // take the slip of (the node before, at x < 0) is on another rank than the new one's
  const std::string data = data_file("thick_first_on", {}, -1.1e-3);
  auto run = [&](MPI_Comm comm) {
    Lammps l(comm);
    define(l, data);
    l.cmd("run 900");
    return Out{l.forces(), store_int(l, "slots")};
  };
  const Out r1 = on(1, run), r2 = on(2, run), r4 = on(4, run);
  if (world_rank() == 0) {
    const double scale = largest(r1.f);
    ASSERT_GT(scale, 0.0);
    EXPECT_GT(r1.slots, 24);
    EXPECT_EQ(r2.slots, r1.slots);
    EXPECT_EQ(r4.slots, r1.slots);
    EXPECT_LE(max_abs_diff(r2.f, r1.f), 1e-10 * scale);
    EXPECT_LE(max_abs_diff(r4.f, r1.f), 1e-10 * scale);
    printf("[ pair ncf/contact ] wrapped scene, %d slots; max |df| / max |f|: 1 vs 2 ranks %.3g, "
           "1 vs 4 ranks %.3g\n",
           r1.slots, max_abs_diff(r2.f, r1.f) / scale, max_abs_diff(r4.f, r1.f) / scale);
  }
}

TEST(PairContactGrowthRanks, RestartBeforeTheGrowthOnOtherRankCounts)
{
  ASSERT_GE(world_size(), 4);
  const std::string data = data_file("thick_first");
  const std::string restart = scratch_dir("contact_growth_mpi_restart") + "/narrow.restart";
  const Out straight = on(1, [&](MPI_Comm comm) {
    Lammps l(comm);
    define(l, data);
    l.cmd("run 20");
    l.cmd("run 580");
    return Out{l.forces(), store_int(l, "slots")};
  });
  on(2, [&](MPI_Comm comm) {
    Lammps l(comm);
    define(l, data);
    l.cmd("run 20");
    l.cmd("write_restart " + restart);
    return Out{{}, store_int(l, "slots")};
  });
  // (the file holds 24 slots: checked by PairContactGrowth.RestartAcrossTheGrowth)
  auto resumed = [&](MPI_Comm comm) {
    Lammps l(comm);
    l.cmd("read_restart " + restart);
    l.cmds("bond_style ncf/chain dtcheck no\n" + settings(STYLE));
    l.cmd("run 580");
    return Out{l.forces(), store_int(l, "slots")};
  };
  const Out r4 = on(4, resumed), r1 = on(1, resumed);
  if (world_rank() == 0) {
    const double scale = largest(straight.f);
    EXPECT_GT(straight.slots, 24);
    EXPECT_EQ(r4.slots, straight.slots);
    EXPECT_LE(max_abs_diff(r4.f, straight.f), 1e-10 * scale);
    EXPECT_LE(max_abs_diff(r1.f, straight.f), 1e-10 * scale);
  }
}

// the comb and the wrap (test_pair_contact_growth.cpp) numbered thin chains first on 2 ranks and
// 4 ranks as numbered thick chain first (one node owns every contact of its segment) on 1 rank
TEST(PairContactGrowthRanks, NumberingDoesNotMatterOnOtherRankCounts)
{
  ASSERT_GE(world_size(), 4);
  for (const bool wrap : {false, true}) {
    SCOPED_TRACE(wrap ? "wrap" : "comb");
    const int natoms = wrap ? NATOMS : NCOMB;
    const std::vector<int> ids = thin_first_ids(natoms);
    const std::string thick = wrap ? data_file("thick_first") : comb_file("thick_first");
    const std::string thin = wrap ? data_file("thin_first", ids) : comb_file("thin_first", ids);
    auto run = [&](const std::string &data, const std::vector<int> &order) {
      return [&, data, order](MPI_Comm comm) {
        Lammps l(comm);
        define(l, data, STYLE, wrap ? 0.5 : 0.05);
        l.cmd("run 300");
        return Out{in_chain_order(l.forces(), order), store_int(l, "slots")};
      };
    };
    std::vector<int> plain(natoms);
    std::iota(plain.begin(), plain.end(), 1);
    const Out a = on(1, run(thick, plain)), b = on(2, run(thin, ids)), c = on(4, run(thin, ids));
    if (world_rank() == 0) {
      const double scale = largest(a.f);
      ASSERT_GT(scale, 0.0);
      if (!wrap) EXPECT_GT(a.slots, 24);
      EXPECT_LE(max_abs_diff(b.f, a.f), 1e-9 * scale);
      EXPECT_LE(max_abs_diff(c.f, a.f), 1e-9 * scale);
      printf("[ pair ncf/contact ] %s, thick chain first on 1 rank vs thin chains first on 2 and 4 "
             "ranks: max |df| / max |f| %.3g, %.3g\n",
             wrap ? "wrap" : "comb", max_abs_diff(b.f, a.f) / scale,
             max_abs_diff(c.f, a.f) / scale);
    }
  }
}
