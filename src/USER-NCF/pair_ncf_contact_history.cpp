/* ----------------------------------------------------------------------
   USER-NCF: pair_style ncf/contact (see pair_ncf_contact.h, doc/pair_ncf_contact.md)
   The friction history: the slip a new contact takes over from a neighbouring pair, the
   history buffers of the pair list loaded from and stored into the per-atom store, and the
   forward communication of its rows.
------------------------------------------------------------------------- */

#include "pair_ncf_contact.h"
#include "pair_ncf_contact_keys.h"

#include "fix_ncf_contact_history.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "update.h"

#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using namespace NCF_PairContact;

void PairNCFContact::other_partner(tagint node, tagint not_this, tagint &out) const
{
  out = 0;
  const int m = atom->map(node);
  if (m < 0) return;
  double **cnb = atom->darray[idx_cnb];
  for (int s = 0; s < 2; s++) {
    const tagint p = (tagint) cnb[m][s];
    if (p != 0 && p != not_this) out = p;
  }
}

// stored slip of the pair (segment owner-ohi, segment blo-bhi) in the history row of the atom
// with index m (the owner node), nullptr if none
const double *PairNCFContact::find_slip_row(int m, tagint ohi, tagint blo, tagint bhi) const
{
  const double *row = fhist->rows()[m];
  const int n = (int) row[0];
  // tags are stored exactly as doubles: compare them as such
  const double h = (double) ohi, l = (double) blo, b = (double) bhi;
  for (int k = 0; k < n; k++) {
    const double *s = row + 1 + 6 * k;
    if (s[0] == h && s[1] == l && s[2] == b) return s + 3;
  }
  return nullptr;
}

// the slip of the previous step of the pair (segment owner-ohi, segment blo-bhi) owned by the
// local node m, from the pair list entries of m, nullptr if none (what find_slip_row finds in the
// row of m, which is only written when LAMMPS needs it: sync_history)
const double *PairNCFContact::find_slip_entry(int m, tagint ohi, tagint blo, tagint bhi) const
{
  const tagint *tag = atom->tag;
  const unsigned char *has = phas[hlast].data();
  for (int e = pfirst[m]; e < pfirst[m + 1]; e++) {
    if (!has[e]) continue;
    const PairCand &pc = plist[e];
    if (tag[real_of(pc.a1)] == ohi && tag[real_of(pc.b0)] == blo && tag[real_of(pc.b1)] == bhi)
      return &pslip[hlast][3 * (size_t) e];
  }
  return nullptr;
}

// the neighbouring segment pairs of a new contact A-B (same chains, one segment further along one
// of them), whose slip it takes over, so that a contact point sliding over a node keeps its
// history: the pair's history is in the row of the lower node of its lower segment M
int PairNCFContact::takeover_candidates(tagint a0, tagint a1, tagint b0, tagint b1,
                                        TakeOver *out) const
{
  const SegKey A{a0, a1}, B{b0, b1};
  SegKey cand[4][2];
  int nc = 0;
  tagint p;
  other_partner(b0, b1, p);
  if (p) cand[nc][0] = A, cand[nc++][1] = make_key(b0, p);
  other_partner(b1, b0, p);
  if (p) cand[nc][0] = A, cand[nc++][1] = make_key(b1, p);
  other_partner(a0, a1, p);
  if (p) cand[nc][0] = make_key(a0, p), cand[nc++][1] = B;
  other_partner(a1, a0, p);
  if (p) cand[nc][0] = make_key(a1, p), cand[nc++][1] = B;
  int n = 0;
  for (int c = 0; c < nc; c++) {
    const SegKey &X = cand[c][0], &Y = cand[c][1];
    if (share_node(X, Y)) continue;
    const SegKey &M = key_less(X, Y) ? X : Y, &O = key_less(X, Y) ? Y : X;
    out[n++] = {atom->map(M.lo), M.hi, O.lo, O.hi};
  }
  return n;
}

// a new contact takes over the slip of the first neighbouring pair (takeover_candidates) that had
// one; only values of the previous step are read (the same on any number of ranks)
// local_only: only rows of owned nodes are up to date (the ghost rows have not been communicated
// this step); returns false, without a result, when a ghost's row would be needed
bool PairNCFContact::inherit_slip(tagint a0, tagint a1, tagint b0, tagint b1, double *slip,
                                  bool local_only) const
{
  TakeOver cand[4];
  const int nc = takeover_candidates(a0, a1, b0, b1, cand);
  for (int c = 0; c < nc; c++) {
    const int m = cand[c].m;
    if (m < 0) continue;
    if (m >= atom->nlocal && local_only) return false;
    // (the rows of ghosts are communicated for the deferred take-overs, the local rows not
    // written every step)
    const double *s = m < atom->nlocal ? find_slip_entry(m, cand[c].mhi, cand[c].olo, cand[c].ohi)
                                       : find_slip_row(m, cand[c].mhi, cand[c].olo, cand[c].ohi);
    if (s && (s[0] != 0.0 || s[1] != 0.0 || s[2] != 0.0)) {
      slip[0] = s[0];
      slip[1] = s[1];
      slip[2] = s[2];
      return true;
    }
  }
  return true;
}

// The rows a take-over may read on some rank (hneed): each rank flags the ghosts whose rows the
// take-overs of its list entries would read, the flags are summed onto the owners (reverse
// communication) and sent back to every ghost copy (forward communication), so that the history
// communication carries only those rows and the sender and every receiver agree on which.
// Collective; after every list build, before the first history communication that follows.
void PairNCFContact::exchange_row_needs()
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const tagint *tag = atom->tag;
  hneed.assign(nall, 0.0);
  // a take-over reads the row of the lower node of A, of B or of a segment next to one of them
  // along its chain (takeover_candidates): those nodes of every entry are flagged, through the
  // chain neighbours of the build (nbr; any periodic image: all copies get the owner's flag)
  auto mark_lower = [&](int i, int j) {
    const int lo = tag[i] < tag[j] ? i : j;
    if (lo >= nlocal) hneed[lo] = 1.0;
  };
  for (const PairCand &pc : plist) {
    const int nodes[4] = {real_of(pc.a0), real_of(pc.a1), real_of(pc.b0), real_of(pc.b1)};
    mark_lower(nodes[0], nodes[1]);
    mark_lower(nodes[2], nodes[3]);
    for (int k = 0; k < 4; k++)
      for (int s = 0; s < 2; s++) {
        int j = nbr[2 * nodes[k] + s];
        // (a neighbour beyond the shell's edge: any image of it, as the take-over finds it)
        if (j == -2) j = atom->map((tagint) atom->darray[idx_cnb][nodes[k]][s]);
        if (j >= 0 && j != nodes[k ^ 1]) mark_lower(nodes[k], j);
      }
  }
  comm_mode = COMM_NEED;
  comm->reverse_comm(this, 1);
  comm->forward_comm(this, 1);
  hneed_valid = true;
}

/* ----------------------------------------------------------------------
   friction history: between two list builds it lives with the pair list entries, in two
   buffers (pslip, phas): one holds the slips of the last step, read by this step (also by the
   take-overs of new contacts, so that every rank sees the same values whatever the order of its
   list), the other receives the slips of this step. The per-atom store (fix ncf/contact/history,
   rows of the owner nodes) is what LAMMPS migrates, sorts and writes to restart files: it is read
   at every build and written only when LAMMPS needs it (sync_history, from fix
   ncf/contact/history before atoms migrate and at the end of a run; and for the take-overs that
   need the rows of ghosts). Its rows have as many slots as the node with the most contacts
   needs: store_history widens it on all ranks together when a node has more contacts than slots
------------------------------------------------------------------------- */

void PairNCFContact::load_history()
{
  const tagint *tag = atom->tag;
  double **hist = fhist->rows();
  const size_t np = plist.size();
  hlast = 0;
  for (int b = 0; b < 2; b++) {
    pslip[b].assign(3 * np, 0.0);
    phas[b].assign(np, 0);
  }
  for (size_t e = 0; e < np; e++) {
    const PairCand &pc = plist[e];
    if (hist[pc.a0][0] == 0.0) continue;
    const double *old = find_slip_row(pc.a0, tag[pc.a1], tag[pc.b0], tag[pc.b1]);    // (real)
    if (!old) continue;
    memcpy(&pslip[0][3 * e], old, 3 * sizeof(double));
    phas[0][e] = 1;
  }
  rows_current = true;
}

// the per-atom rows of the owned nodes from history buffer b (hlast: the last step's); collective
// (the store is widened on all ranks when a node on one of them has more contacts than slots)
// (only_needed: only the rows that take-overs on other ranks or of ghost images may read, hneed)
void PairNCFContact::store_history(int b, bool only_needed)
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  if (nlocal != lists_nlocal)
    error->one(FLERR,
               "pair ncf/contact: the atoms changed before their friction history was stored "
               "(a fix added, deleted or moved atoms in pre_exchange before fix {}: define such "
               "fixes after pair_style ncf/contact)",
               FixNCFContactHistory::ID);
  const unsigned char *has = phas[b].data();
  const double *slip = pslip[b].data();
  // the most contacts of a node (the entries of a node are consecutive: build_lists)
  int need = 0;
  for (int i = 0; i < nlocal; i++) {
    int n = 0;
    for (int e = pfirst[i]; e < pfirst[i + 1]; e++) n += has[e];
    need = n > need ? n : need;
  }
  const int had = fhist->slots();
  // (in steps of 8 slots, so that a node gaining contacts one by one does not widen it each time)
  fhist->agree(need > had ? (need + 7) / 8 * 8 : had);
  if (fhist->slots() != had) {
    comm_forward = fhist->row_width();
    if (comm->me == 0)
      utils::logmesg(lmp,
                     "pair ncf/contact: friction history widened from {} to {} contacts per node "
                     "at step {} (fix {})\n",
                     had, fhist->slots(), update->ntimestep, FixNCFContactHistory::ID);
  }
  double **hist = fhist->rows();
  for (int i = 0; i < nlocal; i++) {
    if (only_needed && hneed[i] == 0.0) continue;
    double *row = hist[i];
    int n = 0;
    for (int e = pfirst[i]; e < pfirst[i + 1]; e++) {
      if (!has[e]) continue;
      const PairCand &pc = plist[e];
      double *h = row + 1 + FixNCFContactHistory::SLOT * n;
      // the slot: key of A's partner and of B, then the slip
      h[0] = (double) tag[real_of(pc.a1)];
      h[1] = (double) tag[real_of(pc.b0)];
      h[2] = (double) tag[real_of(pc.b1)];
      memcpy(h + 3, slip + 3 * (size_t) e, 3 * sizeof(double));
      n++;
    }
    row[0] = n;
  }
}

void PairNCFContact::sync_history()
{
  if (!use_history || !lists_valid || rows_current) return;
  store_history(hlast);
  rows_current = true;
}

/* ---------------------------------------------------------------------- */

int PairNCFContact::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/,
                                      int * /*pbc*/)
{
  if (comm_mode == COMM_NEED) {
    for (int k = 0; k < n; k++) buf[k] = hneed[list[k]];
    return n;
  }
  // variable length: per atom whose row a take-over may read (hneed, the same flag on the owner
  // and every copy) the number of contacts, then 6 values per contact; nothing for the others
  double **hist = fhist->rows();
  int m = 0;
  for (int k = 0; k < n; k++) {
    if (hneed[list[k]] == 0.0) continue;
    const double *row = hist[list[k]];
    const int len = 1 + 6 * (int) row[0];
    memcpy(buf + m, row, sizeof(double) * len);
    m += len;
  }
  return m;
}

void PairNCFContact::unpack_forward_comm(int n, int first, double *buf)
{
  if (comm_mode == COMM_NEED) {
    for (int k = 0; k < n; k++) hneed[first + k] = buf[k];
    return;
  }
  double **hist = fhist->rows();
  int m = 0;
  for (int k = first; k < first + n; k++) {
    if (hneed[k] == 0.0) continue;
    const int len = 1 + 6 * (int) buf[m];
    memcpy(hist[k], buf + m, sizeof(double) * len);
    m += len;
  }
}
