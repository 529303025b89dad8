/* ----------------------------------------------------------------------
   USER-NCF: engine-free contact of a chain segment with a rigid needle (see ncf_needle.h).
   The discretised energy is evaluated with forward-mode derivatives with respect to the six
   coordinates of a0 and a1, so the forces are its exact gradient, including the motion of the
   Gauss points with the clipped integration interval.
------------------------------------------------------------------------- */

#include "ncf_needle.h"

#include <cmath>

namespace NCF {

namespace {

  // value and derivatives with respect to (a0.x, a0.y, a0.z, a1.x, a1.y, a1.z)
  struct D {
    double v = 0.0;
    double d[6] = {0, 0, 0, 0, 0, 0};
  };

  D cst(double v)
  {
    D a;
    a.v = v;
    return a;
  }
  D var(double v, int k)
  {
    D a;
    a.v = v;
    a.d[k] = 1.0;
    return a;
  }
  D operator+(const D &a, const D &b)
  {
    D c;
    c.v = a.v + b.v;
    for (int k = 0; k < 6; k++) c.d[k] = a.d[k] + b.d[k];
    return c;
  }
  D operator-(const D &a, const D &b)
  {
    D c;
    c.v = a.v - b.v;
    for (int k = 0; k < 6; k++) c.d[k] = a.d[k] - b.d[k];
    return c;
  }
  D operator*(const D &a, const D &b)
  {
    D c;
    c.v = a.v * b.v;
    for (int k = 0; k < 6; k++) c.d[k] = a.d[k] * b.v + a.v * b.d[k];
    return c;
  }
  D operator*(double s, const D &a)
  {
    D c;
    c.v = s * a.v;
    for (int k = 0; k < 6; k++) c.d[k] = s * a.d[k];
    return c;
  }
  D operator/(const D &a, const D &b)
  {
    D c;
    c.v = a.v / b.v;
    for (int k = 0; k < 6; k++) c.d[k] = (a.d[k] - c.v * b.d[k]) / b.v;
    return c;
  }
  D dsqrt(const D &a)    // a.v > 0
  {
    D c;
    c.v = std::sqrt(a.v);
    for (int k = 0; k < 6; k++) c.d[k] = 0.5 * a.d[k] / c.v;
    return c;
  }
  // a function of one variable applied to a: value f, derivative df
  D chain(const D &a, double f, double df)
  {
    D c;
    c.v = f;
    for (int k = 0; k < 6; k++) c.d[k] = df * a.d[k];
    return c;
  }

  // profile of the point: phi(t) and phi'(t)
  double phi(double t, double &dphi)
  {
    const double b = NEEDLE_SHOULDER;
    if (t <= 1.0 - b) {
      dphi = 1.0;
      return t;
    }
    if (t >= 1.0 + b) {
      dphi = 0.0;
      return 1.0;
    }
    const double s = 1.0 + b - t;
    dphi = s / (2.0 * b);
    return 1.0 - s * s / (4.0 * b);
  }

  // radius at distance u from the apex along the needle, and d rho / du
  double profile(const Needle &n, double u, double &drho_du)
  {
    const bool lower = u <= n.length - u;
    const double m = lower ? u : n.length - u;
    double dphi;
    const double p = phi(m / n.tip, dphi);
    drho_du = (lower ? 1.0 : -1.0) * n.radius / n.tip * dphi;
    return n.radius * p;
  }

  // Gauss-Legendre, 8 points on [0, 1]
  const double GX[NEEDLE_GAUSS] = {
      0.5 * (1.0 - 0.9602898564975363), 0.5 * (1.0 - 0.7966664774136267),
      0.5 * (1.0 - 0.5255324099163290), 0.5 * (1.0 - 0.1834346424956498),
      0.5 * (1.0 + 0.1834346424956498), 0.5 * (1.0 + 0.5255324099163290),
      0.5 * (1.0 + 0.7966664774136267), 0.5 * (1.0 + 0.9602898564975363)};
  const double GW[NEEDLE_GAUSS] = {0.5 * 0.1012285362903763, 0.5 * 0.2223810344533745,
                                   0.5 * 0.3137066458778873, 0.5 * 0.3626837833783620,
                                   0.5 * 0.3626837833783620, 0.5 * 0.3137066458778873,
                                   0.5 * 0.2223810344533745, 0.5 * 0.1012285362903763};

}    // namespace

double needle_radius(const Needle &n, double z, double *drho_dz)
{
  double d;
  const double rho = profile(n, -n.direction * (z - n.zapex), d);
  if (drho_dz) *drho_dz = -n.direction * d;
  return rho;
}

NeedleContact needle_contact(const Vec3 &a0, const Vec3 &a1, double rc, const Needle &n, double kn)
{
  NeedleContact out;
  const double reach = n.radius + rc;    // largest horizontal distance with g > 0

  // cheap rejections: extent along the needle, then horizontal distance of the segment
  const double margin = rc * n.tip / n.radius;
  const double u0 = -n.direction * (a0.z - n.zapex), u1 = -n.direction * (a1.z - n.zapex);
  if (std::max(u0, u1) <= -margin || std::min(u0, u1) >= n.length + margin) return out;
  const double ex = a1.x - a0.x, ey = a1.y - a0.y;
  const double qx = n.x - a0.x, qy = n.y - a0.y;
  const double h2 = ex * ex + ey * ey;
  {
    double t = h2 > 0.0 ? (qx * ex + qy * ey) / h2 : 0.0;
    t = std::min(1.0, std::max(0.0, t));
    if (std::hypot(qx - t * ex, qy - t * ey) >= reach) return out;
  }

  const D A0[3] = {var(a0.x, 0), var(a0.y, 1), var(a0.z, 2)};
  const D A1[3] = {var(a1.x, 3), var(a1.y, 4), var(a1.z, 5)};
  const D E[3] = {A1[0] - A0[0], A1[1] - A0[1], A1[2] - A0[2]};
  const D L2 = E[0] * E[0] + E[1] * E[1] + E[2] * E[2];
  if (!(L2.v > 0.0)) return out;    // zero length: no contact
  const D L = dsqrt(L2);

  // the part of the segment whose horizontal projection lies within `c` of the foot of the axis
  // on its line: [t* - w, t* + w], w = c / |e_h|, clipped to [0, 1]; c = rho_max + rc bounds the
  // reach of the needle over the segment's heights, so that the Gauss points gather where the
  // contact is also under the point. rho_max: the profile at a smooth bound of the segment's
  // extent along the needle (u_mid +- sqrt(du^2 / 4 + eps^2)), R where it spans the middle.
  D t0 = cst(0.0), t1 = cst(1.0);
  const D H2 = E[0] * E[0] + E[1] * E[1];
  if (H2.v > 0.0) {
    const double eps = 0.05 * n.tip;
    const D U0 = -n.direction * (A0[2] - cst(n.zapex)), U1 = -n.direction * (A1[2] - cst(n.zapex));
    const D um = 0.5 * (U0 + U1), du = U1 - U0;
    const D S = dsqrt(0.25 * (du * du) + cst(eps * eps));
    const D uhi = um + S, ulo = um - S;
    D rmax = cst(n.radius);
    double drho;
    if (uhi.v <= 0.5 * n.length) {
      const double rho = profile(n, uhi.v, drho);
      rmax = chain(uhi, rho, drho);
    } else if (ulo.v >= 0.5 * n.length) {
      const double rho = profile(n, ulo.v, drho);
      rmax = chain(ulo, rho, drho);
    }
    const D c = rmax + cst(rc);
    if (!(c.v > 0.0)) return out;
    const D tf = ((cst(n.x) - A0[0]) * E[0] + (cst(n.y) - A0[1]) * E[1]) / H2;
    const D w = c / dsqrt(H2);
    const D lo = tf - w, hi = tf + w;
    if (lo.v > 0.0) t0 = lo;
    if (hi.v < 1.0) t1 = hi;
    if (!(t1.v > t0.v)) return out;
  }
  const D span = t1 - t0;

  // radial direction used for a point exactly on the axis: the horizontal normal of the segment
  // with a sign independent of the order of the nodes, +x for a vertical segment
  double axis_dir[2] = {1.0, 0.0};
  if (h2 > 0.0) {
    double tx = ex, ty = ey;
    if (tx < 0.0 || (tx == 0.0 && ty < 0.0)) tx = -tx, ty = -ty;
    const double th = std::hypot(tx, ty);
    axis_dir[0] = -ty / th;
    axis_dir[1] = tx / th;
  }

  D sum = cst(0.0);
  double gmax = 0.0;
  for (int i = 0; i < NEEDLE_GAUSS; i++) {
    const D t = t0 + GX[i] * span;
    const D px = A0[0] + t * E[0], py = A0[1] + t * E[1], pz = A0[2] + t * E[2];
    const D dx = px - cst(n.x), dy = py - cst(n.y);
    const double r = std::hypot(dx.v, dy.v);
    double cx, cy;    // d r / d(dx, dy)
    if (r > 0.0) {
      cx = dx.v / r;
      cy = dy.v / r;
    } else {
      cx = axis_dir[0];
      cy = axis_dir[1];
    }
    D R;
    R.v = r;
    for (int k = 0; k < 6; k++) R.d[k] = cx * dx.d[k] + cy * dy.d[k];
    const D u = -n.direction * (pz - cst(n.zapex));
    double drho;
    const double rho = profile(n, u.v, drho);
    const D g = chain(u, rho, drho) + cst(rc) - R;
    if (!(g.v > 0.0)) continue;
    gmax = std::max(gmax, g.v);
    sum = sum + GW[i] * (g * g);
  }
  if (!(gmax > 0.0)) return out;

  const D energy = (0.5 * kn) * (L * span * sum);
  out.active = true;
  out.energy = energy.v;
  out.penetration = gmax;
  out.f[0] = Vec3(-energy.d[0], -energy.d[1], -energy.d[2]);
  out.f[1] = Vec3(-energy.d[3], -energy.d[4], -energy.d[5]);
  out.fneedle = -(out.f[0] + out.f[1]);
  return out;
}

}    // namespace NCF
