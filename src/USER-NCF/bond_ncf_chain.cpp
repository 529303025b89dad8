/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   bond_style ncf/chain (see bond_ncf_chain.h and doc/bond_ncf_chain.md).

   Per-bond reference lengths live in a fix property/atom (ID NCF_CHAIN_L0) with two slots per
   atom: i2_ncf_dtag (partner tag minus own tag, 0 = empty slot) and d2_ncf_l0 (the length). Both
   atoms of a bond carry it. Relative tags make the data invariant under the tag offset of
   "read_data ... add append"; the fix gives migration, ghost communication, restart files and
   data-file sections for free.
------------------------------------------------------------------------- */

#include "bond_ncf_chain.h"

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

#include "lammps_ncf_args.h"
#include "lammps_ncf_compat.h"

#include <cmath>
#include <cstring>
#include <string>
#include <utility>

using namespace LAMMPS_NS;

static constexpr int NSLOT = 2;

/* ---------------------------------------------------------------------- */

BondNCFChain::BondNCFChain(LAMMPS *_lmp) :
    Bond(_lmp), dtcheck(DT_ERROR), capture_pending(true), dt_critical(0.0), comm_mode(COMM_SLOTS),
    idx_dtag(-1), idx_l0(-1), l0_ncalls(-1)
{
  writedata = 1;
  reinitflag = 1;
  comm_forward = 2 * NSLOT;
  comm_reverse = 2 * NSLOT;

  // Before the box exists (bond_style ahead of read_data) the store must exist now so that
  // read_data can fill it from its section. Otherwise (read_restart, or a bond_style after
  // read_data) it is created at init, after read_restart has staged the per-atom restart data
  // that the new fix then picks up.
  if (!domain->box_exist) create_store();
}

/* ---------------------------------------------------------------------- */

BondNCFChain::~BondNCFChain()
{
  // the store fix is left in place on purpose: its data outlive a change of bond style
  if (allocated) memory->destroy(setflag);
}

/* ---------------------------------------------------------------------- */

void BondNCFChain::allocate()
{
  allocated = 1;
  const int n = atom->nbondtypes;
  ea.assign(n + 1, 0.0);
  shrink.assign(n + 1, 0.0);
  compression.assign(n + 1, 1.0);
  maxl0.assign(n + 1, 0.0);
  memory->create(setflag, n + 1, "bond:setflag");
  for (int i = 1; i <= n; i++) setflag[i] = 0;
}

/* ----------------------------------------------------------------------
   bond_style ncf/chain [dtcheck error|warn|no]
------------------------------------------------------------------------- */

void BondNCFChain::settings(int narg, char **arg)
{
  int iarg = 0;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (key == "dtcheck") {
      NCF_LMP::need_values(lmp, "bond_style ncf/chain", key, iarg, narg, 1);
      const std::string val = arg[iarg + 1];
      if (val == "error")
        dtcheck = DT_ERROR;
      else if (val == "warn")
        dtcheck = DT_WARN;
      else if (val == "no")
        dtcheck = DT_NONE;
      else
        error->all(FLERR, "bond_style ncf/chain: dtcheck '{}' is not one of error, warn, no", val);
      iarg += 2;
    } else {
      error->all(FLERR, "bond_style ncf/chain: unknown keyword '{}'", key);
    }
  }
}

/* ----------------------------------------------------------------------
   bond_coeff N ea EA [shrink s] [compression c]
   bond_coeff N modulus E diameter d [shrink s] [compression c]
------------------------------------------------------------------------- */

void BondNCFChain::coeff(int narg, char **arg)
{
  if (narg < 3)
    error->all(FLERR,
               "bond_coeff ncf/chain: expected 'N ea EA' or 'N modulus E diameter d' "
               "[shrink s] [compression c], got {} argument(s)",
               narg);
  if (!allocated) allocate();

  const std::string what = "bond_coeff ncf/chain";
  int ilo, ihi;
  NCF_LMP::types(lmp, what, "bond type", arg[0], atom->nbondtypes, ilo, ihi);

  double ea_in = -1.0, modulus = -1.0, diameter = -1.0, shrink_in = 0.0, compression_in = 1.0;
  std::vector<std::string> given;
  int iarg = 1;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    if (key != "ea" && key != "modulus" && key != "diameter" && key != "shrink" &&
        key != "compression")
      error->all(FLERR, "bond_coeff ncf/chain: unknown keyword '{}'", key);
    NCF_LMP::need_values(lmp, what, key, iarg, narg, 1);
    for (const auto &g : given)
      if (g == key) error->all(FLERR, "bond_coeff ncf/chain: keyword '{}' given twice", key);
    given.push_back(key);
    const double v = NCF_LMP::number(lmp, what, key, arg[iarg + 1]);
    if (key == "ea") {
      if (!(v > 0.0))
        error->all(FLERR, "bond_coeff ncf/chain: ea must be > 0, got {}", arg[iarg + 1]);
      ea_in = v;
    } else if (key == "modulus") {
      if (!(v > 0.0))
        error->all(FLERR, "bond_coeff ncf/chain: modulus must be > 0, got {}", arg[iarg + 1]);
      modulus = v;
    } else if (key == "diameter") {
      if (!(v > 0.0))
        error->all(FLERR, "bond_coeff ncf/chain: diameter must be > 0, got {}", arg[iarg + 1]);
      diameter = v;
    } else if (key == "shrink") {
      if (!(v >= 0.0 && v < 1.0))
        error->all(FLERR, "bond_coeff ncf/chain: shrink must be in [0, 1), got {}", arg[iarg + 1]);
      shrink_in = v;
    } else if (key == "compression") {
      if (!(v >= 0.0 && v <= 1.0))
        error->all(FLERR, "bond_coeff ncf/chain: compression must be in [0, 1], got {}",
                   arg[iarg + 1]);
      compression_in = v;
    }
    iarg += 2;
  }

  if (ea_in > 0.0 && (modulus > 0.0 || diameter > 0.0))
    error->all(FLERR,
               "bond_coeff ncf/chain: give either 'ea' or 'modulus' with 'diameter', not both");
  if (ea_in < 0.0) {
    if (modulus < 0.0 || diameter < 0.0)
      error->all(FLERR,
                 "bond_coeff ncf/chain: no axial stiffness for bond type(s) {}: give 'ea' or "
                 "both 'modulus' and 'diameter'",
                 arg[0]);
    ea_in = modulus * 0.25 * M_PI * diameter * diameter;
    if (!(std::isfinite(ea_in) && ea_in > 0.0))
      error->all(FLERR,
                 "bond_coeff ncf/chain: modulus {} and diameter {} give EA = {}, not a finite "
                 "number > 0",
                 modulus, diameter, ea_in);
  }

  for (int i = ilo; i <= ihi; i++) {
    ea[i] = ea_in;
    shrink[i] = shrink_in;
    compression[i] = compression_in;
    setflag[i] = 1;
  }
}

/* ---------------------------------------------------------------------- */

void BondNCFChain::create_store()
{
  if (!modify->get_fix_by_id(STORE_ID))
    modify->add_fix(fmt::format("{} all property/atom i2_ncf_dtag {} d2_ncf_l0 {} ghost yes",
                                STORE_ID, NSLOT, NSLOT));
  find_store();
}

void BondNCFChain::find_store()
{
  int flag, cols;
  idx_dtag = atom->find_custom("ncf_dtag", flag, cols);
  if (idx_dtag < 0 || flag != 0 || cols != NSLOT)
    error->all(FLERR,
               "bond ncf/chain: per-atom array i2_ncf_dtag of fix {} is missing or malformed",
               STORE_ID);
  idx_l0 = atom->find_custom("ncf_l0", flag, cols);
  if (idx_l0 < 0 || flag != 1 || cols != NSLOT)
    error->all(FLERR, "bond ncf/chain: per-atom array d2_ncf_l0 of fix {} is missing or malformed",
               STORE_ID);
}

/* ---------------------------------------------------------------------- */

void BondNCFChain::init_style()
{
  // (also called by fix adapt after every change of ea, shrink or compression)
  check_coefficients();
  create_store();
  capture_pending = true;
  l0_ncalls = -1;
  update_maxl0();
}

/* ----------------------------------------------------------------------
   the per-type coefficients, at every init: bond_coeff checks what it reads, but fix adapt
   changes them at run time (it calls init through reinit after every change)
------------------------------------------------------------------------- */

void BondNCFChain::check_coefficients()
{
  for (int t = 1; t <= atom->nbondtypes && t < (int) ea.size(); t++) {
    if (!(std::isfinite(ea[t]) && ea[t] > 0.0))
      error->all(FLERR,
                 "bond ncf/chain: ea of bond type {} is {} (changed by fix adapt?); it must be a "
                 "finite number > 0",
                 t, ea[t]);
    if (!(shrink[t] >= 0.0 && shrink[t] < 1.0))
      error->all(FLERR,
                 "bond ncf/chain: shrink of bond type {} is {} (changed by fix adapt?); it must "
                 "be in [0, 1)",
                 t, shrink[t]);
    if (!(compression[t] >= 0.0 && compression[t] <= 1.0))
      error->all(FLERR,
                 "bond ncf/chain: compression of bond type {} is {} (changed by fix adapt?); it "
                 "must be in [0, 1]",
                 t, compression[t]);
  }
}

/* ----------------------------------------------------------------------
   the bonds as the run sees them, at every setup (collective; bond list and ghosts current):
   no bond of length 0, every reference length a finite number > 0, and no pair of nodes bonded
   twice (a duplicate line of a data file, or a ring of two nodes): each node has as many bonds
   as distinct bonded neighbours (LAMMPS's 1-2 list holds every neighbour once)
------------------------------------------------------------------------- */

void BondNCFChain::check_bonds()
{
  double **x = atom->x;
  const tagint *tag = atom->tag;
  int **bondlist = neighbor->bondlist;
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const int newton_bond = force->newton_bond;
  ksum.assign(nall, 0.0);
  for (int n = 0; n < neighbor->nbondlist; n++) {
    const int i1 = bondlist[n][0], i2 = bondlist[n][1];
    const double dx = x[i1][0] - x[i2][0], dy = x[i1][1] - x[i2][1], dz = x[i1][2] - x[i2][2];
    if (!(dx * dx + dy * dy + dz * dz > 0.0))
      error->one(FLERR,
                 "bond ncf/chain: bond {}-{} has length 0: its two atoms are at the same place",
                 tag[i1], tag[i2]);
    const double l0 = reference_length(i1, i2);
    if (!(std::isfinite(l0) && l0 > 0.0))
      error->one(FLERR,
                 "bond ncf/chain: bond {}-{} has the reference length {} (section {} of the data "
                 "file or restart); it must be a finite number > 0",
                 tag[i1], tag[i2], l0, STORE_ID);
    if (newton_bond || i1 < nlocal) ksum[i1] += 1.0;
    if (newton_bond || i2 < nlocal) ksum[i2] += 1.0;
  }
  if (newton_bond) {
    comm_mode = COMM_STIFFNESS;
    comm->reverse_comm(this, 1);
    comm_mode = COMM_SLOTS;
  }
  for (int i = 0; i < nlocal; i++)
    if (ksum[i] > atom->nspecial[i][0])
      error->one(FLERR,
                 "bond ncf/chain: atom {} has {} bonds to {} distinct atom(s): a bond is given "
                 "twice (a repeated line in the Bonds section, or a ring of two atoms)",
                 tag[i], (int) ksum[i], atom->nspecial[i][0]);
  // every filled slot names a bonded neighbour, every empty one holds no length: a row of the
  // data file's section that names another atom, or a length without a partner, is not used by
  // any bond and would be dropped without a word
  int **dtag = atom->iarray[idx_dtag];
  double **l0 = atom->darray[idx_l0];
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < NSLOT; k++) {
      if (dtag[i][k] == 0) {
        if (l0[i][k] != 0.0)
          error->one(FLERR,
                     "bond ncf/chain: atom {} has the reference length {} in slot {} of section "
                     "{} without a partner (its relative tag is 0): a mistyped row",
                     tag[i], l0[i][k], k + 1, STORE_ID);
        continue;
      }
      const tagint partner = tag[i] + dtag[i][k];
      bool bonded = false;
      for (int s = 0; s < atom->nspecial[i][0]; s++) bonded |= atom->special[i][s] == partner;
      if (!bonded)
        error->one(
            FLERR,
            "bond ncf/chain: atom {} has a reference length ({}) for atom {} (relative tag "
            "{}, slot {} of section {}), which is not bonded to it: a mistyped row, or a "
            "bond deleted since (empty the slot: set atom {} i2_ncf_dtag[{}] 0 d2_ncf_l0[{}] "
            "0)",
            tag[i], l0[i][k], partner, dtag[i][k], k + 1, STORE_ID, tag[i], k + 1, k + 1);
    }
}

void BondNCFChain::update_maxl0()
{
  // largest stored L0 per bond type, for the communication-cutoff check of LAMMPS
  const int ntypes = atom->nbondtypes;
  std::vector<double> local(ntypes + 1, 0.0);
  const int nlocal = atom->nlocal;
  const tagint *tag = atom->tag;
  int **dtag = atom->iarray[idx_dtag];
  double **l0 = atom->darray[idx_l0];
  for (int i = 0; i < nlocal; i++) {
    for (int m = 0; m < atom->num_bond[i]; m++) {
      const int type = atom->bond_type[i][m];
      if (type <= 0 || type > ntypes) continue;
      const tagint d = atom->bond_atom[i][m] - tag[i];
      for (int k = 0; k < NSLOT; k++)
        if (dtag[i][k] == d && l0[i][k] > local[type]) local[type] = l0[i][k];
    }
  }
  maxl0.assign(ntypes + 1, 0.0);
  MPI_Allreduce(local.data(), maxl0.data(), ntypes + 1, MPI_DOUBLE, MPI_MAX, world);
}

/* ----------------------------------------------------------------------
   stored reference length of bond i-j (local or ghost indices); the lower tag's copy first, so
   that every rank uses the same number whichever atom it owns
------------------------------------------------------------------------- */

double BondNCFChain::reference_length(int i, int j) const
{
  const tagint *tag = atom->tag;
  if (tag[j] < tag[i]) std::swap(i, j);
  const int d = (int) (tag[j] - tag[i]);
  int **dtag = atom->iarray[idx_dtag];
  double **l0 = atom->darray[idx_l0];
  for (int k = 0; k < NSLOT; k++)
    if (dtag[i][k] == d) return l0[i][k];
  for (int k = 0; k < NSLOT; k++)
    if (dtag[j][k] == -d) return l0[j][k];
  return 0.0;
}

/* ---------------------------------------------------------------------- */

void BondNCFChain::store_slot(int i, int d, double length)
{
  int **dtag = atom->iarray[idx_dtag];
  double **l0 = atom->darray[idx_l0];
  for (int k = 0; k < NSLOT; k++)
    if (dtag[i][k] == d) return;    // first value wins: never overwrite a stored length
  for (int k = 0; k < NSLOT; k++)
    if (dtag[i][k] == 0) {
      dtag[i][k] = d;
      l0[i][k] = length;
      return;
    }
  error->one(FLERR,
             "bond ncf/chain: atom {} has more than {} chain bonds; ncf/chain models chains, "
             "where every node has at most two neighbours",
             atom->tag[i], NSLOT);
}

int BondNCFChain::count_owned_slots() const
{
  int n = 0;
  int **dtag = atom->iarray[idx_dtag];
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < NSLOT; k++)
      if (dtag[i][k] > 0) n++;    // each bond counted once, on its lower-tag atom
  return n;
}

/* ----------------------------------------------------------------------
   bonds without a stored L0 take the current length (collective: called by all ranks from the
   first compute() after init, when the bond list and the ghost atoms are current)
------------------------------------------------------------------------- */

void BondNCFChain::capture_missing()
{
  double **x = atom->x;
  const tagint *tag = atom->tag;
  int **bondlist = neighbor->bondlist;
  const int nbondlist = neighbor->nbondlist;

  const int before = count_owned_slots();
  int missing = 0;
  for (int n = 0; n < nbondlist; n++) {
    const int i1 = bondlist[n][0], i2 = bondlist[n][1];
    if (reference_length(i1, i2) > 0.0) continue;
    const double dx = x[i1][0] - x[i2][0], dy = x[i1][1] - x[i2][1], dz = x[i1][2] - x[i2][2];
    const double r = sqrt(dx * dx + dy * dy + dz * dz);
    if (!(r > 0.0))
      error->one(FLERR, "bond ncf/chain: cannot capture L0 of bond {}-{}: the atoms coincide",
                 tag[i1], tag[i2]);
    const int d = (int) (tag[i2] - tag[i1]);
    store_slot(i1, d, r);
    store_slot(i2, -d, r);
    missing++;
  }
  int anymissing = 0;
  MPI_Allreduce(&missing, &anymissing, 1, MPI_INT, MPI_MAX, world);
  if (!anymissing) return;

  comm_mode = COMM_SLOTS;
  comm->reverse_comm(this);    // ghost slots filled here go to their owners
  comm->forward_comm(this);    // and back to every ghost copy
  int captured = count_owned_slots() - before, total = 0;
  MPI_Allreduce(&captured, &total, 1, MPI_INT, MPI_SUM, world);
  if (comm->me == 0)
    utils::logmesg(
        lmp, "bond ncf/chain: reference length L0 taken from the current geometry for {} bond(s)\n",
        total);
  update_maxl0();
}

/* ----------------------------------------------------------------------
   critical time step of the bond network (explicit central differences):
   omega_max^2 <= max_i 2 sum_b(k_b) / m_i (Gershgorin), dt_c = 2 / omega_max.
   Exact for a uniform chain: dt_c = L0 sqrt(rho / E).
------------------------------------------------------------------------- */

void BondNCFChain::estimate_critical_timestep()
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  ksum.assign(nall, 0.0);
  int **bondlist = neighbor->bondlist;
  for (int n = 0; n < neighbor->nbondlist; n++) {
    const int i1 = bondlist[n][0], i2 = bondlist[n][1], type = bondlist[n][2];
    const double l0 = reference_length(i1, i2);
    if (l0 <= 0.0) continue;
    const double k = ea[type] / l0;
    ksum[i1] += k;
    ksum[i2] += k;
  }
  if (force->newton_bond) {
    comm_mode = COMM_STIFFNESS;
    comm->reverse_comm(this, 1);
    comm_mode = COMM_SLOTS;
  }
  double omega2 = 0.0;
  for (int i = 0; i < nlocal; i++) {
    const double m = atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
    if (m > 0.0 && ksum[i] > 0.0) omega2 = std::max(omega2, 2.0 * ksum[i] / m);
  }
  double all = 0.0;
  MPI_Allreduce(&omega2, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  dt_critical = (all > 0.0) ? 2.0 / sqrt(all) : 0.0;
  if (dtcheck == DT_NONE || update->whichflag != 1) return;
  const double dt = update->dt;
  if (!std::isfinite(all) || !(dt > 0.0)) {
    const std::string msg = !std::isfinite(all)
        ? fmt::format("bond ncf/chain: the critical time step of the chain bonds is 0: the "
                      "stiffness EA/L0 per node mass overflows ({}); check the bond "
                      "coefficients, the reference lengths and the masses",
                      all)
        : fmt::format("bond ncf/chain: timestep {} is not > 0", dt);
    if (dtcheck == DT_ERROR) error->all(FLERR, msg);
    if (comm->me == 0) error->warning(FLERR, msg);
    return;
  }
  if (dt_critical <= 0.0) return;

  if (comm->me == 0)
    utils::logmesg(lmp,
                   "bond ncf/chain: critical time step {:.6g}, timestep {:.6g} ({:.3g} of it)\n",
                   dt_critical, dt, dt / dt_critical);
  if (dt > dt_critical) {
    const std::string msg = fmt::format(
        "bond ncf/chain: timestep {:.6g} is above the critical time step {:.6g} of the chain "
        "bonds (L0 sqrt(rho/E)); the integration would blow up. Reduce the timestep, scale the "
        "masses up, or use 'bond_style ncf/chain dtcheck warn' to run anyway",
        dt, dt_critical);
    if (dtcheck == DT_ERROR) error->all(FLERR, msg);
    if (comm->me == 0) error->warning(FLERR, msg);
  }
}

/* ---------------------------------------------------------------------- */

void BondNCFChain::compute(int eflag, int vflag)
{
  if (capture_pending) {
    capture_missing();
    capture_pending = false;
    if (update->setupflag) {
      check_bonds();
      estimate_critical_timestep();
    }
  }

  ev_init(eflag, vflag);

  double **x = atom->x;
  double **f = atom->f;
  const tagint *tag = atom->tag;
  int **bondlist = neighbor->bondlist;
  const int nbondlist = neighbor->nbondlist;
  const int nlocal = atom->nlocal;
  const int newton_bond = force->newton_bond;

  // the reference lengths in the order of the bond list, looked up again whenever LAMMPS has
  // rebuilt the list (and after every init)
  // (and their stiffnesses, which change only with the coefficients: bond_coeff is followed by an
  // init, which asks for a refill)
  if (l0_ncalls != neighbor->ncalls || (int) l0_list.size() != nbondlist) {
    l0_list.resize(nbondlist);
    k_list.resize(nbondlist);
    for (int n = 0; n < nbondlist; n++) {
      const int i1 = bondlist[n][0], i2 = bondlist[n][1];
      l0_list[n] = reference_length(i1, i2);
      if (l0_list[n] <= 0.0)
        error->one(FLERR, "bond ncf/chain: bond {}-{} has no reference length", tag[i1], tag[i2]);
      k_list[n] = NCF::rod_stiffness(rod(bondlist[n][2]), l0_list[n]);
    }
    l0_ncalls = neighbor->ncalls;
  }

  for (int n = 0; n < nbondlist; n++) {
    const int i1 = bondlist[n][0], i2 = bondlist[n][1], type = bondlist[n][2];
    const double l0 = l0_list[n];

    const double delx = x[i1][0] - x[i2][0];
    const double dely = x[i1][1] - x[i2][1];
    const double delz = x[i1][2] - x[i2][2];
    const double r = sqrt(delx * delx + dely * dely + delz * delz);
    // (the shrink factor changes during a run: fix ncf/shrink)
    const NCF::RodResult res = NCF::rod_force(k_list[n], l0 * (1.0 - shrink[type]), r);
    const double fbond = res.fpair;

    if (newton_bond || i1 < nlocal) {
      f[i1][0] += delx * fbond;
      f[i1][1] += dely * fbond;
      f[i1][2] += delz * fbond;
    }
    if (newton_bond || i2 < nlocal) {
      f[i2][0] -= delx * fbond;
      f[i2][1] -= dely * fbond;
      f[i2][2] -= delz * fbond;
    }
    if (evflag) ev_tally(i1, i2, nlocal, newton_bond, res.energy, fbond, delx, dely, delz);
  }
}

/* ---------------------------------------------------------------------- */

double BondNCFChain::equilibrium_distance(int type)
{
  if (type < 1 || type >= (int) maxl0.size()) return 0.0;
  return maxl0[type];
}

/* ---------------------------------------------------------------------- */

void BondNCFChain::write_restart(FILE *fp)
{
  const int n = atom->nbondtypes;
  fwrite(&ea[1], sizeof(double), n, fp);
  fwrite(&shrink[1], sizeof(double), n, fp);
  fwrite(&compression[1], sizeof(double), n, fp);
}

void BondNCFChain::read_restart(FILE *fp)
{
  allocate();
  const int n = atom->nbondtypes;
  if (comm->me == 0) {
    utils::sfread(FLERR, &ea[1], sizeof(double), n, fp, nullptr, error);
    utils::sfread(FLERR, &shrink[1], sizeof(double), n, fp, nullptr, error);
    utils::sfread(FLERR, &compression[1], sizeof(double), n, fp, nullptr, error);
  }
  MPI_Bcast(&ea[1], n, MPI_DOUBLE, 0, world);
  MPI_Bcast(&shrink[1], n, MPI_DOUBLE, 0, world);
  MPI_Bcast(&compression[1], n, MPI_DOUBLE, 0, world);
  for (int i = 1; i <= n; i++) setflag[i] = 1;
}

void BondNCFChain::write_restart_settings(FILE *fp)
{
  fwrite(&dtcheck, sizeof(int), 1, fp);
}

void BondNCFChain::read_restart_settings(FILE *fp)
{
  if (comm->me == 0) utils::sfread(FLERR, &dtcheck, sizeof(int), 1, fp, nullptr, error);
  MPI_Bcast(&dtcheck, 1, MPI_INT, 0, world);
}

/* ----------------------------------------------------------------------
   Bond Coeffs section: full precision so that read_data restores the same values
------------------------------------------------------------------------- */

void BondNCFChain::write_data(FILE *fp)
{
  for (int i = 1; i <= atom->nbondtypes; i++)
    NCF_COMPAT::print(fp, "{} ea {} shrink {} compression {}\n", i, ea[i], shrink[i],
                      compression[i]);
}

/* ---------------------------------------------------------------------- */

double BondNCFChain::single(int type, double rsq, int i, int j, double &fforce)
{
  const double l0 = reference_length(i, j);
  if (l0 <= 0.0)
    error->one(FLERR, "bond ncf/chain: bond {}-{} has no reference length", atom->tag[i],
               atom->tag[j]);
  const NCF::RodResult res = NCF::rod_force(rod(type), l0, sqrt(rsq));
  fforce = res.fpair;
  return res.energy;
}

/* ----------------------------------------------------------------------
   per-type parameters for fix adapt and fix ncf/shrink
------------------------------------------------------------------------- */

void *BondNCFChain::extract(const char *str, int &dim)
{
  dim = 1;
  if (strcmp(str, "ea") == 0) return ea.data();
  if (strcmp(str, "shrink") == 0) return shrink.data();
  if (strcmp(str, "compression") == 0) return compression.data();
  return nullptr;
}

/* ---------------------------------------------------------------------- */

int BondNCFChain::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  int **dtag = atom->iarray[idx_dtag];
  double **l0 = atom->darray[idx_l0];
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const int j = list[ii];
    for (int k = 0; k < NSLOT; k++) {
      buf[m++] = ubuf(dtag[j][k]).d;
      buf[m++] = l0[j][k];
    }
  }
  return m;
}

void BondNCFChain::unpack_forward_comm(int n, int first, double *buf)
{
  int **dtag = atom->iarray[idx_dtag];
  double **l0 = atom->darray[idx_l0];
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int k = 0; k < NSLOT; k++) {
      dtag[i][k] = (int) ubuf(buf[m++]).i;
      l0[i][k] = buf[m++];
    }
}

int BondNCFChain::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  if (comm_mode == COMM_STIFFNESS) {
    for (int i = first; i < first + n; i++) buf[m++] = ksum[i];
    return m;
  }
  int **dtag = atom->iarray[idx_dtag];
  double **l0 = atom->darray[idx_l0];
  for (int i = first; i < first + n; i++)
    for (int k = 0; k < NSLOT; k++) {
      buf[m++] = ubuf(dtag[i][k]).d;
      buf[m++] = l0[i][k];
    }
  return m;
}

void BondNCFChain::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  if (comm_mode == COMM_STIFFNESS) {
    for (int ii = 0; ii < n; ii++) ksum[list[ii]] += buf[m++];
    return;
  }
  for (int ii = 0; ii < n; ii++) {
    const int j = list[ii];
    for (int k = 0; k < NSLOT; k++) {
      const int d = (int) ubuf(buf[m++]).i;
      const double length = buf[m++];
      if (d != 0) store_slot(j, d, length);
    }
  }
}
