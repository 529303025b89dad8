/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: the clock of a tool's prescribed motion (fix ncf/plate, fix ncf/needles). Inline,
   LAMMPS-side (the *_lammps.h helpers are included by styles only).

   The time of the motion since the fix was defined, the same bits however a run is cut into
   pieces. LAMMPS's own time (atime + (step - atimestep) dt) is summed anew at the end of every
   run, so `run 3` + `run 4` can give a time one bit off that of `run 7`, and a tool another
   height. The clock counts steps from a base of its own instead, t = base + (step - step_base)
   dt, and rebases on LAMMPS's time only where the two differ by more than round-off
   (reset_timestep) or the time step changed.
------------------------------------------------------------------------- */

#ifndef LAMMPS_NCF_CLOCK_H
#define LAMMPS_NCF_CLOCK_H

#include "lmptype.h"
#include "update.h"

#include <cmath>

namespace NCF_LMP {

class ToolClock {
 public:
  // the fix is defined now
  void start(const LAMMPS_NS::Update *u)
  {
    t0 = lammps_time(u);
    base = 0.0;
    step_base = u->ntimestep;
    dt = u->dt;
  }
  // the time since the definition at the current step
  double time(const LAMMPS_NS::Update *u)
  {
    const double tl = lammps_time(u) - t0;
    const double t = base + (double) (u->ntimestep - step_base) * u->dt;
    if (u->dt == dt && std::fabs(t - tl) <= 1e-9 * (std::fabs(tl) + u->dt)) return t;
    base = tl;
    step_base = u->ntimestep;
    dt = u->dt;
    return tl;
  }
  // restart files: NPACK numbers
  static constexpr int NPACK = 4;
  void pack(double *buf) const
  {
    buf[0] = t0;
    buf[1] = base;
    buf[2] = (double) step_base;
    buf[3] = dt;
  }
  void unpack(const double *buf)
  {
    t0 = buf[0];
    base = buf[1];
    step_base = (LAMMPS_NS::bigint) buf[2];
    dt = buf[3];
  }
  // a restart file written before the clock existed holds the time origin only
  void resume_from_origin(const LAMMPS_NS::Update *u, double origin)
  {
    t0 = origin;
    base = lammps_time(u) - t0;
    step_base = u->ntimestep;
    dt = u->dt;
  }
  // first number of the restart data of a fix that holds a clock (where a restart file written
  // before held the bare time origin, a time that is never this)
  static constexpr double MARK = -1.0e300;

 private:
  double t0 = 0.0;      // LAMMPS time at the definition
  double base = 0.0;    // time of the motion at step_base
  LAMMPS_NS::bigint step_base = 0;
  double dt = 0.0;    // time step since step_base
  static double lammps_time(const LAMMPS_NS::Update *u)
  {
    return u->atime + (double) (u->ntimestep - u->atimestep) * u->dt;
  }
};

}    // namespace NCF_LMP

#endif
