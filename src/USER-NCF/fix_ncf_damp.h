/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/damp: viscous damping F = -gamma v, as fix viscous, whose drag at the setup of a run
   is the one of the step before it (kept per atom, also in restart files): a run cut in two, or
   restarted, goes on as the uncut run; see doc/fix_ncf_damp.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(ncf/damp,FixNCFDamp);
// clang-format on
#else

#ifndef LMP_FIX_NCF_DAMP_H
#define LMP_FIX_NCF_DAMP_H

#include "fix.h"

#include <string>

namespace LAMMPS_NS {

class FixNCFDamp : public Fix {
 public:
  FixNCFDamp(class LAMMPS *, int, char **);
  ~FixNCFDamp() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void post_force(int) override;
  double compute_scalar() override;
  int modify_param(int, char **) override;

  double memory_usage() override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;

 protected:
  double gamma;    // drag coefficient [force/velocity]
  // per atom: the velocity the drag of the last step was computed with and that step (a step
  // number as a double, exact below 2^53; -1: none yet)
  static constexpr int NKEEP = 4;
  double **kept;

  void drag(int i, const double *vel);
  double read_gamma(const std::string &what, const char *text);
};

}    // namespace LAMMPS_NS

#endif
#endif
