/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/plate: rigid plane plates (lower and/or upper) with prescribed motion, penalty contact
   and Coulomb friction on chain nodes. Contact law in ncf_wall.h and ncf_contact.h;
   see doc/fix_ncf_plate.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(ncf/plate,FixNCFPlate);
// clang-format on
#else

#ifndef LMP_FIX_NCF_PLATE_H
#define LMP_FIX_NCF_PLATE_H

#include "fix.h"

#include "lammps_ncf_clock.h"
#include "ncf_contact_model.h"
#include "ncf_motion.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixNCFPlate : public Fix {
 public:
  FixNCFPlate(class LAMMPS *, int, char **);
  ~FixNCFPlate() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void min_setup(int) override;
  void post_force(int) override;
  void min_post_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  int image(int *&, double **&) override;

  double memory_usage() override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;

 protected:
  struct Plate {
    NCF::Motion motion;    // prescribed motion (ncf_motion.h)
    std::string var;       // VARIABLE: equal-style variable name
    int ivar = -1;
    double z = 0.0, vz = 0.0;    // current position and velocity
  };
  Plate plate[2];                  // 0: lower (normal +z), 1: upper (normal -z)
  NCF::ContactCoeffs cc;           // the plates' contact with the chains (ncf_contact_model.h)
  std::vector<double> diameter;    // per atom type, 0 = none (given, or pair ncf/contact's)
  NCF_LMP::ToolClock clock;        // time of the motion since the fix definition
  double zprev[2];                 // VARIABLE: previous position for the plate velocity

  double **slip;    // per atom: slip vectors against the lower (0..2) and upper (3..5) plate
  int use_history;

  double totals[2][5];    // per plate: Fz on the fabric, Fx, Fy, contacts, max penetration
  double energy;          // elastic energy of all plate contacts
  double dt_contact;      // critical time step of the stiffest node contact (setup)
  int idx_l0;

  std::vector<int> imgtype;
  std::vector<double> imgbuf;
  std::vector<double *> imgrows;

  void parse(int, char **);
  void update_plates();
  void apply();
  double tributary_length(int i) const;
  void check_nodes();
};

}    // namespace LAMMPS_NS

#endif
#endif
