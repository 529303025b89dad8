/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/contact/history: created by pair_style ncf/contact (not by hand). The pair keeps the
   friction history of its contacts with its pair list; this fix is the per-atom store of that
   history that LAMMPS migrates, sorts and writes to restart files: one row per node, the number
   of its contacts and 6 values per contact, in as many slots as the node with the most contacts
   needs (the width grows on all ranks together, never shrinks). The pair writes the rows only
   when the store is about to be used: before atoms migrate (pre_exchange), at the end of a step
   that writes a restart file (end_of_step) and at the end of a run. See
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

// What the store asks of the pair style whose history it holds (pair ncf/contact implements it):
// the store knows this interface only, not the pair
class NCFContactHistoryOwner {
 public:
  // any contact with friction: the history is kept and stored
  virtual bool friction_active() const = 0;
  // write the friction history of the last step into the rows of the store
  virtual void sync_history() = 0;

 protected:
  // (not deleted through this interface: the pair style is LAMMPS's to delete)
  ~NCFContactHistoryOwner() = default;
};

class FixNCFContactHistory : public Fix {
 public:
  // the ID under which pair_style ncf/contact creates it
  static constexpr const char *ID = "NCF_CONTACT_HISTORY";
  // values per contact slot: key of A's partner node, of B (2 tags), slip vector (3)
  static constexpr int SLOT = 6;

  FixNCFContactHistory(class LAMMPS *, int, char **);
  ~FixNCFContactHistory() override;
  int setmask() override;
  void init() override;
  void pre_exchange() override;
  void min_pre_exchange() override;
  void end_of_step() override;
  void post_run() override;

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  double memory_usage() override;
  void *extract(const char *, int &) override;

  // the rows (local and ghost atoms): row[0] the number of contacts n, then n slots of SLOT
  // values; nullptr while no slot exists (no friction)
  double **rows() const { return hist; }
  int slots() const { return nslots; }
  int row_width() const { return 1 + SLOT * nslots; }
  // at least n slots on this rank (keeps the rows); not collective
  void widen(int n);
  // at least n slots, and as many as the widest rank has (collective)
  void agree(int n);
  // row i set to `row` (its number of contacts first), widened if needed; not collective
  void set_row(int i, const double *row);

 private:
  double **hist;
  int nslots;    // slots per row
  int nmax;      // rows allocated
  int grows;     // number of widenings (extract "grows", for tests and the log)
  // the pair style ncf/contact that owns the store (nullptr if there is none now)
  NCFContactHistoryOwner *owner() const;
};

}    // namespace LAMMPS_NS

#endif
#endif
