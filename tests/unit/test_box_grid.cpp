// Unit tests of the binned boxes of pair ncf/contact's list build (ncf_box_grid.h): a search finds
// every box that overlaps the search box (against a brute-force test of all pairs) and no box
// farther than the grid's slack, with the key filter applied; the bins hold each entry once in
// bin order; empty, single-point and very flat grids; a grid reused for a second build.

#include "ncf_box_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

using Grid = NCF::BoxGrid<int>;

namespace {
struct Box {
  double c[3], h[3];
  int key;
};

// boxes with centres in [0, span]^3 (span_z in z) and half extents up to hmax
std::vector<Box> random_boxes(std::mt19937 &rng, int n, double span, double span_z, double hmax)
{
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Box> out(n);
  for (int k = 0; k < n; k++) {
    Box &b = out[k];
    const double s[3] = {span, span, span_z};
    for (int d = 0; d < 3; d++) {
      b.c[d] = s[d] * u(rng) - 0.5 * s[d];
      b.h[d] = hmax * u(rng);
    }
    b.key = k;
  }
  return out;
}

void fill(Grid &g, const std::vector<Box> &boxes)
{
  g.clear();
  for (const Box &b : boxes) {
    const double r = std::sqrt(b.h[0] * b.h[0] + b.h[1] * b.h[1] + b.h[2] * b.h[2]);
    g.add(b.c, b.h, r, b.key, 2 * b.key, 3 * b.key, b.key, -b.key);
  }
  g.bin();
}

// the gap of two boxes in the direction where they are farthest apart (<= 0: they overlap)
double box_gap(const Box &a, const Box &b)
{
  double gap = -1e300;
  for (int d = 0; d < 3; d++) gap = std::max(gap, std::fabs(a.c[d] - b.c[d]) - (a.h[d] + b.h[d]));
  return gap;
}

// the keys a search finds, through the grid's own index arrays
std::set<int> search(const Grid &g, const Box &q, int key_above)
{
  std::vector<int> cand(g.size() + 1);
  const int nc = g.scan(
      q.c, q.h,
      [key_above](const Grid::Filter &f) {
        return f.k0 > key_above;
      },
      cand.data());
  std::set<int> found;
  for (int c = 0; c < nc; c++) {
    const int n = cand[c];
    EXPECT_EQ(g.t1[n], 2 * g.t0[n]);    // the entry's arrays moved together
    EXPECT_EQ(g.t2[n], 3 * g.t0[n]);
    EXPECT_EQ(g.i0[n], g.t0[n]);
    EXPECT_EQ(g.i1[n], -g.t0[n]);
    EXPECT_TRUE(found.insert(g.t0[n]).second) << "entry found twice";
  }
  return found;
}

void check_against_brute_force(const std::vector<Box> &boxes, const std::vector<Box> &queries,
                               const Grid &g, int &nfound)
{
  double span = 0.0, hmax = 0.0;
  for (const Box &b : boxes)
    for (int d = 0; d < 3; d++) {
      span = std::max(span, 2.0 * std::fabs(b.c[d]));
      hmax = std::max(hmax, b.h[d]);
    }
  for (const Box &q : queries) {
    const int key_above = q.key;
    const std::set<int> found = search(g, q, key_above);
    // the slack the grid allows: 1e-6 of its span and of the search box's half extents, and the
    // single precision of the centres
    const double slack =
        1e-6 * (span + 2.0 * hmax) + 1e-6 * (q.h[0] + q.h[1] + q.h[2]) + 1e-6 * (span + hmax);
    for (const Box &b : boxes) {
      const double gap = box_gap(q, b);
      const bool keep = b.key > key_above;
      if (keep && gap <= 0.0) {
        EXPECT_TRUE(found.count(b.key)) << "box " << b.key << " overlaps, gap " << gap;
      }
      if (found.count(b.key)) {
        EXPECT_TRUE(keep) << "box " << b.key << " found despite the key filter";
        EXPECT_LE(gap, slack) << "box " << b.key << " found " << gap << " apart";
      }
    }
    nfound += (int) found.size();
  }
}
}    // namespace

TEST(BoxGrid, SearchFindsEveryOverlapAndNothingFarther)
{
  std::mt19937 rng(7);
  // small boxes densely, large boxes sparsely (bins then larger than the boxes)
  const double spans[3] = {2.0, 10.0, 10.0}, hmaxs[3] = {0.02, 0.2, 2.0};
  for (int c = 0; c < 3; c++) {
    const double span = spans[c], hmax = hmaxs[c];
    const std::vector<Box> boxes = random_boxes(rng, 2000, span, span, hmax);
    Grid g;
    fill(g, boxes);
    std::vector<Box> queries = random_boxes(rng, 200, 1.1 * span, 1.1 * span, 2.0 * hmax);
    for (int k = 0; k < (int) queries.size(); k++) queries[k].key = k % 3 == 0 ? -1 : 5 * k;
    int nfound = 0;
    check_against_brute_force(boxes, queries, g, nfound);
    EXPECT_GT(nfound, 0) << "the test found nothing to check at hmax " << hmax;
  }
}

TEST(BoxGrid, BinsHoldEachEntryOnceInOrder)
{
  std::mt19937 rng(11);
  const std::vector<Box> boxes = random_boxes(rng, 500, 4.0, 1.0, 0.1);
  Grid g;
  fill(g, boxes);
  const int nbins = g.nb[0] * g.nb[1] * g.nb[2];
  ASSERT_EQ((int) g.start.size(), nbins + 1);
  EXPECT_EQ(g.start[0], 0);
  EXPECT_EQ(g.start[nbins], 500);
  EXPECT_LE(nbins, 4 * 500 + 1000);
  std::vector<int> seen(500, 0);
  for (int b = 0; b < nbins; b++) {
    ASSERT_LE(g.start[b], g.start[b + 1]);
    for (int n = g.start[b]; n < g.start[b + 1]; n++) {
      seen[g.t0[n]]++;
      // the entry's centre lies in its bin
      const double c[3] = {g.cx[n], g.cy[n], g.cz[n]};
      int c0[3], c1[3];
      g.cells(c, c, c0, c1);
      EXPECT_EQ((c0[2] * g.nb[1] + c0[1]) * g.nb[0] + c0[0], b);
      // the filter record is that of the entry
      EXPECT_EQ(g.fb[n].k0, g.t0[n]);
      EXPECT_FLOAT_EQ(g.fb[n].c[0], (float) (g.cx[n] - g.lo[0]));
      EXPECT_FLOAT_EQ(g.fb[n].h[2], (float) g.hz[n]);
    }
  }
  for (int k = 0; k < 500; k++) EXPECT_EQ(seen[k], 1) << "entry " << k;
}

TEST(BoxGrid, EmptyPointAndFlatGrids)
{
  Grid g;
  g.clear();
  g.bin();
  const Box q{{0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, -1};
  EXPECT_TRUE(search(g, q, -1).empty());

  // every centre at one point, zero half extents: one bin, found by a search through the point
  std::vector<Box> same(50, Box{{1.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, 0});
  for (int k = 0; k < 50; k++) same[k].key = k;
  fill(g, same);
  EXPECT_EQ(g.nb[0] * g.nb[1] * g.nb[2], 1);
  const Box at{{1.0, 2.0, 3.0}, {0.0, 0.0, 0.0}, -1};
  EXPECT_EQ(search(g, at, -1).size(), 50u);
  const Box off{{1.0, 2.0, 3.5}, {0.1, 0.1, 0.1}, -1};
  EXPECT_TRUE(search(g, off, -1).empty());

  // a flat layer (all z equal): a search above it finds nothing, one through it what overlaps
  std::mt19937 rng(3);
  std::vector<Box> flat = random_boxes(rng, 400, 5.0, 0.0, 0.05);
  int nfound = 0;
  fill(g, flat);
  std::vector<Box> queries = random_boxes(rng, 100, 5.0, 0.2, 0.1);
  for (Box &b : queries) b.key = -1;
  check_against_brute_force(flat, queries, g, nfound);
  EXPECT_GT(nfound, 0);
}

TEST(BoxGrid, ReusedForANewBuild)
{
  // a second build on the same grid (the pair keeps its grids between builds) gives what a new
  // grid gives
  std::mt19937 rng(5);
  Grid reused, fresh;
  fill(reused, random_boxes(rng, 800, 6.0, 6.0, 0.3));
  const std::vector<Box> second = random_boxes(rng, 300, 3.0, 3.0, 0.5);
  fill(reused, second);
  fill(fresh, second);
  ASSERT_EQ(reused.size(), 300);
  for (int d = 0; d < 3; d++) EXPECT_EQ(reused.nb[d], fresh.nb[d]);
  EXPECT_EQ(reused.start, fresh.start);
  EXPECT_EQ(reused.t0, fresh.t0);
  EXPECT_EQ(reused.cx, fresh.cx);
  const Box q{{0.2, -0.1, 0.3}, {0.7, 0.7, 0.7}, -1};
  EXPECT_EQ(search(reused, q, -1), search(fresh, q, -1));
}
