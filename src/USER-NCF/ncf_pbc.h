/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free algebra of the averaged periodic boundary conditions (paper section 4.3, Eq. 2):
   the boundary mesh on a pair of opposite faces, the merging of empty cells, and the Lagrange
   multiplier that makes the averaged constraint exact. No LAMMPS dependency.
------------------------------------------------------------------------- */

#ifndef NCF_PBC_H
#define NCF_PBC_H

#include <vector>

namespace NCF {

// One chain end node on one of two opposite faces, in the face's own coordinates:
// u along the face's periodic in-plane direction, v along its non-periodic one (thickness).
struct FaceNode {
  int side = 0;    // -1: lower face (xlo or ylo), +1: upper face (xhi or yhi)
  double u = 0.0, v = 0.0;
};

// Regular mesh on a face: nu x nv cells over [u0, u0 + lu) (periodic) x [vlo, vhi].
struct FaceMesh {
  int nu = 1, nv = 1;
  double lu = 1.0, u0 = 0.0, vlo = 0.0, vhi = 1.0;
  int cell_of(double u, double v) const;    // u wrapped into the period, v clamped to [vlo, vhi]
  double cell_u(int cell) const;            // cell centre
  double cell_v(int cell) const;
};

// Mesh sized so that on average one end node per face lies in a cell (paper section 4.3).
// If the lower face's nodes form a regular lattice (a mat without orientation variability), the
// mesh is that lattice, cells centred on its points, so that the constraint pairs each end node
// with its periodic image and reduces to ordinary periodicity. Otherwise cells are as square as
// the face allows over the nodes' thickness range. lu: period of the face along u.
FaceMesh auto_face_mesh(const std::vector<FaceNode> &nodes, double lu);

// Groups of the averaged constraint: start with one group per cell (the same cell index on both
// faces, so the two meshes stay periodic); every group lacking a node on either face is merged
// into the nearest group (cell-centre distance, periodic in u; ties to the lower index) until
// every group has nodes on both faces. Returns the group index (0..ngroups-1, in order of first
// cell) of every node. Deterministic: same input, same groups, on every rank.
// Throws NCF::InputError (ncf_input_error.h) if one face has no node at all.
std::vector<int> face_groups(const FaceMesh &mesh, const std::vector<FaceNode> &nodes,
                             int &ngroups);

// Weight of a node in its group's constraint  sum_i w_i u_i = delta:  +1/n_plus on the upper
// face, -1/n_minus on the lower face (Eq. 2 applied to both reference points). The weights of a
// group sum to zero, so constraint forces w_i * lambda conserve momentum.
std::vector<double> face_weights(const std::vector<FaceNode> &nodes, const std::vector<int> &group,
                                 int ngroups);

// Multiplier that makes a linear constraint exact after one explicit step: the unconstrained
// predicted residual r = sum_i w_i x_i^pred - target is removed by forces F_i = w_i lambda, which
// move node i by w_i lambda dt^2 / m_i:  lambda = -r / (dt^2 sum_i w_i^2 / m_i).
inline double constraint_multiplier(double residual, double dt2_sum_w2_over_m)
{
  return -residual / dt2_sum_w2_over_m;
}

// Face-normal hold (fix ncf/pbc normal hold): every end node i of a group on the faces of pair p
// keeps its reduced coordinate along the face normal, the linear constraint
//     n . x_i = b_i,   n = e_p + a e_u,
// with e_u the face's in-plane periodic direction (a = -xy/ly on the x faces of a box tilted by
// xy, 0 otherwise), while the group's constraint along u, sum_j w_j x_j,u = T, still holds (the
// group's constraint along the normal follows from the node holds and is not imposed again).
// Forces F_i = lambda_i n + w_i mu e_u make both exact after one explicit step; the two couple
// only through a. With r_i = n . x_i^pred - b_i and R = sum_j w_j x_j,u^pred - T (the predicted
// residuals) and sum_w_r = sum_j w_j r_j:
//     mu       = -((1 + a^2) R - a sum_w_r) / (dt^2 sum_j w_j^2 / m_j)
//     lambda_i = -(r_i m_i / dt^2 + w_i mu a) / (1 + a^2)
// (with a = 0: the group multiplier above and lambda_i = -r_i m_i / dt^2, node by node).
// Minimisation projects forces with the same expressions at m = dt = 1, r_i = n . f_i, R = sum w f_u.
inline double held_group_multiplier(double residual, double sum_w_r, double a,
                                    double dt2_sum_w2_over_m)
{
  return -((1.0 + a * a) * residual - a * sum_w_r) / dt2_sum_w2_over_m;
}

inline double held_node_multiplier(double residual, double weight, double mu, double a,
                                   double m_over_dt2)
{
  return -(residual * m_over_dt2 + weight * mu * a) / (1.0 + a * a);
}

}    // namespace NCF

#endif
