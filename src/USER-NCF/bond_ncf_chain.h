/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   bond_style ncf/chain: digital-chain rod element (axial force only) with a per-bond reference
   length L0 and a per-type shrink factor. Physics in ncf_rod.h; see doc/bond_ncf_chain.md.
------------------------------------------------------------------------- */

#ifdef BOND_CLASS
// clang-format off
BondStyle(ncf/chain,BondNCFChain);
// clang-format on
#else

#ifndef LMP_BOND_NCF_CHAIN_H
#define LMP_BOND_NCF_CHAIN_H

#include "bond.h"
#include "ncf_rod.h"

#include <vector>

namespace LAMMPS_NS {

class BondNCFChain : public Bond {
 public:
  // ID of the fix property/atom that holds the per-bond reference lengths (and the name of its
  // section in data files)
  static constexpr const char *STORE_ID = "NCF_CHAIN_L0";

  BondNCFChain(class LAMMPS *);
  ~BondNCFChain() override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  void compute(int, int) override;
  double equilibrium_distance(int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  void write_data(FILE *) override;
  double single(int, double, int, int, double &) override;
  void *extract(const char *, int &) override;

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;

  // reference length of the bond between local or ghost atoms i and j; 0 if none is stored
  double reference_length(int i, int j) const;
  // critical time step estimated at the last setup (0 before the first run)
  double critical_timestep() const { return dt_critical; }

 protected:
  enum DtCheck { DT_ERROR, DT_WARN, DT_NONE };
  enum CommMode { COMM_SLOTS, COMM_STIFFNESS };

  // per bond type, index 0 unused; separate arrays so that extract() can hand them to fix adapt
  std::vector<double> ea, shrink, compression;
  std::vector<double> maxl0;    // per bond type: largest L0 known at init
  int dtcheck;
  bool capture_pending;
  double dt_critical;
  int comm_mode;
  std::vector<double> ksum;    // per atom: sum of attached bond stiffnesses (time-step estimate)

  int idx_dtag, idx_l0;                     // indices of the custom per-atom arrays of the store
  std::vector<double> l0_list;              // reference length per entry of LAMMPS's bond list
  std::vector<NCF::RodStiffness> k_list;    // its stiffness (with l0_list)
  bigint l0_ncalls;                         // neighbor->ncalls when l0_list was filled (-1: refill)

  void allocate();
  void create_store();
  void find_store();
  void store_slot(int i, int dtag, double l0);
  void capture_missing();
  void update_maxl0();
  NCF::RodParams rod(int type) const { return {ea[type], shrink[type], compression[type]}; }
  void estimate_critical_timestep();
  void check_coefficients();
  void check_bonds();
  int count_owned_slots() const;
};

}    // namespace LAMMPS_NS

#endif
#endif
