/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   One piece of the node caps' integral (see node_contact in ncf_contact.h), shared by the
   scalar node_contact and the batched node_contact_batch. Internal to ncf_contact.cpp and
   ncf_cap_batch.cpp; no LAMMPS dependency.
------------------------------------------------------------------------- */

#ifndef NCF_CAP_INTEGRAL_PIECE_H
#define NCF_CAP_INTEGRAL_PIECE_H

namespace NCF {

// the radial profile of the node's sphere: D^2, 1/(2D), 1/D; the core's D_c^2 and 1/(2 D_c);
// kh = kappa/2, kd = kappa/D_c (kappa 0: no core)
struct CapProfile {
  double d2, inv2d, invd, c2, inv2c, kh, kd;
};

// the moments of one piece, summed over its Gauss points: alpha (1, xi, xi^2), eps, and
// om ddp / 2 (1, xi) (node_contact's comments)
struct CapPiece {
  double al, ax, axx, ep, bt, bx;
};

// The interval [a, b] of A's parameter xi, on which the deficit is dm + dsl (xi - mid) (dm at the
// middle of the interval): its positive part (the interval split at the zero where the deficit
// changes sign; nothing where the deficit is not positive at the middle of that part) integrated
// with the 4-point Gauss rule. |x - n|^2 = rc2 + la2 (xi - xc)^2 along A. Without branches, so
// that it vectorises over intervals (node_contact) or over caps (node_contact_batch), and
// always inlined, so that every version of those (target_clones) compiles it for its own
// instruction set.
inline __attribute__((always_inline)) CapPiece cap_piece(double a, double b, double dm, double dsl,
                                                         double xc, double rc2, double la2,
                                                         const CapProfile &p)
{
  constexpr double GX0 = 0.8611363115940526, GX1 = 0.3399810435848563;
  constexpr double GW0 = 0.3478548451374538, GW1 = 0.6521451548625461;
  const double hf = 0.5 * (b - a), mf = 0.5 * (b + a);
  const double fa = dm - dsl * hf, fb = dm + dsl * hf;
  const double xz = mf - dm / (dsl != 0.0 ? dsl : 1.0);
  const double xa = xz > a ? xz : a;
  const double x = xa < b ? xa : b;
  const double pa = ((fa < 0.0) & (fb > 0.0)) ? x : a, pb = ((fa > 0.0) & (fb < 0.0)) ? x : b;
  const double half = 0.5 * (pb - pa), mid = 0.5 * (pb + pa);
  const double defmid = dm + dsl * (mid - mf);
  const double hw = ((half > 0.0) & (defmid > 0.0)) ? half : 0.0;    // om = hw gw
  CapPiece s = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  auto point = [&](double y, double w) __attribute__((always_inline))
  {
    const double xi = mid + y, t = xi - xc;
    const double r2 = rc2 + la2 * (t * t);
    // energy density hh of the node's sphere (with the core; its term vanishes by itself outside
    // the core, whose boundary is a break point) and hd = -2 d(hh)/d(r^2)
    const double h0 = (p.d2 - r2) * p.inv2d, hc0 = (p.c2 - r2) * p.inv2c;
    const double h = h0 > 0.0 ? h0 : 0.0, hc = hc0 > 0.0 ? hc0 : 0.0;
    const double hh = 0.5 * h * h + p.kh * hc * hc;
    const double hd = h * p.invd + p.kd * hc;
    // the deficit enters squared, so that the energy is smooth (C1) where a chain passes through
    // straight (the deficit grows like the kink angle)
    const double df0 = defmid + dsl * y;
    const double def = df0 > 0.0 ? df0 : 0.0;
    const double od = (hw * w) * def, odd = od * def;
    const double al = odd * hd, bt = od * hh;    // alpha; om ddp / 2
    const double ax = al * xi;
    s.al += al;
    s.ax += ax;
    s.axx += ax * xi;
    s.ep += odd * hh;
    s.bt += bt;
    s.bx += bt * xi;
  };
  point(-half * GX0, GW0);
  point(-half * GX1, GW1);
  point(half * GX1, GW1);
  point(half * GX0, GW0);
  return s;
}

}    // namespace NCF

#endif
