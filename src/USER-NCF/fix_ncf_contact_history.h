/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/contact/history: created by pair_style ncf/contact (not by hand). The pair keeps the
   friction history of its contacts with its pair list and writes it into the per-atom store
   that LAMMPS migrates, sorts and writes to restart files only when that store is about to be
   used: before atoms migrate (pre_exchange), at the end of a step that writes a restart file
   (end_of_step) and at the end of a run. See
   doc/fix_ncf_contact_history.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(ncf/contact/history,FixNCFContactHistory);
// clang-format on
#else

#ifndef LMP_FIX_NCF_CONTACT_HISTORY_H
#define LMP_FIX_NCF_CONTACT_HISTORY_H

#include "fix.h"

namespace LAMMPS_NS {

class FixNCFContactHistory : public Fix {
 public:
  // the ID under which pair_style ncf/contact creates it
  static constexpr const char *ID = "NCF_CONTACT_HISTORY";

  FixNCFContactHistory(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void pre_exchange() override;
  void min_pre_exchange() override;
  void end_of_step() override;
  void post_run() override;

 private:
  class PairNCFContact *pair() const;
};

}    // namespace LAMMPS_NS

#endif
#endif
