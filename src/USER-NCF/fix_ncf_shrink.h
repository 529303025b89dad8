/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/shrink: ramps the shrink factor of a bond type of bond_style ncf/chain smoothly to a
   target (the paper's negative thermal load on the stitching yarn); see doc/fix_ncf_shrink.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(ncf/shrink,FixNCFShrink);
// clang-format on
#else

#ifndef LMP_FIX_NCF_SHRINK_H
#define LMP_FIX_NCF_SHRINK_H

#include "fix.h"

namespace LAMMPS_NS {

class FixNCFShrink : public Fix {
 public:
  FixNCFShrink(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void setup_pre_force(int) override;
  void pre_force(int) override;
  void min_pre_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;

  // shrink factor at progress tau in [0, 1] (smooth: zero rate at both ends for 'cosine')
  static double ramp(int shape, double tau);
  enum Shape { LINEAR, COSINE };
  int bond_type() const { return btype; }

 protected:
  int btype;        // bond type
  double target;    // final shrink factor
  double start;     // shrink factor when the ramp starts
  bigint step0;     // first step of the ramp
  bigint nsteps;    // length of the ramp in steps
  int shape;
  double *shrink;    // the bond style's per-type array
  double current;

  void apply();
};

}    // namespace LAMMPS_NS

#endif
#endif
