/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free kernel of the digital-chain rod (truss) element.
   No LAMMPS dependency: shared by bond_style ncf/chain and the unit tests.
------------------------------------------------------------------------- */

#ifndef NCF_ROD_H
#define NCF_ROD_H

#include <cmath>
#include <cstdint>
#include <cstring>

namespace NCF {

// Axial rod (truss) element between two nodes: force along the axis only, no bending.
//
//   rest length     Lr = L0 (1 - s)          s: shrink factor (pretension, thermal load)
//   stiffness       k  = EA / L0             (per unit extension)
//   axial force     N  = k (r - Lr)          tension positive
//   energy          E  = k (r - Lr)^2 / 2
//
// In compression (r < Lr) the force and energy are multiplied by `compression`, in [0, 1]:
// 1 (default) is the linear truss of the paper (Abaqus T3D2), 0 a tension-only element.
struct RodParams {
  double ea = 0.0;             // axial rigidity E*A of the chain (force units)
  double shrink = 0.0;         // shrink factor s, 0 <= s < 1
  double compression = 1.0;    // compression stiffness ratio, 0 <= c <= 1
};

struct RodResult {
  double axial = 0.0;     // axial force N (tension > 0)
  double fpair = 0.0;     // LAMMPS convention: force on node 1 = fpair * (x1 - x2)
  double energy = 0.0;    // stored elastic energy
};

// The stiffness of an element of reference length l0: k = EA / L0 in tension, k * compression
// in compression (fixed between changes of the coefficients, so a caller may keep it per element)
struct RodStiffness {
  double k = 0.0, kc = 0.0;
};
inline RodStiffness rod_stiffness(const RodParams &p, double l0)
{
  const double k = p.ea / l0;
  return {k, k * p.compression};
}

// a if c, else b, without a branch (whether an element is stretched or compressed is
// unpredictable from one to the next)
inline double select_bits(bool c, double a, double b)
{
  std::uint64_t ia, ib;
  std::memcpy(&ia, &a, sizeof ia);
  std::memcpy(&ib, &b, sizeof ib);
  const std::uint64_t m = std::uint64_t(0) - std::uint64_t(c);
  const std::uint64_t ir = (ia & m) | (ib & ~m);
  double out;
  std::memcpy(&out, &ir, sizeof out);
  return out;
}

// s: stiffness (rod_stiffness), lrest: rest length L0 (1 - s), r: current node distance (> 0 for
// a defined direction).
inline RodResult rod_force(const RodStiffness &s, double lrest, double r)
{
  RodResult out;
  const double dr = r - lrest;
  const double kk = select_bits(dr < 0.0, s.kc, s.k);
  out.axial = kk * dr;
  out.energy = 0.5 * kk * dr * dr;
  // the direction is undefined at r = 0: no force, the energy stays defined
  out.fpair = (r > 0.0) ? -out.axial / r : 0.0;
  return out;
}

// r: current node distance (> 0 for a defined direction), l0: reference length (> 0).
inline RodResult rod_force(const RodParams &p, double l0, double r)
{
  return rod_force(rod_stiffness(p, l0), l0 * (1.0 - p.shrink), r);
}

// Critical (CFL) time step of an explicit central-difference integration for one element with
// lumped masses (half the element mass on each node): dt_c = L0 * sqrt(rho / E) = L0 / c.
inline double rod_critical_dt(double l0, double ea, double mass_per_length)
{
  return l0 * std::sqrt(mass_per_length / ea);
}

}    // namespace NCF

#endif
