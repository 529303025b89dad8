// pair ncf/contact: the friction history store grows when a node has more contacts than it has
// slots (maxcontacts), and the history does not make the result depend on the atom numbering.
// Scenes (test_pair_contact_wrapped.h): a thin chain wrapped 10 times around a thick one, or thin
// chains crossing a thick one (the comb); the thick chain pulled along its axis, the thin chains
// held, friction on. With the thick chain numbered first, one of its nodes owns every contact of
// its segment (up to 60 in the wrap, 35 in the comb; the default is 24 slots); numbered the other
// way, every thin node owns one or two. Compared: the history in the store (every contact's key
// and slip) and the forces of a growing store against a store wide enough from the start; the
// history read back from restart files written before and after the growth (and in the format of
// earlier versions); both scenes numbered three ways give the same result.

#include "ncf_lammps_test.h"
#include "test_pair_contact_wrapped.h"

#include "fmt/format.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>

using namespace ncftest;
using namespace contactscene;

using namespace wrappedscene;

// default maxcontacts (24): the store grows during the run (several times, in steps of 8 slots);
// after every piece of 20 steps the history in the store (every contact's key and slip) and the
// forces are those of a store wide enough from the start, bit for bit
TEST(PairContactGrowth, GrowsAndKeepsEveryContact)
{
  auto dir = scratch_dir("contact_growth");
  const std::string data = scene(dir + "/w.data");
  // (one LAMMPS instance at a time: the plugin registers its styles with one)
  struct Piece {
    History h;
    std::vector<double> f;
  };
  auto run = [&](const std::string &style, int &slots, int &grows, int &most) {
    Lammps l;
    define(l, data, style);
    std::vector<Piece> out;
    most = 0;
    for (int piece = 0; piece < 30; piece++) {
      l.cmd("run 20");
      out.push_back({history_of(l), l.forces()});
      most = std::max(most, most_contacts(l));
    }
    slots = store_int(l, "slots");
    grows = store_int(l, "grows");
    return out;
  };
  int slots_g, grows_g, most, slots_w, grows_w, most_w;
  const auto grown = run(STYLE, slots_g, grows_g, most);
  const auto wide = run(std::string(STYLE) + " maxcontacts 200", slots_w, grows_w, most_w);
  int differ = 0;
  for (size_t p = 0; p < grown.size(); p++)
    differ += grown[p].h != wide[p].h || max_abs_diff(grown[p].f, wide[p].f) != 0.0;
  EXPECT_EQ(differ, 0) << "pieces of 20 steps whose history or forces differ";
  EXPECT_GT(most, 24) << "a node of the thick chain must own more contacts than the default slots";
  EXPECT_GE(slots_g, most);
  EXPECT_GE(grows_g, 3);    // (24 at init, then wider at least twice)
  EXPECT_EQ(slots_w, 200);
  // the slips are not trivial: sliding contacts (at the Coulomb limit) and others
  double smax = 0.0;
  for (const auto &kv : grown.back().h)
    for (double v : kv.second) smax = std::max(smax, std::fabs(v));
  EXPECT_GT(smax, 1e-7);
}

// restart files written before the growth (24 slots) and after it, read into runs that need more
// slots than the file has or that start with fewer than the file has: the history read back is the
// one written, and the run goes on as the uncut one
TEST(PairContactGrowth, RestartAcrossTheGrowth)
{
  auto dir = scratch_dir("contact_growth_restart");
  const std::string data = scene(dir + "/w.data");
  std::vector<double> ref;
  History at_narrow, at_wide, at_end;
  int slots_mid = -1;
  {
    Lammps l;
    define(l, data);
    l.cmd("run 20");
    EXPECT_EQ(store_int(l, "slots"), 24) << "no node needs more than 24 slots yet";
    at_narrow = history_of(l);
    l.cmd("write_restart " + dir + "/narrow.restart");
    l.cmd("run 380");
    slots_mid = store_int(l, "slots");
    at_wide = history_of(l);
    l.cmd("write_restart " + dir + "/wide.restart");
    l.cmd("run 10");
    ref = l.forces();
    at_end = history_of(l);
  }
  ASSERT_GT(slots_mid, 24) << "the second file must be written after the growth";
  ASSERT_FALSE(at_narrow.empty());
  const double scale = largest(ref);
  auto resumed = [&](const std::string &file, const std::string &style, int steps, int slots,
                     const History &written) {
    SCOPED_TRACE(file + " read with " + style);
    Lammps l;
    l.cmd("read_restart " + dir + "/" + file);
    l.cmds("bond_style ncf/chain dtcheck no\n" + settings(style));
    l.cmd("run 0");
    EXPECT_EQ(store_int(l, "slots"), slots);
    EXPECT_TRUE(history_of(l) == written) << "the history read back is the one written";
    l.cmd(fmt::format("run {}", steps));
    EXPECT_LE(max_abs_diff(l.forces(), ref), 1e-10 * scale);
    const History h = history_of(l);
    double worst = h.size() == at_end.size() ? 0.0 : 1e300;
    for (const auto &kv : at_end) {
      auto it = h.find(kv.first);
      for (int d = 0; d < 3; d++)
        worst = std::max(worst, it == h.end() ? 1e300 : std::fabs(it->second[d] - kv.second[d]));
    }
    EXPECT_LE(worst, 1e-12) << "the history at the end";
  };
  resumed("narrow.restart", STYLE, 390, 24, at_narrow);
  resumed("wide.restart", STYLE, 10, slots_mid, at_wide);
  // a pair style asking for fewer slots than the file has keeps the file's
  resumed("wide.restart", std::string(STYLE) + " maxcontacts 4", 10, slots_mid, at_wide);
}

// The comb (every contact inside a segment of both chains) and the wrap (a kink at every node of
// the thin chain, contacts straddling nodes: where the one-way law of earlier versions depended on
// which segment is A) numbered thick chain first (one of its segments owns every contact: the
// store grows), thin chains first and at random: after every piece of 10 steps the same forces on
// every node to round-off (the sums run in other orders, friction carries the differences on) and
// the same number of contacts
TEST(PairContactGrowth, SameResultWhateverTheNumbering)
{
  auto dir = scratch_dir("contact_growth_numbering");
  struct Result {
    std::vector<std::vector<double>> f;
    std::vector<double> contacts, energy;
    int slots;
  };
  for (const bool wrap : {false, true}) {
    SCOPED_TRACE(wrap ? "wrap" : "comb");
    const int natoms = wrap ? NATOMS : NCOMB;
    std::vector<int> thick_first(natoms), thin_first = thin_first_ids(natoms);
    std::iota(thick_first.begin(), thick_first.end(), 1);
    std::vector<int> shuffled = thick_first;
    std::mt19937 rng(7);
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    auto run = [&](const std::string &name, const std::vector<int> &ids) {
      Lammps l;
      const std::string file = dir + "/" + (wrap ? "wrap_" : "comb_") + name + ".data";
      // (the comb slowly: its contacts stick for about 100 steps, so that a lost slip shows for
      // as long; the wrap at the speed that brings the thick chain's end into the helix)
      define(l, wrap ? scene(file, ids) : comb_scene(file, ids), STYLE, wrap ? 0.5 : 0.05);
      Result r;
      for (int piece = 0; piece < 30; piece++) {
        l.cmd("run 10");
        r.f.push_back(in_chain_order(l.forces(), ids));
        r.contacts.push_back(l.value("c_pc[1]"));
        r.energy.push_back(l.value("pe"));
      }
      r.slots = store_int(l, "slots");
      return r;
    };
    const Result a = run("thick_first", thick_first), b = run("thin_first", thin_first),
                 c = run("shuffled", shuffled);
    EXPECT_GT(a.slots, 24);
    EXPECT_EQ(b.slots, 24) << "thin chains first: every node owns a few contacts at most";
    EXPECT_GE(a.contacts.back(), wrap ? 20.0 : 35.0);
    for (const Result *r : {&b, &c}) {
      double worst = 0.0, worst_e = 0.0;
      for (size_t p = 0; p < a.f.size(); p++) {
        EXPECT_EQ(r->contacts[p], a.contacts[p]) << "piece " << p;
        worst = std::max(worst, max_abs_diff(r->f[p], a.f[p]) / largest(a.f[p]));
        worst_e = std::max(worst_e, std::fabs(r->energy[p] - a.energy[p]) / a.energy[p]);
      }
      EXPECT_LE(worst, 1e-9);
      EXPECT_LE(worst_e, 1e-9);
      printf("[ pair ncf/contact ] %s renumbered (%s): max |df| / max |f| %.3g, energy %.3g\n",
             wrap ? "wrap" : "comb", r == &b ? "thin chains first" : "at random", worst, worst_e);
    }
  }
}

// `law oneway` (the one-way law of earlier versions, cheaper) is an option: on the wrap it depends
// on the numbering (so the symmetric default above is what makes the results independent of it),
// and a restart file keeps the law (pe after read_restart and run 0 that of the run that wrote it)
TEST(PairContactGrowth, OneWayLawIsAnOptionAndRestarts)
{
  auto dir = scratch_dir("contact_growth_oneway");
  const std::vector<int> thin = thin_first_ids(NATOMS);
  std::vector<int> plain(NATOMS);
  std::iota(plain.begin(), plain.end(), 1);
  const std::string style = std::string(STYLE) + " law oneway";
  auto run = [&](const std::string &name, const std::vector<int> &ids, const std::string &st,
                 bool restart) {
    Lammps l;
    define(l, scene(dir + "/" + name + ".data", ids), st, 0.5);
    l.cmd("run 200");
    const double pe = l.value("pe");
    if (restart) l.cmd("write_restart " + dir + "/" + name + ".restart");
    return pe;
  };
  const double a = run("plain", plain, style, true), b = run("thin", thin, style, false);
  EXPECT_GT(std::fabs(a - b), 0.01 * std::fabs(a)) << "the one-way law depends on the numbering";
  const double s = run("sym", plain, STYLE, false);
  EXPECT_GT(std::fabs(a - s), 0.01 * std::fabs(a)) << "the two laws differ on the wrap";
  Lammps l;
  l.cmd("read_restart " + dir + "/plain.restart");
  // (pair_style and its settings from the file: only what read_restart does not restore)
  l.cmds("bond_style ncf/chain dtcheck no\n" + settings("", 0.5));
  l.cmd("run 0");
  EXPECT_NEAR(l.value("pe"), a, 1e-12 * std::fabs(a)) << "the law read back from the restart file";
}

// a restart file in the format of earlier versions (the history in a fix property/atom
// NCF_CONTACT_HIST of 1 + 6 maxcontacts columns): made here by copying a run's history into such a
// fix and emptying the store (unfix: write_restart creates it again, empty); read back, the
// history is taken over into the store
TEST(PairContactGrowth, RestartFileOfEarlierVersions)
{
  auto dir = scratch_dir("contact_growth_old_restart");
  const std::string data = scene(dir + "/w.data");
  const std::string style = std::string(STYLE) + " maxcontacts 20";
  History written;
  {
    Lammps l;
    define(l, data, style);
    l.cmd("run 20");
    written = history_of(l);
    ASSERT_FALSE(written.empty());
    ASSERT_LE(most_contacts(l), 20);
    l.cmd("fix NCF_CONTACT_HIST all property/atom d2_ncf_chist 121 ghost no writedata no");
    std::map<double, int> n;
    for (const auto &kv : written) {
      const int id = (int) kv.first[0], k = n[kv.first[0]]++;
      const double v[6] = {kv.first[1],  kv.first[2],  kv.first[3],
                           kv.second[0], kv.second[1], kv.second[2]};
      for (int c = 0; c < 6; c++)
        l.cmd(fmt::format("set atom {} d2_ncf_chist[{}] {:.17g}", id, 2 + 6 * k + c, v[c]));
    }
    for (const auto &kv : n)
      l.cmd(fmt::format("set atom {} d2_ncf_chist[1] {}", (int) kv.first, kv.second));
    l.cmd("unfix NCF_CONTACT_HISTORY");
    l.cmd("write_restart " + dir + "/old.restart");
  }
  Lammps l;
  l.cmd("read_restart " + dir + "/old.restart");
  l.cmds("bond_style ncf/chain dtcheck no\n" + settings(style));
  l.cmd("run 0");
  EXPECT_TRUE(history_of(l) == written) << "the history of the file taken over";
  EXPECT_EQ(l.lmp->modify->get_fix_by_id("NCF_CONTACT_HIST"), nullptr);
}
