/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/settle (see fix_ncf_settle.h, doc/fix_ncf_settle.md)
------------------------------------------------------------------------- */

#include "fix_ncf_settle.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "input.h"
#include "modify.h"
#include "output.h"
#include "timer.h"
#include "update.h"
#include "variable.h"

#include "lammps_ncf_args.h"
#include "ncf_input_error.h"

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
const char STYLE[] = "fix ncf/settle";
const int DEFAULT_WINDOW = 5;
}    // namespace

/* ----------------------------------------------------------------------
   fix ID group ncf/settle N criterion ... [window W] [active yes|no]
     criterion: ke v_REF TOL | fmax F | steady v_X TOL
------------------------------------------------------------------------- */

FixNCFSettle::FixNCFSettle(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), settle(DEFAULT_WINDOW), every(1), active(true), stopped(false),
    run_start(0), run_end(0), settled_at(-1)
{
  if (narg < 4) error->all(FLERR, "{}: needs the check interval N and a criterion", STYLE);
  // (end_of_step every step: Modify keeps each fix's interval from init, and the step after a
  // check that settled is the run's last one; the checks are every N)
  every = (int) NCF_LMP::integer(lmp, STYLE, "N", arg[3], 1, 1000000000);
  nevery = 1;
  parse(narg, arg);
  vector_flag = 1;
  size_vector = 2 + settle.size();
  global_freq = 1;
  extvector = 0;
}

void FixNCFSettle::parse(int narg, char **arg)
{
  struct Pending {
    NCF::Settle::Kind kind;
    Source source;
    std::string var, name;
    double tol;
  };
  std::vector<Pending> crit;
  int window = DEFAULT_WINDOW;
  NCF_LMP::KeywordsOnce once(lmp, STYLE, {"steady"});
  // v_NAME of keyword `key`: the variable's name (checked to exist and be equal-style in init)
  auto variable = [&](const std::string &key, const char *text) {
    const std::string t = text;
    if (t.rfind("v_", 0) != 0 || t.size() < 3)
      error->all(FLERR, "{}: {} '{}' is not a variable v_NAME", STYLE, key, t);
    return t.substr(2);
  };
  int iarg = 4;
  while (iarg < narg) {
    const std::string key = arg[iarg];
    once(key);
    if (key == "ke" || key == "steady") {
      const char *what = key == "ke" ? "a reference energy v_REF and a tolerance"
                                     : "a variable v_X and a tolerance";
      NCF_LMP::need_values(lmp, STYLE, key, iarg, narg, 2, what);
      const std::string var = variable(key, arg[iarg + 1]);
      const double tol = NCF_LMP::number(lmp, STYLE, key, arg[iarg + 2]);
      if (!(tol >= 0.0)) error->all(FLERR, "{}: {} tolerance {} must be >= 0", STYLE, key, tol);
      if (key == "ke")
        crit.push_back({NCF::Settle::KE_RATIO, KE_OVER, var, "KE / max v_" + var, tol});
      else
        crit.push_back({NCF::Settle::STEADY, VARIABLE, var, "v_" + var, tol});
      iarg += 3;
    } else if (key == "fmax") {
      NCF_LMP::need_values(lmp, STYLE, key, iarg, narg, 1);
      const double f = NCF_LMP::number(lmp, STYLE, key, arg[iarg + 1]);
      if (!(f > 0.0)) error->all(FLERR, "{}: fmax {} must be > 0", STYLE, arg[iarg + 1]);
      crit.push_back({NCF::Settle::AT_MOST, FMAX, "", "fmax", f});
      iarg += 2;
    } else if (key == "window") {
      NCF_LMP::need_values(lmp, STYLE, key, iarg, narg, 1);
      window = (int) NCF_LMP::integer(lmp, STYLE, key, arg[iarg + 1], 1, 1000000);
      iarg += 2;
    } else if (key == "active") {
      NCF_LMP::need_values(lmp, STYLE, key, iarg, narg, 1);
      active = NCF_LMP::logical(lmp, STYLE, key, arg[iarg + 1]);
      iarg += 2;
    } else
      error->all(FLERR, "{}: unknown keyword '{}'", STYLE, key);
  }
  if (crit.empty()) error->all(FLERR, "{}: give at least one criterion (ke, fmax, steady)", STYLE);
  try {
    settle = NCF::Settle(window);
    for (const auto &c : crit) {
      settle.add(c.kind, c.name, c.tol);
      Input in;
      in.source = c.source;
      in.var = c.var;
      inputs.push_back(in);
    }
  } catch (NCF::InputError &e) {
    error->all(FLERR, "{}: {}", STYLE, e.what());
  }
}

int FixNCFSettle::setmask()
{
  return END_OF_STEP | POST_RUN;
}

void FixNCFSettle::init()
{
  for (auto &in : inputs) {
    if (in.source == FMAX) continue;
    in.ivar = input->variable->find(in.var.c_str());
    if (in.ivar < 0) error->all(FLERR, "{}: variable '{}' does not exist", STYLE, in.var);
    if (!input->variable->equalstyle(in.ivar))
      error->all(FLERR, "{}: variable '{}' is not equal-style", STYLE, in.var);
  }
}

// a new run: its own checks, its cap the run's length
void FixNCFSettle::setup(int)
{
  new_run();
}

void FixNCFSettle::new_run()
{
  settle.reset();
  stopped = false;
  settled_at = -1;
  run_start = update->firststep;
  run_end = update->laststep;
  // (the variables may invoke computes: ask for them on the next check step)
  modify->addstep_compute_all(next_check());
}

bigint FixNCFSettle::next_check() const
{
  return (update->ntimestep / every) * every + every;
}

double FixNCFSettle::kinetic_energy() const
{
  double **v = atom->v;
  const int *mask = atom->mask;
  const int *type = atom->type;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  double ke = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double m = rmass ? rmass[i] : mass[type[i]];
    ke += m * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
  }
  double all = 0.0;
  MPI_Allreduce(&ke, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return 0.5 * force->mvv2e * all;
}

double FixNCFSettle::largest_force() const
{
  double **f = atom->f;
  const int *mask = atom->mask;
  double f2 = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & groupbit)
      f2 = std::fmax(f2, f[i][0] * f[i][0] + f[i][1] * f[i][1] + f[i][2] * f[i][2]);
  double all = 0.0;
  MPI_Allreduce(&f2, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  return std::sqrt(all);
}

void FixNCFSettle::end_of_step()
{
  const bigint step = update->ntimestep;
  // (a run that continues with `pre no` calls no setup: a new first step tells; its checks start
  // at the next check step, for which the computes are asked now)
  if (update->firststep != run_start || (settled_at < 0 && update->laststep != run_end)) {
    new_run();
    return;
  }
  // the step after it settled is the run's last one (see below): stop here
  if (settled_at >= 0 && !stopped) {
    stopped = true;
    timer->force_timeout();
    return;
  }
  if (!active || settled_at >= 0 || step % every) return;

  modify->clearstep_compute();
  // (value, reference) per criterion, as one array that rank 0 sends: every rank decides alike
  std::vector<double> values(2 * inputs.size(), 0.0);
  const double ke = kinetic_energy();
  for (size_t k = 0; k < inputs.size(); k++) {
    const Input &in = inputs[k];
    if (in.source == FMAX)
      values[2 * k] = largest_force();
    else if (in.source == KE_OVER) {
      values[2 * k] = ke;
      values[2 * k + 1] = input->variable->compute_equal(in.ivar);
    } else
      values[2 * k] = input->variable->compute_equal(in.ivar);
  }
  modify->addstep_compute(next_check());
  MPI_Bcast(values.data(), (int) values.size(), MPI_DOUBLE, 0, world);
  std::vector<NCF::Settle::Sample> samples(inputs.size());
  for (size_t k = 0; k < inputs.size(); k++) samples[k] = {values[2 * k], values[2 * k + 1]};
  if (!settle.check(samples)) return;
  settled_at = step;
  if (step >= run_end) {
    if (comm->me == 0)
      utils::logmesg(lmp, "{} {}: quasi-static at the run's last step {}: {}\n", STYLE, id, step,
                     settle.report());
    return;
  }

  // Settled. The next step becomes the run's last: the styles that do something on a run's last
  // step (the per-node contact force of pair ncf/contact, the multipliers fix ncf/pbc keeps for
  // the next run) and the thermo output see it as such; this fix ends the run after it.
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "{} {}: quasi-static at step {}, {} steps into the run of {} (its cap): {}; "
                   "the run ends at step {}\n",
                   STYLE, id, step, step - run_start, run_end - run_start, settle.report(),
                   step + 1);
  update->laststep = step + 1;
  output->reset_timestep(step + 1);
  // (the thermo output of that step needs the energies tallied there)
  modify->addstep_compute_all(step + 1);
}

void FixNCFSettle::post_run()
{
  if (stopped) timer->reset_timeout();
  if (settled_at < 0 && active && run_end > run_start && comm->me == 0)
    error->warning(FLERR, "{} {}: not quasi-static at the end of the run (its cap of {} steps): {}",
                   STYLE, id, run_end - run_start, settle.report());
}

// fix_modify ID active yes|no: check in the runs or not (a stage's motions and its holds in
// one sequence of runs)
int FixNCFSettle::modify_param(int narg, char **arg)
{
  if (std::string(arg[0]) != "active") return 0;
  NCF_LMP::need_values(lmp, "fix_modify ncf/settle", "active", 0, narg, 1);
  active = NCF_LMP::logical(lmp, "fix_modify ncf/settle", "active", arg[1]);
  settle.reset();
  // (the computes of the first check: asked for now, as the run may start with `pre no`)
  if (active) modify->addstep_compute_all(next_check());
  return 2;
}

/* ----------------------------------------------------------------------
   1: 1 if the last (or current) run settled, 2: the steps that run took (ended after it settled,
   or so far), 3..: each criterion's measure at the last check (ratio, value or change)
------------------------------------------------------------------------- */

double FixNCFSettle::compute_vector(int n)
{
  if (n == 0) return settled_at >= 0 ? 1.0 : 0.0;
  if (n == 1)
    return (double) (std::min(settled_at >= 0 ? settled_at + 1 : update->ntimestep, run_end) -
                     run_start);
  return settle.measure(n - 2);
}
