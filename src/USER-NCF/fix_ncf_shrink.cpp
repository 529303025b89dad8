/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/shrink (see fix_ncf_shrink.h, doc/fix_ncf_shrink.md)
------------------------------------------------------------------------- */

#include "fix_ncf_shrink.h"

#include "atom.h"
#include "bond.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "update.h"

#include "lammps_ncf_args.h"

#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ----------------------------------------------------------------------
   fix ID group ncf/shrink btype T strain S steps N [ramp cosine|linear]
   fix ID group ncf/shrink btype T thermal ALPHA DT steps N [ramp cosine|linear]
------------------------------------------------------------------------- */

FixNCFShrink::FixNCFShrink(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), btype(0), target(-1.0), start(0.0), step0(0), nsteps(0), shape(COSINE),
    shrink(nullptr), current(0.0)
{
  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 2;
  global_freq = 1;
  extscalar = extvector = 0;
  restart_global = 1;

  int iarg = 3;
  auto need = [&](int n, const std::string &key) {
    NCF_LMP::need_values(lmp, "fix ncf/shrink", key, iarg, narg, n);
  };
  auto number = [&](int k, const std::string &key) {
    return NCF_LMP::number(lmp, "fix ncf/shrink", key, arg[iarg + k]);
  };
  NCF_LMP::KeywordsOnce once(lmp, "fix ncf/shrink");
  while (iarg < narg) {
    const std::string key = arg[iarg];
    once(key, key == "strain" || key == "thermal" ? "load" : "");
    if (key == "btype") {
      need(1, key);
      const long long b =
          utils::is_integer(arg[iarg + 1]) ? utils::bnumeric(FLERR, arg[iarg + 1], false, lmp) : 0;
      if (b < 1 || b > atom->nbondtypes)
        error->all(FLERR, "fix ncf/shrink: btype {} is not a bond type (1-{})", arg[iarg + 1],
                   atom->nbondtypes);
      btype = (int) b;
      iarg += 2;
    } else if (key == "strain") {
      need(1, key);
      target = number(1, key);
      if (!(target >= 0.0 && target < 1.0))
        error->all(FLERR, "fix ncf/shrink: strain {} must be in [0, 1)", arg[iarg + 1]);
      iarg += 2;
    } else if (key == "thermal") {
      need(2, key);
      const double alpha = number(1, key);
      const double dT = number(2, key);
      // a thermal strain alpha dT < 0 shortens the rest length: shrink = -alpha dT
      target = -alpha * dT;
      if (!(target >= 0.0 && target < 1.0))
        error->all(FLERR,
                   "fix ncf/shrink: thermal load alpha {} x dT {} gives a shrink {} outside "
                   "[0, 1) (a negative thermal strain alpha dT < 0 shrinks the yarn)",
                   alpha, dT, target);
      iarg += 3;
    } else if (key == "steps") {
      need(1, key);
      if (!utils::is_integer(arg[iarg + 1]))
        error->all(FLERR, "fix ncf/shrink: steps '{}' is not an integer", arg[iarg + 1]);
      nsteps = NCF_LMP::integer(lmp, "fix ncf/shrink", key, arg[iarg + 1], LLONG_MIN, MAXBIGINT);
      if (nsteps < 1) error->all(FLERR, "fix ncf/shrink: steps {} must be >= 1", nsteps);
      iarg += 2;
    } else if (key == "ramp") {
      need(1, key);
      const std::string v = arg[iarg + 1];
      if (v == "cosine")
        shape = COSINE;
      else if (v == "linear")
        shape = LINEAR;
      else
        error->all(FLERR, "fix ncf/shrink: ramp '{}' is not one of cosine, linear", v);
      iarg += 2;
    } else
      error->all(FLERR, "fix ncf/shrink: unknown keyword '{}'", key);
  }
  if (btype == 0) error->all(FLERR, "fix ncf/shrink: keyword 'btype' is required");
  if (target < 0.0)
    error->all(FLERR, "fix ncf/shrink: give the target with 'strain S' or 'thermal ALPHA DT'");
  if (nsteps == 0) error->all(FLERR, "fix ncf/shrink: keyword 'steps' is required");

  if (!force->bond || !utils::strmatch(force->bond_style, "^ncf/chain"))
    error->all(FLERR, "fix ncf/shrink needs bond_style ncf/chain");
  int dim;
  shrink = static_cast<double *>(force->bond->extract("shrink", dim));
  start = shrink[btype];
  step0 = update->ntimestep;
  current = start;
}

int FixNCFShrink::setmask()
{
  return PRE_FORCE | MIN_PRE_FORCE;
}

void FixNCFShrink::init()
{
  // the bond style may have been redefined (restart, new bond_style): fetch the array again
  if (!force->bond || !utils::strmatch(force->bond_style, "^ncf/chain"))
    error->all(FLERR, "fix ncf/shrink needs bond_style ncf/chain");
  int dim;
  shrink = static_cast<double *>(force->bond->extract("shrink", dim));
  // two ramps on one bond type would overwrite each other's shrink factor at every step
  for (auto *f : modify->get_fix_by_style("^ncf/shrink")) {
    if (f == this) break;
    auto *other = dynamic_cast<FixNCFShrink *>(f);
    if (other && other->bond_type() == btype)
      error->all(FLERR,
                 "fix ncf/shrink: fixes {} and {} both ramp the shrink factor of bond type {}; "
                 "one fix per bond type",
                 f->id, id, btype);
  }
}

double FixNCFShrink::ramp(int shape, double tau)
{
  if (tau <= 0.0) return 0.0;
  if (tau >= 1.0) return 1.0;
  return shape == COSINE ? 0.5 * (1.0 - cos(M_PI * tau)) : tau;
}

void FixNCFShrink::apply()
{
  const double tau = (double) (update->ntimestep - step0) / (double) nsteps;
  current = start + (target - start) * ramp(shape, tau);
  shrink[btype] = current;
}

void FixNCFShrink::setup_pre_force(int)
{
  apply();
}
void FixNCFShrink::pre_force(int)
{
  apply();
}
void FixNCFShrink::min_pre_force(int)
{
  apply();
}

double FixNCFShrink::compute_scalar()
{
  return current;
}

double FixNCFShrink::compute_vector(int n)
{
  if (n == 0) return current;
  const double tau = (double) (update->ntimestep - step0) / (double) nsteps;
  return tau < 0.0 ? 0.0 : (tau > 1.0 ? 1.0 : tau);
}

/* ----------------------------------------------------------------------
   restart: the ramp continues where it was (start value, first step)
------------------------------------------------------------------------- */

void FixNCFShrink::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  double buf[6] = {(double) btype, target, start, (double) step0, (double) nsteps, (double) shape};
  int size = sizeof(buf);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(buf, sizeof(double), 6, fp);
}

void FixNCFShrink::restart(char *raw)
{
  auto *buf = (double *) raw;
  if ((int) buf[0] != btype || buf[1] != target || (bigint) buf[4] != nsteps ||
      (int) buf[5] != shape) {
    if (comm->me == 0)
      error->warning(FLERR,
                     "fix ncf/shrink: defined differently from the restart file: the ramp "
                     "starts anew from the current shrink factor");
    return;
  }
  start = buf[2];
  step0 = (bigint) buf[3];
}
