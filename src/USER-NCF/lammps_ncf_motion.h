/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: parsing of a tool motion (ncf_motion.h) from style arguments, shared by
   fix ncf/plate and fix ncf/needles. Inline, LAMMPS-side (the *_lammps.h helpers are included by
   styles only; ncf_*.cpp stay free of LAMMPS).

     z Z | move Z0 V | target Z0 ZT V | v_NAME
------------------------------------------------------------------------- */

#ifndef LAMMPS_NCF_MOTION_H
#define LAMMPS_NCF_MOTION_H

#include "error.h"
#include "input.h"
#include "lammps.h"
#include "utils.h"
#include "variable.h"

#include "ncf_motion.h"

#include <cmath>
#include <cstdlib>
#include <string>

namespace NCF_LMP {

// Parses the motion starting at arg[iarg] (its kind word); returns the index after it. `what`
// names the tool in messages (e.g. "fix ncf/plate: 'upper"), allow_fixed permits "z Z".
// For v_NAME the variable name goes to `var` and must be an existing equal-style variable.
inline int parse_motion(LAMMPS_NS::LAMMPS *lmp, const std::string &what, int iarg, int narg,
                        char **arg, NCF::Motion &m, std::string &var, bool allow_fixed)
{
  auto *error = lmp->error;
  if (iarg >= narg)
    error->all(FLERR, "{}' needs a motion: {}move Z0 V, target Z0 ZT V or v_NAME", what,
               allow_fixed ? "z Z, " : "");
  const std::string kind = arg[iarg];
  auto number = [&](int k) {
    if (iarg + k >= narg) error->all(FLERR, "{} {}' needs more values", what, kind);
    if (!LAMMPS_NS::utils::is_double(arg[iarg + k]))
      error->all(FLERR, "{} {}': value '{}' is not a number", what, kind, arg[iarg + k]);
    if (!std::isfinite(std::strtod(arg[iarg + k], nullptr)))
      error->all(FLERR, "{} {}': value '{}' is not a finite number", what, kind, arg[iarg + k]);
    return LAMMPS_NS::utils::numeric(FLERR, arg[iarg + k], false, lmp);
  };
  if (kind == "z" && allow_fixed) {
    m.kind = NCF::Motion::FIXED;
    m.z0 = number(1);
    return iarg + 2;
  }
  if (kind == "move") {
    m.kind = NCF::Motion::MOVE;
    m.z0 = number(1);
    m.speed = number(2);
    return iarg + 3;
  }
  if (kind == "target") {
    m.kind = NCF::Motion::TARGET;
    m.z0 = number(1);
    m.ztarget = number(2);
    m.speed = std::fabs(number(3));
    if (m.speed == 0.0) error->all(FLERR, "{} target' needs a speed > 0", what);
    return iarg + 4;
  }
  if (LAMMPS_NS::utils::strmatch(kind, "^v_")) {
    m.kind = NCF::Motion::VARIABLE;
    var = kind.substr(2);
    const int ivar = lmp->input->variable->find(var.c_str());
    if (ivar < 0) error->all(FLERR, "{}': variable '{}' does not exist", what, var);
    if (!lmp->input->variable->equalstyle(ivar))
      error->all(FLERR, "{}': variable '{}' is not equal-style", what, var);
    return iarg + 1;
  }
  error->all(FLERR, "{}': unknown motion '{}' ({}move, target, v_NAME)", what, kind,
             allow_fixed ? "z, " : "");
  return narg;
}

}    // namespace NCF_LMP

#endif
