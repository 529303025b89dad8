/* ----------------------------------------------------------------------
   USER-NCF: pair_style ncf/contact (see pair_ncf_contact.h, doc/pair_ncf_contact.md)
   The candidate lists: the segments of every local and ghost node, the grids of boxes binned by
   their centres, and the pair list and node caps built from them when LAMMPS reneighbours.
------------------------------------------------------------------------- */

#include "pair_ncf_contact.h"
#include "pair_ncf_contact_keys.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "neighbor.h"

#include "ncf_contact.h"

#include <algorithm>
#include <cmath>
#include <vector>

using namespace LAMMPS_NS;
using NCF::Vec3;
using NCF_PairContact::SegKey;
using NCF_PairContact::share_node;

namespace {
// the reach of a pair list entry (PairCand::reach): a float not above gap / grow, one float step
// lower still, so that gap - grow s < 0 (in double precision) implies reach < s for every s >= 0
inline float entry_reach(double gap, double grow)
{
  const double q = gap / grow;
  float r = (float) q;
  if ((double) r > q) r = std::nextafter(r, -HUGE_VALF);
  return std::nextafter(r, -HUGE_VALF);
}

// How fast the gap between two segments extended beyond their nodes can close: if no node of A
// moved more than m_A and no node of B more than m_B since the build, the extended segments are
// at most g (m_A + m_B) closer than they were. An end extended by E along a segment of length L
// (at the build) moves by at most m + E |change of the unit vector| <= m + E 2 (2 m) / L.
// la, lb: lengths of A and B; ea, eb: their largest extension. Rounded up; a huge value for a
// degenerate extended segment (always evaluated).
inline double gap_growth(double la, double ea, double lb, double eb)
{
  constexpr double HUGE_GROWTH = 1e30;
  double g = 1.0;
  const double l[2] = {la, lb}, e[2] = {ea, eb};
  for (int k = 0; k < 2; k++) {
    if (!(e[k] > 0.0)) continue;
    if (!(l[k] > 4.0 * e[k] / HUGE_GROWTH)) return HUGE_GROWTH;
    g = std::max(g, 1.0 + 4.0 * e[k] / l[k]);
  }
  return std::min(g * (1.0 + 1e-6), HUGE_GROWTH);
}
}    // namespace

/* ----------------------------------------------------------------------
   partner indices of the segments owned by every local and ghost atom (2 slots per atom):
   -1 no segment, -2 partner node not present on this rank
------------------------------------------------------------------------- */

void PairNCFContact::set_segments()
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const tagint *tag = atom->tag;
  double **cnb = atom->darray[idx_cnb];
  double **x = atom->x;
  segp.assign(2 * (size_t) nall, -1);
  nbr.assign(2 * (size_t) nall, -1);
  for (int k = 0; k < nall; k++)
    for (int s = 0; s < 2; s++) {
      const tagint p = (tagint) cnb[k][s];
      if (p == 0) continue;
      const int m = atom->map(p);
      int q = (m < 0) ? -2 : domain->closest_image(k, m);
      if (q >= 0 && k >= nlocal) {
        // a ghost at the outer edge of the ghost shell may lack the image of its partner that
        // belongs to it (closest_image then returns a far one): treat it as missing
        const double ex = x[q][0] - x[k][0], ey = x[q][1] - x[k][1], ez = x[q][2] - x[k][2];
        if (ex * ex + ey * ey + ez * ez > lmax_used * lmax_used * (1.0 + 1e-12)) q = -2;
      }
      nbr[2 * k + s] = q;
      if (p <= tag[k]) continue;
      segp[2 * k + s] = q;
    }
}

/* ----------------------------------------------------------------------
   candidate lists, rebuilt only when LAMMPS reneighbours (ghosts and atom indices change only
   then). Between two builds no node moves more than skin/2 (the distance check of LAMMPS, which
   also accounts for a changing box), so the distance of two segments (or of a segment and a
   node) changes by less than the skin: a pair farther apart than its reach plus the skin at the
   build cannot come into contact before the next build.
   A segment pair is kept when the distance of the two segments is below D (1 + ramp) + skin plus
   the extensions at free chain ends of both (the law is zero unless A comes within D of B
   extended by the ramps), a node cap when the distance of the segment from the node is below
   D + skin. Candidates come from grids of boxes binned by their centres (local and ghost
   segments and nodes, periodic images included):
   - a segment's box is its bounding box, inflated on every side by its own extension at free
     ends and by half the largest reach + skin: two segments within reach + skin + extensions
     have boxes that overlap (|centre difference| <= sum of half extents per direction: the two
     closest points lie in the bounding boxes). Likewise for the bounding spheres;
   - segments extended at free ends (few) have a grid of their own, so that their larger boxes
     do not widen the search of all the others;
   - the caps: a grid of the interior nodes, boxes of half width D + skin around the node.
   All bounds carry a small slack for round-off, so the candidates are a superset of the pairs
   and caps the exact tests below keep.
------------------------------------------------------------------------- */

void PairNCFContact::build_lists()
{
  const ListBounds lb = prepare_build();
  plist.clear();
  clist.clear();
  fill_grids(lb);
  search_owned_segments(lb);
  if (use_history) load_history();
  mark_used_ghosts();
  make_virtual_ends();
}

/* ----------------------------------------------------------------------
   the segments and free-end extensions of every local and ghost node, the positions at the
   build, the longest owned segment, and the bounds of the search (with a slack for the round-off
   relative to the reach and to the coordinates that the distances are computed from)
------------------------------------------------------------------------- */

PairNCFContact::ListBounds PairNCFContact::prepare_build()
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  double **x = atom->x;
  const int *type = atom->type;
  const tagint *tag = atom->tag;
  double **cnb = atom->darray[idx_cnb];

  set_segments();
  // extension of the segments at free chain ends (nodes with one bond), per local/ghost node
  endext.assign(nall, 0.0);
  for (int k = 0; k < nall; k++)
    if (cnb[k][0] != 0.0 && cnb[k][1] == 0.0) endext[k] = endcap_frac * table.diameter(type[k]);
  xbuild.resize(3 * (size_t) nall);
  double xabs = 0.0;
  for (int k = 0; k < nall; k++)
    for (int d = 0; d < 3; d++) {
      xbuild[3 * (size_t) k + d] = x[k][d];
      xabs = std::max(xabs, std::fabs(x[k][d]));
    }

  // every owned segment has its partner here; the longest of them
  lseg_build = 0.0;
  for (int i = 0; i < nlocal; i++)
    for (int sa = 0; sa < 2; sa++) {
      const int p = segp[2 * i + sa];
      if (p == -2)
        error->one(FLERR, "pair ncf/contact: partner node of owned node {} is missing on this rank",
                   tag[i]);
      if (p >= 0) lseg_build = std::max(lseg_build, NCF::norm(Vec3(x[p]) - Vec3(x[i])));
    }

  ListBounds lb;
  lb.skin = neighbor->skin;
  // largest reach + skin of a segment pair (without the extensions at free ends)
  const double margin = reach_max + lb.skin;
  lb.slack = 1e-9 * margin + 1e-12 * xabs;
  lb.hm = 0.5 * margin + lb.slack;
  lb.gap_slack = 1e-9 * reach_max + 1e-12 * xabs;
  lb.hcap = (diam_max + lb.skin) * (1.0 + 1e-9) + lb.slack;
  return lb;
}

/* ----------------------------------------------------------------------
   segment pair (A = ao-ia with ao owned, B = bo-jb), key(A) < key(B) checked by the caller: kept
   if the two segments are within reach + skin
------------------------------------------------------------------------- */

void PairNCFContact::consider_pair(const ListBounds &lb, int ao, int ia, int bo, int jb)
{
  double **x = atom->x;
  const int *type = atom->type;
  const tagint *tag = atom->tag;
  const double skin = lb.skin;
  const double lim = reachf[type[ao]][type[bo]] + skin;
  if (jb == -2) {
    // B's partner node lies beyond the ghost shell (2 lmax + reach + skin around the sub-domain),
    // so no point of B is within reach + skin of A (A reaches at most lmax beyond the
    // sub-domain, B is at most lmax long). An error if B's own end node is that close: then the
    // shell is too short for this pair.
    const NCF::ClosestPoints cp =
        NCF::closest_points_segments(Vec3(x[ao]), Vec3(x[ia]), Vec3(x[bo]), Vec3(x[bo]));
    if (cp.dist2 < lim * lim)
      error->one(FLERR,
                 "pair ncf/contact: partner node of segment owner {} (neighbour of {}) is not "
                 "present on this rank; communication cutoff too short",
                 tag[bo], tag[ao]);
    return;
  }
  const SegKey A{tag[ao], tag[ia]}, B{tag[bo], tag[jb]};
  if (share_node(A, B)) return;
  // the law (both ways, NCF::chain_contact) is zero while A, extended at free chain ends, stays D
  // away from B, extended there and by the ramp half-width e beyond both nodes, and B likewise
  // from A extended by e (NCF::segment_contact_possible both ways): the entry keeps the gap of
  // the way that can close first, as gap / growth (a bound of how fast it closes)
  const TypePair &tp = tpar[type_pair(type[ao], type[bo])];
  const Vec3 ra0(x[ao]), ra1(x[ia]), rb0(x[bo]), rb1(x[jb]);
  const double la = NCF::norm(ra1 - ra0), lbl = NCF::norm(rb1 - rb0);
  const double ema = MAX(endext[ao], endext[ia]), emb = MAX(endext[bo], endext[jb]);
  auto gap_of = [&](double ra, double rb) {
    Vec3 pa0 = ra0, pa1 = ra1, pb0 = rb0, pb1 = rb1;
    NCF::extend_segment(pa0, pa1, endext[ao] + ra, endext[ia] + ra);
    NCF::extend_segment(pb0, pb1, endext[bo] + rb, endext[jb] + rb);
    return std::sqrt(NCF::closest_points_segments(pa0, pa1, pb0, pb1).dist2) - tp.dc - lb.gap_slack;
  };
  const double gap_ab = gap_of(0.0, tp.ramp), grow_ab = gap_growth(la, ema, lbl, emb + tp.ramp);
  // (the one-way law, pair_style law oneway, only A against B)
  const double gap_ba = oneway ? 0.0 : gap_of(tp.ramp, 0.0);
  const double grow_ba = gap_growth(la, ema + tp.ramp, lbl, emb);
  const bool ab_first = oneway || gap_ab / grow_ab <= gap_ba / grow_ba;
  const double gap = ab_first ? gap_ab : gap_ba, grow = ab_first ? grow_ab : grow_ba;
  // no node moves more than skin / 2 before the next build (checked in compute)
  if (gap >= grow * skin) return;
  const bool ext = endext[ao] != 0.0 || endext[ia] != 0.0 || endext[bo] != 0.0 || endext[jb] != 0.0;
  plist.push_back({ao, ia, bo, jb, (unsigned) type_pair(type[ao], type[bo]), ext ? 1u : 0u,
                   entry_reach(gap, grow)});
}

/* ----------------------------------------------------------------------
   the boxes: every segment (owner node, partner) known here, and every interior node
------------------------------------------------------------------------- */

void PairNCFContact::fill_grids(const ListBounds &lb)
{
  const int nall = atom->nlocal + atom->nghost;
  double **x = atom->x;
  const tagint *tag = atom->tag;
  double **cnb = atom->darray[idx_cnb];
  const double hm = lb.hm, hcap = lb.hcap;
  gseg.clear();
  gext.clear();
  gcap.clear();
  const double hcapv[3] = {hcap, hcap, hcap};
  for (int k = 0; k < nall; k++) {
    for (int sl = 0; sl < 2; sl++) {
      const int p = segp[2 * k + sl];
      if (p == -1) continue;
      if (p >= 0) {
        double c[3], h[3], l2 = 0.0;
        const double e = endext[k] + endext[p];
        for (int d = 0; d < 3; d++) {
          const double dx = x[p][d] - x[k][d];
          c[d] = x[k][d] + 0.5 * dx;
          h[d] = 0.5 * std::fabs(dx) + e + hm;
          l2 += dx * dx;
        }
        (e > 0.0 ? gext : gseg).add(c, h, 0.5 * std::sqrt(l2) + e + hm, tag[k], tag[p], 0, k, p);
      } else {
        // partner missing: only its node is known (an error if that node is within reach + skin
        // of an owned segment, which needs no extension)
        const double h[3] = {hm, hm, hm};
        gseg.add(x[k], h, hm, tag[k], (tagint) cnb[k][sl], 0, k, -2);
      }
    }
    if (cnb[k][0] != 0.0 && cnb[k][1] != 0.0)
      gcap.add(x[k], hcapv, hcap, tag[k], (tagint) cnb[k][0], (tagint) cnb[k][1], k, -1);
  }
  gseg.bin();
  gext.bin();
  gcap.bin();
  gcand.resize(MAX(MAX(gseg.cx.size(), gext.cx.size()), gcap.cx.size()));
}

/* ----------------------------------------------------------------------
   The pair list and the node caps of every owned segment, in the order of their owner nodes
   (LAMMPS sorts them spatially): the lists come out in that order, so that the positions, forces
   and history rows of a step are visited nearly in memory order (store_history relies on it);
   each node's work estimate
------------------------------------------------------------------------- */

void PairNCFContact::search_owned_segments(const ListBounds &lb)
{
  const int nlocal = atom->nlocal;
  double **x = atom->x;
  const tagint *tag = atom->tag;
  const double hm = lb.hm;
  pfirst.resize(nlocal + 1);
  double *work_est = idx_work >= 0 ? atom->dvector[idx_work] : nullptr;
  for (int ao = 0; ao < nlocal; ao++) {
    pfirst[ao] = (int) plist.size();
    const std::size_t cfirst = clist.size();
    for (int sa = 0; sa < 2; sa++) {
      const int ia = segp[2 * ao + sa];
      if (ia < 0) continue;
      const tagint ta = tag[ao], tpa = tag[ia];
      const double ea = endext[ao] + endext[ia];
      double ca[3], exa[3], ha[3], l2 = 0.0;
      for (int d = 0; d < 3; d++) {
        const double dx = x[ia][d] - x[ao][d];
        ca[d] = x[ao][d] + 0.5 * dx;
        exa[d] = 0.5 * std::fabs(dx);
        ha[d] = exa[d] + ea + hm;
        l2 += dx * dx;
      }
      const double ra = 0.5 * std::sqrt(l2) + ea + hm;

      // segment pairs: boxes, then bounding spheres, overlap. The boxes are tested without
      // branches (most entries of the scanned rows fail, unpredictably), the entries that pass
      // collected in gcand
      for (const BoxGrid *gp : {&gseg, &gext}) {
        const BoxGrid &g = *gp;
        const double *gx = g.cx.data(), *gy = g.cy.data(), *gz = g.cz.data(), *gr = g.r.data();
        int *cand = gcand.data();
        // B after A in the key order
        const int nc = g.scan(
            ca, ha,
            [ta, tpa](const BoxGrid::Filter &b) {
              return (b.k0 > ta) | ((b.k0 == ta) & (b.k1 > tpa));
            },
            cand);
        for (int c = 0; c < nc; c++) {
          const int n = cand[c];
          const double ex = ca[0] - gx[n], ey = ca[1] - gy[n], ez = ca[2] - gz[n];
          const double lim = ra + gr[n];
          if (ex * ex + ey * ey + ez * ez > lim * lim) continue;
          consider_pair(lb, ao, ia, g.i0[n], g.i1[n]);
        }
      }
      search_caps(lb, ao, ia, ca, exa);
    }
    // the node's share of this rank's work until the next build (fix balance ... weight var)
    if (work_est) {
      int nnear = 0;
      for (std::size_t e = pfirst[ao]; e < plist.size(); e++) nnear += plist[e].reach <= 0.0f;
      const int nfar = (int) (plist.size() - pfirst[ao]) - nnear;
      work_est[ao] =
          1.0 + WORK_NEAR * nnear + WORK_FAR * nfar + WORK_CAP * (double) (clist.size() - cfirst);
    }
  }
  pfirst[nlocal] = (int) plist.size();
}

/* ----------------------------------------------------------------------
   node caps: interior nodes of other chains (or far along this one) near segment A = ao-ia (box
   centre ca, half extents exa), the node within D + skin of A's bounding box first (most
   candidates are not)
------------------------------------------------------------------------- */

void PairNCFContact::search_caps(const ListBounds &lb, int ao, int ia, const double *ca,
                                 const double *exa)
{
  double **x = atom->x;
  const int *type = atom->type;
  const tagint *tag = atom->tag;
  const tagint ta = tag[ao], tpa = tag[ia];
  const BoxGrid &g = gcap;
  int *cand = gcand.data();
  const int nc = g.scan(
      ca, exa,
      [](const BoxGrid::Filter &) {
        return true;
      },
      cand);
  const Vec3 a0(x[ao]), a1(x[ia]);
  for (int c = 0; c < nc; c++) {
    const int n = cand[c];
    const tagint tn = g.t0[n], tp = g.t1[n], tq = g.t2[n];
    if (tn == ta || tn == tpa || tp == ta || tp == tpa || tq == ta || tq == tpa) continue;
    const int k = g.i0[n];
    const double dcap = 0.5 * (table.diameter(type[ao]) + table.diameter(type[k])) + lb.skin;
    const double dist2 = NCF::point_segment_dist2(a0, a1, Vec3(x[k]));
    if (dist2 >= dcap * dcap) continue;
    const int kp = nbr[2 * k], kq = nbr[2 * k + 1];
    if (kp < 0 || kq < 0)
      error->one(FLERR,
                 "pair ncf/contact: a chain neighbour of node {} (near segment {}-{}) is not "
                 "present on this rank; communication cutoff too short",
                 tag[k], tag[ao], tag[ia]);
    const int tpk = type_pair(type[ao], type[k]);
    clist.push_back({ao, ia, kp, k, kq, tpk, std::sqrt(dist2) - tpar[tpk].dc - lb.gap_slack});
  }
}

/* ----------------------------------------------------------------------
   the ghosts that a list entry or cap refers to (the others, beyond the reach of any, need no
   node row)
------------------------------------------------------------------------- */

void PairNCFContact::mark_used_ghosts()
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  std::vector<char> used(nall - nlocal, 0);
  auto mark = [&](int k) {
    if (k >= nlocal) used[k - nlocal] = 1;
  };
  for (const PairCand &pc : plist) {
    mark(pc.a1);
    mark(pc.b0);
    mark(pc.b1);
  }
  for (const CapCand &cc : clist) {
    mark(cc.a1);
    mark(cc.p);
    mark(cc.n);
    mark(cc.q);
  }
  ghosts_used.clear();
  for (int k = nlocal; k < nall; k++)
    if (used[k - nlocal]) ghosts_used.push_back(k);
}

/* ----------------------------------------------------------------------
   The segments at free chain ends enter the law extended (end caps): the free end k by endext[k]
   along its segment. In the pair list entries such a node is replaced by a virtual node (index
   nall + v), whose row holds the extended end (its position and velocity, from those of k and
   its chain neighbour; compute) and which collects the contact forces on it, mapped back onto k
   and the neighbour at the end of the step (the chain rule). So the lanes of the batched law need
   no extension and no mapping back of their own. (Its displacement bound is that of k: the gaps
   and growth bounds of the list already count the extension.)
------------------------------------------------------------------------- */

void PairNCFContact::make_virtual_ends()
{
  const int nall = atom->nlocal + atom->nghost;
  const tagint *tag = atom->tag;
  nall_build = nall;
  vreal.clear();
  vnbr.clear();
  std::vector<int> vof(nall, -1);
  for (PairCand &pc : plist) {
    if (!pc.ext) continue;
    const int node[4] = {pc.a0, pc.a1, pc.b0, pc.b1};
    int *slot[4] = {&pc.a0, &pc.a1, &pc.b0, &pc.b1};
    for (int m = 0; m < 4; m++) {
      const int k = node[m], j = node[m ^ 1];    // the segment's other node
      if (endext[k] == 0.0) continue;
      if (vof[k] < 0) {
        vof[k] = (int) vreal.size();
        vreal.push_back(k);
        vnbr.push_back(j);
      } else if (vnbr[vof[k]] != j)
        error->one(FLERR, "pair ncf/contact: free chain end {} has two different neighbours {}, {}",
                   tag[k], tag[vnbr[vof[k]]], tag[j]);
      *slot[m] = nall + vof[k];
    }
  }
}
