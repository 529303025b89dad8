/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free contact of a chain segment (cylinder of radius r_c around a0-a1) with a rigid
   needle: a vertical body of revolution around the axis (x_n, y_n). No LAMMPS dependency; used by
   fix ncf/needles and unit-tested directly (tests/unit/test_needle.cpp).

   Needle profile. u = distance along the needle from its apex (u = -direction (z - z_apex)).
   The radius grows linearly from 0 at the apex to R at u = tip (the conical point), stays R along
   the shaft, and the far end at u = length is the mirror image of the point (so that no energy
   jumps where a chain leaves the needle's end):

     rho(u) = R phi(min(u, length - u) / tip),   phi(t) = t (t <= 1 - b), 1 (t >= 1 + b),
                                                  1 - (1 + b - t)^2 / (4 b) in between,

   b = NEEDLE_SHOULDER: the shoulder between point and shaft is rounded over +-b tip so that the
   axial force is continuous there. phi(t) = t also for t < 0, so rho < 0 below the apex.

   Contact. A point p of the chain's axis at horizontal distance r from the needle's axis
   penetrates by  g = rho(u(p)) + r_c - r  (the needle widened horizontally by r_c; below the
   apex this is a cone of the same angle whose apex lies r_c tip / R under the needle's). The
   penalty is monotonic in g and integrated along the segment,

     E = (k_n / 2) * integral over the segment of max(g, 0)^2 dl,

   discretised with NEEDLE_GAUSS Gauss-Legendre points on the part of the segment whose horizontal
   projection lies within rho_max + r_c of the foot of the axis on it (outside, g < 0; rho_max
   bounds the needle's radius over the segment's heights, so the points gather on the contact
   also where a narrow point meets the chain). The forces are
   the exact gradient of this discretised energy (forward-mode derivatives), so they are
   conservative. Per point, -dE/dp = k_n g (e_r - drho/dz e_z): along the outward normal of the
   needle's surface, radial in the plane plus the cone's axial part, of magnitude growing with g
   up to the axis itself. A point exactly on the axis has no radial direction; it takes the
   horizontal normal of the segment (sign fixed so that it does not depend on the order of a0,
   a1), or +x for a vertical segment. The energy depends only on positions relative to the needle,
   so the needle's force is -(f0 + f1) exactly.

   A straight chain that crosses the axis is pushed apart along its length (each node away from
   the axis) and, by the point, down; its net sideways force vanishes as it passes exactly through
   the axis (as for any body of revolution). Hinged chains leave that unstable position quickly.

   Units: k_n per unit contact length [Pa], as in pair_style ncf/contact: a chain parallel to the
   shaft at penetration g over a length l carries F = k_n g l.
------------------------------------------------------------------------- */

#ifndef NCF_NEEDLE_H
#define NCF_NEEDLE_H

#include "ncf_geometry.h"

namespace NCF {

constexpr double NEEDLE_SHOULDER = 0.1;    // half-width of the rounded shoulder / tip
constexpr int NEEDLE_GAUSS = 8;            // Gauss points per segment

struct Needle {
  double x = 0.0, y = 0.0;    // axis [m]
  double zapex = 0.0;         // height of the apex [m]
  int direction = -1;         // -1: point down, shaft above; +1: point up, shaft below
  double radius = 0.0;        // R, shaft radius [m] (> 0)
  double tip = 0.0;           // length of the conical point [m] (> 0)
  double length = 0.0;        // apex to far end [m], >= needle_min_length(tip)
};

// Shortest needle that still has a full shaft: both ends' shoulders fit.
inline double needle_min_length(double tip)
{
  return 2.0 * (1.0 + NEEDLE_SHOULDER) * tip;
}

// Radius of the needle at height z (negative beyond the ends), and d rho / dz.
double needle_radius(const Needle &n, double z, double *drho_dz = nullptr);

struct NeedleContact {
  bool active = false;         // some Gauss point penetrates (g > 0)
  double energy = 0.0;         // E [J]
  Vec3 f[2];                   // forces on a0, a1 [N] (= -dE/dx)
  Vec3 fneedle;                // force on the needle = -(f[0] + f[1]) [N]
  double penetration = 0.0;    // largest g at the Gauss points [m]
};

// Contact of the chain segment a0-a1 (radius rc > 0) with needle n, stiffness kn [Pa].
// Finite inputs give finite outputs (also on the axis and for a zero-length segment, which
// carries no contact).
NeedleContact needle_contact(const Vec3 &a0, const Vec3 &a1, double rc, const Needle &n, double kn);

}    // namespace NCF

#endif
