/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/contact/history (see fix_ncf_contact_history.h, doc/fix_ncf_contact_history.md)
------------------------------------------------------------------------- */

#include "fix_ncf_contact_history.h"

#include "error.h"
#include "force.h"
#include "modify.h"
#include "output.h"
#include "pair_ncf_contact.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;

/* ----------------------------------------------------------------------
   fix ID group ncf/contact/history   (no arguments; created by pair_style ncf/contact)
------------------------------------------------------------------------- */

FixNCFContactHistory::FixNCFContactHistory(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg != 3)
    error->all(FLERR,
               "fix ncf/contact/history takes no arguments (got {}); pair_style ncf/contact "
               "creates it",
               narg - 3);
}

int FixNCFContactHistory::setmask()
{
  return PRE_EXCHANGE | MIN_PRE_EXCHANGE | END_OF_STEP;
}

PairNCFContact *FixNCFContactHistory::pair() const
{
  return dynamic_cast<PairNCFContact *>(force->pair_match("ncf/contact", 1));
}

void FixNCFContactHistory::init()
{
  PairNCFContact *p = pair();
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
  if (PairNCFContact *p = pair()) p->sync_history();
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
