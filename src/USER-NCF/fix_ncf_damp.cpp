/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/damp (see fix_ncf_damp.h, doc/fix_ncf_damp.md)
------------------------------------------------------------------------- */

#include "fix_ncf_damp.h"

#include "atom.h"
#include "error.h"
#include "memory.h"
#include "update.h"

#include "lammps_ncf_args.h"

#include <mpi.h>

#include <cstring>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ----------------------------------------------------------------------
   fix ID group ncf/damp gamma
------------------------------------------------------------------------- */

FixNCFDamp::FixNCFDamp(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), gamma(0.0), kept(nullptr)
{
  if (narg != 4) {
    std::string words;
    for (int k = 3; k < narg; k++) words += (k > 3 ? " " : "") + std::string(arg[k]);
    error->all(FLERR,
               "fix ncf/damp: expected 'fix ID group ncf/damp gamma', got {} argument(s) after "
               "the style{}{}",
               narg - 3, narg > 3 ? ": " + words : std::string(),
               narg > 4 ? " (one gamma for the group: fix viscous's scale keyword is not taken)"
                        : "");
  }
  gamma = read_gamma("fix ncf/damp", arg[3]);

  scalar_flag = 1;
  global_freq = 1;
  extscalar = 1;
  energy_global_flag = 0;
  dynamic_group_allow = 1;
  create_attribute = 1;

  restart_peratom = 1;
  FixNCFDamp::grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nmax; i++) FixNCFDamp::set_arrays(i);
}

FixNCFDamp::~FixNCFDamp()
{
  if (copymode) return;
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(kept);
}

int FixNCFDamp::setmask()
{
  return POST_FORCE;
}

void FixNCFDamp::init()
{
  if (!utils::strmatch(update->integrate_style, "^verlet"))
    error->all(FLERR, "fix ncf/damp: run_style {} is not supported (verlet only)",
               update->integrate_style);
}

/* ----------------------------------------------------------------------
   the drag of the setup: that of the step the atom's drag was last computed on when that is the
   current step (a run continued, or read from a restart file written at its end), the full-step
   velocity's otherwise (an atom new to the fix, the first run)
------------------------------------------------------------------------- */

void FixNCFDamp::setup(int /*vflag*/)
{
  double **v = atom->v;
  int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const double step = (double) update->ntimestep;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    if (kept[i][3] == step)
      drag(i, kept[i]);
    else
      drag(i, v[i]);
  }
}

void FixNCFDamp::post_force(int /*vflag*/)
{
  double **v = atom->v;
  int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) drag(i, v[i]);
}

// F = -gamma vel on atom i, and vel kept as the velocity of this step's drag (vel may be kept[i])
void FixNCFDamp::drag(int i, const double *vel)
{
  double **f = atom->f;
  const double u[3] = {vel[0], vel[1], vel[2]};
  for (int d = 0; d < 3; d++) {
    f[i][d] -= gamma * u[d];
    kept[i][d] = u[d];
  }
  kept[i][3] = (double) update->ntimestep;
}

/* ----------------------------------------------------------------------
   fix_modify ID gamma G: another drag coefficient, the kept velocities kept
------------------------------------------------------------------------- */

int FixNCFDamp::modify_param(int narg, char **arg)
{
  if (strcmp(arg[0], "gamma") != 0) return 0;
  if (narg < 2) error->all(FLERR, "fix_modify {} (ncf/damp): keyword 'gamma' needs a value", id);
  gamma = read_gamma("fix_modify " + std::string(id) + " (ncf/damp)", arg[1]);
  return 2;
}

// a drag coefficient: a finite number > 0 (`what` names the command in the messages)
double FixNCFDamp::read_gamma(const std::string &what, const char *text)
{
  const double g = NCF_LMP::number(lmp, what, "gamma", text);
  if (!(g > 0.0)) error->all(FLERR, "{}: gamma {} must be > 0 (force/velocity units)", what, text);
  return g;
}

/* ----------------------------------------------------------------------
   the power of the drag on the group at the last step it was applied (<= 0)
------------------------------------------------------------------------- */

double FixNCFDamp::compute_scalar()
{
  int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  double p = 0.0;
  for (int i = 0; i < nlocal; i++)
    if ((mask[i] & groupbit) && kept[i][3] >= 0.0)
      p -= gamma * (kept[i][0] * kept[i][0] + kept[i][1] * kept[i][1] + kept[i][2] * kept[i][2]);
  double all = 0.0;
  MPI_Allreduce(&p, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return all;
}

/* ----------------------------------------------------------------------
   per-atom state
------------------------------------------------------------------------- */

double FixNCFDamp::memory_usage()
{
  return (double) atom->nmax * NKEEP * sizeof(double);
}

void FixNCFDamp::grow_arrays(int nmax)
{
  memory->grow(kept, nmax, NKEEP, "ncf/damp:kept");
}

void FixNCFDamp::set_arrays(int i)
{
  kept[i][0] = kept[i][1] = kept[i][2] = 0.0;
  kept[i][3] = -1.0;
}

void FixNCFDamp::copy_arrays(int i, int j, int /*delflag*/)
{
  for (int d = 0; d < NKEEP; d++) kept[j][d] = kept[i][d];
}

int FixNCFDamp::pack_exchange(int i, double *buf)
{
  for (int d = 0; d < NKEEP; d++) buf[d] = kept[i][d];
  return NKEEP;
}

int FixNCFDamp::unpack_exchange(int nlocal, double *buf)
{
  for (int d = 0; d < NKEEP; d++) kept[nlocal][d] = buf[d];
  return NKEEP;
}

int FixNCFDamp::pack_restart(int i, double *buf)
{
  buf[0] = NKEEP + 1;
  for (int d = 0; d < NKEEP; d++) buf[d + 1] = kept[i][d];
  return NKEEP + 1;
}

void FixNCFDamp::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  for (int d = 0; d < NKEEP; d++) kept[nlocal][d] = extra[nlocal][m++];
}

int FixNCFDamp::size_restart(int /*nlocal*/)
{
  return NKEEP + 1;
}

int FixNCFDamp::maxsize_restart()
{
  return NKEEP + 1;
}
