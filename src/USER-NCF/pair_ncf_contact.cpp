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
   The friction history of the pair lives with A's owner node (a fix property/atom array), so it
   migrates and restarts with it; the rank that computes the pair always owns it. Between two
   list builds the history of a pair is read and updated in its list entry; the per-atom store is
   loaded at the build and rewritten after every step. Ghost rows of the store are communicated
   only in steps where a new contact takes over the slip of a pair owned by another rank.
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
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include "ncf_contact.h"
#include "ncf_lammps_compat.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;
using NCF::Vec3;

namespace {
enum { COMM_HIST, COMM_FORCE };

struct SegKey {
  tagint lo, hi;
};
inline bool key_less(const SegKey &a, const SegKey &b)
{
  return a.lo < b.lo || (a.lo == b.lo && a.hi < b.hi);
}
inline bool share_node(const SegKey &a, const SegKey &b)
{
  return a.lo == b.lo || a.lo == b.hi || a.hi == b.lo || a.hi == b.hi;
}
inline SegKey make_key(tagint a, tagint b)
{
  return a < b ? SegKey{a, b} : SegKey{b, a};
}

// How fast the gap between two segments extended beyond their nodes can close: if no node of A
// moved more than m_A and no node of B more than m_B since the build, the extended segments are
// at most g (m_A + m_B) closer than they were. An end extended by E along a segment of length L
// (at the build) moves by at most m + E |change of the unit vector| <= m + E 2 (2 m) / L.
// la, lb: lengths of A and B; ea, eb: their largest extension. Rounded up; a huge value for a
// degenerate extended segment (always evaluated).
// the reach of a pair list entry (PairCand::reach): a float not above gap / grow, one float step
// lower still, so that gap - grow s < 0 (in double precision) implies reach < s for every s >= 0
inline float entry_reach(double gap, double grow)
{
  const double q = gap / grow;
  float r = (float) q;
  if ((double) r > q) r = std::nextafter(r, -HUGE_VALF);
  return std::nextafter(r, -HUGE_VALF);
}

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

/* ---------------------------------------------------------------------- */

PairNCFContact::PairNCFContact(LAMMPS *lmp) : Pair(lmp)
{
  restartinfo = 1;
  single_enable = 0;
  one_coeff = 0;
  manybody_flag = 0;
  ramp_frac = 0.25;
  core = NCF::DEFAULT_CORE;
  endcap_frac = NCF::DEFAULT_ENDCAP;
  lmax_user = 0.0;
  maxcontacts = 24;
  fatom_flag = 0;
  dtcheck = 2;
  dt_critical = 0.0;
  kn = ktr = mu = damp = cut = reachf = nullptr;
  tstride = 0;
  given = nullptr;
  lmax_used = 0.0;
  reach_max = diam_max = 0.0;
  use_history = use_velocity = false;
  idx_cnb = idx_hist = idx_fc = -1;
  ncol = 1 + 6 * maxcontacts;
  comm_mode = COMM_HIST;
  lists_valid = false;
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

PairNCFContact::~PairNCFContact()
{
  delete[] pvector;
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(kn);
    memory->destroy(ktr);
    memory->destroy(mu);
    memory->destroy(damp);
    memory->destroy(cut);
    memory->destroy(reachf);
    memory->destroy(given);
  }
}

void PairNCFContact::allocate()
{
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  memory->create(kn, n + 1, n + 1, "pair:kn");
  memory->create(ktr, n + 1, n + 1, "pair:ktr");
  memory->create(mu, n + 1, n + 1, "pair:mu");
  memory->create(damp, n + 1, n + 1, "pair:damp");
  memory->create(cut, n + 1, n + 1, "pair:cut");
  memory->create(reachf, n + 1, n + 1, "pair:reach");
  memory->create(given, n + 1, n + 1, "pair:given");
  for (int i = 0; i <= n; i++)
    for (int j = 0; j <= n; j++) {
      setflag[i][j] = given[i][j] = 0;
      kn[i][j] = ktr[i][j] = mu[i][j] = damp[i][j] = cut[i][j] = reachf[i][j] = 0.0;
    }
  diameter.assign(n + 1, 0.0);
  diamset.assign(n + 1, 0);
}

/* ----------------------------------------------------------------------
   pair_style ncf/contact [ramp f] [core kappa] [endcap f] [lmax L] [maxcontacts N] [fatom yes|no]
                          [dtcheck error|warn|no]
------------------------------------------------------------------------- */

void PairNCFContact::settings(int narg, char **arg)
{
  int iarg = 0;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (iarg + 2 > narg) error->all(FLERR, "pair_style ncf/contact: keyword {} needs a value", key);
    const char *val = arg[iarg + 1];
    if (key == "ramp") {
      ramp_frac = utils::numeric(FLERR, val, false, lmp);
      if (!(ramp_frac > 0.0) || ramp_frac > 1.0)
        error->all(FLERR, "pair_style ncf/contact: ramp {} out of range (0, 1]", val);
    } else if (key == "core") {
      core = utils::numeric(FLERR, val, false, lmp);
      if (!(core >= 0.0) || core > 1000.0)
        error->all(FLERR, "pair_style ncf/contact: core {} out of range [0, 1000]", val);
    } else if (key == "endcap") {
      endcap_frac = utils::numeric(FLERR, val, false, lmp);
      if (!(endcap_frac >= 0.0) || endcap_frac > 2.0)
        error->all(FLERR, "pair_style ncf/contact: endcap {} out of range [0, 2]", val);
    } else if (key == "lmax") {
      lmax_user = utils::numeric(FLERR, val, false, lmp);
      if (lmax_user < 0.0) error->all(FLERR, "pair_style ncf/contact: lmax {} must be >= 0", val);
    } else if (key == "maxcontacts") {
      maxcontacts = utils::inumeric(FLERR, val, false, lmp);
      if (maxcontacts < 1 || maxcontacts > 1000)
        error->all(FLERR, "pair_style ncf/contact: maxcontacts {} out of range [1, 1000]", val);
    } else if (key == "fatom") {
      fatom_flag = utils::logical(FLERR, val, false, lmp);
    } else if (key == "dtcheck") {
      if (strcmp(val, "error") == 0)
        dtcheck = 2;
      else if (strcmp(val, "warn") == 0)
        dtcheck = 1;
      else if (strcmp(val, "no") == 0)
        dtcheck = 0;
      else
        error->all(FLERR, "pair_style ncf/contact: dtcheck {} is not one of error, warn, no", val);
    } else {
      error->all(FLERR, "pair_style ncf/contact: unknown keyword {}", key);
    }
    iarg += 2;
  }
  ncol = 1 + 6 * maxcontacts;
  // the per-atom contact force exists from here on, so that a dump or variable defined before the
  // first run can name d_ncf_fcontact
  if (fatom_flag && domain->box_exist && !modify->get_fix_by_id(FORCE_ID))
    modify->add_fix(
        fmt::format("{} all property/atom d_ncf_fcontact ghost no writedata no", FORCE_ID));
}

/* ----------------------------------------------------------------------
   pair_coeff I J kn <Pa> [kt <ratio>] [mu <value>] [damp <N s/m^2>] [diameter <m>]
   diameter sets the chain diameter of every type named in I and J
------------------------------------------------------------------------- */

void PairNCFContact::coeff(int narg, char **arg)
{
  if (narg < 2) error->all(FLERR, "pair_coeff ncf/contact: expected I J kn <value> ...");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);

  double kn_one = -1.0, kt_one = 1.0, mu_one = 0.0, damp_one = 0.0, d_one = -1.0;
  int iarg = 2;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (iarg + 2 > narg) error->all(FLERR, "pair_coeff ncf/contact: keyword {} needs a value", key);
    const char *val = arg[iarg + 1];
    const double v = utils::numeric(FLERR, val, false, lmp);
    if (key == "kn") {
      if (!(v > 0.0)) error->all(FLERR, "pair_coeff ncf/contact: kn {} must be > 0", val);
      kn_one = v;
    } else if (key == "kt") {
      if (v < 0.0) error->all(FLERR, "pair_coeff ncf/contact: kt {} must be >= 0", val);
      kt_one = v;
    } else if (key == "mu") {
      if (v < 0.0) error->all(FLERR, "pair_coeff ncf/contact: mu {} must be >= 0", val);
      mu_one = v;
    } else if (key == "damp") {
      if (v < 0.0) error->all(FLERR, "pair_coeff ncf/contact: damp {} must be >= 0", val);
      damp_one = v;
    } else if (key == "diameter") {
      if (!(v > 0.0)) error->all(FLERR, "pair_coeff ncf/contact: diameter {} must be > 0", val);
      d_one = v;
    } else {
      error->all(FLERR, "pair_coeff ncf/contact: unknown keyword {}", key);
    }
    iarg += 2;
  }
  if (kn_one < 0.0 && d_one < 0.0)
    error->all(FLERR, "pair_coeff ncf/contact: give kn (and optionally kt, mu, damp, diameter)");

  int count = 0;
  for (int i = ilo; i <= ihi; i++) {
    if (d_one > 0.0) {
      diameter[i] = d_one;
      diamset[i] = 1;
    }
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      if (d_one > 0.0) {
        diameter[j] = d_one;
        diamset[j] = 1;
      }
      if (kn_one > 0.0) {
        kn[i][j] = kn_one;
        ktr[i][j] = kt_one;
        mu[i][j] = mu_one;
        damp[i][j] = damp_one;
        setflag[i][j] = given[i][j] = 1;
      }
      count++;
    }
  }
  if (count == 0)
    error->all(FLERR, "pair_coeff ncf/contact: no type pair in {} {}", arg[0], arg[1]);
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

  idx_hist = -1;
  if (use_history) {
    create_history_fix();
    if (!modify->get_fix_by_id(HIST_ID))
      modify->add_fix(
          fmt::format("{} all property/atom d2_ncf_chist {} ghost no writedata no", HIST_ID, ncol));
    idx_hist = atom->find_custom("ncf_chist", flag, cols);
    if (idx_hist < 0 || flag != 1 || cols != ncol)
      error->all(FLERR,
                 "pair ncf/contact: friction history d2_ncf_chist of fix {} has {} columns, "
                 "expected {} (maxcontacts {}): was maxcontacts changed? unfix {} to start anew",
                 HIST_ID, cols, ncol, maxcontacts, HIST_ID);
  }
  idx_fc = -1;
  if (fatom_flag) {
    if (!modify->get_fix_by_id(FORCE_ID))
      modify->add_fix(
          fmt::format("{} all property/atom d_ncf_fcontact ghost no writedata no", FORCE_ID));
    idx_fc = atom->find_custom("ncf_fcontact", flag, cols);
    if (idx_fc < 0 || flag != 1 || cols != 0)
      error->all(FLERR, "pair ncf/contact: d_ncf_fcontact of fix {} is malformed", FORCE_ID);
  }
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
  double lmax = 0.0;
  for (int i = 0; i < nlocal; i++)
    for (int s = 0; s < atom->nspecial[i][0] && s < 2; s++) {
      const tagint p = atom->special[i][s];
      if (p <= atom->tag[i]) continue;
      double r2 = 0.0;
      for (int d = 0; d < 3; d++) {
        const double dx = xall[3 * p + d] - xall[3 * atom->tag[i] + d];
        r2 += dx * dx;
      }
      lmax = std::max(lmax, std::sqrt(r2));
    }
  // critical time step of the contacts: a node of mass m pressed against an equal one by parallel
  // contacts over half its two segments, stiffness k = kn (L_1 + L_2)/2: dt_c = sqrt(2 m / k)
  double knmax = 0.0;
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++)
      if (given[i][j]) knmax = MAX(knmax, kn[i][j]);
  double omega2 = 0.0;
  for (int i = 0; i < nlocal; i++) {
    double len = 0.0;
    for (int s = 0; s < atom->nspecial[i][0] && s < 2; s++) {
      const tagint p = atom->special[i][s];
      double r2 = 0.0;
      for (int d = 0; d < 3; d++) {
        const double dx = xall[3 * p + d] - xall[3 * atom->tag[i] + d];
        r2 += dx * dx;
      }
      len += 0.5 * std::sqrt(r2);
    }
    const double m = atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
    if (m > 0.0 && len > 0.0) omega2 = MAX(omega2, 2.0 * knmax * len / m);
  }
  double omega2all;
  MPI_Allreduce(&omega2, &omega2all, 1, MPI_DOUBLE, MPI_MAX, world);
  dt_critical = omega2all > 0.0 ? 2.0 / std::sqrt(omega2all) : 0.0;

  double all;
  MPI_Allreduce(&lmax, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  lmax_used = lmax_user > 0.0 ? lmax_user : 1.1 * all;
  if (lmax_user > 0.0 && all > lmax_user)
    error->all(FLERR, "pair ncf/contact: longest segment {:.6g} exceeds lmax {:.6g}", all,
               lmax_user);
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
    if (!diamset[i])
      error->all(FLERR,
                 "pair ncf/contact: no diameter for atom type {} (pair_coeff {} {} diameter D)", i,
                 i, i);

  use_history = use_velocity = false;
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      double m = mu[i][j], g = damp[i][j];
      if (!given[i][j]) {    // mixed values (init_one mixes the same way)
        m = std::sqrt(mu[i][i] * mu[j][j]);
        g = std::sqrt(damp[i][i] * damp[j][j]);
      }
      if (m > 0.0) use_history = true;
      if (m > 0.0 || g > 0.0) use_velocity = true;
    }
  if (use_velocity && !comm->ghost_velocity)
    error->all(FLERR,
               "pair ncf/contact with friction (mu > 0) or damping requires ghost velocities: "
               "use comm_modify vel yes");
  comm_forward = use_history ? ncol : 0;
  comm_reverse = fatom_flag ? 3 : 0;

  lists_valid = false;
  create_stores();
  fill_topology();
  find_lmax();
  reach_max = 0.0;
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
  for (int i = 1; i <= atom->ntypes; i++) diam_max = MAX(diam_max, diameter[i]);
  const double need = diam_max * (1.0 + ramp_frac + 4.0 * endcap_frac) + neighbor->skin +
      (use_history ? 3.0 : 2.0) * lmax_used;
  if (comm->cutghostuser < need) {
    if (comm->me == 0)
      utils::logmesg(lmp, "pair ncf/contact: communication cutoff raised to {:.6g} (lmax {:.6g})\n",
                     need, lmax_used);
    comm->cutghostuser = need;
  }
}

double PairNCFContact::init_one(int i, int j)
{
  if (!given[i][j]) {
    if (!given[i][i] || !given[j][j])
      error->all(FLERR, "pair ncf/contact: coefficients for types {} {} neither given nor mixable",
                 i, j);
    // springs in series for the stiffness; geometric mean for friction and damping
    kn[i][j] = 2.0 * kn[i][i] * kn[j][j] / (kn[i][i] + kn[j][j]);
    ktr[i][j] = 0.5 * (ktr[i][i] + ktr[j][j]);
    mu[i][j] = std::sqrt(mu[i][i] * mu[j][j]);
    damp[i][j] = std::sqrt(damp[i][i] * damp[j][j]);
  }
  kn[j][i] = kn[i][j];
  ktr[j][i] = ktr[i][j];
  mu[j][i] = mu[i][j];
  damp[j][i] = damp[i][j];
  const double dc = 0.5 * (diameter[i] + diameter[j]);
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
  tpij.kn = kn[i][j];
  tpij.ramp = ramp_frac * dc;
  tpij.kt = ktr[i][j] * kn[i][j];
  tpij.mu = mu[i][j];
  tpij.damp = damp[i][j];
  tpar[type_pair(j, i)] = tpij;
  return cut[i][j];
}

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
  const double *row = atom->darray[idx_hist][m];
  const int n = (int) row[0];
  // tags are stored exactly as doubles: compare them as such
  const double h = (double) ohi, l = (double) blo, b = (double) bhi;
  for (int k = 0; k < n && k < maxcontacts; k++) {
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

// a new contact takes over the slip of a contact of a neighbouring segment pair (same chains,
// one segment further along one of them), so that a contact point sliding over a node keeps its
// history; only values of the previous step are read (the same on any number of ranks)
// local_only: only rows of owned nodes are up to date (the ghost rows have not been communicated
// this step); returns false, without a result, when a ghost's row would be needed
bool PairNCFContact::inherit_slip(tagint a0, tagint a1, tagint b0, tagint b1, double *slip,
                                  bool local_only) const
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
  for (int c = 0; c < nc; c++) {
    const SegKey &X = cand[c][0], &Y = cand[c][1];
    if (share_node(X, Y)) continue;
    const SegKey &M = key_less(X, Y) ? X : Y, &O = key_less(X, Y) ? Y : X;
    const int m = atom->map(M.lo);
    if (m < 0) continue;
    if (m >= atom->nlocal && local_only) return false;
    // (the rows of ghosts are communicated for the deferred take-overs, the local rows not
    // written every step)
    const double *s = m < atom->nlocal ? find_slip_entry(m, M.hi, O.lo, O.hi)
                                       : find_slip_row(m, M.hi, O.lo, O.hi);
    if (s && (s[0] != 0.0 || s[1] != 0.0 || s[2] != 0.0)) {
      slip[0] = s[0];
      slip[1] = s[1];
      slip[2] = s[2];
      return true;
    }
  }
  return true;
}

/* ----------------------------------------------------------------------
   boxes binned by their centres (build_lists)
------------------------------------------------------------------------- */

void PairNCFContact::BoxGrid::clear()
{
  cx.clear();
  cy.clear();
  cz.clear();
  hx.clear();
  hy.clear();
  hz.clear();
  r.clear();
  t0.clear();
  t1.clear();
  t2.clear();
  i0.clear();
  i1.clear();
}

void PairNCFContact::BoxGrid::add(const double *c, const double *h, double rad, tagint a, tagint b,
                                  tagint q, int j0, int j1)
{
  cx.push_back(c[0]);
  cy.push_back(c[1]);
  cz.push_back(c[2]);
  hx.push_back(h[0]);
  hy.push_back(h[1]);
  hz.push_back(h[2]);
  r.push_back(rad);
  t0.push_back(a);
  t1.push_back(b);
  t2.push_back(q);
  i0.push_back(j0);
  i1.push_back(j1);
}

// bins c0..c1 (per direction) that hold every centre in the box lo_pos..hi_pos: the bin index is
// monotonic in the position (clamped to the grid; no conversion of an out-of-range value to int)
void PairNCFContact::BoxGrid::cells(const double *lo_pos, const double *hi_pos, int *c0,
                                    int *c1) const
{
  for (int d = 0; d < 3; d++) {
    const double top = nb[d] - 1;
    double a = (lo_pos[d] - lo[d]) * inv[d], b = (hi_pos[d] - lo[d]) * inv[d];
    a = a < 0.0 ? 0.0 : (a > top ? top : a);
    b = b < 0.0 ? 0.0 : (b > top ? top : b);
    c0[d] = (int) a;
    c1[d] = (int) b;
  }
}

// the entries of the grid whose (inflated) box overlaps the box of centre c and half extents h,
// with keep(filter record) true, into cand (returns their number). The tests run without branches
// (most entries of the scanned rows fail, unpredictably), in single precision with the slack of
// the grid plus 1e-6 of the half extents
template <class Keep>
int PairNCFContact::BoxGrid::scan(const double *c, const double *h, Keep keep, int *cand) const
{
  double rlo[3], rhi[3];
  for (int d = 0; d < 3; d++) {
    rlo[d] = c[d] - (h[d] + hmax[d]);
    rhi[d] = c[d] + (h[d] + hmax[d]);
  }
  int c0[3], c1[3];
  cells(rlo, rhi, c0, c1);
  float fa[3], fh[3];
  const float fs = fslack + (float) (1e-6 * (h[0] + h[1] + h[2]));
  for (int d = 0; d < 3; d++) {
    fa[d] = (float) (c[d] - lo[d]);
    fh[d] = (float) h[d] + fs;
  }
  const Filter *f = fb.data();
  int nc = 0;
  for (int cz = c0[2]; cz <= c1[2]; cz++)
    for (int cy = c0[1]; cy <= c1[1]; cy++) {
      const int row = (cz * nb[1] + cy) * nb[0];
      const int nend = start[row + c1[0] + 1];
      for (int n = start[row + c0[0]]; n < nend; n++) {
        const Filter &b = f[n];
        cand[nc] = n;
        nc += keep(b) & (std::fabs(fa[0] - b.c[0]) <= fh[0] + b.h[0]) &
            (std::fabs(fa[1] - b.c[1]) <= fh[1] + b.h[1]) &
            (std::fabs(fa[2] - b.c[2]) <= fh[2] + b.h[2]);
      }
    }
  return nc;
}

// sort the entries of a grid by bin (counting sort through gtmp) and fill its bin index. Bins of
// about the largest half extent per direction: a search reaches over (own + largest) half extent
// on either side, a few bins, and the rows it scans are not much longer than the search box
void PairNCFContact::bin_grid(BoxGrid &g)
{
  const int n = (int) g.cx.size();
  const std::vector<double> *cen[3] = {&g.cx, &g.cy, &g.cz};
  const std::vector<double> *hal[3] = {&g.hx, &g.hy, &g.hz};
  double hi[3];
  for (int d = 0; d < 3; d++) {
    g.lo[d] = 1e300;
    hi[d] = -1e300;
    g.hmax[d] = 0.0;
    for (int k = 0; k < n; k++) {
      g.lo[d] = MIN(g.lo[d], (*cen[d])[k]);
      hi[d] = MAX(hi[d], (*cen[d])[k]);
      g.hmax[d] = MAX(g.hmax[d], (*hal[d])[k]);
    }
  }
  if (n == 0) {
    for (int d = 0; d < 3; d++) {
      g.nb[d] = 1;
      g.lo[d] = 0.0;
      g.inv[d] = 1.0;
    }
    g.start.assign(2, 0);
    g.fb.clear();
    g.fslack = 0.0f;
    return;
  }
  double bs[3];
  for (int d = 0; d < 3; d++) {
    bs[d] = MAX(g.hmax[d], 1e-6 * (hi[d] - g.lo[d]));
    if (!(bs[d] > 0.0)) bs[d] = 1.0;
  }
  for (;;) {
    double total = 1.0;
    for (int d = 0; d < 3; d++) {
      g.nb[d] = (int) MIN((hi[d] - g.lo[d]) / bs[d], 1e8) + 1;
      total *= g.nb[d];
    }
    if (total <= 4.0 * n + 1000.0) break;
    for (int d = 0; d < 3; d++) bs[d] *= 1.5;
  }
  for (int d = 0; d < 3; d++) g.inv[d] = 1.0 / bs[d];
  const int nbins = g.nb[0] * g.nb[1] * g.nb[2];
  g.start.assign(nbins + 1, 0);
  gbin.resize(n);
  for (int k = 0; k < n; k++) {
    const double c[3] = {g.cx[k], g.cy[k], g.cz[k]};
    int c0[3], c1[3];
    g.cells(c, c, c0, c1);
    gbin[k] = (c0[2] * g.nb[1] + c0[1]) * g.nb[0] + c0[0];
    g.start[gbin[k] + 1]++;
  }
  for (int b = 0; b < nbins; b++) g.start[b + 1] += g.start[b];
  gfill.assign(g.start.begin(), g.start.end() - 1);
  // positions of the entries in bin order
  for (int k = 0; k < n; k++) gbin[k] = gfill[gbin[k]]++;
  auto put = [&](auto &src, auto &dst) {
    dst.resize(n);
    for (int k = 0; k < n; k++) dst[gbin[k]] = src[k];
    src.swap(dst);
  };
  put(g.cx, gtmp.cx);
  put(g.cy, gtmp.cy);
  put(g.cz, gtmp.cz);
  put(g.hx, gtmp.hx);
  put(g.hy, gtmp.hy);
  put(g.hz, gtmp.hz);
  put(g.r, gtmp.r);
  put(g.t0, gtmp.t0);
  put(g.t1, gtmp.t1);
  put(g.t2, gtmp.t2);
  put(g.i0, gtmp.i0);
  put(g.i1, gtmp.i1);

  // single precision copies for the box test: centres relative to lo. The round-off of a test
  // that holds exactly (a few roundings, relative 2^-24 each, of values below the span of the
  // grid plus the half extents of the two boxes) stays far below the slack of 1e-6 (span +
  // 2 hmax) plus 1e-6 times the half extents of the searching box added to its bound
  double big = 0.0;
  for (int d = 0; d < 3; d++) big = MAX(big, (hi[d] - g.lo[d]) + 2.0 * g.hmax[d]);
  g.fslack = (float) (1e-6 * big);
  g.fb.resize(n);
  for (int k = 0; k < n; k++) {
    BoxGrid::Filter &f = g.fb[k];
    f.c[0] = (float) (g.cx[k] - g.lo[0]);
    f.c[1] = (float) (g.cy[k] - g.lo[1]);
    f.c[2] = (float) (g.cz[k] - g.lo[2]);
    f.h[0] = (float) g.hx[k];
    f.h[1] = (float) g.hy[k];
    f.h[2] = (float) g.hz[k];
    f.k0 = g.t0[k];
    f.k1 = g.t1[k];
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
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  double **x = atom->x;
  const int *type = atom->type;
  const tagint *tag = atom->tag;
  const double skin = neighbor->skin;
  double **cnb = atom->darray[idx_cnb];

  set_segments();
  // extension of the segments at free chain ends (nodes with one bond), per local/ghost node
  endext.assign(nall, 0.0);
  for (int k = 0; k < nall; k++)
    if (cnb[k][0] != 0.0 && cnb[k][1] == 0.0) endext[k] = endcap_frac * diameter[type[k]];
  plist.clear();
  clist.clear();
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

  // largest reach + skin of a segment pair (without the extensions at free ends)
  const double margin = reach_max + skin;
  // slack for the round-off of the bounds (relative to the reach, and to the coordinates that
  // the distances are computed from)
  const double slack = 1e-9 * margin + 1e-12 * xabs;
  const double hm = 0.5 * margin + slack;
  // (the gap of a pair list entry is rounded down by this much)
  const double gap_slack = 1e-9 * reach_max + 1e-12 * xabs;

  // segment pair (A = ao-ia with ao owned, B = bo-jb), key(A) < key(B) checked by the caller:
  // kept if the two segments are within reach + skin
  auto add_pair = [&](int ao, int ia, int bo, int jb) {
    const double lim = reachf[type[ao]][type[bo]] + skin;
    if (jb == -2) {
      // B's partner node lies beyond the ghost shell (2 lmax + reach + skin around the
      // sub-domain), so no point of B is within reach + skin of A (A reaches at most lmax beyond
      // the sub-domain, B is at most lmax long). An error if B's own end node is that close:
      // then the shell is too short for this pair.
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
    // the law is zero while A, extended at free chain ends, stays D away from B, extended there
    // and by the ramp half-width e beyond both nodes (NCF::segment_contact_possible): the entry
    // keeps that gap at the build, and a bound of how fast it can close (growth)
    const TypePair &tp = tpar[type_pair(type[ao], type[bo])];
    Vec3 pa0(x[ao]), pa1(x[ia]), pb0(x[bo]), pb1(x[jb]);
    const double la = NCF::norm(pa1 - pa0), lb = NCF::norm(pb1 - pb0);
    NCF::extend_segment(pa0, pa1, endext[ao], endext[ia]);
    NCF::extend_segment(pb0, pb1, endext[bo] + tp.ramp, endext[jb] + tp.ramp);
    const double gap =
        std::sqrt(NCF::closest_points_segments(pa0, pa1, pb0, pb1).dist2) - tp.dc - gap_slack;
    const double grow =
        gap_growth(la, MAX(endext[ao], endext[ia]), lb, MAX(endext[bo], endext[jb]) + tp.ramp);
    // no node moves more than skin / 2 before the next build (checked in compute)
    if (gap >= grow * skin) return;
    const bool ext = endext[ao] != 0.0 || endext[ia] != 0.0 || endext[bo] != 0.0 ||
        endext[jb] != 0.0;
    plist.push_back({ao, ia, bo, jb, (unsigned) type_pair(type[ao], type[bo]), ext ? 1u : 0u,
                     entry_reach(gap, grow)});
  };

  // the boxes: every segment (owner node, partner) known here, and every interior node
  gseg.clear();
  gext.clear();
  gcap.clear();
  const double hcap = (diam_max + skin) * (1.0 + 1e-9) + slack;
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
  bin_grid(gseg);
  bin_grid(gext);
  bin_grid(gcap);
  gcand.resize(MAX(MAX(gseg.cx.size(), gext.cx.size()), gcap.cx.size()));

  // the owned segments in the order of their owner nodes (LAMMPS sorts them spatially): the
  // lists come out in that order, so that the positions, forces and history rows of a step are
  // visited nearly in memory order (store_history relies on it)
  pfirst.resize(nlocal + 1);
  for (int ao = 0; ao < nlocal; ao++) {
    pfirst[ao] = (int) plist.size();
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
          add_pair(ao, ia, g.i0[n], g.i1[n]);
        }
      }

      // node caps: interior nodes of other chains (or far along this one) near segment A
      {
        const BoxGrid &g = gcap;
        int *cand = gcand.data();
        // the node within D + skin of A's bounding box first (most candidates are not)
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
          const double dcap = 0.5 * (diameter[type[ao]] + diameter[type[k]]) + skin;
          const double dist2 = NCF::point_segment_dist2(a0, a1, Vec3(x[k]));
          if (dist2 >= dcap * dcap) continue;
          const int kp = nbr[2 * k], kq = nbr[2 * k + 1];
          if (kp < 0 || kq < 0)
            error->one(FLERR,
                       "pair ncf/contact: a chain neighbour of node {} (near segment {}-{}) is not "
                       "present on this rank; communication cutoff too short",
                       tag[k], tag[ao], tag[ia]);
          const int tpk = type_pair(type[ao], type[k]);
          clist.push_back({ao, ia, kp, k, kq, tpk, std::sqrt(dist2) - tpar[tpk].dc - gap_slack});
        }
      }
    }
  }
  pfirst[nlocal] = (int) plist.size();
  if (use_history) load_history();

  // the ghosts that a list entry or cap refers to (the others, beyond the reach of any, need no
  // node row)
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

  // The segments at free chain ends enter the law extended (end caps): the free end k by
  // endext[k] along its segment. In the pair list entries such a node is replaced by a virtual
  // node (index nall + v), whose row holds the extended end (its position and velocity, from
  // those of k and its chain neighbour; compute) and which collects the contact forces on it,
  // mapped back onto k and the neighbour at the end of the step (the chain rule). So the lanes
  // of the batched law need no extension and no mapping back of their own. (Its displacement
  // bound is that of k: the gaps and growth bounds of the list already count the extension.)
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

/* ----------------------------------------------------------------------
   friction history: between two list builds it lives with the pair list entries, in two
   buffers (pslip, phas): one holds the slips of the last step, read by this step (also by the
   take-overs of new contacts, so that every rank sees the same values whatever the order of its
   list), the other receives the slips of this step. The per-atom store (NCF_CONTACT_HIST, rows of
   the owner nodes) is what LAMMPS migrates, sorts and writes to restart files: it is read at
   every build and written only when LAMMPS needs it (sync_history, from fix
   ncf/contact/history before atoms migrate and at the end of a run; and for the take-overs that
   need the rows of ghosts)
------------------------------------------------------------------------- */

void PairNCFContact::load_history()
{
  const tagint *tag = atom->tag;
  double **hist = atom->darray[idx_hist];
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

// the per-atom rows of the owned nodes from history buffer b (hlast: the last step's)
void PairNCFContact::store_history(int b)
{
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  double **hist = atom->darray[idx_hist];
  if (nlocal != lists_nlocal)
    error->one(FLERR,
               "pair ncf/contact: the atoms changed before their friction history was stored "
               "(a fix added, deleted or moved atoms in pre_exchange before fix {}: define such "
               "fixes after pair_style ncf/contact)",
               FixNCFContactHistory::ID);
  const unsigned char *has = phas[b].data();
  const double *slip = pslip[b].data();
  for (int i = 0; i < nlocal; i++) {
    double *row = hist[i];
    int n = 0;
    // the entries of a node are consecutive (build_lists)
    for (int e = pfirst[i]; e < pfirst[i + 1]; e++) {
      if (!has[e]) continue;
      if (n >= maxcontacts)
        error->one(FLERR,
                   "pair ncf/contact: node {} has more than {} contacts; raise pair_style keyword "
                   "maxcontacts",
                   tag[i], maxcontacts);
      const PairCand &pc = plist[e];
      double *h = row + 1 + 6 * n;
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

void PairNCFContact::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);

  // x, v, f as flat arrays (LAMMPS allocates them contiguously): one load less per node access
  using Row = double[3];
  const Row *x = atom->x ? (const Row *) atom->x[0] : nullptr;
  const Row *v = atom->v ? (const Row *) atom->v[0] : nullptr;
  Row *f = atom->f ? (Row *) atom->f[0] : nullptr;
  const tagint *tag = atom->tag;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const double dt = update->dt;
  // the setup of a run (or of a minimisation) computes the forces of the state as it is: the
  // friction history is neither advanced nor kept (the slips of the last step stay the last
  // step's), and each contact's friction force is that of its stored slip, the force the step
  // that stored it gave. So `run 0` changes nothing, and a run cut into pieces is the same run.
  const bool advance = !update->setupflag;

  // the lists hold atom indices: rebuilt whenever LAMMPS has reneighboured (new ghosts, atoms
  // exchanged or sorted) and after every init
  if (!lists_valid || neighbor->ago == 0 || neighbor->ncalls != lists_ncalls ||
      nlocal != lists_nlocal || nall != lists_nall) {
    build_lists();
    lists_valid = true;
    lists_ncalls = neighbor->ncalls;
    lists_nlocal = nlocal;
    lists_nall = nall;
  }
  // (virtual nodes at free chain ends: build_lists)
  const int nvirt = (int) vreal.size();
  fvirt.assign(3 * (size_t) nvirt, 0.0);
  if (fatom_flag) fcon.assign(3 * (size_t) (nall + nvirt), 0.0);

  double ncontact = 0.0, pensum = 0.0, penmax = 0.0, ncap = 0.0;

  // displacement of every local and ghost node since the build (all below skin/2): the distance
  // of two segments, or of a segment and a node, has changed by at most the sum of the largest
  // displacement of a node of each, so a listed pair whose distance at the build minus that
  // bound is beyond its reach needs no test this step, and one within D minus it no prefilter.
  // Per node, one cache line of 8 doubles (x, y, z, displacement bound, vx, vy, vz, end-cap
  // extension), so that the random accesses of the list loops fetch one line per node.
  constexpr int NR = 8;
  xd.resize(NR * (size_t) (nall + nvirt) + NR);
  double *const X = xd.data() + ((64 - ((uintptr_t) xd.data() & 63)) & 63) / sizeof(double);
  // and the displacement bounds again in one dense array (the filter of many entries, below)
  dmn.resize(nall + nvirt);
  double *const DM = dmn.data();
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
  double dmove2 = pack(nlocal, [](int i) {
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
      const double dvn = dvx * ex + dvy * ey + dvz * ez, s = e * il;
      xv[4] = v[k][0] + s * (dvx - dvn * ex);
      xv[5] = v[k][1] + s * (dvy - dvn * ey);
      xv[6] = v[k][2] + s * (dvz - dvn * ez);
    }
    xv[7] = 0.0;
  }
  // twice the largest bound of a node: not below the bound of any pair or cap (computed the same
  // way, and doubling is exact), so a pair beyond the largest reach by it is skipped before its
  // node data are loaded
  const double dglob = 2.0 * (std::sqrt(dmove2) * (1.0 + 1e-12) + 0.5e-12 * reach_max);
  auto xof = [X](int k) {
    return X + NR * (size_t) k;
  };
  // the displacement bound of a node of A plus that of a node of B (the largest of each): the gap
  // of a pair list entry can have closed by grow times that since the build, so the entry is
  // tested only where this reaches its reach (gap / grow)
  auto closing = [DM](const PairCand &pc) {
    return MAX(DM[pc.a0], DM[pc.a1]) + MAX(DM[pc.b0], DM[pc.b1]);
  };

  // every owned segment within the length the cutoffs were sized for: checked one by one only when
  // the longest at the build plus twice the largest displacement could exceed it
  const double lmax2 = lmax_used * lmax_used;
  const bool check_lengths = !(lseg_build * (1.0 + 1e-12) + dglob < lmax_used);
  for (int i = 0; i < (check_lengths ? nlocal : 0); i++)
    for (int sa = 0; sa < 2; sa++) {
      const int ia = segp[2 * i + sa];
      if (ia < 0) continue;
      const double dx = x[ia][0] - x[i][0], dy = x[ia][1] - x[i][1], dz = x[ia][2] - x[i][2];
      const double l2 = dx * dx + dy * dy + dz * dz;
      if (l2 > lmax2)
        error->one(FLERR,
                   "pair ncf/contact: segment {}-{} is {:.6g} long, longer than lmax {:.6g} that "
                   "the cutoffs were sized for; set pair_style keyword lmax",
                   tag[i], tag[ia], std::sqrt(l2), lmax_used);
    }

  // friction history: the last step's read, this step's written (load_history)
  const int hwr = 1 - hlast;
  const double *slip_rd = nullptr;
  const unsigned char *has_rd = nullptr;
  double *slip_wr = nullptr;
  unsigned char *has_wr = nullptr;
  if (use_history) {
    slip_rd = pslip[hlast].data();
    has_rd = phas[hlast].data();
    slip_wr = pslip[hwr].data();
    has_wr = phas[hwr].data();
    memset(has_wr, 0, plist.size());
  }

  // Contact of segment A = a0-a1 (a0 owned here) with segment B = b0-b1, key(A) < key(B), per
  // list entry. A new contact whose take-over needs the history of a pair owned by another rank
  // (a ghost's row) is deferred (put on `deferred`) until that history has been communicated
  deferred.clear();
  // the positions of the four nodes of a list entry (A0, A1, B0, B1); the ends of segments at
  // free chain ends are virtual nodes, whose rows hold the extended ends, so the law sees no
  // extension left (ContactOptions::ext 0)
  struct EntryNodes {
    Vec3 x[4];
  };
  auto nodes_of = [&](const PairCand &pc) {
    EntryNodes en;
    const int ids[4] = {pc.a0, pc.a1, pc.b0, pc.b1};
    for (int m = 0; m < 4; m++) en.x[m] = Vec3(xof(ids[m]));
    return en;
  };
  // the penetration of the chains themselves (their real nodes: two extended tips may overlap
  // without any chain coming closer to another)
  auto real_penetration = [&](const PairCand &pc) {
    const int ids[4] = {real_of(pc.a0), real_of(pc.a1), real_of(pc.b0), real_of(pc.b1)};
    return NCF::segment_penetration(Vec3(x[ids[0]]), Vec3(x[ids[1]]), Vec3(x[ids[2]]),
                                    Vec3(x[ids[3]]), tpar[pc.tp].dc);
  };
  // where the force on node k of a list entry goes: LAMMPS's array, or that of the virtual nodes
  double *const FV = fvirt.data();
  auto fdst = [f, FV, nall](int k) -> double * {
    return k < nall ? f[k] : FV + 3 * (size_t) (k - nall);
  };
  // The contact of a list entry by the scalar law (deferred take-overs) in three parts: prepare
  // (bookkeeping, bounds, prefilter; false if the law need not be evaluated), the law, finish
  // (friction, forces, counters; true if deferred). The main loop evaluates the law in batches
  // (below).
  auto prepare = [&](int e, bool &had) -> bool {
    const PairCand &pc = plist[e];
    // whether the pair was in contact (had a stored slip) in the previous step
    had = use_history && has_rd[e] != 0;
    const double close = closing(pc);
    if (!(pc.reach < close)) return false;
    // (the prefilter only rejects pairs whose law is zero)
    if (pc.reach < -close) return true;
    const TypePair &tp = tpar[pc.tp];
    const EntryNodes en = nodes_of(pc);
    const double no_ext[4] = {0.0, 0.0, 0.0, 0.0};
    return NCF::segment_contact_possible(en.x[0], en.x[1], en.x[2], en.x[3], tp.dc, tp.ramp,
                                         no_ext);
  };
  // the law of entry e by the scalar kernel (any case)
  auto law = [&](int e) {
    const PairCand &pc = plist[e];
    const TypePair &tp = tpar[pc.tp];
    const EntryNodes en = nodes_of(pc);
    NCF::ContactOptions opt;
    opt.core = core;
    return NCF::segment_contact(en.x[0], en.x[1], en.x[2], en.x[3], tp.dc, tp.kn, tp.ramp,
                                eflag_global != 0, opt);
  };
  // After the law: the slip a contact with friction starts from, in this step's buffer: the
  // pair's own of the previous step or, for a new contact, that of a neighbouring pair (or
  // zero); nullptr if that needs the rows of ghosts, not yet communicated (the entry is deferred)
  auto start_slip = [&](int e, bool had, bool may_defer) -> double * {
    double *slip = slip_wr + 3 * (size_t) e;
    if (had) {
      memcpy(slip, slip_rd + 3 * (size_t) e, 3 * sizeof(double));
      return slip;
    }
    slip[0] = slip[1] = slip[2] = 0.0;
    const PairCand &pc = plist[e];
    if (!inherit_slip(tag[real_of(pc.a0)], tag[real_of(pc.a1)], tag[real_of(pc.b0)],
                      tag[real_of(pc.b1)], slip, may_defer)) {
      deferred.push_back(e);
      return nullptr;
    }
    return slip;
  };
  // the forces of a contact added to its four nodes, its energy and penetration counted
  // (fs(m, d): component d of the force on node m)
  auto apply = [&](int e, auto &&fs, double energy, double pen) {
    const PairCand &pc = plist[e];
    const int nodes[4] = {pc.a0, pc.a1, pc.b0, pc.b1};
    for (int k = 0; k < 4; k++) {
      double *fk = fdst(nodes[k]);
      fk[0] += fs(k, 0);
      fk[1] += fs(k, 1);
      fk[2] += fs(k, 2);
      if (fatom_flag) {
        fcon[3 * nodes[k] + 0] += fs(k, 0);
        fcon[3 * nodes[k] + 1] += fs(k, 1);
        fcon[3 * nodes[k] + 2] += fs(k, 2);
      }
    }
    if (eflag_global) eng_vdwl += energy;
    ncontact += 1.0;
    pensum += pen;
    penmax = MAX(penmax, pen);
  };
  // the rest of a contact evaluated by the scalar law: dashpot and friction
  // (NCF::contact_tangential), forces; true if deferred
  auto finish = [&](int e, NCF::SegmentContact c, bool had, bool may_defer) -> bool {
    if (!c.active) return false;
    const PairCand &pc = plist[e];
    const TypePair &tp = tpar[pc.tp];
    double espring = 0.0;
    if (use_velocity && c.fn > 0.0) {
      double *slip = nullptr;
      Vec3 sv;
      if (tp.mu > 0.0) {
        slip = start_slip(e, had, may_defer);
        if (!slip) return true;
        sv = Vec3(slip);
      }
      const int ids[4] = {pc.a0, pc.a1, pc.b0, pc.b1};
      Vec3 vel[4];
      for (int m = 0; m < 4; m++) vel[m] = Vec3(xof(ids[m]) + 4);
      espring = NCF::contact_tangential(c, vel, sv, tp.kt, tp.mu, tp.damp, dt, advance);
      if (slip) {
        // kept (also a zero slip: the contact exists)
        slip[0] = sv.x;
        slip[1] = sv.y;
        slip[2] = sv.z;
        has_wr[e] = 1;
      }
    }
    apply(
        e,
        [&c](int m, int d) {
          return c.f[m][d];
        },
        c.energy + espring, (pc.ext && eflag_global) ? real_penetration(pc) : c.penetration);
    return false;
  };
  auto pair_contact = [&](int e, bool may_defer) -> bool {
    bool had;
    if (!prepare(e, had)) return false;
    return finish(e, law(e), had, may_defer);
  };
  // the entries within the largest reach after the displacement bound of all nodes, gathered
  // without branches first (about a third drop out, unpredictably); the others are no contact
  // (the distances d of the pair list are net of the extensions at free ends)
  const int npairs = (int) plist.size();
  const int ncaps = (int) clist.size();
  work.resize(MAX(npairs, ncaps));
  int nwork = 0;
  for (int e = 0; e < npairs; e++) {
    work[nwork] = e;
    nwork += plist[e].reach < dglob;
  }
  // When many of these drop out at the test by the bounds of their own nodes (nodes moving fast
  // somewhere, as in a compaction: judged by the last step), that test on the dense bounds
  // first, without branches: cheaper than loading the node rows of entries that then drop out.
  // (At rest nearly all are kept: the test on the rows below is cheaper there.) The same test
  // either way, so the same results.
  const int nnear_pairs = nwork;
  if (keep_last < 0.8) {
    int nkeep = 0;
    for (int k = 0; k < nwork; k++) {
      const int e = work[k];
      work[nkeep] = e;
      nkeep += plist[e].reach < closing(plist[e]);
    }
    nwork = nkeep;
  }
  // The pairs go through the batched law, which evaluates the common case several pairs per
  // vector instruction and hands the others back to the scalar law (NCF::segment_contact_batch),
  // then the contacts through the batched dashpot and friction (NCF::tangential_batch)
  int lane_e[NCF::CONTACT_BATCH];
  bool lane_had[NCF::CONTACT_BATCH];
  bool lane_go[NCF::CONTACT_BATCH], lane_fric[NCF::CONTACT_BATCH];
  double lane_pen[NCF::CONTACT_BATCH];
  int lane_node[NCF::CONTACT_BATCH][4];    // the node rows of the lanes (A0, A1, B0, B1)
  batch.n = 0;
  auto flush = [&]() {
    NCF::fill_lanes_from_rows(batch, tbatch, X, lane_node, use_velocity);
    NCF::segment_contact_batch(batch, core);
    // The lanes in contact (status 1) go on, those with friction with their slip; the others are
    // no contact (0) or left to the scalar law (-1). Flags first, without branches; then the few
    // lanes that need more: the scalar law, the penetration output, the slip a new contact with
    // friction takes over (or its entry deferred)
    const bool hist = use_history, eng = eflag_global != 0;
    int special[NCF::CONTACT_BATCH], nspecial = 0;
    for (int l = 0; l < batch.n; l++) {
      const double st = batch.status[l];
      const bool go = st > 0.0;
      const bool fric = hist & go & (tbatch.mu[l] > 0.0) & (batch.fn[l] > 0.0);
      lane_go[l] = go;
      lane_fric[l] = fric;
      lane_pen[l] = 0.0;
      special[nspecial] = l;
      nspecial += (st < 0.0) | (go & (eng | (fric & !lane_had[l])));
    }
    for (int k = 0; k < nspecial; k++) {
      const int l = special[k], e = lane_e[l];
      if (batch.status[l] < 0.0) {
        finish(e, law(e), lane_had[l], use_history);
        continue;
      }
      if (eng) lane_pen[l] = real_penetration(plist[e]);
      // (the slip of the last step is in the lane already; the new one is written after it)
      if (lane_fric[l] && !lane_had[l]) {
        const double *slip = start_slip(e, false, use_history);
        if (!slip) {
          lane_go[l] = lane_fric[l] = false;
          continue;
        }
        for (int d = 0; d < 3; d++) tbatch.slip[d][l] = slip[d];
      }
    }
    if (use_velocity) NCF::tangential_batch(batch, tbatch, dt, advance);
    // the contacts' slips kept and forces added (as apply does, with the counters in locals, so
    // that they stay in registers; the same operations in the same order)
    double *const fc = fatom_flag ? fcon.data() : nullptr;
    double nc = ncontact, ps = pensum, pm = penmax, ev = eng_vdwl;
    // (the lanes in contact listed first, without branches: which are is unpredictable)
    int go_lane[NCF::CONTACT_BATCH], ngo = 0;
    for (int l = 0; l < batch.n; l++) {
      go_lane[ngo] = l;
      ngo += lane_go[l];
    }
    for (int k = 0; k < ngo; k++) {
      const int l = go_lane[k], e = lane_e[l];
      double espring = 0.0;
      if (lane_fric[l]) {
        // kept (also a zero slip: the contact exists)
        double *slip = slip_wr + 3 * (size_t) e;
        for (int d = 0; d < 3; d++) slip[d] = tbatch.slip[d][l];
        has_wr[e] = 1;
        espring = tbatch.energy[l];
      }
      const PairCand &pc = plist[e];
      const int nodes[4] = {pc.a0, pc.a1, pc.b0, pc.b1};
      for (int m = 0; m < 4; m++) {
        double *fm = fdst(nodes[m]);
        for (int d = 0; d < 3; d++) fm[d] += batch.f[3 * m + d][l];
      }
      if (fc)
        for (int m = 0; m < 4; m++)
          for (int d = 0; d < 3; d++) fc[3 * nodes[m] + d] += batch.f[3 * m + d][l];
      // (the energy and penetration sums only where they are output)
      if (eng) {
        ev += batch.energy[l] + espring;
        const double pen = lane_pen[l];
        ps += pen;
        pm = MAX(pm, pen);
      }
      nc += 1.0;
    }
    ncontact = nc;
    pensum = ps;
    penmax = pm;
    eng_vdwl = ev;
    batch.n = 0;
  };
  // with one set of coefficients for all type pairs (the usual case) they are put into every lane
  // once, not lane by lane
  const int ntypes = atom->ntypes;
  bool uniform = true;
  for (int i = 1; i <= ntypes; i++)
    for (int j = 1; j <= ntypes; j++) {
      const TypePair &a = tpar[type_pair(1, 1)], &b = tpar[type_pair(i, j)];
      uniform = uniform && a.dc == b.dc && a.kn == b.kn && a.ramp == b.ramp && a.kt == b.kt &&
          a.mu == b.mu && a.damp == b.damp;
    }
  auto set_coefficients = [&](int l, const TypePair &tp) {
    batch.dc[l] = tp.dc;
    batch.kn[l] = tp.kn;
    batch.ramp[l] = tp.ramp;
    tbatch.kt[l] = tp.kt;
    tbatch.mu[l] = tp.mu;
    tbatch.damp[l] = tp.damp;
  };
  if (uniform)
    for (int l = 0; l < NCF::CONTACT_BATCH; l++) set_coefficients(l, tpar[type_pair(1, 1)]);
  // Each entry within the largest reach goes into the next lane if it is also within reach after
  // the displacement bounds of its own nodes (read from the rows just loaded)
  int nkept = 0;
  for (int k = 0; k < nwork; k++) {
    const int e = work[k];
    // (the node rows of an entry a few ahead requested now: ~3 % of the pair's time)
    if (k + 16 < nwork) {
      const PairCand &pn = plist[work[k + 16]];
      __builtin_prefetch(xof(pn.a1));
      __builtin_prefetch(xof(pn.b0));
      __builtin_prefetch(xof(pn.b1));
    }
    const PairCand &pc = plist[e];
    const int l = batch.n;
    const double *row[4] = {xof(pc.a0), xof(pc.a1), xof(pc.b0), xof(pc.b1)};
    const double close = MAX(row[0][3], row[1][3]) + MAX(row[2][3], row[3][3]);
    // (most entries are kept at rest, few where the nodes move fast: the branch is predictable
    // in both cases, and the lane is not filled in vain in the second)
    if (!(pc.reach < close)) continue;
    nkept++;
    // (the positions and velocities are copied in flush, four lanes at a time)
    lane_node[l][0] = pc.a0;
    lane_node[l][1] = pc.a1;
    lane_node[l][2] = pc.b0;
    lane_node[l][3] = pc.b1;
    if (!uniform) set_coefficients(l, tpar[pc.tp]);
    lane_e[l] = e;
    if (use_history) {
      // the slip of the last step (zero if the pair was not in contact), used only with friction
      // (read whether used or not, so that the choice is a select, not a mispredicted branch)
      const bool had = has_rd[e] != 0;
      const double *sr = slip_rd + 3 * (size_t) e;
      const double s0 = sr[0], s1 = sr[1], s2 = sr[2];
      tbatch.slip[0][l] = had ? s0 : 0.0;
      tbatch.slip[1][l] = had ? s1 : 0.0;
      tbatch.slip[2][l] = had ? s2 : 0.0;
      lane_had[l] = had;
    } else {
      for (int d = 0; d < 3; d++) tbatch.slip[d][l] = 0.0;
      lane_had[l] = false;
    }
    batch.n++;
    if (batch.n == NCF::CONTACT_BATCH) flush();
  }
  if (batch.n > 0) flush();
  keep_last = nnear_pairs > 0 ? (double) nkept / nnear_pairs : 1.0;
  // the history rows of ghost nodes are needed only by deferred take-overs: communicated (the
  // rows of the previous step, not yet replaced) only in steps where some rank has one
  if (use_history) {
    int need = deferred.empty() ? 0 : 1, any = need;
    if (comm->nprocs > 1) MPI_Allreduce(&need, &any, 1, MPI_INT, MPI_MAX, world);
    if (any) {
      // the rows of the last step, sent to the ghosts
      store_history(hlast);
      comm_mode = COMM_HIST;
      comm->forward_comm(this);
      for (const int e : deferred) pair_contact(e, false);
    }
  }

  // cap contact of segment ao-ia (ao owned here) with the interior node k (chain kp-k-kq)
  // (the caps within the largest diameter after the displacement bound of all nodes gathered
  // first, without branches)
  int nnear = 0;
  for (int e = 0; e < ncaps; e++) {
    work[nnear] = e;
    nnear += clist[e].gap - dglob < 0.0;
  }
  // then those within reach after the displacement bounds of their own nodes (again without
  // branches); whether A comes within D of the node at all is the batch's first test
  int ncapin = 0;
  for (int w = 0; w < nnear; w++) {
    if (w + 16 < nnear) {
      const CapCand &cn = clist[work[w + 16]];
      __builtin_prefetch(xof(cn.a1));
      __builtin_prefetch(xof(cn.n));
    }
    const CapCand &cc = clist[work[w]];
    work[ncapin] = work[w];
    ncapin += cc.gap - (MAX(xof(cc.a0)[3], xof(cc.a1)[3]) + xof(cc.n)[3]) < 0.0;
  }
  // in batches of CAP_BATCH caps through the batched caps (NCF::node_contact_batch), which hands
  // back the caps outside its case to node_contact; the forces are added in the order of the caps
  for (int w0 = 0; w0 < ncapin; w0 += NCF::CAP_BATCH) {
    cbatch.n = MIN(NCF::CAP_BATCH, ncapin - w0);
    for (int l = 0; l < cbatch.n; l++) {
      const CapCand &cc = clist[work[w0 + l]];
      const TypePair &tp = tpar[cc.tp];
      cbatch.set(l, xof(cc.a0), xof(cc.a1), xof(cc.p), xof(cc.n), xof(cc.q), tp.dc, tp.kn, tp.ramp);
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
        c = NCF::node_contact(Vec3(xof(cc.a0)), Vec3(xof(cc.a1)), Vec3(xof(cc.p)), Vec3(xof(cc.n)),
                              Vec3(xof(cc.q)), tp.dc, tp.kn, tp.ramp, core);
        if (!c.active) continue;
      } else {
        c = cbatch.result(l);
      }
      for (int m = 0; m < 5; m++) {
        f[ids[m]][0] += c.f[m].x;
        f[ids[m]][1] += c.f[m].y;
        f[ids[m]][2] += c.f[m].z;
        if (fatom_flag) {
          fcon[3 * ids[m] + 0] += c.f[m].x;
          fcon[3 * ids[m] + 1] += c.f[m].y;
          fcon[3 * ids[m] + 2] += c.f[m].z;
        }
      }
      if (eflag_global) eng_vdwl += c.energy;
      ncap += 1.0;
      penmax = MAX(penmax, c.penetration);
    }
  }

  // the forces on the virtual nodes (extended free chain ends) onto their real nodes: the end k
  // at x_k + e u, u = (x_k - x_j) / l, so F on it gives F + g on k and -g on its neighbour j,
  // g = (e / l)(F - u (u.F)) (the chain rule; the contact energy depends on x_k and x_j through
  // the extended end only)
  auto map_virtual = [&](const double *fv, auto &&dst) {
    for (int vn = 0; vn < nvirt; vn++) {
      const int k = vreal[vn], j = vnbr[vn];
      const double *gv = &vgeom[4 * (size_t) vn];
      const double ex = gv[0], ey = gv[1], ez = gv[2], s = gv[3];
      const double *F = fv + 3 * (size_t) vn;
      const double fu = F[0] * ex + F[1] * ey + F[2] * ez;
      const double g[3] = {s * (F[0] - fu * ex), s * (F[1] - fu * ey), s * (F[2] - fu * ez)};
      double *fk = dst(k), *fj = dst(j);
      for (int d = 0; d < 3; d++) {
        fk[d] += F[d] + g[d];
        fj[d] -= g[d];
      }
    }
  };
  map_virtual(FV, [f](int k) {
    return f[k];
  });
  if (fatom_flag)
    map_virtual(fcon.data() + 3 * (size_t) nall, [this](int k) {
      return fcon.data() + 3 * (size_t) k;
    });

  // this step's history is the last step's of the next (its rows are written when needed); not
  // in a setup (advance)
  if (use_history && advance) {
    hlast = hwr;
    rows_current = false;
  }

  if (fatom_flag) {
    comm_mode = COMM_FORCE;
    comm->reverse_comm(this);
    double *fc = atom->dvector[idx_fc];
    for (int i = 0; i < nlocal; i++)
      fc[i] = std::sqrt(fcon[3 * i] * fcon[3 * i] + fcon[3 * i + 1] * fcon[3 * i + 1] +
                        fcon[3 * i + 2] * fcon[3 * i + 2]);
  }

  if (eflag_global) {
    // compute pair sums pvector over the ranks: the maximum is reduced here and put on rank 0
    double all;
    MPI_Allreduce(&penmax, &all, 1, MPI_DOUBLE, MPI_MAX, world);
    pvector[0] = ncontact;
    pvector[1] = pensum;
    pvector[2] = (comm->me == 0) ? all : 0.0;
    pvector[3] = ncap;
  }

  if (vflag_fdotr) virial_fdotr_compute();
}

/* ---------------------------------------------------------------------- */

int PairNCFContact::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/,
                                      int * /*pbc*/)
{
  // variable length: per atom the number of contacts, then 6 values per contact
  double **hist = atom->darray[idx_hist];
  int m = 0;
  for (int k = 0; k < n; k++) {
    const double *row = hist[list[k]];
    const int len = 1 + 6 * (int) row[0];
    memcpy(buf + m, row, sizeof(double) * len);
    m += len;
  }
  return m;
}

void PairNCFContact::unpack_forward_comm(int n, int first, double *buf)
{
  double **hist = atom->darray[idx_hist];
  int m = 0;
  for (int k = first; k < first + n; k++) {
    const int len = 1 + 6 * (int) buf[m];
    memcpy(hist[k], buf + m, sizeof(double) * len);
    m += len;
  }
}

int PairNCFContact::pack_reverse_comm(int n, int first, double *buf)
{
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
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    fcon[3 * j] += buf[m++];
    fcon[3 * j + 1] += buf[m++];
    fcon[3 * j + 2] += buf[m++];
  }
}

/* ---------------------------------------------------------------------- */

void PairNCFContact::write_restart_settings(FILE *fp)
{
  fwrite(&ramp_frac, sizeof(double), 1, fp);
  fwrite(&lmax_user, sizeof(double), 1, fp);
  fwrite(&maxcontacts, sizeof(int), 1, fp);
  fwrite(&fatom_flag, sizeof(int), 1, fp);
  fwrite(&dtcheck, sizeof(int), 1, fp);
  fwrite(&core, sizeof(double), 1, fp);
  fwrite(&endcap_frac, sizeof(double), 1, fp);
}

void PairNCFContact::read_restart_settings(FILE *fp)
{
  if (comm->me == 0) {
    utils::sfread(FLERR, &ramp_frac, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &lmax_user, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &maxcontacts, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &fatom_flag, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &dtcheck, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &core, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &endcap_frac, sizeof(double), 1, fp, nullptr, error);
  }
  MPI_Bcast(&ramp_frac, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&lmax_user, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&maxcontacts, 1, MPI_INT, 0, world);
  MPI_Bcast(&fatom_flag, 1, MPI_INT, 0, world);
  MPI_Bcast(&dtcheck, 1, MPI_INT, 0, world);
  MPI_Bcast(&core, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&endcap_frac, 1, MPI_DOUBLE, 0, world);
  ncol = 1 + 6 * maxcontacts;
}

void PairNCFContact::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  const int n = atom->ntypes;
  for (int i = 1; i <= n; i++) {
    fwrite(&diamset[i], sizeof(int), 1, fp);
    fwrite(&diameter[i], sizeof(double), 1, fp);
    for (int j = i; j <= n; j++) {
      fwrite(&given[i][j], sizeof(int), 1, fp);
      if (given[i][j]) {
        fwrite(&kn[i][j], sizeof(double), 1, fp);
        fwrite(&ktr[i][j], sizeof(double), 1, fp);
        fwrite(&mu[i][j], sizeof(double), 1, fp);
        fwrite(&damp[i][j], sizeof(double), 1, fp);
      }
    }
  }
}

void PairNCFContact::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int n = atom->ntypes;
  const int me = comm->me;
  for (int i = 1; i <= n; i++) {
    if (me == 0) {
      utils::sfread(FLERR, &diamset[i], sizeof(int), 1, fp, nullptr, error);
      utils::sfread(FLERR, &diameter[i], sizeof(double), 1, fp, nullptr, error);
    }
    MPI_Bcast(&diamset[i], 1, MPI_INT, 0, world);
    MPI_Bcast(&diameter[i], 1, MPI_DOUBLE, 0, world);
    for (int j = i; j <= n; j++) {
      if (me == 0) utils::sfread(FLERR, &given[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&given[i][j], 1, MPI_INT, 0, world);
      if (given[i][j]) {
        double buf[4];
        if (me == 0) utils::sfread(FLERR, buf, sizeof(double), 4, fp, nullptr, error);
        MPI_Bcast(buf, 4, MPI_DOUBLE, 0, world);
        kn[i][j] = buf[0];
        ktr[i][j] = buf[1];
        mu[i][j] = buf[2];
        damp[i][j] = buf[3];
        setflag[i][j] = 1;
      }
    }
  }
}

void *PairNCFContact::extract(const char *str, int &dim)
{
  dim = 2;
  if (strcmp(str, "kn") == 0) return (void *) kn;
  if (strcmp(str, "mu") == 0) return (void *) mu;
  if (strcmp(str, "damp") == 0) return (void *) damp;
  dim = 1;
  if (strcmp(str, "diameter") == 0) return (void *) diameter.data();
  return nullptr;
}
