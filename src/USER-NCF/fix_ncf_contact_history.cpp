/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/contact/history (see fix_ncf_contact_history.h, doc/fix_ncf_contact_history.md)
------------------------------------------------------------------------- */

#include "fix_ncf_contact_history.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "output.h"
#include "pair.h"
#include "update.h"

#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ----------------------------------------------------------------------
   fix ID group ncf/contact/history   (no arguments; created by pair_style ncf/contact)
------------------------------------------------------------------------- */

FixNCFContactHistory::FixNCFContactHistory(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), hist(nullptr), nslots(0), nmax(0), grows(0)
{
  if (narg != 3)
    error->all(FLERR,
               "fix ncf/contact/history takes no arguments (got {}); pair_style ncf/contact "
               "creates it",
               narg - 3);
  restart_global = 1;
  restart_peratom = 1;
  create_attribute = 1;
  maxexchange_dynamic = 1;
  maxexchange = 1;
  // no slots (and no memory) until the pair style asks for them (friction on)
  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
}

FixNCFContactHistory::~FixNCFContactHistory()
{
  if (copymode) return;
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(hist);
}

int FixNCFContactHistory::setmask()
{
  return PRE_EXCHANGE | MIN_PRE_EXCHANGE | END_OF_STEP;
}

NCFContactHistoryOwner *FixNCFContactHistory::owner() const
{
  return dynamic_cast<NCFContactHistoryOwner *>(force->pair_match("ncf/contact", 1));
}

void FixNCFContactHistory::init()
{
  NCFContactHistoryOwner *p = owner();
  if (!p || !p->friction_active()) return;
  // the history must be in the per-atom store before any fix moves atoms between ranks in its
  // own pre_exchange (as for LAMMPS's fix neigh/history)
  for (const auto &ifix : modify->get_fix_list()) {
    if (ifix == this) break;
    if (ifix->pre_exchange_migrate)
      error->all(FLERR,
                 "fix {} ({}) migrates atoms in pre_exchange before fix {} (created by pair_style "
                 "ncf/contact) has stored the friction history: define pair_style ncf/contact "
                 "(after the box exists) before fix {}",
                 ifix->id, ifix->style, id, ifix->id);
  }
}

void FixNCFContactHistory::pre_exchange()
{
  if (NCFContactHistoryOwner *p = owner()) p->sync_history();
}

void FixNCFContactHistory::min_pre_exchange()
{
  pre_exchange();
}

// a restart file written during a run (restart command) holds the history of its step, so that
// the run read from it continues the same run (end_of_step comes before LAMMPS's output)
void FixNCFContactHistory::end_of_step()
{
  if (update->ntimestep == output->next_restart) pre_exchange();
}

// also for write_restart, write_data and the next run's list build after this run
void FixNCFContactHistory::post_run()
{
  pre_exchange();
}

/* ----------------------------------------------------------------------
   the store: nmax rows of 1 + SLOT * nslots values
------------------------------------------------------------------------- */

void FixNCFContactHistory::widen(int n)
{
  if (n <= nslots) return;
  const int w_old = row_width(), w_new = 1 + SLOT * n;
  double **wider = nullptr;
  if (nmax > 0) {
    memory->create(wider, nmax, w_new, "ncf/contact/history:hist");
    for (int i = 0; i < nmax; i++) {
      // the used part of a row (rows never filled hold 0 contacts)
      const int len = hist ? 1 + SLOT * (int) hist[i][0] : 1;
      if (hist)
        memcpy(wider[i], hist[i], sizeof(double) * (len <= w_old ? len : 1));
      else
        wider[i][0] = 0.0;
    }
  }
  memory->destroy(hist);
  hist = wider;
  nslots = n;
  grows++;
  // the rows hold atom IDs (the keys of the contacts): reset_atoms id refuses to run
  stores_ids = 1;
  maxexchange = row_width();
}

void FixNCFContactHistory::agree(int n)
{
  int need = n > nslots ? n : nslots, all = need;
  MPI_Allreduce(&need, &all, 1, MPI_INT, MPI_MAX, world);
  widen(all);
}

void FixNCFContactHistory::set_row(int i, const double *row)
{
  const int n = (int) row[0];
  widen(n);
  if (hist) memcpy(hist[i], row, sizeof(double) * (1 + SLOT * n));
}

void FixNCFContactHistory::grow_arrays(int n)
{
  if (nslots > 0) {
    memory->grow(hist, n, row_width(), "ncf/contact/history:hist");
    for (int i = nmax; i < n; i++) hist[i][0] = 0.0;
  }
  nmax = n;
}

void FixNCFContactHistory::copy_arrays(int i, int j, int /*delflag*/)
{
  if (!hist) return;
  memcpy(hist[j], hist[i], sizeof(double) * (1 + SLOT * (int) hist[i][0]));
}

void FixNCFContactHistory::set_arrays(int i)
{
  if (hist) hist[i][0] = 0.0;
}

int FixNCFContactHistory::pack_exchange(int i, double *buf)
{
  if (!hist) {
    buf[0] = 0.0;
    return 1;
  }
  const int len = 1 + SLOT * (int) hist[i][0];
  memcpy(buf, hist[i], sizeof(double) * len);
  return len;
}

int FixNCFContactHistory::unpack_exchange(int nlocal, double *buf)
{
  const int n = (int) buf[0], len = 1 + SLOT * n;
  widen(n);    // (all ranks have the same width; kept safe all the same)
  if (hist) memcpy(hist[nlocal], buf, sizeof(double) * len);
  return len;
}

/* ----------------------------------------------------------------------
   restart: the width (global), and per atom the used part of its row
------------------------------------------------------------------------- */

void FixNCFContactHistory::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    double list[1] = {(double) nslots};
    int size = sizeof(list);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), 1, fp);
  }
}

void FixNCFContactHistory::restart(char *buf)
{
  double width;
  memcpy(&width, buf, sizeof(double));
  widen((int) width);
}

int FixNCFContactHistory::pack_restart(int i, double *buf)
{
  const int n = hist ? (int) hist[i][0] : 0;
  // buf[0]: the number of values of this fix, itself included (the convention of LAMMPS)
  buf[0] = 2 + SLOT * n;
  buf[1] = n;
  if (n) memcpy(buf + 2, hist[i] + 1, sizeof(double) * SLOT * n);
  return 2 + SLOT * n;
}

void FixNCFContactHistory::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += (int) extra[nlocal][m];
  const int n = (int) extra[nlocal][m + 1];
  widen(n);
  if (!hist) return;
  hist[nlocal][0] = n;
  memcpy(hist[nlocal] + 1, &extra[nlocal][m + 2], sizeof(double) * SLOT * n);
}

int FixNCFContactHistory::size_restart(int i)
{
  return 2 + SLOT * (hist ? (int) hist[i][0] : 0);
}

int FixNCFContactHistory::maxsize_restart()
{
  return 2 + SLOT * nslots;
}

double FixNCFContactHistory::memory_usage()
{
  return hist ? (double) nmax * row_width() * sizeof(double) : 0.0;
}

// "slots": slots per row (int, dim 0); "grows": how often the store was widened (int, dim 0);
// "rows": the rows (double **, dim 2; nullptr without slots)
void *FixNCFContactHistory::extract(const char *name, int &dim)
{
  dim = 0;
  if (strcmp(name, "slots") == 0) return &nslots;
  if (strcmp(name, "grows") == 0) return &grows;
  if (strcmp(name, "rows") == 0) {
    dim = 2;
    return hist;
  }
  return nullptr;
}
