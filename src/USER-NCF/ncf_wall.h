/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free contact of a chain node with a rigid plane (plates). Node-based contact is exact
   for a plane: the node carries the chain radius and the half-lengths of its elements. The
   tangential part is NCF::friction_step of ncf_contact.h, the same law as between segments.
   No LAMMPS dependency.
------------------------------------------------------------------------- */

#ifndef NCF_WALL_H
#define NCF_WALL_H

#include <cmath>

namespace NCF {

// Plane z = zplane with outward normal +z (side = +1, a lower plate pushing up) or -z
// (side = -1, an upper plate pushing down). A node at height z with chain radius r penetrates by
//   g = r - side (z - zplane)    (> 0 in contact)
// and carries the normal force  F = kn l g - c l v_n  (never pulling: F >= 0), kn [Pa] and
// c [Pa s] per unit chain length, l the node's tributary length (half of each adjacent element),
// v_n the node's approach speed along the normal relative to the plate. Energy kn l g^2 / 2.
struct WallResult {
  bool contact = false;
  double penetration = 0.0;    // g [m]
  double force = 0.0;          // normal force on the node along the plate's normal [N], >= 0
  double energy = 0.0;         // elastic energy [J]
};

inline WallResult plane_contact(double z, double radius, double zplane, int side, double kn,
                                double length, double damp, double vn_rel)
{
  WallResult out;
  const double g = radius - side * (z - zplane);
  if (!(g > 0.0)) return out;
  out.contact = true;
  out.penetration = g;
  const double elastic = kn * length * g;
  // vn_rel: node velocity minus plate velocity, along z; approach = moving against the normal
  double f = elastic - damp * length * side * vn_rel;
  out.force = f > 0.0 ? f : 0.0;
  out.energy = 0.5 * elastic * g;
  return out;
}

// Openings in a plate (the needle plate's holes under the needles): round holes of radius R
// centred at (cx[k], cy[k]), the plane periodic with lengths lx, ly where these are > 0 (0: not
// periodic). A node at horizontal distance rho from the nearest centre meets the plate with the
// weight
//   w = 0 for rho <= R,   w = s^2 (3 - 2 s), s = (rho - R) / rim, for R < rho < R + rim,   1 beyond,
// a rim rounded over `rim` (the node's chain radius): the contact's energy is w E, its normal
// force w F, and the weight adds the in-plane force -E grad w, toward the hole, so that the force
// stays -dE/dx. The rims of two holes must not overlap (holes_overlap), so that the nearest hole
// alone sets w.
struct HoleWeight {
  double w = 1.0;               // weight of the plate contact
  double gx = 0.0, gy = 0.0;    // its gradient in the plane [1/m]
};

inline HoleWeight hole_weight(double x, double y, const double *cx, const double *cy, int n,
                              double radius, double rim, double lx, double ly)
{
  HoleWeight out;
  if (n == 0) return out;
  double best = 1e300, bx = 0.0, by = 0.0;
  for (int k = 0; k < n; k++) {
    double dx = x - cx[k], dy = y - cy[k];
    if (lx > 0.0) dx -= lx * std::round(dx / lx);
    if (ly > 0.0) dy -= ly * std::round(dy / ly);
    const double d2 = dx * dx + dy * dy;
    if (d2 < best) {
      best = d2;
      bx = dx;
      by = dy;
    }
  }
  const double rho = std::sqrt(best);
  if (rho >= radius + rim) return out;
  if (rho <= radius) {
    out.w = 0.0;
    return out;
  }
  const double s = (rho - radius) / rim;
  out.w = s * s * (3.0 - 2.0 * s);
  const double dw = 6.0 * s * (1.0 - s) / rim;    // dw/drho
  out.gx = dw * bx / rho;
  out.gy = dw * by / rho;
  return out;
}

// true if two of the holes (with their rims) overlap, also through the periodic images, or a
// hole overlaps its own image (a box narrower than the hole and its rim)
inline bool holes_overlap(const double *cx, const double *cy, int n, double radius, double rim,
                          double lx, double ly)
{
  const double reach = 2.0 * (radius + rim);
  if ((lx > 0.0 && lx < reach) || (ly > 0.0 && ly < reach)) return n > 0;
  for (int a = 0; a < n; a++)
    for (int b = a + 1; b < n; b++) {
      double dx = cx[a] - cx[b], dy = cy[a] - cy[b];
      if (lx > 0.0) dx -= lx * std::round(dx / lx);
      if (ly > 0.0) dy -= ly * std::round(dy / ly);
      if (dx * dx + dy * dy < reach * reach) return true;
    }
  return false;
}

}    // namespace NCF

#endif
