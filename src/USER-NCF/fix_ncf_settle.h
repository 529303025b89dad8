/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/settle: ends a run (a hold, a relaxation) when its quasi-static criterion holds; the
   run's length is the cap. The criterion is NCF::Settle (ncf_settle.h); see
   doc/fix_ncf_settle.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(ncf/settle,FixNCFSettle);
// clang-format on
#else

#ifndef LMP_FIX_NCF_SETTLE_H
#define LMP_FIX_NCF_SETTLE_H

#include "fix.h"

#include "ncf_settle.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixNCFSettle : public Fix {
 public:
  FixNCFSettle(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void setup(int) override;
  void end_of_step() override;
  void post_run() override;
  int modify_param(int, char **) override;
  double compute_vector(int) override;

 protected:
  // what a criterion measures: the group's kinetic energy over an energy variable, the largest
  // force on a node of the group, or an equal-style variable
  enum Source { KE_OVER, FMAX, VARIABLE };
  struct Input {
    Source source = FMAX;
    std::string var;    // the variable's name (KE_OVER: the reference energy; VARIABLE)
    int ivar = -1;
  };
  std::vector<Input> inputs;    // one per criterion of `settle`, in its order
  NCF::Settle settle;
  int every;            // the check interval N
  bool active;          // checking in the runs (fix_modify ID active yes|no)
  bool stopped;         // this fix ended the current run
  bigint run_start;     // first step of the current run
  bigint run_end;       // the step the current run would end at (its cap)
  bigint settled_at;    // the step it settled at in the last run, -1 when it did not

  void parse(int narg, char **arg);
  void new_run();
  bigint next_check() const;    // the first check step after this one
  double kinetic_energy() const;
  double largest_force() const;
};

}    // namespace LAMMPS_NS

#endif
#endif
