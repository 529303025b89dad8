/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/pbc: averaged periodic boundary conditions on chain end nodes (paper section 4.3,
   Eq. 2). Algebra in ncf_pbc.h; see doc/fix_ncf_pbc.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(ncf/pbc,FixNCFPBC);
// clang-format on
#else

#ifndef LMP_FIX_NCF_PBC_H
#define LMP_FIX_NCF_PBC_H

#include "fix.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixNCFPBC : public Fix {
 public:
  FixNCFPBC(class LAMMPS *, int, char **);
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
  double memory_usage() override;

 protected:
  // one end node of the constraint; the same list on every rank
  struct EndNode {
    tagint tag;
    int pair;          // 0: x faces, 1: y faces
    int group;         // global group index
    double weight;     // +1/n_upper or -1/n_lower within its group
    double xref[3];    // unwrapped position in the reference state
  };
  std::vector<EndNode> nodes;
  int ngroups;
  std::vector<int> group_pair;    // face pair of each group
  std::vector<double> sum_w2;     // per group: sum of w^2 (minimisation projection)
  std::vector<double> dref;       // per group: D_g = sum_i w_i X_i^ref (3 components)
  double href[6];                 // box h (xprd, yprd, zprd, yz, xz, xy) of the reference state
  double loref[3];                // box origin of the reference state
  // keyword normal: 1 hold (every end node keeps its reduced coordinate along its face normal,
  // the walls of the paper's section 4.3 together with Eq. 2), 0 free (Eq. 2 alone, the default)
  int normal_hold = 0;
  bool normal_given = false;
  std::vector<double> sref;            // per node: reduced coordinate along its face normal
  std::vector<double> rnode;           // per own node (order of mine): predicted hold residual
  double residual_node_local = 0.0;    // largest |hold residual| of this rank's nodes, last step
  std::string endface_name;            // per-atom integer with the face codes, or "" for auto
  std::string from_id;                 // keyword from: the fix ncf/pbc whose state this one takes
  int pair_on[2];                      // which face pairs are constrained
  int faces_auto;                      // 1: constrain the pairs that have end nodes
  int user_cells[2][2];                // user mesh per pair (0 = auto)
  int mesh_cells[2][2];                // mesh used
  int nmerged[2];                      // groups lost to merging, per pair
  double residual_max;                 // largest |constraint| before the last correction (length)

  std::vector<double> work, sums, lambda;    // per-step buffers
  // the end nodes this rank owns: (index into nodes, local atom index), in the order of nodes;
  // found again at every neighbour list build (atoms change ranks and places only then) and
  // whenever the node list changes (mine_ncalls -1), so that a step costs O(own end nodes)
  std::vector<std::pair<int, int>> mine;
  bigint mine_ncalls = -1;
  int mine_nlocal = -1;
  void find_mine();
  // the multipliers of the last step of a run and its number: the setup of the next run at that
  // step applies them again, rather than ones predicted from the full-step velocities that
  // LAMMPS has then (the steps have the half-step ones), so that a run cut into pieces (or
  // through a restart file) is the same run
  std::vector<double> lambda_last;
  bigint lambda_step;
  // the same for the per-node multipliers of the hold (indexed as nodes), gathered on the last
  // step of a run and on restart-writing steps only (the setup may find the nodes on other ranks)
  std::vector<double> node_lambda, node_lambda_last;
  bigint node_lambda_step = -1;
  // defined in a tilted box: no reference captured; an error at init unless a restart file
  // restored one (a restart written after a shear by fix deform)
  bool tilted_at_definition = false;

  void parse(int, char **);
  void capture_reference();
  std::vector<double> gather_end_nodes();
  void group_face_pair(int p, const std::vector<double> &all, const std::vector<int> &order);
  void take_state_of(const std::string &other_id);
  void finish_groups();
  double hold_residual(const EndNode &e, const double *xu, const double *lo, const double *prd,
                       double a) const;
  void check_fix_order();
};

}    // namespace LAMMPS_NS

#endif
#endif
