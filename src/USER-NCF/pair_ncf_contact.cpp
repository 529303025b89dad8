/* ----------------------------------------------------------------------
   USER-NCF: pair_style ncf/contact (see pair_ncf_contact.h, doc/pair_ncf_contact.md)

   How each segment pair is visited exactly once:
   - a segment (bond i-j of a chain) is owned by its lower-tag node;
   - when LAMMPS reneighbours, a cell list of the midpoints of all segments known to the rank
     (owned and ghost, periodic images included) gives the candidate pairs; a pair is listed when
     the two segments are within D (1 + ramp) + skin, so the list stays complete until the next
     reneighbouring (no node moves more than skin/2 in between); the node caps likewise;
   - the pair (A owned by i, B owned by j) is listed only where key(A) < key(B), key = (lower
     tag, higher tag), on the rank that owns A's owner node, whatever rank owns B;
   - forces on ghost nodes go back by LAMMPS's reverse communication (newton_pair on).
   The friction history of the pair lives with A's owner node (the per-atom store of fix
   ncf/contact/history, as wide as the node with the most contacts needs), so it migrates and
   restarts with it; the rank that computes the pair always owns it. Between two
   list builds the history of a pair is read and updated in its list entry; the per-atom store is
   loaded at the build and written when LAMMPS needs it (fix ncf/contact/history). Ghost rows of
   the store are communicated only in steps where a new contact takes over the slip of a pair
   owned by another rank.

   The style in four files:
   pair_ncf_contact.cpp          arguments, coefficients, init, stores, restart, extract (this)
   pair_ncf_contact_list.cpp     candidate lists: segments, build_lists (binning: ncf_box_grid.h)
   pair_ncf_contact_history.cpp  friction history: take-overs, load/store, its communication
   pair_ncf_contact_compute.cpp  compute() as named steps: batches of the contact law, caps, free
                                 ends, outputs
------------------------------------------------------------------------- */

#include "pair_ncf_contact.h"

#include "fix_ncf_contact_history.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include "lammps_ncf_args.h"
#include "lammps_ncf_compat.h"
#include "ncf_contact.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

/* ---------------------------------------------------------------------- */

PairNCFContact::PairNCFContact(LAMMPS *lmp) : Pair(lmp)
{
  restartinfo = 1;
  single_enable = 0;
  centroidstressflag = CENTROID_AVAIL;    // (tally_contact)
  one_coeff = 0;
  manybody_flag = 0;
  ramp_frac = 0.25;
  core = NCF::DEFAULT_CORE;
  endcap_frac = NCF::DEFAULT_ENDCAP;
  lmax_user = 0.0;
  maxcontacts = 24;
  fatom_every = 0;
  work_flag = 0;
  dtcheck = 2;
  oneway = 0;
  dt_critical = 0.0;
  ghost_user = ghost_set = -1.0;
  cut = reachf = nullptr;
  tstride = 0;
  lmax_used = 0.0;
  reach_max = diam_max = 0.0;
  use_history = use_velocity = false;
  idx_cnb = idx_fc = idx_work = -1;
  fhist = nullptr;
  comm_sized = 0;
  comm_mode = COMM_HIST;
  lists_valid = false;
  hneed_valid = false;
  lists_ncalls = -1;
  lists_nlocal = lists_nall = -1;
  lseg_build = 0.0;
  keep_last = 1.0;
  nall_build = 0;
  hlast = 0;
  rows_current = true;
  nextra = 4;
  pvector = new double[nextra];
  for (int k = 0; k < nextra; k++) pvector[k] = 0.0;
  // created now, so that it comes before the fixes of the input that migrate atoms (fix
  // ncf/contact/history, init); without a box yet, at the first init
  if (domain->box_exist) create_history_fix();
}

void PairNCFContact::create_history_fix()
{
  if (!modify->get_fix_by_id(FixNCFContactHistory::ID))
    modify->add_fix(fmt::format("{} all ncf/contact/history", FixNCFContactHistory::ID));
}

// the history store at init (friction on): after read_restart the fix is created again in its
// place (LAMMPS replaces a fix of the same ID and style where it stands), so that it takes its
// width and rows from the file; it has at least maxcontacts slots, as many on every rank
void PairNCFContact::attach_history_store()
{
  // (restart data not yet handed out exist only before the first run after read_restart; the
  // fix created with the pair style in read_restart came before them)
  const bool after_restart = modify->nfix_restart_peratom > 0;
  if (after_restart && modify->get_fix_by_id(FixNCFContactHistory::ID))
    modify->add_fix(fmt::format("{} all ncf/contact/history", FixNCFContactHistory::ID));
  else
    create_history_fix();
  fhist = dynamic_cast<FixNCFContactHistory *>(modify->get_fix_by_id(FixNCFContactHistory::ID));
  if (!fhist)
    error->all(FLERR, "pair ncf/contact: fix {} is not of style ncf/contact/history",
               FixNCFContactHistory::ID);
  if (after_restart) import_old_history();
  fhist->agree(maxcontacts);
}

// a restart file of a version that kept the history in a fix property/atom (ID OLD_HIST_ID, 1 +
// 6 maxcontacts columns, maxcontacts of the file's pair style): that fix is created for a moment
// to take its per-atom data (rows of zeros if the file has none), its rows copied into the empty
// rows of the store, and deleted
void PairNCFContact::import_old_history()
{
  if (modify->get_fix_by_id(OLD_HIST_ID)) return;
  const int ncol = 1 + FixNCFContactHistory::SLOT * maxcontacts;
  modify->add_fix(
      fmt::format("{} all property/atom d2_ncf_chist {} ghost no writedata no", OLD_HIST_ID, ncol));
  int flag, cols;
  const int idx = atom->find_custom("ncf_chist", flag, cols);
  if (idx >= 0 && flag == 1 && cols == ncol) {
    double **old = atom->darray[idx];
    for (int i = 0; i < atom->nlocal; i++) {
      const int n = (int) old[i][0];
      const bool empty = !fhist->rows() || fhist->rows()[i][0] == 0.0;
      if (n > 0 && n <= maxcontacts && empty) fhist->set_row(i, old[i]);
    }
  }
  modify->delete_fix(OLD_HIST_ID);
}

PairNCFContact::~PairNCFContact()
{
  delete[] pvector;
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(cut);
    memory->destroy(reachf);
  }
}

void PairNCFContact::allocate()
{
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  memory->create(cut, n + 1, n + 1, "pair:cut");
  memory->create(reachf, n + 1, n + 1, "pair:reach");
  for (int i = 0; i <= n; i++)
    for (int j = 0; j <= n; j++) {
      setflag[i][j] = 0;
      cut[i][j] = reachf[i][j] = 0.0;
    }
  table.resize(n);
}

/* ----------------------------------------------------------------------
   pair_style ncf/contact [ramp f] [core kappa] [endcap f] [lmax L] [maxcontacts N] [fatom yes|no|N]
                          [dtcheck error|warn|no] [law symmetric|oneway] [work yes|no]
------------------------------------------------------------------------- */

void PairNCFContact::settings(int narg, char **arg)
{
  int iarg = 0;
  NCF_LMP::KeywordsOnce once(lmp, "pair_style ncf/contact");
  while (iarg < narg) {
    const std::string key = arg[iarg];
    once(key);
    const std::string W = "pair_style ncf/contact";
    NCF_LMP::need_values(lmp, W, key, iarg, narg, 1);
    const char *val = arg[iarg + 1];
    if (key == "ramp") {
      ramp_frac = NCF_LMP::number(lmp, W, key, val);
      if (!(ramp_frac > 0.0) || ramp_frac > 1.0)
        error->all(FLERR, "pair_style ncf/contact: ramp {} out of range (0, 1]", val);
    } else if (key == "core") {
      core = NCF_LMP::number(lmp, W, key, val);
      if (!(core >= 0.0) || core > 1000.0)
        error->all(FLERR, "pair_style ncf/contact: core {} out of range [0, 1000]", val);
    } else if (key == "endcap") {
      endcap_frac = NCF_LMP::number(lmp, W, key, val);
      if (!(endcap_frac >= 0.0) || endcap_frac > 2.0)
        error->all(FLERR, "pair_style ncf/contact: endcap {} out of range [0, 2]", val);
    } else if (key == "lmax") {
      lmax_user = NCF_LMP::number(lmp, W, key, val);
      if (lmax_user < 0.0) error->all(FLERR, "pair_style ncf/contact: lmax {} must be >= 0", val);
    } else if (key == "maxcontacts") {
      maxcontacts = (int) NCF_LMP::integer(lmp, W, key, val, 1, 1000);
    } else if (key == "fatom") {
      // yes (every step), no, or N: every N steps (and the last step of every run)
      if (utils::is_integer(val))
        fatom_every = (int) NCF_LMP::integer(lmp, W, key, val, 0, MAXSMALLINT);
      else if (!strcmp(val, "yes") || !strcmp(val, "on") || !strcmp(val, "true"))
        fatom_every = 1;
      else if (!strcmp(val, "no") || !strcmp(val, "off") || !strcmp(val, "false"))
        fatom_every = 0;
      else
        error->all(FLERR,
                   "pair_style ncf/contact: fatom {} is not one of yes, no or a number of steps N",
                   val);
    } else if (key == "dtcheck") {
      if (strcmp(val, "error") == 0)
        dtcheck = 2;
      else if (strcmp(val, "warn") == 0)
        dtcheck = 1;
      else if (strcmp(val, "no") == 0)
        dtcheck = 0;
      else
        error->all(FLERR, "pair_style ncf/contact: dtcheck {} is not one of error, warn, no", val);
    } else if (key == "law") {
      if (strcmp(val, "symmetric") == 0)
        oneway = 0;
      else if (strcmp(val, "oneway") == 0)
        oneway = 1;
      else
        error->all(FLERR, "pair_style ncf/contact: law {} is not one of symmetric, oneway", val);
    } else if (key == "work") {
      work_flag = NCF_LMP::logical(lmp, W, key, val) ? 1 : 0;
    } else {
      error->all(FLERR, "pair_style ncf/contact: unknown keyword '{}'", key);
    }
    iarg += 2;
  }
  // the per-atom contact force and work estimate exist from here on, so that a dump, variable or
  // fix balance defined before the first run can name d_ncf_fcontact and d_ncf_work
  if (domain->box_exist) create_peratom_outputs();
}

// the per-atom stores of the outputs asked for: d_ncf_fcontact (fatom), d_ncf_work (work)
void PairNCFContact::create_peratom_outputs()
{
  const struct {
    bool on;
    const char *id, *name;
    int &idx;
  } outs[] = {{fatom_every != 0, FORCE_ID, "ncf_fcontact", idx_fc},
              {work_flag != 0, WORK_ID, "ncf_work", idx_work}};
  for (const auto &o : outs) {
    o.idx = -1;
    if (!o.on) continue;
    if (!modify->get_fix_by_id(o.id))
      modify->add_fix(fmt::format("{} all property/atom d_{} ghost no writedata no", o.id, o.name));
    int flag, cols;
    o.idx = atom->find_custom(o.name, flag, cols);
    if (o.idx < 0 || flag != 1 || cols != 0)
      error->all(FLERR, "pair ncf/contact: d_{} of fix {} is malformed", o.name, o.id);
  }
  // nodes without an estimate yet (0: the store was just created, or the atoms were added since
  // the last list build) weigh as a node without contacts, so that a fix balance before the first
  // build sees valid weights (> 0)
  if (idx_work >= 0) {
    double *w = atom->dvector[idx_work];
    for (int i = 0; i < atom->nlocal; i++)
      if (!(w[i] >= 1.0)) w[i] = 1.0;
  }
}

/* ----------------------------------------------------------------------
   pair_coeff I J kn <Pa> [kt <ratio>] [mu <value>] [damp <N s/m^2>] [diameter <m>]
   diameter sets the chain diameter of every type named in I and J
------------------------------------------------------------------------- */

void PairNCFContact::coeff(int narg, char **arg)
{
  if (narg < 2) error->all(FLERR, "pair_coeff ncf/contact: expected I J kn <value> ...");
  if (!allocated) allocate();
  const std::string W = "pair_coeff ncf/contact";
  int ilo, ihi, jlo, jhi;
  NCF_LMP::types(lmp, W, "I", arg[0], atom->ntypes, ilo, ihi);
  NCF_LMP::types(lmp, W, "J", arg[1], atom->ntypes, jlo, jhi);

  NCF::ContactCoeffs one;
  double d_one = -1.0;
  NCF_LMP::ContactReader reader(lmp, W);
  int iarg = 2;
  while (iarg < narg) {
    if (reader.read(iarg, narg, arg, one)) continue;
    const std::string key = arg[iarg];
    if (key != "diameter") error->all(FLERR, "{}: unknown keyword '{}'", W, key);
    reader.once(key);
    NCF_LMP::need_values(lmp, W, key, iarg, narg, 1);
    d_one = NCF_LMP::number(lmp, W, key, arg[iarg + 1]);
    if (!(d_one > 0.0)) error->all(FLERR, "{}: diameter {} must be > 0", W, arg[iarg + 1]);
    NCF_LMP::diameter_in_box(lmp, W, "diameter", arg[iarg + 1], d_one);
    iarg += 2;
  }
  if (!reader.has(NCF::ContactKey::KN) && d_one < 0.0)
    error->all(FLERR, "{}: give kn (and optionally kt, mu, damp, diameter)", W);
  if (!reader.has(NCF::ContactKey::KN) && !reader.keys().empty())
    error->all(FLERR,
               "{}: keyword {} for types {} {} needs kn in the same pair_coeff (a line without kn "
               "sets only the diameter)",
               W, reader.keys().front(), arg[0], arg[1]);

  int count = 0;
  for (int i = ilo; i <= ihi; i++) {
    if (d_one > 0.0) table.set_diameter(i, d_one);
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      if (d_one > 0.0) table.set_diameter(j, d_one);
      // (a diameter only: init_style says which kn is missing)
      if (reader.has(NCF::ContactKey::KN)) table.set(i, j, one);
      setflag[i][j] = 1;
      count++;
    }
  }
  if (count == 0) error->all(FLERR, "{}: no type pair in {} {}", W, arg[0], arg[1]);
}

/* ---------------------------------------------------------------------- */

void PairNCFContact::create_stores()
{
  if (!modify->get_fix_by_id(TOPO_ID))
    modify->add_fix(
        fmt::format("{} all property/atom d2_ncf_cnb 2 ghost yes writedata no", TOPO_ID));
  int flag, cols;
  idx_cnb = atom->find_custom("ncf_cnb", flag, cols);
  if (idx_cnb < 0 || flag != 1 || cols != 2)
    error->all(FLERR, "pair ncf/contact: per-atom array d2_ncf_cnb of fix {} is malformed",
               TOPO_ID);

  fhist = nullptr;
  if (use_history) attach_history_store();
  create_peratom_outputs();
}

// chain neighbours (tags) of the owned atoms, from the 1-2 special list
void PairNCFContact::fill_topology()
{
  double **cnb = atom->darray[idx_cnb];
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    const int n = atom->nspecial[i][0];
    if (n > 2)
      error->one(FLERR,
                 "pair ncf/contact: node {} has {} bonded neighbours; chains must be linear (<= 2)",
                 atom->tag[i], n);
    cnb[i][0] = n > 0 ? (double) atom->special[i][0] : 0.0;
    cnb[i][1] = n > 1 ? (double) atom->special[i][1] : 0.0;
  }
}

// longest segment of the system now (unwrapped positions gathered by tag, once per run)
void PairNCFContact::find_lmax()
{
  const int nlocal = atom->nlocal;
  const tagint maxtag = atom->map_tag_max;
  std::vector<double> xall(3 * (size_t) (maxtag + 1), 0.0), mine(xall.size(), 0.0);
  double unwrap[3];
  for (int i = 0; i < nlocal; i++) {
    domain->unmap(atom->x[i], atom->image[i], unwrap);
    for (int d = 0; d < 3; d++) mine[3 * atom->tag[i] + d] = unwrap[d];
  }
  MPI_Allreduce(mine.data(), xall.data(), (int) xall.size(), MPI_DOUBLE, MPI_SUM, world);
  // segment length from the unwrapped positions, as the nearest image across periodic faces: a
  // chain closed on itself through the box (a stitching yarn) has no consistent image flags, so
  // its closing bond would otherwise measure a box length
  const double prd[3] = {domain->xprd, domain->yprd, domain->zprd};
  const int periodic[3] = {domain->xperiodic, domain->yperiodic, domain->zperiodic};
  auto seg_length = [&](tagint a, tagint b) {
    double r2 = 0.0;
    for (int d = 0; d < 3; d++) {
      double dx = xall[3 * b + d] - xall[3 * a + d];
      if (periodic[d]) dx -= prd[d] * std::round(dx / prd[d]);
      r2 += dx * dx;
    }
    return std::sqrt(r2);
  };
  double lmax = 0.0;
  for (int i = 0; i < nlocal; i++)
    for (int s = 0; s < atom->nspecial[i][0] && s < 2; s++) {
      const tagint p = atom->special[i][s];
      if (p <= atom->tag[i]) continue;
      lmax = std::max(lmax, seg_length(atom->tag[i], p));
    }
  // critical time step of the contacts: a node of mass m pressed against an equal one by parallel
  // contacts over half its two segments, stiffness k = kn (L_1 + L_2)/2: dt_c = sqrt(2 m / k)
  double knmax = 0.0;
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++)
      if (table.given(i, j)) knmax = MAX(knmax, table.coeffs(i, j).kn);
  double omega2 = 0.0;
  for (int i = 0; i < nlocal; i++) {
    double len = 0.0;
    for (int s = 0; s < atom->nspecial[i][0] && s < 2; s++) {
      len += 0.5 * seg_length(atom->tag[i], atom->special[i][s]);
    }
    const double m = atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
    if (m > 0.0 && len > 0.0) omega2 = MAX(omega2, 2.0 * knmax * len / m);
  }
  double omega2all;
  MPI_Allreduce(&omega2, &omega2all, 1, MPI_DOUBLE, MPI_MAX, world);
  dt_critical = omega2all > 0.0 ? 2.0 / std::sqrt(omega2all) : 0.0;

  check_coincident(xall);

  double all;
  MPI_Allreduce(&lmax, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  lmax_used = lmax_user > 0.0 ? lmax_user : 1.1 * all;
  if (lmax_user > 0.0 && all > lmax_user)
    error->all(FLERR, "pair ncf/contact: longest segment {:.6g} exceeds lmax {:.6g}", all,
               lmax_user);
  // another bond style's bonds may stretch far more than the 10 % the default allows
  if (lmax_user == 0.0 && !lmax_note().empty() && comm->me == 0 && !lmax_warned) {
    error->warning(FLERR,
                   "pair ncf/contact: lmax {:.6g} (1.1 x the longest segment now){}; give "
                   "pair_style keyword lmax for the longest segment the run will have",
                   lmax_used, lmax_note());
    lmax_warned = true;
  }
}

// what the messages about lmax add for a bond style other than ncf/chain (empty for ncf/chain)
std::string PairNCFContact::lmax_note() const
{
  const std::string style = force->bond_style ? force->bond_style : "none";
  if (utils::strmatch(style, "^ncf/chain")) return "";
  return " (bond_style " + style +
      ": its bonds are not the stiff elements of bond_style ncf/chain and may stretch beyond it)";
}

/* ----------------------------------------------------------------------
   no two segments on top of each other (both nodes of one at the places of both nodes of
   another: chains read twice, or stacked by a generator): the contact law has no direction
   between coincident axes. Single coincident nodes (chains crossing at a node) are fine.
   xall: the unwrapped position of every tag (zero for tags that do not exist), the same on
   every rank, so every rank finds the same nodes; only their segments are gathered.
------------------------------------------------------------------------- */

void PairNCFContact::check_coincident(const std::vector<double> &xall)
{
  const tagint maxtag = atom->map_tag_max;
  const int periodic[3] = {domain->xperiodic, domain->yperiodic, domain->zperiodic};
  std::vector<double> w(xall.size());
  for (tagint t = 1; t <= maxtag; t++)
    for (int d = 0; d < 3; d++) {
      double x = xall[3 * t + d];
      if (periodic[d]) x -= domain->prd[d] * std::floor((x - domain->boxlo[d]) / domain->prd[d]);
      w[3 * t + d] = x;
    }
  auto place_less = [&](tagint a, tagint b) {
    for (int d = 0; d < 3; d++)
      if (w[3 * a + d] != w[3 * b + d]) return w[3 * a + d] < w[3 * b + d];
    return false;
  };
  auto same_place = [&](tagint a, tagint b) {
    return !place_less(a, b) && !place_less(b, a);
  };
  std::vector<tagint> order;
  order.reserve(maxtag);
  for (tagint t = 1; t <= maxtag; t++) order.push_back(t);
  std::sort(order.begin(), order.end(), [&](tagint a, tagint b) {
    return place_less(a, b) || (!place_less(b, a) && a < b);
  });
  // tags sharing their place with another (tags that do not exist sit at the origin too)
  std::vector<char> shared(maxtag + 1, 0);
  bool any = false;
  for (std::size_t k = 1; k < order.size(); k++)
    if (same_place(order[k - 1], order[k])) {
      shared[order[k - 1]] = shared[order[k]] = 1;
      any = true;
    }
  if (!any) return;    // (the same on every rank)

  // the segments (tag, partner tag > tag) of owned nodes with both nodes at shared places
  std::vector<double> mine;
  for (int i = 0; i < atom->nlocal; i++) {
    const tagint a = atom->tag[i];
    if (!shared[a]) continue;
    for (int s = 0; s < atom->nspecial[i][0] && s < 2; s++) {
      const tagint b = atom->special[i][s];
      if (b > a && shared[b]) mine.insert(mine.end(), {(double) a, (double) b});
    }
  }
  int n = (int) mine.size(), nprocs = comm->nprocs;
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int q = 1; q < nprocs; q++) displs[q] = displs[q - 1] + counts[q - 1];
  std::vector<double> segs(displs[nprocs - 1] + counts[nprocs - 1]);
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, segs.data(), counts.data(), displs.data(), MPI_DOUBLE,
                 world);
  // each segment as (end at the lower place, end at the higher place); equal pairs of places
  // are segments on top of each other
  const std::size_t nseg = segs.size() / 2;
  std::vector<std::pair<tagint, tagint>> ends(nseg);
  for (std::size_t k = 0; k < nseg; k++) {
    tagint a = (tagint) segs[2 * k], b = (tagint) segs[2 * k + 1];
    if (place_less(b, a)) std::swap(a, b);
    ends[k] = {a, b};
  }
  std::vector<std::size_t> idx(nseg);
  for (std::size_t k = 0; k < nseg; k++) idx[k] = k;
  auto seg_less = [&](std::size_t p, std::size_t q) {
    if (place_less(ends[p].first, ends[q].first)) return true;
    if (place_less(ends[q].first, ends[p].first)) return false;
    if (place_less(ends[p].second, ends[q].second)) return true;
    if (place_less(ends[q].second, ends[p].second)) return false;
    return ends[p] < ends[q];
  };
  std::sort(idx.begin(), idx.end(), seg_less);
  for (std::size_t k = 1; k < nseg; k++) {
    const auto &p = ends[idx[k - 1]], &q = ends[idx[k]];
    if (same_place(p.first, q.first) && same_place(p.second, q.second))
      error->all(FLERR,
                 "pair ncf/contact: bonds {}-{} and {}-{} lie on top of each other (their atoms at "
                 "the same places, e.g. ({}, {}, {})): chains on top of each other (a chain read "
                 "twice?) have no contact direction",
                 std::min(p.first, p.second), std::max(p.first, p.second),
                 std::min(q.first, q.second), std::max(q.first, q.second), w[3 * p.first],
                 w[3 * p.first + 1], w[3 * p.first + 2]);
  }
}

void PairNCFContact::init_style()
{
  if (!atom->molecular || !atom->nspecial)
    error->all(FLERR,
               "pair ncf/contact requires a molecular atom style with bonds (atom_style bond)");
  if (force->newton_pair == 0) error->all(FLERR, "pair ncf/contact requires newton pair on");
  if (atom->map_style == Atom::MAP_NONE) error->all(FLERR, "pair ncf/contact requires an atom map");
  tstride = atom->ntypes + 1;
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++)
      if (!table.given(i, j) && (!table.given(i, i) || !table.given(j, j)))
        error->all(FLERR,
                   "pair ncf/contact: no kn for atom types {} {} (pair_coeff {} {} kn KN), and "
                   "none to mix from",
                   i, j, i, j);
  for (int i = 1; i <= atom->ntypes; i++)
    if (!table.diameter_given(i))
      error->all(FLERR,
                 "pair ncf/contact: no diameter for atom type {} (pair_coeff {} {} diameter D)", i,
                 i, i);

  use_history = use_velocity = false;
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      // (mixed values as init_one mixes them)
      const NCF::ContactCoeffs c =
          table.given(i, j) ? table.coeffs(i, j) : NCF::mix(table.coeffs(i, i), table.coeffs(j, j));
      const double m = c.mu, g = c.damp;
      if (m > 0.0) use_history = true;
      if (m > 0.0 || g > 0.0) use_velocity = true;
    }
  if (use_velocity && !comm->ghost_velocity)
    error->all(FLERR,
               "pair ncf/contact with friction (mu > 0) or damping requires ghost velocities: "
               "use comm_modify vel yes");
  if (!use_velocity && comm->ghost_velocity && comm->me == 0)
    utils::logmesg(lmp,
                   "pair ncf/contact: no contact uses velocities (mu = 0 and damp = 0): unless "
                   "another style needs them, 'comm_modify vel no' saves communicating those of "
                   "the ghost nodes\n");
  // (the reverse communication carries the contact forces, fatom, or the flags of the history
  // rows that take-overs need, one per atom)
  comm_reverse = fatom_every ? 3 : (use_history ? 1 : 0);

  lists_valid = false;
  create_stores();
  // (variable length: per node its number of contacts and 6 values per contact)
  comm_forward = use_history ? fhist->row_width() : 0;
  comm_sized = comm_forward;
  fill_topology();
  find_lmax();
  reach_max = 0.0;
  if (dtcheck && update->whichflag == 1 && !(update->dt > 0.0)) {
    const std::string msg = fmt::format("pair ncf/contact: timestep {} is not > 0", update->dt);
    if (dtcheck == 2) error->all(FLERR, msg);
    if (comm->me == 0) error->warning(FLERR, msg);
  }
  if (dt_critical > 0.0 && dtcheck && update->whichflag == 1) {
    const double dt = update->dt;
    if (comm->me == 0)
      utils::logmesg(
          lmp, "pair ncf/contact: critical time step {:.6g}, timestep {:.6g} ({:.3g} of it)\n",
          dt_critical, dt, dt / dt_critical);
    if (dt > dt_critical) {
      const std::string msg = fmt::format(
          "pair ncf/contact: timestep {:.6g} is above the critical time step {:.6g} of the "
          "contacts (sqrt(2 m / (kn L))); the integration would blow up. Reduce the timestep or "
          "kn, scale the masses up, or use 'pair_style ncf/contact dtcheck warn' to run anyway",
          dt, dt_critical);
      if (dtcheck == 2) error->all(FLERR, msg);
      if (comm->me == 0) error->warning(FLERR, msg);
    }
  }

  // no neighbour list: candidate pairs come from a cell list of segment midpoints (compute)

  // the ghost shell must hold both nodes of every segment B within reach + skin of an owned
  // segment A: A reaches lmax beyond the sub-domain, B another lmax beyond A's reach + skin
  // (2 lmax + reach + skin); for the friction history
  // also the owners of the segments next to B along its chain (+ lmax)
  diam_max = 0.0;
  for (int i = 1; i <= atom->ntypes; i++) diam_max = MAX(diam_max, table.diameter(i));
  const double need = diam_max * (1.0 + ramp_frac + 4.0 * endcap_frac) + neighbor->skin +
      (use_history ? 3.0 : 2.0) * lmax_used;
  // The cutoff is the user's raised to this need, set anew at every init: it shrinks again when
  // the need does (friction switched off, shorter segments), also after a restart (the user's
  // value is in the style's restart data: LAMMPS's own holds the raised one). A value different
  // from the one set last is the user's (comm_modify cutoff since).
  if (ghost_user < 0.0 || comm->cutghostuser != ghost_set) ghost_user = comm->cutghostuser;
  const double cut_comm = MAX(ghost_user, need);
  if (cut_comm != comm->cutghostuser && comm->me == 0)
    utils::logmesg(lmp,
                   "pair ncf/contact: communication cutoff {} {:.6g} (lmax {:.6g}{}; given "
                   "{:.6g})\n",
                   cut_comm > comm->cutghostuser ? "raised to" : "lowered to", cut_comm, lmax_used,
                   use_history ? ", friction history" : "", ghost_user);
  comm->cutghostuser = ghost_set = cut_comm;
}

double PairNCFContact::init_one(int i, int j)
{
  if (!table.resolve(i, j))
    error->all(FLERR, "pair ncf/contact: coefficients for types {} {} neither given nor mixable", i,
               j);
  // the coefficients as the run will use them: pair_coeff checks what it reads, but fix adapt
  // changes kn, mu, damp and diameter at run time (and calls init_one again, through reinit)
  const NCF::ContactCoeffs c = table.coeffs(i, j);
  double bad = 0.0;
  if (const char *name = NCF::invalid_coeff(c, &bad))
    error->all(FLERR,
               "pair ncf/contact: {} of atom types {} {} is {} (changed by fix adapt?); it "
               "must be a finite number {}",
               name, i, j, bad, std::string(name) == "kn" ? "> 0" : ">= 0");
  for (int t : {i, j})
    if (!(std::isfinite(table.diameter(t)) && table.diameter(t) > 0.0))
      error->all(FLERR,
                 "pair ncf/contact: diameter of atom type {} is {} (changed by fix adapt?); it "
                 "must be a finite number > 0",
                 t, table.diameter(t));
  const double dc = 0.5 * (table.diameter(i) + table.diameter(j));
  // the reach of the law between the axes of two segments, D (1 + ramp). LAMMPS uses it (plus the
  // skin) for its bins, among them those by which it sorts the atoms in memory (atom_modify
  // sort): nodes close in space stay close in memory, which the random accesses of the contact
  // loops need. The ghost shell the style needs (nodes up to 2 lmax farther, end caps) is set in
  // init_style.
  cut[i][j] = cut[j][i] = dc * (1.0 + ramp_frac);
  reachf[i][j] = reachf[j][i] = dc * (1.0 + ramp_frac);
  reach_max = MAX(reach_max, reachf[i][j]);
  tpar.resize((size_t) tstride * tstride);
  TypePair &tpij = tpar[type_pair(i, j)];
  tpij.dc = dc;
  tpij.kn = c.kn;
  tpij.ramp = ramp_frac * dc;
  tpij.kt = c.kt_stiffness();
  tpij.mu = c.mu;
  tpij.damp = c.damp;
  tpar[type_pair(j, i)] = tpij;
  return cut[i][j];
}

/* ---------------------------------------------------------------------- */

void PairNCFContact::write_restart_settings(FILE *fp)
{
  fwrite(&ramp_frac, sizeof(double), 1, fp);
  fwrite(&lmax_user, sizeof(double), 1, fp);
  fwrite(&maxcontacts, sizeof(int), 1, fp);
  fwrite(&fatom_every, sizeof(int), 1, fp);
  // (the law packed into the dtcheck word, so that restart files keep the layout of earlier
  // versions; theirs read back with the default, symmetric law and without the work estimate;
  // bit 16: the communication cutoff the user gave follows the other settings; bit 32: work yes)
  const int dtlaw = dtcheck + 8 * oneway + 16 + 32 * work_flag;
  fwrite(&dtlaw, sizeof(int), 1, fp);
  fwrite(&core, sizeof(double), 1, fp);
  fwrite(&endcap_frac, sizeof(double), 1, fp);
  fwrite(&ghost_user, sizeof(double), 1, fp);
}

void PairNCFContact::read_restart_settings(FILE *fp)
{
  if (comm->me == 0) {
    utils::sfread(FLERR, &ramp_frac, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &lmax_user, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &maxcontacts, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &fatom_every, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &dtcheck, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &core, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &endcap_frac, sizeof(double), 1, fp, nullptr, error);
  }
  MPI_Bcast(&ramp_frac, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&lmax_user, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&maxcontacts, 1, MPI_INT, 0, world);
  MPI_Bcast(&fatom_every, 1, MPI_INT, 0, world);
  MPI_Bcast(&dtcheck, 1, MPI_INT, 0, world);
  const bool has_ghost = dtcheck & 16;
  oneway = (dtcheck / 8) & 1;
  work_flag = (dtcheck / 32) & 1;
  dtcheck %= 8;
  MPI_Bcast(&core, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&endcap_frac, 1, MPI_DOUBLE, 0, world);
  // the communication cutoff the user gave; LAMMPS has read the one this style set from the
  // restart file's header (files of earlier versions: unknown, the cutoff stays as read)
  if (has_ghost) {
    if (comm->me == 0) utils::sfread(FLERR, &ghost_user, sizeof(double), 1, fp, nullptr, error);
    MPI_Bcast(&ghost_user, 1, MPI_DOUBLE, 0, world);
    ghost_set = ghost_user >= 0.0 ? comm->cutghostuser : -1.0;
  }
}

void PairNCFContact::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  struct Writer {
    FILE *fp;
    void i(int v) { fwrite(&v, sizeof(int), 1, fp); }
    void d(double v) { fwrite(&v, sizeof(double), 1, fp); }
  } w{fp};
  table.write(w);
}

void PairNCFContact::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  // rank 0 reads the table, every rank gets it through the same reader fed by a broadcast
  std::vector<double> vals;
  struct Reader {
    PairNCFContact *p;
    FILE *fp;
    std::vector<double> &vals;
    bool reading;
    std::size_t next = 0;
    int i()
    {
      if (!reading) return (int) vals[next++];
      int v;
      utils::sfread(FLERR, &v, sizeof(int), 1, fp, nullptr, p->error);
      vals.push_back(v);
      return v;
    }
    double d()
    {
      if (!reading) return vals[next++];
      double v;
      utils::sfread(FLERR, &v, sizeof(double), 1, fp, nullptr, p->error);
      vals.push_back(v);
      return v;
    }
  };
  if (comm->me == 0) {
    Reader r{this, fp, vals, true};
    table.read(r);
  }
  int nvals = (int) vals.size();
  MPI_Bcast(&nvals, 1, MPI_INT, 0, world);
  vals.resize(nvals);
  MPI_Bcast(vals.data(), nvals, MPI_DOUBLE, 0, world);
  if (comm->me != 0) {
    Reader r{this, nullptr, vals, false};
    table.read(r);
  }
  const int n = atom->ntypes;
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++)
      if (table.given(i, j)) setflag[i][j] = 1;
}

void *PairNCFContact::extract(const char *str, int &dim)
{
  dim = 2;
  if (strcmp(str, "kn") == 0) return (void *) table.kn_rows();
  if (strcmp(str, "kt") == 0) return (void *) table.kt_rows();
  if (strcmp(str, "mu") == 0) return (void *) table.mu_rows();
  if (strcmp(str, "damp") == 0) return (void *) table.damp_rows();
  dim = 1;
  if (strcmp(str, "diameter") == 0) return (void *) table.diameters();
  return nullptr;
}
