/* ----------------------------------------------------------------------
   USER-NCF: pair_style ncf/contact (see pair_ncf_contact.h, doc/pair_ncf_contact.md)
   compute() as a sequence of named steps, each a member function on the state of the step
   (struct Step, below):
     refresh_lists       the candidate lists rebuilt when LAMMPS has reneighboured
     load_rows           the node rows of the step (position, displacement bound, velocity,
                         end-cap extension) and those of the virtual free-chain ends
     check_lengths       every owned segment within the length the cutoffs were sized for
     begin_history       this step's friction history buffer
     gather_pairs        the pair list entries that can be in contact
     pairs_batched       those through the batched contact law and friction (flush_lanes); the
                         lanes the batch hands back through the scalar law (pair_contact)
     deferred_takeovers  the new contacts whose slip take-over waited for ghost history rows
     node_caps           the node caps, batched
     map_virtual_forces  the forces on the virtual free-chain ends onto their real nodes
     finish_outputs      the history buffers swapped, per-atom contact force, compute pair sums
------------------------------------------------------------------------- */

#include "pair_ncf_contact.h"

#include "fix_ncf_contact_history.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "neighbor.h"
#include "timer.h"
#include "update.h"

#include "ncf_contact.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using NCF::Vec3;

/* ----------------------------------------------------------------------
   the state of one compute(): LAMMPS's arrays, what is asked of the step, the node rows, the
   friction history buffers, the counters of compute pair, the lanes of the batch being filled
------------------------------------------------------------------------- */

struct PairNCFContact::Step {
  // x, v, f as flat arrays (LAMMPS allocates them contiguously): one load less per node access
  using Row = double[3];
  const Row *x, *v;
  Row *f;
  const tagint *tag;
  int nlocal, nall, nvirt;
  double dt;
  // the setup of a run (or of a minimisation) computes the forces of the state as it is: the
  // friction history is neither advanced nor kept (the slips of the last step stay the last
  // step's), and each contact's friction force is that of its stored slip, the force the step
  // that stored it gave. So `run 0` changes nothing, and a run cut into pieces is the same run.
  bool advance;
  // per-atom energy or virial requested, or the global virial without f dot r (pair_modify
  // nofdotr): every contact tallied (tally_contact); otherwise nothing of it runs and the forces
  // are the same bits either way
  bool tally;
  bool eng;          // global energy (and penetrations) wanted
  bool fatom_now;    // the per-node contact force on this step
  // per node, one cache line of NR doubles (x, y, z, displacement bound, vx, vy, vz, end-cap
  // extension), so that the random accesses of the list loops fetch one line per node
  static constexpr int NR = 8;
  double *X;     // the rows (local, ghost, virtual nodes)
  double *DM;    // the displacement bounds again in one dense array
  double *FV;    // the forces on the virtual nodes
  // twice the largest displacement bound of a node (load_rows)
  double dglob;
  // friction history: the last step's read, this step's written (buffer hwr)
  int hwr;
  const double *slip_rd;
  const unsigned char *has_rd;
  double *slip_wr;
  unsigned char *has_wr;
  // compute pair: contacts, sum and largest penetration, node caps in contact
  double ncontact, pensum, penmax, ncap;
  // the lanes of the batched law (pairs_batched, flush_lanes)
  bool uniform;    // one set of coefficients for all type pairs, put into every lane once
  int lane_e[NCF::CONTACT_BATCH];    // the pair list entry of a lane
  bool lane_had[NCF::CONTACT_BATCH], lane_go[NCF::CONTACT_BATCH], lane_fric[NCF::CONTACT_BATCH];
  double lane_pen[NCF::CONTACT_BATCH];
  int lane_node[NCF::CONTACT_BATCH][4];    // the node rows of the lanes (A0, A1, B0, B1)

  double *xof(int k) const { return X + NR * (size_t) k; }
  // where the force on node k of a list entry goes: LAMMPS's array, or that of the virtual nodes
  double *fdst(int k) const { return k < nall ? f[k] : FV + 3 * (size_t) (k - nall); }
  // the displacement bound of a node of A plus that of a node of B (the largest of each): the gap
  // of a pair list entry can have closed by grow times that since the build, so the entry is
  // tested only where this reaches its reach (gap / grow)
  double closing(const PairCand &pc) const
  {
    return MAX(DM[pc.a0], DM[pc.a1]) + MAX(DM[pc.b0], DM[pc.b1]);
  }
};

/* ---------------------------------------------------------------------- */

void PairNCFContact::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);

  Step s;
  s.x = atom->x ? (const Step::Row *) atom->x[0] : nullptr;
  s.v = atom->v ? (const Step::Row *) atom->v[0] : nullptr;
  s.f = atom->f ? (Step::Row *) atom->f[0] : nullptr;
  s.tag = atom->tag;
  s.nlocal = atom->nlocal;
  s.nall = s.nlocal + atom->nghost;
  s.dt = update->dt;
  s.advance = !update->setupflag;
  s.tally = eflag_atom || vflag_atom || cvflag_atom || vflag_global;
  s.eng = eflag_global != 0;

  refresh_lists(s);
  // (virtual nodes at free chain ends: build_lists)
  s.nvirt = (int) vreal.size();
  fvirt.assign(3 * (size_t) s.nvirt, 0.0);
  s.FV = fvirt.data();
  // the per-node contact force (fatom) on the steps it is asked for: every fatom_every steps, the
  // last step of a run and its setup, every step of a minimisation; the other steps leave it
  // (and its reverse communication) out
  s.fatom_now = fatom_every > 0 &&
      (update->setupflag || update->whichflag != 1 || update->ntimestep % fatom_every == 0 ||
       update->ntimestep == update->laststep);
  if (s.fatom_now) fcon.assign(3 * (size_t) (s.nall + s.nvirt), 0.0);
  s.ncontact = s.pensum = s.penmax = s.ncap = 0.0;

  load_rows(s);
  check_lengths(s);
  begin_history(s);
  int nnear = 0;
  const int nwork = gather_pairs(s, nnear);
  pairs_batched(s, nwork, nnear);
  deferred_takeovers(s);
  node_caps(s);
  map_virtual_forces(s);
  finish_outputs(s);

  if (vflag_fdotr) virial_fdotr_compute();
}

/* ----------------------------------------------------------------------
   the lists hold atom indices: rebuilt whenever LAMMPS has reneighboured (new ghosts, atoms
   exchanged or sorted) and after every init
------------------------------------------------------------------------- */

void PairNCFContact::refresh_lists(const Step &s)
{
  if (lists_valid && neighbor->ago != 0 && neighbor->ncalls == lists_ncalls &&
      s.nlocal == lists_nlocal && s.nall == lists_nall)
    return;
  build_lists();
  lists_valid = true;
  hneed_valid = false;
  lists_ncalls = neighbor->ncalls;
  lists_nlocal = s.nlocal;
  lists_nall = s.nall;
}

/* ----------------------------------------------------------------------
   The node rows of the step. The displacement of every local and ghost node since the build (all
   below skin/2): the distance of two segments, or of a segment and a node, has changed by at most
   the sum of the largest displacement of a node of each, so a listed pair whose distance at the
   build minus that bound is beyond its reach needs no test this step, and one within D minus it
   no prefilter.
------------------------------------------------------------------------- */

void PairNCFContact::load_rows(Step &s)
{
  constexpr int NR = Step::NR;
  const int nall = s.nall, nvirt = s.nvirt;
  const Step::Row *const x = s.x, *const v = s.v;
  xd.resize(NR * (size_t) (nall + nvirt) + NR);
  double *const X = xd.data() + ((64 - ((uintptr_t) xd.data() & 63)) & 63) / sizeof(double);
  dmn.resize(nall + nvirt);
  double *const DM = dmn.data();
  s.X = X;
  s.DM = DM;
  // (relative margin for the round-off of the distances)
  const double dm_margin = 0.5e-12 * reach_max;
  const double *const XB = xbuild.data();
  const double *const EX = endext.data();
  const bool copy_v = use_velocity;
  auto pack = [&](int n, auto &&node) {
    double d2max = 0.0;
    for (int i = 0; i < n; i++) {
      const int k = node(i);
      const double *xb = XB + 3 * (size_t) k;
      const double dx = x[k][0] - xb[0], dy = x[k][1] - xb[1], dz = x[k][2] - xb[2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      d2max = MAX(d2max, d2);
      double *xk = X + NR * (size_t) k;
      xk[0] = x[k][0];
      xk[1] = x[k][1];
      xk[2] = x[k][2];
      xk[3] = DM[k] = std::sqrt(d2) * (1.0 + 1e-12) + dm_margin;
      if (copy_v) {
        xk[4] = v[k][0];
        xk[5] = v[k][1];
        xk[6] = v[k][2];
      }
      xk[7] = EX[k];
    }
    return d2max;
  };
  double dmove2 = pack(s.nlocal, [](int i) {
    return i;
  });
  // the lists rely on LAMMPS reneighbouring before any node has moved more than skin/2
  // (neigh_modify every 1 delay 0 check yes, the default); otherwise contacts could be missed
  if (dmove2 > 0.25 * neighbor->skin * neighbor->skin * (1.0 + 1e-9))
    error->one(FLERR,
               "pair ncf/contact: a node moved {:.6g} since the last reneighbouring, more than "
               "half the neighbour skin {:.6g}; its contact lists could miss contacts. Use "
               "'neigh_modify every 1 delay 0 check yes' (the default) or a larger skin",
               std::sqrt(dmove2), neighbor->skin);
  // of the ghosts only those a list entry or cap refers to (the others' rows are never read)
  const int *const GU = ghosts_used.data();
  const double dmove2_ghost = pack((int) ghosts_used.size(), [GU](int i) {
    return GU[i];
  });    // (not inside MAX: it would run twice)
  dmove2 = MAX(dmove2, dmove2_ghost);
  // the rows of the virtual nodes: the free end k moved by its extension e along its segment,
  // x = x_k + e u (u: unit vector from its neighbour j to k), velocity v_k + e du/dt with
  // du/dt = (I - u u^T)(v_k - v_j) / l; the displacement bound of k. (u and e / l kept for
  // mapping the forces back at the end of the step: vgeom)
  vgeom.resize(4 * (size_t) nvirt);
  for (int vn = 0; vn < nvirt; vn++) {
    const int k = vreal[vn], j = vnbr[vn];
    double *xv = X + NR * (size_t) (nall + vn);
    const double e = EX[k];
    const double ux = x[k][0] - x[j][0], uy = x[k][1] - x[j][1], uz = x[k][2] - x[j][2];
    const double l = std::sqrt(ux * ux + uy * uy + uz * uz);
    const double il = l > 0.0 ? 1.0 / l : 0.0;
    const double ex = il * ux, ey = il * uy, ez = il * uz;
    double *gv = &vgeom[4 * (size_t) vn];
    gv[0] = ex;
    gv[1] = ey;
    gv[2] = ez;
    gv[3] = e * il;
    xv[0] = x[k][0] + e * ex;
    xv[1] = x[k][1] + e * ey;
    xv[2] = x[k][2] + e * ez;
    xv[3] = DM[nall + vn] = DM[k];
    if (copy_v) {
      const double dvx = v[k][0] - v[j][0], dvy = v[k][1] - v[j][1], dvz = v[k][2] - v[j][2];
      const double dvn = dvx * ex + dvy * ey + dvz * ez, sc = e * il;
      xv[4] = v[k][0] + sc * (dvx - dvn * ex);
      xv[5] = v[k][1] + sc * (dvy - dvn * ey);
      xv[6] = v[k][2] + sc * (dvz - dvn * ez);
    }
    xv[7] = 0.0;
  }
  // twice the largest bound of a node: not below the bound of any pair or cap (computed the same
  // way, and doubling is exact), so a pair beyond the largest reach by it is skipped before its
  // node data are loaded
  s.dglob = 2.0 * (std::sqrt(dmove2) * (1.0 + 1e-12) + 0.5e-12 * reach_max);
}

/* ----------------------------------------------------------------------
   every owned segment within the length the cutoffs were sized for: checked one by one only when
   the longest at the build plus twice the largest displacement could exceed it
------------------------------------------------------------------------- */

void PairNCFContact::check_lengths(const Step &s)
{
  if (lseg_build * (1.0 + 1e-12) + s.dglob < lmax_used) return;
  const Step::Row *const x = s.x;
  const double lmax2 = lmax_used * lmax_used;
  for (int i = 0; i < s.nlocal; i++)
    for (int sa = 0; sa < 2; sa++) {
      const int ia = segp[2 * i + sa];
      if (ia < 0) continue;
      const double dx = x[ia][0] - x[i][0], dy = x[ia][1] - x[i][1], dz = x[ia][2] - x[i][2];
      const double l2 = dx * dx + dy * dy + dz * dz;
      if (l2 > lmax2)
        error->one(FLERR,
                   "pair ncf/contact: segment {}-{} is {:.6g} long, longer than lmax {:.6g} that "
                   "the cutoffs were sized for; set pair_style keyword lmax{}",
                   s.tag[i], s.tag[ia], std::sqrt(l2), lmax_used, lmax_note());
    }
}

/* ----------------------------------------------------------------------
   friction history: the last step's read, this step's written (load_history); a new contact
   whose take-over needs the history of a pair owned by another rank (a ghost's row) is deferred
   (put on `deferred`) until that history has been communicated
------------------------------------------------------------------------- */

void PairNCFContact::begin_history(Step &s)
{
  s.hwr = 1 - hlast;
  s.slip_rd = nullptr;
  s.has_rd = nullptr;
  s.slip_wr = nullptr;
  s.has_wr = nullptr;
  if (use_history) {
    s.slip_rd = pslip[hlast].data();
    s.has_rd = phas[hlast].data();
    s.slip_wr = pslip[s.hwr].data();
    s.has_wr = phas[s.hwr].data();
    memset(s.has_wr, 0, plist.size());
  }
  deferred.clear();
}

/* ----------------------------------------------------------------------
   The contact of one pair list entry (segment A = a0-a1, a0 owned here, with segment B = b0-b1,
   key(A) < key(B)) by the scalar law, in three parts: scalar_prepare (bookkeeping, bounds,
   prefilter; false if the law need not be evaluated), scalar_law, scalar_finish (friction,
   forces, counters; true if deferred). The ends of segments at free chain ends are virtual
   nodes, whose rows hold the extended ends, so the law sees no extension left
   (ContactOptions::ext 0). The batched law (flush_lanes) hands its special lanes to these.
------------------------------------------------------------------------- */

bool PairNCFContact::scalar_prepare(const Step &s, int e, bool &had) const
{
  const PairCand &pc = plist[e];
  // whether the pair was in contact (had a stored slip) in the previous step
  had = use_history && s.has_rd[e] != 0;
  const double close = s.closing(pc);
  if (!(pc.reach < close)) return false;
  // (the prefilter only rejects pairs whose law is zero)
  if (pc.reach < -close) return true;
  const TypePair &tp = tpar[pc.tp];
  const Vec3 a0(s.xof(pc.a0)), a1(s.xof(pc.a1)), b0(s.xof(pc.b0)), b1(s.xof(pc.b1));
  const double no_ext[4] = {0.0, 0.0, 0.0, 0.0};
  // (both ways for the symmetric law, the mean of A against B and B against A)
  return NCF::segment_contact_possible(a0, a1, b0, b1, tp.dc, tp.ramp, no_ext) ||
      (!oneway && NCF::segment_contact_possible(b0, b1, a0, a1, tp.dc, tp.ramp, no_ext));
}

NCF::SegmentContact PairNCFContact::scalar_law(const Step &s, int e) const
{
  const PairCand &pc = plist[e];
  const TypePair &tp = tpar[pc.tp];
  const Vec3 a0(s.xof(pc.a0)), a1(s.xof(pc.a1)), b0(s.xof(pc.b0)), b1(s.xof(pc.b1));
  NCF::ContactOptions opt;
  opt.core = core;
  return oneway ? NCF::segment_contact(a0, a1, b0, b1, tp.dc, tp.kn, tp.ramp, s.eng, opt)
                : NCF::chain_contact(a0, a1, b0, b1, tp.dc, tp.kn, tp.ramp, s.eng, opt);
}

// the penetration of the chains themselves (their real nodes: two extended tips may overlap
// without any chain coming closer to another)
double PairNCFContact::real_penetration(const Step &s, const PairCand &pc) const
{
  const int ids[4] = {real_of(pc.a0), real_of(pc.a1), real_of(pc.b0), real_of(pc.b1)};
  return NCF::segment_penetration(Vec3(s.x[ids[0]]), Vec3(s.x[ids[1]]), Vec3(s.x[ids[2]]),
                                  Vec3(s.x[ids[3]]), tpar[pc.tp].dc);
}

// After the law: the slip a contact with friction starts from, in this step's buffer: the pair's
// own of the previous step or, for a new contact, that of a neighbouring pair (or zero); nullptr
// if that needs the rows of ghosts, not yet communicated (the entry is deferred)
double *PairNCFContact::start_slip(const Step &s, int e, bool had, bool may_defer)
{
  double *slip = s.slip_wr + 3 * (size_t) e;
  if (had) {
    memcpy(slip, s.slip_rd + 3 * (size_t) e, 3 * sizeof(double));
    return slip;
  }
  slip[0] = slip[1] = slip[2] = 0.0;
  const PairCand &pc = plist[e];
  if (!inherit_slip(s.tag[real_of(pc.a0)], s.tag[real_of(pc.a1)], s.tag[real_of(pc.b0)],
                    s.tag[real_of(pc.b1)], slip, may_defer)) {
    deferred.push_back(e);
    return nullptr;
  }
  return slip;
}

// the rest of a contact evaluated by the scalar law: dashpot and friction
// (NCF::contact_tangential), its forces added to its four nodes, its energy and penetration
// counted; true if deferred
bool PairNCFContact::scalar_finish(Step &s, int e, NCF::SegmentContact c, bool had, bool may_defer)
{
  if (!c.active) return false;
  const PairCand &pc = plist[e];
  const TypePair &tp = tpar[pc.tp];
  const int nodes[4] = {pc.a0, pc.a1, pc.b0, pc.b1};
  double espring = 0.0;
  if (use_velocity && c.fn > 0.0) {
    double *slip = nullptr;
    Vec3 sv;
    if (tp.mu > 0.0) {
      slip = start_slip(s, e, had, may_defer);
      if (!slip) return true;
      sv = Vec3(slip);
    }
    Vec3 vel[4];
    for (int m = 0; m < 4; m++) vel[m] = Vec3(s.xof(nodes[m]) + 4);
    espring = NCF::contact_tangential(c, vel, sv, tp.kt, tp.mu, tp.damp, s.dt, s.advance);
    if (slip) {
      // kept (also a zero slip: the contact exists)
      slip[0] = sv.x;
      slip[1] = sv.y;
      slip[2] = sv.z;
      s.has_wr[e] = 1;
    }
  }
  const double energy = c.energy + espring;
  const double pen = (pc.ext && s.eng) ? real_penetration(s, pc) : c.penetration;
  for (int k = 0; k < 4; k++) {
    double *fk = s.fdst(nodes[k]);
    fk[0] += c.f[k][0];
    fk[1] += c.f[k][1];
    fk[2] += c.f[k][2];
    if (s.fatom_now) {
      fcon[3 * nodes[k] + 0] += c.f[k][0];
      fcon[3 * nodes[k] + 1] += c.f[k][1];
      fcon[3 * nodes[k] + 2] += c.f[k][2];
    }
  }
  if (s.eng) eng_vdwl += energy;
  if (s.tally) {
    double fm[12];
    const double *xm[4];
    int rn[4];
    for (int m = 0; m < 4; m++) {
      for (int d = 0; d < 3; d++) fm[3 * m + d] = c.f[m][d];
      xm[m] = s.xof(nodes[m]);
      rn[m] = real_of(nodes[m]);
    }
    tally_contact(4, rn, xm, fm, energy);
  }
  s.ncontact += 1.0;
  s.pensum += pen;
  s.penmax = MAX(s.penmax, pen);
  return false;
}

bool PairNCFContact::pair_contact(Step &s, int e, bool may_defer)
{
  bool had;
  if (!scalar_prepare(s, e, had)) return false;
  return scalar_finish(s, e, scalar_law(s, e), had, may_defer);
}

/* ----------------------------------------------------------------------
   The pair list entries within the largest reach after the displacement bound of all nodes,
   gathered into `work` without branches first (about a third drop out, unpredictably); the
   others are no contact (the distances d of the pair list are net of the extensions at free
   ends). nnear: how many; returns how many of them go on to the batch.
------------------------------------------------------------------------- */

int PairNCFContact::gather_pairs(const Step &s, int &nnear)
{
  const int npairs = (int) plist.size();
  work.resize(MAX(npairs, (int) clist.size()));
  const double dglob = s.dglob;
  int nwork = 0;
  for (int e = 0; e < npairs; e++) {
    work[nwork] = e;
    nwork += plist[e].reach < dglob;
  }
  nnear = nwork;
  // When many of these drop out at the test by the bounds of their own nodes (nodes moving fast
  // somewhere, as in a compaction: judged by the last step), that test on the dense bounds
  // first, without branches: cheaper than loading the node rows of entries that then drop out.
  // (At rest nearly all are kept: the test on the rows in pairs_batched is cheaper there.) The
  // same test either way, so the same results.
  if (keep_last < 0.8) {
    int nkeep = 0;
    for (int k = 0; k < nwork; k++) {
      const int e = work[k];
      work[nkeep] = e;
      nkeep += plist[e].reach < s.closing(plist[e]);
    }
    nwork = nkeep;
  }
  return nwork;
}

/* ----------------------------------------------------------------------
   The gathered pairs through the batched law, which evaluates the common case several pairs per
   vector instruction and hands the others back to the scalar law (NCF::segment_contact_batch),
   then the contacts through the batched dashpot and friction (NCF::tangential_batch). Each entry
   goes into the next lane if it is also within reach after the displacement bounds of its own
   nodes (read from the rows just loaded).
------------------------------------------------------------------------- */

void PairNCFContact::pairs_batched(Step &s, int nwork, int nnear)
{
  // with one set of coefficients for all type pairs (the usual case) they are put into every lane
  // once, not lane by lane
  const int ntypes = atom->ntypes;
  s.uniform = true;
  for (int i = 1; i <= ntypes; i++)
    for (int j = 1; j <= ntypes; j++) {
      const TypePair &a = tpar[type_pair(1, 1)], &b = tpar[type_pair(i, j)];
      s.uniform = s.uniform && a.dc == b.dc && a.kn == b.kn && a.ramp == b.ramp && a.kt == b.kt &&
          a.mu == b.mu && a.damp == b.damp;
    }
  if (s.uniform)
    for (int l = 0; l < NCF::CONTACT_BATCH; l++) set_lane_coefficients(l, tpar[type_pair(1, 1)]);
  batch.n = 0;
  int nkept = 0;
  for (int k = 0; k < nwork; k++) {
    const int e = work[k];
    // (the node rows of an entry a few ahead requested now: ~3 % of the pair's time)
    if (k + 16 < nwork) {
      const PairCand &pn = plist[work[k + 16]];
      __builtin_prefetch(s.xof(pn.a1));
      __builtin_prefetch(s.xof(pn.b0));
      __builtin_prefetch(s.xof(pn.b1));
    }
    const PairCand &pc = plist[e];
    const int l = batch.n;
    const double *row[4] = {s.xof(pc.a0), s.xof(pc.a1), s.xof(pc.b0), s.xof(pc.b1)};
    const double close = MAX(row[0][3], row[1][3]) + MAX(row[2][3], row[3][3]);
    // (most entries are kept at rest, few where the nodes move fast: the branch is predictable
    // in both cases, and the lane is not filled in vain in the second)
    if (!(pc.reach < close)) continue;
    nkept++;
    // (the positions and velocities are copied in flush_lanes, four lanes at a time)
    s.lane_node[l][0] = pc.a0;
    s.lane_node[l][1] = pc.a1;
    s.lane_node[l][2] = pc.b0;
    s.lane_node[l][3] = pc.b1;
    if (!s.uniform) set_lane_coefficients(l, tpar[pc.tp]);
    s.lane_e[l] = e;
    if (use_history) {
      // the slip of the last step (zero if the pair was not in contact), used only with friction
      // (read whether used or not, so that the choice is a select, not a mispredicted branch)
      const bool had = s.has_rd[e] != 0;
      const double *sr = s.slip_rd + 3 * (size_t) e;
      const double s0 = sr[0], s1 = sr[1], s2 = sr[2];
      tbatch.slip[0][l] = had ? s0 : 0.0;
      tbatch.slip[1][l] = had ? s1 : 0.0;
      tbatch.slip[2][l] = had ? s2 : 0.0;
      s.lane_had[l] = had;
    } else {
      for (int d = 0; d < 3; d++) tbatch.slip[d][l] = 0.0;
      s.lane_had[l] = false;
    }
    batch.n++;
    if (batch.n == NCF::CONTACT_BATCH) flush_lanes(s);
  }
  if (batch.n > 0) flush_lanes(s);
  keep_last = nnear > 0 ? (double) nkept / nnear : 1.0;
}

void PairNCFContact::set_lane_coefficients(int l, const TypePair &tp)
{
  batch.dc[l] = tp.dc;
  batch.kn[l] = tp.kn;
  batch.ramp[l] = tp.ramp;
  tbatch.kt[l] = tp.kt;
  tbatch.mu[l] = tp.mu;
  tbatch.damp[l] = tp.damp;
}

/* ----------------------------------------------------------------------
   The filled lanes through the batched law. The lanes in contact (status 1) go on, those with
   friction with their slip; the others are no contact (0) or left to the scalar law (-1). Flags
   first, without branches; then the few lanes that need more: the scalar law, the penetration
   output, the slip a new contact with friction takes over (or its entry deferred). Then the
   contacts' slips kept and forces added (as scalar_finish does, with the counters in locals, so
   that they stay in registers; the same operations in the same order).
------------------------------------------------------------------------- */

void PairNCFContact::flush_lanes(Step &s)
{
  NCF::fill_lanes_from_rows(batch, tbatch, s.X, s.lane_node, use_velocity);
  if (oneway)
    NCF::segment_contact_batch(batch, core);
  else
    NCF::chain_contact_batch(batch, core);
  const bool hist = use_history, eng = s.eng;
  int special[NCF::CONTACT_BATCH], nspecial = 0;
  for (int l = 0; l < batch.n; l++) {
    const double st = batch.status[l];
    const bool go = st > 0.0;
    const bool fric = hist & go & (tbatch.mu[l] > 0.0) & (batch.fn[l] > 0.0);
    s.lane_go[l] = go;
    s.lane_fric[l] = fric;
    s.lane_pen[l] = 0.0;
    special[nspecial] = l;
    nspecial += (st < 0.0) | (go & (eng | (fric & !s.lane_had[l])));
  }
  for (int k = 0; k < nspecial; k++) {
    const int l = special[k], e = s.lane_e[l];
    if (batch.status[l] < 0.0) {
      scalar_finish(s, e, scalar_law(s, e), s.lane_had[l], use_history);
      continue;
    }
    if (eng) s.lane_pen[l] = real_penetration(s, plist[e]);
    // (the slip of the last step is in the lane already; the new one is written after it)
    if (s.lane_fric[l] && !s.lane_had[l]) {
      const double *slip = start_slip(s, e, false, use_history);
      if (!slip) {
        s.lane_go[l] = s.lane_fric[l] = false;
        continue;
      }
      for (int d = 0; d < 3; d++) tbatch.slip[d][l] = slip[d];
    }
  }
  if (use_velocity) NCF::tangential_batch(batch, tbatch, s.dt, s.advance);
  double *const fc = s.fatom_now ? fcon.data() : nullptr;
  double nc = s.ncontact, ps = s.pensum, pm = s.penmax, ev = eng_vdwl;
  // (the lanes in contact listed first, without branches: which are is unpredictable)
  int go_lane[NCF::CONTACT_BATCH], ngo = 0;
  for (int l = 0; l < batch.n; l++) {
    go_lane[ngo] = l;
    ngo += s.lane_go[l];
  }
  for (int k = 0; k < ngo; k++) {
    const int l = go_lane[k], e = s.lane_e[l];
    double espring = 0.0;
    if (s.lane_fric[l]) {
      // kept (also a zero slip: the contact exists)
      double *slip = s.slip_wr + 3 * (size_t) e;
      for (int d = 0; d < 3; d++) slip[d] = tbatch.slip[d][l];
      s.has_wr[e] = 1;
      espring = tbatch.energy[l];
    }
    const PairCand &pc = plist[e];
    const int nodes[4] = {pc.a0, pc.a1, pc.b0, pc.b1};
    for (int m = 0; m < 4; m++) {
      double *fm = s.fdst(nodes[m]);
      for (int d = 0; d < 3; d++) fm[d] += batch.f[3 * m + d][l];
    }
    if (fc)
      for (int m = 0; m < 4; m++)
        for (int d = 0; d < 3; d++) fc[3 * nodes[m] + d] += batch.f[3 * m + d][l];
    if (s.tally) {
      double fm[12];
      const double *xm[4];
      int rn[4];
      for (int m = 0; m < 4; m++) {
        for (int d = 0; d < 3; d++) fm[3 * m + d] = batch.f[3 * m + d][l];
        xm[m] = s.xof(nodes[m]);
        rn[m] = real_of(nodes[m]);
      }
      tally_contact(4, rn, xm, fm, batch.energy[l] + espring);
    }
    // (the energy and penetration sums only where they are output)
    if (eng) {
      ev += batch.energy[l] + espring;
      const double pen = s.lane_pen[l];
      ps += pen;
      pm = MAX(pm, pen);
    }
    nc += 1.0;
  }
  s.ncontact = nc;
  s.pensum = ps;
  s.penmax = pm;
  eng_vdwl = ev;
  batch.n = 0;
}

/* ----------------------------------------------------------------------
   The history rows of ghost nodes are needed only by deferred take-overs: communicated (the rows
   of the previous step, not yet replaced) only in steps where some rank has one. The wait for
   the other ranks in the reduction and this communication are timed as Comm, not as Pair: the
   Pair time stays the work of this rank, which 'balance ... weight time' divides. Only the rows
   that some take-over may read are written and sent (hneed); which ones, the ranks agree in the
   first such step after a list build (bit 2 of the reduction: some rank rebuilt).
------------------------------------------------------------------------- */

void PairNCFContact::deferred_takeovers(Step &s)
{
  if (!use_history) return;
  int need = (deferred.empty() ? 0 : 1) | (hneed_valid ? 0 : 2), any = need;
  if (comm->nprocs > 1) {
    timer->stamp(Timer::PAIR);
    MPI_Allreduce(&need, &any, 1, MPI_INT, MPI_BOR, world);
  }
  if (any & 1) {
    if (any & 2) exchange_row_needs();
    // the rows of the last step, sent to the ghosts
    store_history(hlast, true);
    comm_mode = COMM_HIST;
    if (comm_forward > comm_sized) {
      // the rows were widened in this run: LAMMPS's buffers were sized at init for the old
      // width; forward_comm_array grows them (and sends the whole rows, of which again only
      // those flagged in hneed are read)
      comm->forward_comm_array(comm_forward, fhist->rows());
      comm_sized = comm_forward;
    } else {
      comm->forward_comm(this);
    }
  }
  if (comm->nprocs > 1) timer->stamp(Timer::COMM);
  if (any & 1)
    for (const int e : deferred) pair_contact(s, e, false);
}

/* ----------------------------------------------------------------------
   Cap contact of segment ao-ia (ao owned here) with the interior node k (chain kp-k-kq), at half
   weight in the symmetric law (each cap fills the gap of one of its two ways). The caps within
   the largest diameter after the displacement bound of all nodes gathered first, without
   branches; then those within reach after the displacement bounds of their own nodes (again
   without branches); whether A comes within D of the node at all is the batch's first test. In
   batches of CAP_BATCH caps through the batched caps (NCF::node_contact_batch), which hands back
   the caps outside its case to node_contact; the forces are added in the order of the caps.
------------------------------------------------------------------------- */

void PairNCFContact::node_caps(Step &s)
{
  const double cap_weight = oneway ? 1.0 : NCF::CAP_WEIGHT;
  const int ncaps = (int) clist.size();
  Step::Row *const f = s.f;
  const double dglob = s.dglob;
  int nnear = 0;
  for (int e = 0; e < ncaps; e++) {
    work[nnear] = e;
    nnear += clist[e].gap - dglob < 0.0;
  }
  int ncapin = 0;
  for (int w = 0; w < nnear; w++) {
    if (w + 16 < nnear) {
      const CapCand &cn = clist[work[w + 16]];
      __builtin_prefetch(s.xof(cn.a1));
      __builtin_prefetch(s.xof(cn.n));
    }
    const CapCand &cc = clist[work[w]];
    work[ncapin] = work[w];
    ncapin += cc.gap - (MAX(s.xof(cc.a0)[3], s.xof(cc.a1)[3]) + s.xof(cc.n)[3]) < 0.0;
  }
  for (int w0 = 0; w0 < ncapin; w0 += NCF::CAP_BATCH) {
    cbatch.n = MIN(NCF::CAP_BATCH, ncapin - w0);
    for (int l = 0; l < cbatch.n; l++) {
      const CapCand &cc = clist[work[w0 + l]];
      const TypePair &tp = tpar[cc.tp];
      cbatch.set(l, s.xof(cc.a0), s.xof(cc.a1), s.xof(cc.p), s.xof(cc.n), s.xof(cc.q), tp.dc,
                 cap_weight * tp.kn, tp.ramp);
    }
    NCF::node_contact_batch(cbatch, core);
    // (the caps in contact or left to node_contact listed first, without branches)
    int act[NCF::CAP_BATCH], nact = 0;
    for (int l = 0; l < cbatch.n; l++) {
      act[nact] = l;
      nact += cbatch.status[l] != 0.0;
    }
    for (int k = 0; k < nact; k++) {
      const int l = act[k];
      const double st = cbatch.status[l];
      const CapCand &cc = clist[work[w0 + l]];
      const int ids[5] = {cc.a0, cc.a1, cc.p, cc.n, cc.q};
      NCF::NodeContact c;
      if (st < 0.0) {
        const TypePair &tp = tpar[cc.tp];
        c = NCF::node_contact(Vec3(s.xof(cc.a0)), Vec3(s.xof(cc.a1)), Vec3(s.xof(cc.p)),
                              Vec3(s.xof(cc.n)), Vec3(s.xof(cc.q)), tp.dc, cap_weight * tp.kn,
                              tp.ramp, core);
        if (!c.active) continue;
      } else {
        c = cbatch.result(l);
      }
      for (int m = 0; m < 5; m++) {
        f[ids[m]][0] += c.f[m].x;
        f[ids[m]][1] += c.f[m].y;
        f[ids[m]][2] += c.f[m].z;
        if (s.fatom_now) {
          fcon[3 * ids[m] + 0] += c.f[m].x;
          fcon[3 * ids[m] + 1] += c.f[m].y;
          fcon[3 * ids[m] + 2] += c.f[m].z;
        }
      }
      if (s.eng) eng_vdwl += c.energy;
      if (s.tally) {
        double fm[15];
        const double *xm[5];
        for (int m = 0; m < 5; m++) {
          fm[3 * m] = c.f[m].x;
          fm[3 * m + 1] = c.f[m].y;
          fm[3 * m + 2] = c.f[m].z;
          xm[m] = s.xof(ids[m]);
        }
        tally_contact(5, ids, xm, fm, c.energy);
      }
      s.ncap += 1.0;
      s.penmax = MAX(s.penmax, c.penetration);
    }
  }
}

/* ----------------------------------------------------------------------
   The forces on the virtual nodes (extended free chain ends) onto their real nodes: the end k at
   x_k + e u, u = (x_k - x_j) / l, so F on it gives F + g on k and -g on its neighbour j,
   g = (e / l)(F - u (u.F)) (the chain rule; the contact energy depends on x_k and x_j through the
   extended end only); the virial of that mapping (the contacts were tallied at the extended
   ends); the same for the per-node contact force.
------------------------------------------------------------------------- */

void PairNCFContact::map_virtual_forces(Step &s)
{
  const int nvirt = s.nvirt;
  auto map_virtual = [&](const double *fv, auto &&dst) {
    for (int vn = 0; vn < nvirt; vn++) {
      const int k = vreal[vn], j = vnbr[vn];
      const double *gv = &vgeom[4 * (size_t) vn];
      const double ex = gv[0], ey = gv[1], ez = gv[2], sc = gv[3];
      const double *F = fv + 3 * (size_t) vn;
      const double fu = F[0] * ex + F[1] * ey + F[2] * ez;
      const double g[3] = {sc * (F[0] - fu * ex), sc * (F[1] - fu * ey), sc * (F[2] - fu * ez)};
      double *fk = dst(k), *fj = dst(j);
      for (int d = 0; d < 3; d++) {
        fk[d] += F[d] + g[d];
        fj[d] -= g[d];
      }
    }
  };
  Step::Row *const f = s.f;
  map_virtual(s.FV, [f](int k) {
    return f[k];
  });
  if (vflag_atom || cvflag_atom || vflag_global)
    for (int vn = 0; vn < nvirt; vn++)
      tally_virtual_end(vreal[vn], vnbr[vn], endext[vreal[vn]], &vgeom[4 * (size_t) vn],
                        s.FV + 3 * (size_t) vn);
  if (s.fatom_now)
    map_virtual(fcon.data() + 3 * (size_t) s.nall, [this](int k) {
      return fcon.data() + 3 * (size_t) k;
    });
}

/* ----------------------------------------------------------------------
   this step's history is the last step's of the next (its rows are written when needed; not in
   a setup: advance); the per-node contact force summed over the ghosts; compute pair's sums
------------------------------------------------------------------------- */

void PairNCFContact::finish_outputs(Step &s)
{
  if (use_history && s.advance) {
    hlast = s.hwr;
    rows_current = false;
  }

  if (s.fatom_now) {
    comm_mode = COMM_FORCE;
    comm->reverse_comm(this);
    double *fc = atom->dvector[idx_fc];
    for (int i = 0; i < s.nlocal; i++)
      fc[i] = std::sqrt(fcon[3 * i] * fcon[3 * i] + fcon[3 * i + 1] * fcon[3 * i + 1] +
                        fcon[3 * i + 2] * fcon[3 * i + 2]);
  }

  if (s.eng) {
    // compute pair sums pvector over the ranks: the maximum is reduced here and put on rank 0
    double all;
    MPI_Allreduce(&s.penmax, &all, 1, MPI_DOUBLE, MPI_MAX, world);
    pvector[0] = s.ncontact;
    pvector[1] = s.pensum;
    pvector[2] = (comm->me == 0) ? all : 0.0;
    pvector[3] = s.ncap;
  }
}

/* ----------------------------------------------------------------------
   Per-atom energy and virial of one contact (segment pair: n = 4 nodes, node cap: n = 5), and
   its share of the global virial when f dot r is not used (pair_modify nofdotr). The contact's
   energy and its virial W = sum_m (x_m - x_0) (x) f_m (= sum_m x_m (x) f_m: the forces of a
   contact balance) are split equally over its nodes, as ev_tally4 does for a dihedral. xm: the
   positions the law saw (for a virtual node the extended end), node: the atom indices (local or
   ghost; LAMMPS's computes sum the ghosts' shares back with newton pair on). Components in
   LAMMPS's order xx, yy, zz, xy, xz, yz with xy = sum dx fy (the friction couple makes W
   asymmetric, by the order of mu; LAMMPS keeps this half, as fdotr does). The centroid form
   (compute centroid/stress/atom, all nine components) gives each node its own
   (x_m - x_c) (x) f_m, x_c the mean of the contact's node positions (as Dihedral::ev_tally).
------------------------------------------------------------------------- */

void PairNCFContact::tally_contact(int n, const int *node, const double *const *xm,
                                   const double *fm, double energy)
{
  if (eflag_atom) {
    const double share = energy / n;
    for (int m = 0; m < n; m++) eatom[node[m]] += share;
  }
  if (cvflag_atom) {
    double xc[3] = {0.0, 0.0, 0.0};
    for (int m = 0; m < n; m++)
      for (int d = 0; d < 3; d++) xc[d] += xm[m][d];
    for (int d = 0; d < 3; d++) xc[d] /= n;
    for (int m = 0; m < n; m++) {
      const double a[3] = {xm[m][0] - xc[0], xm[m][1] - xc[1], xm[m][2] - xc[2]};
      const double *f = fm + 3 * m;
      double *cv = cvatom[node[m]];
      cv[0] += a[0] * f[0];
      cv[1] += a[1] * f[1];
      cv[2] += a[2] * f[2];
      cv[3] += a[0] * f[1];
      cv[4] += a[0] * f[2];
      cv[5] += a[1] * f[2];
      cv[6] += a[1] * f[0];
      cv[7] += a[2] * f[0];
      cv[8] += a[2] * f[1];
    }
  }
  if (!(vflag_atom || vflag_global)) return;
  double v[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int m = 1; m < n; m++) {
    const double dx = xm[m][0] - xm[0][0], dy = xm[m][1] - xm[0][1], dz = xm[m][2] - xm[0][2];
    const double *f = fm + 3 * m;
    v[0] += dx * f[0];
    v[1] += dy * f[1];
    v[2] += dz * f[2];
    v[3] += dx * f[1];
    v[4] += dx * f[2];
    v[5] += dy * f[2];
  }
  if (vflag_global)
    for (int c = 0; c < 6; c++) virial[c] += v[c];
  if (vflag_atom) {
    const double s = 1.0 / n;
    for (int m = 0; m < n; m++)
      for (int c = 0; c < 6; c++) vatom[node[m]][c] += s * v[c];
  }
}

/* ----------------------------------------------------------------------
   The virial of mapping the force fv on the virtual node of a free end k (at x_k + e u, u the
   unit vector from its neighbour j to k) onto k and j: the contacts were tallied at the extended
   end, the forces act at x_k and x_j, and x_k (x) (fv + g) - x_j (x) g - (x_k + e u) (x) fv =
   -e (u . fv) u (x) u (g = (e / l)(fv - u (u . fv))); split equally over k and j (per-atom and
   centroid form alike: it is symmetric). u: vgeom row.
------------------------------------------------------------------------- */

void PairNCFContact::tally_virtual_end(int k, int j, double e, const double *u, const double *fv)
{
  const double c = -e * (u[0] * fv[0] + u[1] * fv[1] + u[2] * fv[2]);
  const double v[6] = {c * u[0] * u[0], c * u[1] * u[1], c * u[2] * u[2],
                       c * u[0] * u[1], c * u[0] * u[2], c * u[1] * u[2]};
  if (vflag_global)
    for (int m = 0; m < 6; m++) virial[m] += v[m];
  if (vflag_atom)
    for (int m = 0; m < 6; m++) {
      vatom[k][m] += 0.5 * v[m];
      vatom[j][m] += 0.5 * v[m];
    }
  if (cvflag_atom) {
    // (xx yy zz xy xz yz, then yx zx zy: the same as xy xz yz)
    const int from[9] = {0, 1, 2, 3, 4, 5, 3, 4, 5};
    for (int m = 0; m < 9; m++) {
      cvatom[k][m] += 0.5 * v[from[m]];
      cvatom[j][m] += 0.5 * v[from[m]];
    }
  }
}

int PairNCFContact::pack_reverse_comm(int n, int first, double *buf)
{
  if (comm_mode == COMM_NEED) {
    for (int k = 0; k < n; k++) buf[k] = hneed[first + k];
    return n;
  }
  int m = 0;
  for (int k = first; k < first + n; k++) {
    buf[m++] = fcon[3 * k];
    buf[m++] = fcon[3 * k + 1];
    buf[m++] = fcon[3 * k + 2];
  }
  return m;
}

void PairNCFContact::unpack_reverse_comm(int n, int *list, double *buf)
{
  if (comm_mode == COMM_NEED) {
    for (int k = 0; k < n; k++) hneed[list[k]] += buf[k];
    return;
  }
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    fcon[3 * j] += buf[m++];
    fcon[3 * j + 1] += buf[m++];
    fcon[3 * j + 2] += buf[m++];
  }
}
