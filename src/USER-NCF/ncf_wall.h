/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free contact of a chain node with a rigid plane (plates). Node-based contact is exact
   for a plane: the node carries the chain radius and the half-lengths of its elements. The
   tangential part is NCF::friction_step of ncf_contact.h, the same law as between segments.
   No LAMMPS dependency.
------------------------------------------------------------------------- */

#ifndef NCF_WALL_H
#define NCF_WALL_H

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

}    // namespace NCF

#endif
