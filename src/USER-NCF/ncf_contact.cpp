/* ----------------------------------------------------------------------
   USER-NCF: engine-free segment-segment contact law (see ncf_contact.h).
------------------------------------------------------------------------- */

#include "ncf_contact.h"

#include "ncf_cap_integral_piece.h"

#include <algorithm>
#include <cmath>

namespace NCF {

namespace {

  // interval [lo, hi] of xi where q(xi) = qa xi^2 + qb xi + qc' < 0 (qc' = qc - D^2 folded in);
  // false if empty. qa >= 0.
  bool negative_interval(double qa, double qb, double qc, double qa_tiny, double &lo, double &hi)
  {
    constexpr double BIG = 1e300;
    if (qa <= qa_tiny) {
      // (nearly) exactly parallel: linear or constant
      if (qb == 0.0) {
        if (qc < 0.0) {
          lo = -BIG;
          hi = BIG;
          return true;
        }
        return false;
      }
      const double root = -qc / qb;
      if (qb > 0.0) {
        lo = -BIG;
        hi = root;
      } else {
        lo = root;
        hi = BIG;
      }
      return true;
    }
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc <= 0.0) return false;
    const double sq = std::sqrt(disc);
    const double qq = -0.5 * (qb + (qb >= 0.0 ? sq : -sq));    // never 0 since disc > 0
    const double x1 = qq / qa, x2 = qc / qq;
    lo = std::min(x1, x2);
    hi = std::max(x1, x2);
    return true;
  }

  // The radial profile of the law with its optional core (ncf_contact.h): for a squared distance
  // r2 from the axis (or node), hh = h^2/2 + kappa h_c^2/2 and hd = -2 d(hh)/d(r2)
  // = h/D + kappa h_c/D_c, with h = (D^2 - r2)/(2D) > 0 and h_c = (D_c^2 - r2)/(2 D_c) > 0.
  struct Profile {
    double d2, inv2d, invd;         // D^2, 1/(2D), 1/D
    double c2, inv2c, invc, kap;    // the same for D_c; kappa (0: no core)
    // (one division: D_c = D / sqrt(3))
    Profile(double dc, double core) :
        d2(dc * dc), inv2d(0.5 / dc), invd(2.0 * inv2d), c2(CORE_FRACTION * CORE_FRACTION * d2),
        inv2c(SQRT3 * inv2d), invc(2.0 * inv2c), kap(core)
    {
    }
    // whether the point at squared distance r2 lies in the core (a piece of the integral lies
    // either inside or outside it: its break points include the core's boundary)
    bool in_core(double r2) const { return kap > 0.0 && r2 < c2; }
    // hh and hd at r2 (zero where r2 >= D^2; the core's term where incore)
    void at(double r2, bool incore, double &hh, double &hd) const
    {
      const double h = std::max(0.0, (d2 - r2) * inv2d);
      hh = 0.5 * h * h;
      hd = h * invd;
      if (incore) {
        const double hc = std::max(0.0, (c2 - r2) * inv2c);
        hh += 0.5 * kap * hc * hc;
        hd += kap * hc * invc;
      }
    }
    // the core's boundary (r2 = D_c^2) along a line with r2(xi) = qa xi^2 + qb xi + qc: its
    // crossings inside (lo, hi) appended to the break points
    void core_breaks(double qa, double qb, double qc, double tiny, double lo, double hi,
                     double *brk, int &nb) const
    {
      double clo, chi;
      if (!(kap > 0.0) || !negative_interval(qa, qb, qc - c2, tiny, clo, chi)) return;
      if (clo > lo && clo < hi) brk[nb++] = clo;
      if (chi > lo && chi < hi) brk[nb++] = chi;
    }
  };

  // The weight W = clamp(min(wa, wb), 0, 1) of a segment of length l at arc position s
  // (wa = 1/2 + s / 2e, wb = 1/2 + (l - s) / 2e) is one of four polynomials: its regime is
  // 0 zero, 1 the ramp at the first node (W = wa), 2 the ramp at the second (W = wb), 3 plateau
  inline int weight_regime(double s, double l, double inv2e)
  {
    const double wa = 0.5 + s * inv2e, wb = 0.5 + (l - s) * inv2e;
    const double w = std::min(wa, wb);
    return w >= 1.0 ? 3 : (w <= 0.0 ? 0 : (wa <= wb ? 1 : 2));
  }
  inline double weight_in(int reg, double s, double l, double inv2e)
  {
    return reg == 3 ? 1.0 : (reg == 0 ? 0.0 : (reg == 1 ? 0.5 + s * inv2e : 0.5 + (l - s) * inv2e));
  }

  // Break points of the piecewise polynomial integrands come as short lists that are each
  // already in order, so they are merged instead of sorted (a sort of random values mispredicts
  // most of its branches).
  //
  // the positions xi = (c_k - s0) / s1 where the arc position s(xi) = s0 + s1 xi along a line
  // takes the values c_0 <= c_1 <= ... (inv_s1 = 1 / s1, never 0), inside (lo, hi), appended to
  // out in increasing xi
  inline void line_breaks(const double *c, int n, double s0, double inv_s1, double lo, double hi,
                          double *out, int &nout)
  {
    for (int k = 0; k < n; k++) {
      const double x = (c[inv_s1 > 0.0 ? k : n - 1 - k] - s0) * inv_s1;
      if (x > lo && x < hi) out[nout++] = x;
    }
  }
  // merge of two increasing lists into out (after the nout values already there)
  inline void merge_breaks(const double *a, int na, const double *b, int nb, double *out, int &nout)
  {
    int i = 0, j = 0;
    while (i < na && j < nb) out[nout++] = a[i] <= b[j] ? a[i++] : b[j++];
    while (i < na) out[nout++] = a[i++];
    while (j < nb) out[nout++] = b[j++];
  }

}    // namespace

namespace {
  SegmentContact contact_of_segments(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1,
                                     double dc, double kn, double ramp, bool with_penetration,
                                     double core)
  {
    SegmentContact out;
    if (!(dc > 0.0) || !(ramp > 0.0)) return out;
    const Vec3 da = a1 - a0, u = b1 - b0;
    const double la2 = norm2(da), lb2 = norm2(u);
    const double lmin2 = MIN_LENGTH * MIN_LENGTH * dc * dc;
    if (!(la2 > lmin2) || !(lb2 > lmin2)) return out;

    // along A: t(xi) = t0 + t1 xi (position on B's line as a fraction of L_B), r(xi) = r0 + xi r1
    // (offset from it). The cheap rejections come first: no square root before A's line is
    // known to come within D of B's line inside A
    const double inv_lb2 = 1.0 / lb2;
    const Vec3 w0 = a0 - b0;
    const double t0 = dot(w0, u) * inv_lb2, t1 = dot(da, u) * inv_lb2;
    const Vec3 r0 = w0 - t0 * u, r1 = da - t1 * u;
    const double d2 = dc * dc;
    const double qa = norm2(r1), qb = 2.0 * dot(r0, r1), qc = norm2(r0);
    const double tiny = 1e-28 * la2;
    double lo, hi;
    if (!negative_interval(qa, qb, qc - d2, tiny, lo, hi)) return out;
    const double xvert = 0.5 * (lo + hi);    // the point of A's line closest to B's (qa > tiny)
    lo = std::max(lo, 0.0);
    hi = std::min(hi, 1.0);
    if (!(hi > lo)) return out;
    // arc position on B's line: s(xi) = s0 + s1 xi; where the weight W(s) is non-zero:
    // -e < s < lb + e
    const double inv_lb = std::sqrt(inv_lb2), lb = lb2 * inv_lb, la = std::sqrt(la2);
    const double s0 = t0 * lb, s1 = t1 * lb;
    const double e = ramp;
    const bool sloped = std::fabs(s1) > 1e-14 * la;
    const double inv_s1 = sloped ? 1.0 / s1 : 0.0;
    if (sloped) {
      double x1 = (-e - s0) * inv_s1, x2 = (lb + e - s0) * inv_s1;
      if (x1 > x2) std::swap(x1, x2);
      lo = std::max(lo, x1);
      hi = std::min(hi, x2);
    } else if (s0 <= -e || s0 >= lb + e) {
      return out;
    }
    if (!(hi > lo)) return out;

    // break points of the piecewise polynomial integrand: the kinks of W = clamp(min(wa, wb), 0, 1)
    // inside (lo, hi). W reaches 0 at s = -e and lb + e, which bound (lo, hi) already; it reaches 1
    // at s = e and lb - e; wa = wb at s = lb/2 is a kink only where W < 1 there (lb < 2e)
    double cbrk[3], kbrk[2];
    int ncb = 0, nkb = 0;
    if (sloped) {
      if (lb >= 2.0 * e) {
        const double corners[2] = {e, lb - e};
        line_breaks(corners, 2, s0, inv_s1, lo, hi, cbrk, ncb);
      } else {
        const double corners[3] = {lb - e, 0.5 * lb, e};
        line_breaks(corners, 3, s0, inv_s1, lo, hi, cbrk, ncb);
      }
    }
    // the core's boundary r = D_c is a break point as well
    const Profile prof(dc, core);
    prof.core_breaks(qa, qb, qc, tiny, lo, hi, kbrk, nkb);
    double brk[7];
    int nb = 0;
    brk[nb++] = lo;
    merge_breaks(cbrk, ncb, kbrk, nkb, brk, nb);
    brk[nb++] = hi;

    const double inv2e = 0.5 / e;

    // The integrand is linear in r(xi) = r0 + xi r1 and in the ramp gradients (constant or linear
    // in r), so the energy, the gradient, the normal resultant and its centroid follow from a few
    // scalar moments of the pieces (c = hd W, p = hh W, q = hh W' split by the active ramp, a at
    // B0 or b at B1):
    double C0 = 0.0, C1 = 0.0, C2 = 0.0;                  // integral of c, c xi, c xi^2
    double P0 = 0.0, L0 = 0.0;                            // integral of p; of W
    double QA0 = 0.0, QA1 = 0.0, QB0 = 0.0, QB1 = 0.0;    // integral of q, q xi per ramp

    // On a piece xi = mid + y, |y| <= hw, every factor is a polynomial in y: W = wm + wy y,
    // g = D^2 - r^2 = g0 + g1 y + g2 y^2, hd = A0 + A1 y + A2 y^2, hh = B0 + ... + B4 y^4 (with
    // the core's terms where the piece lies in the core). The moments are exact in closed form
    // from the even moments of y (the odd ones vanish); centred on the piece, they keep the
    // accuracy of evaluating g pointwise (no powers of xi that cancel).
    const double kd = prof.inv2d * prof.invd, bd = 0.5 * prof.inv2d * prof.inv2d;
    const double kc = prof.kap * prof.inv2c * prof.invc,
                 bc = 0.5 * prof.kap * prof.inv2c * prof.inv2c;
    for (int k = 0; k + 1 < nb; k++) {
      const double hw = 0.5 * (brk[k + 1] - brk[k]);
      if (!(hw > 0.0)) continue;
      const double mid = 0.5 * (brk[k + 1] + brk[k]);
      // W and the core are each one polynomial on the piece: their branch is taken at its middle
      const double sm = s0 + s1 * mid;
      const int wr = weight_regime(sm, lb, inv2e);
      if (wr == 0) continue;
      const double wm = weight_in(wr, sm, lb, inv2e);
      const double wy = wr == 1 ? s1 * inv2e : (wr == 2 ? -s1 * inv2e : 0.0);
      const double r2m = (qa * mid + qb) * mid + qc;
      const double g0 = prof.d2 - r2m, g1 = -(2.0 * qa * mid + qb), g2 = -qa;
      double A0 = kd * g0, A1 = kd * g1, A2 = kd * g2;
      double B0 = bd * g0 * g0, B1 = bd * 2.0 * g0 * g1, B2 = bd * (g1 * g1 + 2.0 * g0 * g2),
             B3 = bd * 2.0 * g1 * g2, B4 = bd * g2 * g2;
      if (prof.in_core(r2m)) {
        const double c0 = prof.c2 - r2m;
        A0 += kc * c0;
        A1 += kc * g1;
        A2 += kc * g2;
        B0 += bc * c0 * c0;
        B1 += bc * 2.0 * c0 * g1;
        B2 += bc * (g1 * g1 + 2.0 * c0 * g2);
        B3 += bc * 2.0 * g1 * g2;
        B4 += bc * g2 * g2;
      }
      const double hw2 = hw * hw;
      const double m0 = 2.0 * hw, m2 = m0 * hw2 * (1.0 / 3.0), m4 = m0 * hw2 * hw2 * 0.2;
      const double H0 = B0 * m0 + B2 * m2 + B4 * m4;    // integral of hh
      const double H1 = B1 * m2 + B3 * m4;              // integral of hh y
      const double I0 = A0 * m0 + A2 * m2, I1 = A1 * m2, I2 = A0 * m2 + A2 * m4;    // hd y^k
      const double I3 = A1 * m4;
      const double c0 = wm * I0 + wy * I1;    // integral of W hd, W hd y, W hd y^2
      const double c1 = wm * I1 + wy * I2;
      const double c2 = wm * I2 + wy * I3;
      L0 += wm * m0;
      P0 += wm * H0 + wy * H1;
      C0 += c0;
      C1 += mid * c0 + c1;
      C2 += mid * (mid * c0 + 2.0 * c1) + c2;
      if (wr == 1) {
        QA0 += H0 * inv2e;
        QA1 += (mid * H0 + H1) * inv2e;
      } else if (wr == 2) {
        QB0 += H0 * inv2e;
        QB1 += (mid * H0 + H1) * inv2e;
      }
    }
    const double energy = kn * la * P0, length = la * L0;
    if (!(energy > 0.0) && !(length > 0.0)) return out;

    // dE/dx of A0, A1, B0, B1 (K = kn la): through r (the distance), through the ramp variable
    // (gradients +-eb at the point of A, -eb - r/lb and r/lb at B0, B1 for the ramp at B0; r/lb and
    // eb - r/lb for the ramp at B1) and through la
    // dE/dx of A0, A1, B0, B1 (K = kn la): through r (the distance), through the ramp variable
    // (gradients +-eb at the point of A, -eb - r/lb and r/lb at B0, B1 for the ramp at B0; r/lb and
    // eb - r/lb for the ramp at B1) and through la
    const Vec3 eb = inv_lb * u;
    const double inv_la = 1.0 / la;
    const double K = kn * la;
    const Vec3 cr_sum = C0 * r0 + C1 * r1;                         // sum c r
    const Vec3 cxr_sum = C1 * r0 + C2 * r1;                        // sum c xi r
    const Vec3 ctr_sum = inv_lb * (s0 * cr_sum + s1 * cxr_sum);    // sum c t r, t = s / lb
    const Vec3 qa_rl = inv_lb * (QA0 * r0 + QA1 * r1);             // sum q r / lb, ramp at B0
    const Vec3 qb_rl = inv_lb * (QB0 * r0 + QB1 * r1);             // the same, ramp at B1
    const Vec3 lpart = (kn * P0 * inv_la) * da;
    Vec3 g[4];
    g[0] = K * (((QA0 - QA1) - (QB0 - QB1)) * eb - (cr_sum - cxr_sum)) - lpart;
    g[1] = K * ((QA1 - QB1) * eb - cxr_sum) + lpart;
    g[2] = K * ((cr_sum - ctr_sum) - QA0 * eb - qa_rl + qb_rl);
    g[3] = K * (ctr_sum + qa_rl + QB0 * eb - qb_rl);
    const Vec3 fres = K * cr_sum;    // resultant normal force on A

    out.active = true;
    out.energy = energy;
    for (int n = 0; n < 4; n++) out.f[n] = -g[n];
    out.length = length;
    // contact point: the centroid of the penetration density c (zero at the rim of the zone)
    if (C0 > 0.0) {
      out.xi = C1 / C0;
    } else {
      out.xi = 0.5 * (lo + hi);
    }
    out.t = clamp01((s0 + s1 * out.xi) * inv_lb);
    // normal direction: the offset from B's line of the point of A's line closest to it (the
    // common perpendicular of the two lines), that point being kept within one contact distance
    // of this pair's contact zone on A. Two pairs that share one contact (a crossing on a node of
    // A, or of B) therefore take the same normal and their normal forces add up without loss or
    // excess; for (nearly) parallel segments it is the offset at the end of the zone nearest to
    // B's line. Where the axes touch: the direction of the resultant.
    double xs = 0.5 * (lo + hi);
    if (qa > tiny) {
      const double ext = dc * inv_la;
      xs = std::min(hi + ext, std::max(lo - ext, xvert));
    }
    const Vec3 rs = r0 + xs * r1;
    const double rn2 = norm2(rs);
    if (rn2 > 1e-18 * d2) {
      out.normal = (1.0 / std::sqrt(rn2)) * rs;
      out.fn = std::max(0.0, dot(fres, out.normal));
    } else {
      const double fr = norm(fres);
      if (fr > 0.0) {
        out.normal = (1.0 / fr) * fres;
        out.fn = fr;
      }
    }
    if (with_penetration) out.penetration = segment_penetration(a0, a1, b0, b1, dc);
    return out;
  }

  // forces on the extended end points q0 = p0 - e0 u, q1 = p1 + e1 u (u = unit axis p0 -> p1)
  // mapped back to p0, p1 (chain rule; the sum of the two forces is unchanged); the contact point
  // parameter likewise
  void unextend(const Vec3 &p0, const Vec3 &p1, double e0, double e1, Vec3 &f0, Vec3 &f1,
                double &param)
  {
    // (a segment not extended keeps its forces and parameter as they are, bit for bit; usually
    // only one of the two segments of a contact at a free end is)
    if (e0 == 0.0 && e1 == 0.0) return;
    const Vec3 u = p1 - p0;
    const double l = norm(u);
    if (!(l > 0.0)) return;
    const Vec3 eu = (1.0 / l) * u;
    // d(q_k)/d(p1) = [k] + (t_k / l) (I - eu eu^T), t_0 = -e0, t_1 = e1; d(q_k)/d(p0) the rest
    const Vec3 g = (e1 / l) * f1 - (e0 / l) * f0;
    const Vec3 gp = g - dot(g, eu) * eu;
    const Vec3 ftot = f0 + f1;
    f1 += gp;
    f0 = ftot - f1;
    const double lq = l + e0 + e1;
    param = (param * lq - e0) / l;
  }
}    // namespace

void unextend_contact(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1,
                      const double *ext, SegmentContact &c)
{
  unextend(a0, a1, ext[0], ext[1], c.f[0], c.f[1], c.xi);
  unextend(b0, b1, ext[2], ext[3], c.f[2], c.f[3], c.t);
}

SegmentContact segment_contact(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1,
                               double dc, double kn, double ramp, bool with_penetration,
                               const ContactOptions &opt)
{
  const double *e = opt.ext;
  if (e[0] == 0.0 && e[1] == 0.0 && e[2] == 0.0 && e[3] == 0.0)
    return contact_of_segments(a0, a1, b0, b1, dc, kn, ramp, with_penetration, opt.core);
  Vec3 qa0 = a0, qa1 = a1, qb0 = b0, qb1 = b1;
  extend_segment(qa0, qa1, e[0], e[1]);
  extend_segment(qb0, qb1, e[2], e[3]);
  SegmentContact out = contact_of_segments(qa0, qa1, qb0, qb1, dc, kn, ramp, false, opt.core);
  if (!out.active) return out;
  unextend_contact(a0, a1, b0, b1, e, out);
  // the penetration of the chains themselves: two extended tips may overlap (their weights
  // fade out there) without any chain coming closer to another
  if (with_penetration) out.penetration = segment_penetration(a0, a1, b0, b1, dc);
  return out;
}

SegmentContact combine_both_ways(const SegmentContact &ab, const SegmentContact &ba)
{
  SegmentContact out;
  out.active = ab.active || ba.active;
  if (!out.active) return out;
  // (an inactive way counts as zero, whatever its fields hold)
  const double ea = ab.active ? ab.energy : 0.0, eb = ba.active ? ba.energy : 0.0;
  const double fa = ab.active ? ab.fn : 0.0, fb = ba.active ? ba.fn : 0.0;
  const double la = ab.active ? ab.length : 0.0, lb = ba.active ? ba.length : 0.0;
  out.energy = 0.5 * (ea + eb);
  // B against A has B's nodes first: its forces on B0, B1 are f[0], f[1]
  for (int m = 0; m < 4; m++) {
    const Vec3 pa = ab.active ? ab.f[m] : Vec3();
    const Vec3 pb = ba.active ? ba.f[(m + 2) % 4] : Vec3();
    out.f[m] = 0.5 * (pa + pb);
  }
  out.fn = 0.5 * (fa + fb);
  out.length = 0.5 * (la + lb);
  // the normal (from B to A) and the contact points weighted by the normal force of each way, so
  // that they move continuously when one way comes into contact or leaves it
  const Vec3 m = fa * ab.normal - fb * ba.normal;
  const double m2 = norm2(m);
  if (m2 > 0.0)
    out.normal = (1.0 / std::sqrt(m2)) * m;
  else
    out.normal = ab.active ? ab.normal : -ba.normal;
  const double w = fa + fb;
  if (w > 0.0) {
    out.xi = (fa * ab.xi + fb * ba.t) / w;
    out.t = (fa * ab.t + fb * ba.xi) / w;
  } else {
    out.xi = ab.active ? ab.xi : ba.t;
    out.t = ab.active ? ab.t : ba.xi;
  }
  out.penetration = std::max(ab.penetration, ba.penetration);
  return out;
}

SegmentContact chain_contact(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1,
                             double dc, double kn, double ramp, bool with_penetration,
                             const ContactOptions &opt)
{
  ContactOptions swapped = opt;
  for (int k = 0; k < 4; k++) swapped.ext[k] = opt.ext[(k + 2) % 4];
  return combine_both_ways(
      segment_contact(a0, a1, b0, b1, dc, kn, ramp, with_penetration, opt),
      segment_contact(b0, b1, a0, a1, dc, kn, ramp, with_penetration, swapped));
}

namespace {
  constexpr double DEFICIT_TOL = NODE_DEFICIT_TOL;
}    // namespace

// Compiled for AVX-512, AVX2 and the x86-64 baseline, picked at run time (as the batched kernels):
// the quadrature's loop over the pieces is vectorised, with the same operations (no FMA) in every
// version, which therefore give the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define NCF_TARGET_CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define NCF_TARGET_CLONES
#endif
NCF_TARGET_CLONES
NodeContact node_contact(const Vec3 &a0, const Vec3 &a1, const Vec3 &p, const Vec3 &n,
                         const Vec3 &q, double dc, double kn, double ramp, double core)
{
  NodeContact out;
  if (!(dc > 0.0) || !(ramp > 0.0)) return out;
  const Vec3 da = a1 - a0, u1 = n - p, u2 = q - n;
  const double la2 = norm2(da), la = std::sqrt(la2), l1 = norm(u1), l2 = norm(u2);
  const double lmin = MIN_LENGTH * dc;
  if (!(la > lmin) || !(l1 > lmin) || !(l2 > lmin)) return out;
  const double il1 = 1.0 / l1, il2 = 1.0 / l2;
  const Vec3 e1 = il1 * u1, e2 = il2 * u2;
  const double d2 = dc * dc, e = ramp;

  // |x(xi) - n|^2 < D^2 along A
  const Vec3 w0 = a0 - n;
  const double qb = 2.0 * dot(w0, da), qc = norm2(w0);
  double lo, hi;
  if (!negative_interval(la2, qb, qc - d2, 1e-28 * la2, lo, hi)) return out;
  lo = std::max(lo, 0.0);
  hi = std::min(hi, 1.0);
  if (!(hi > lo)) return out;

  // Exact early exit on the concave side of the kink. Where both segments are at least D + e
  // long, only their ramps at n act within D of n: W1 = c(z1), W2 = c(z2) with c = clamp(., 0, 1),
  // z1 = 1/2 - (x - n).e1 / 2e, z2 = 1/2 + (x - n).e2 / 2e. Since c(z1) + c(z2) >= min(1, z1 + z2)
  // for all z1, z2, the deficit 1 - W1 - W2 is at most max(0, (x - n).(e1 - e2) / 2e), which is
  // linear along A: not above the tolerance at both ends of A's part within D of n, no cap.
  if (l1 >= dc + e && l2 >= dc + e) {
    const Vec3 de = e1 - e2;
    const double g0 = dot(w0 + lo * da, de), g1 = dot(w0 + hi * da, de);
    if (std::max(g0, g1) * (0.5 / e) <= DEFICIT_TOL) return out;
  }

  // arc positions on the two segments: s1 = (x - p).e1, s2 = (x - n).e2, linear in xi
  const Vec3 ap = a0 - p;
  const double s10 = dot(ap, e1), s11 = dot(da, e1);
  const double s20 = dot(a0 - n, e2), s21 = dot(da, e2);
  // The break points: the corners of the two weights (in increasing arc position: -e, e, l/2,
  // l - e, l + e, or -e, l - e, l/2, e, l + e for a segment shorter than 2e; reversed where s
  // decreases along A; none where s is constant along A: there the factor 0 puts them all at
  // xi = 0, not inside (lo, hi)), then the core's boundary |x - n| = D_c: three increasing lists
  // of the points inside (lo, hi), merged without branches that depend on the values (a kink of
  // a few degrees puts the corners of the two weights at n close together, in either order)
  constexpr double BIG = 1e300;
  const bool up1 = s11 > 0.0, up2 = s21 > 0.0;
  const double i11 = std::fabs(s11) > 1e-14 * la ? 1.0 / s11 : 0.0;
  const double i21 = std::fabs(s21) > 1e-14 * la ? 1.0 / s21 : 0.0;
  const double lo1 = std::min(e, l1 - e), hi1 = std::max(e, l1 - e);
  const double lo2 = std::min(e, l2 - e), hi2 = std::max(e, l2 - e);
  const double cs[10] = {up1 ? -e : l1 + e, up1 ? lo1 : hi1,   0.5 * l1,        up1 ? hi1 : lo1,
                         up1 ? l1 + e : -e, up2 ? -e : l2 + e, up2 ? lo2 : hi2, 0.5 * l2,
                         up2 ? hi2 : lo2,   up2 ? l2 + e : -e};
  double xs[10];
  for (int k = 0; k < 10; k++) xs[k] = (cs[k] - (k < 5 ? s10 : s20)) * (k < 5 ? i11 : i21);
  double b1[6], b2[6], kb[3];
  int n1 = 0, n2 = 0, nk = 0;
  for (int k = 0; k < 5; k++) {
    b1[n1] = xs[k];
    n1 += (xs[k] > lo) & (xs[k] < hi);
    b2[n2] = xs[k + 5];
    n2 += (xs[k + 5] > lo) & (xs[k + 5] < hi);
  }
  const Profile prof(dc, core);
  prof.core_breaks(la2, qb, qc, 1e-28 * la2, lo, hi, kb, nk);
  b1[n1] = b2[n2] = kb[nk] = BIG;
  // lo, at most 12 break points, hi; the rest hi (the intervals are padded to chunks of 8)
  double brk[14 + 8];
  for (int i = 0; i < 14 + 8; i++) brk[i] = hi;
  brk[0] = lo;
  int nb = 1;
  for (int m = 0, i1 = 0, i2 = 0, ik = 0; m < n1 + n2 + nk; m++) {
    const double x1 = b1[i1], x2 = b2[i2], xk = kb[ik];
    const bool t1 = (x1 <= x2) & (x1 <= xk), t2 = !t1 & (x2 <= xk);
    brk[nb++] = std::min(x1, std::min(x2, xk));
    i1 += t1;
    i2 += t2;
    ik += !t1 & !t2;
  }
  nb++;    // hi

  const double inv2e = 0.5 / e;
  // |x - n|^2 from the point of A's line closest to n (no cancellation)
  const double xc = -0.5 * qb / la2, rc2 = norm2(w0 + xc * da);
  const double kap = prof.kap > 0.0 ? prof.kap : 0.0;
  const double kh = 0.5 * kap, kd = kap * prof.invc;
  const CapProfile cprof = {prof.d2, prof.inv2d, prof.invd, prof.c2, prof.inv2c, kh, kd};

  // One pass over the intervals between the break points, in chunks of 8 (one lane each,
  // vectorised; padded with empty intervals at hi), without branches:
  //
  // The weight W = clamp(min(wa, wb), 0, 1) of a segment (wa = 1/2 + s / 2e, wb = 1/2 +
  // (l - s) / 2e: weight_regime and weight_in without their branches) is linear on each
  // interval, and so is the deficit 1 - W1 - W2. The regimes of the two weights at the middle of
  // the interval give the sign sigma_k of the slope of W_k in s_k (+1: the ramp at the first node
  // of segment k, -1: at its second, 0: none), the deficit there and its slope. The piece
  // integrated is the part of the interval where the deficit is positive (split at its zero
  // where it changes sign), if half > 0 and the deficit at its middle defmid > 0 (else its
  // weights om are 0).
  //
  // On a piece the integrand is one polynomial (the core is in or out: its boundary is a break
  // point): with x = a0 + xi da, rn = x - n = w0 + xi da and the offsets r1 = R10 + xi R11,
  // r2 = R20 + xi R21 of x from the two lines, the gradient is a sum of scalar moments times
  // these vectors. Per Gauss point: alpha = om hd dd, beta_k = om ddp W_k' (= sigma_k om ddp /
  // 2e), eps = om hh dd (dd = deficit^2, ddp = 2 deficit hh). Summed over the piece's points:
  // alpha (1, xi, xi^2), eps, om ddp / 2 (1, xi); times sigma_k (and sigma_k^2) per piece they
  // give the ramp moments. Each lane accumulates its pieces; the lanes are summed in a fixed
  // order at the end, so that every instruction set computes the same operations in the same
  // order (the same bits; no reassociation needed to vectorise). (Lanes over the pieces rather
  // than over the Gauss points: no point arrays written and read back, which cost more time
  // than the lanes left empty.)
  const int npc = nb - 1, npcp = (npc + 7) & ~7;    // at most 13 intervals
  constexpr int NM = 10;                            // A0, A1, A2, E0, S1, Q1, S1x, S2, Q2, S2x
  alignas(64) double acc[NM][8];
  // (the first chunk sets the accumulators, the others add to them)
  auto chunk = [&](int c, bool first) __attribute__((always_inline))
  {
    for (int j = 0; j < 8; j++) {
      const double a = brk[c + j], b = brk[c + j + 1];
      const double mf = 0.5 * (b + a);
      // the regimes of the two weights on the interval (at its middle) and the deficit there
      const double s1m = s10 + s11 * mf, s2m = s20 + s21 * mf;
      const double wa1 = 0.5 + s1m * inv2e, wb1 = 0.5 + (l1 - s1m) * inv2e;
      const double wa2 = 0.5 + s2m * inv2e, wb2 = 0.5 + (l2 - s2m) * inv2e;
      const double w1 = std::min(wa1, wb1), w2 = std::min(wa2, wb2);
      // (wa <= wb: the ramp at the first node, +1; at the second, -1)
      const double sg1 = ((w1 > 0.0) & (w1 < 1.0)) ? std::copysign(1.0, wb1 - wa1) : 0.0;
      const double sg2 = ((w2 > 0.0) & (w2 < 1.0)) ? std::copysign(1.0, wb2 - wa2) : 0.0;
      const double dm = 1.0 - std::min(1.0, std::max(0.0, w1)) - std::min(1.0, std::max(0.0, w2)) -
          DEFICIT_TOL;    // round-off of straight chains
      const double dsl = -(sg1 * s11 + sg2 * s21) * inv2e;
      // its positive part, integrated (4-point Gauss: the integrand, deficit^2 h^2, and its
      // gradient have degree <= 7 on each piece)
      const CapPiece pc = cap_piece(a, b, dm, dsl, xc, rc2, la2, cprof);
      const double sb1 = sg1 * pc.bt, sb2 = sg2 * pc.bt;
      const double v[NM] = {pc.al,     pc.ax,       pc.axx, pc.ep,     sb1,
                            sg1 * sb1, sg1 * pc.bx, sb2,    sg2 * sb2, sg2 * pc.bx};
      for (int m = 0; m < NM; m++) acc[m][j] = first ? v[m] : acc[m][j] + v[m];
    }
  };
  chunk(0, true);
  for (int c = 8; c < npcp; c += 8) chunk(c, false);
  // the lanes summed in a fixed order (written so that it vectorises per moment)
  double t4[NM][4], t2[NM][2], mom[NM];
  for (int m = 0; m < NM; m++)
    for (int j = 0; j < 4; j++) t4[m][j] = acc[m][j] + acc[m][j + 4];
  for (int m = 0; m < NM; m++)
    for (int j = 0; j < 2; j++) t2[m][j] = t4[m][j] + t4[m][j + 2];
  for (int m = 0; m < NM; m++) mom[m] = t2[m][0] + t2[m][1];
  const double A0 = mom[0], A1 = mom[1], A2 = mom[2], E0 = mom[3];
  const double energy = kn * la * E0;
  if (!(energy > 0.0)) return out;

  // The forces -dE/dx (K = kn la): through rn (the distance from n), through the ramp variables
  // of the two segments and through la. The ramp moments carry the factor 2 of ddp and the ramp
  // slope 1/2e: sum sigma beta (S), its xi moment (Sx) and beta at the ramp at p (B1a =
  // (Q1 + S1) / 2) and at q (B2b = (Q2 - S2) / 2). The offsets r1 = R10 + xi R11 of the points of
  // A from the line of segment 1 (R10 = (a0 - p) - s10 e1, R11 = da - s11 e1) and r2 (R20 =
  // w0 - s20 e2, R21 = da - s21 e2) enter the forces on p and q as sum sigma beta r / l, here
  // expanded in a0 - p (or w0), da and e1 (e2). The force on n balances the other four (the
  // energy depends on distances only).
  const double K = kn * la, kr = K * (2.0 * inv2e), lp = kn * E0 / la;
  const double S1 = kr * mom[4], S1x = kr * mom[6], B1a = 0.5 * (kr * mom[5] + S1);
  const double S2 = kr * mom[7], S2x = kr * mom[9], B2b = 0.5 * (kr * mom[8] - S2);
  const double c1a = S1 * il1, c1d = S1x * il1, c1e = B1a - (S1 * s10 + S1x * s11) * il1;
  const double c2w = S2 * il2, c2d = S2x * il2, c2e = B2b - (S2 * s20 + S2x * s21) * il2;
  out.active = true;
  out.energy = energy;
  out.f[0] = (K * (A0 - A1)) * w0 + (K * (A1 - A2) + lp) * da + (S1 - S1x) * e1 + (S2 - S2x) * e2;
  out.f[1] = (K * A1) * w0 + (K * A2 - lp) * da + S1x * e1 + S2x * e2;
  out.f[2] = -(c1a * ap + c1d * da + c1e * e1);
  out.f[4] = c2w * w0 + c2d * da + c2e * e2;
  out.f[3] = -(out.f[0] + out.f[1] + out.f[2] + out.f[4]);
  // penetration: D - the distance of n from segment A (point_segment_dist2)
  const double xn = clamp01(xc);
  out.penetration = std::max(0.0, dc - std::sqrt(norm2(w0 + xn * da)));
  return out;
}

FrictionResult friction_step(Vec3 &slip, const Vec3 &normal, const Vec3 &vrel, double dt, double kt,
                             double fn, double mu, bool advance)
{
  FrictionResult out;
  if (!(kt > 0.0) || !(fn > 0.0) || !(mu > 0.0)) {
    slip = Vec3();
    return out;
  }
  if (advance) {
    // keep the stored slip in the current tangent plane, with its magnitude
    const double sn = dot(slip, normal);
    if (sn != 0.0) {
      const double mag2 = norm2(slip);
      slip -= sn * normal;
      const double t2 = norm2(slip);
      slip = (t2 > 0.0) ? std::sqrt(mag2 / t2) * slip : Vec3();
    }
    const Vec3 vt = vrel - dot(vrel, normal) * normal;
    slip += dt * vt;
    const Vec3 f = -kt * slip;
    const double fm2 = norm2(f), cap = mu * fn;
    if (fm2 > cap * cap) {
      slip = (-1.0 / kt) * ((cap / std::sqrt(fm2)) * f);
      out.sliding = true;
    }
  }
  // the force of the slip as it is kept: the setup of the next run (advance false) gives it again
  out.force = -kt * slip;
  out.energy = 0.5 * norm2(out.force) / kt;
  return out;
}

double contact_tangential(SegmentContact &c, const Vec3 *v, Vec3 &slip, double kt, double mu,
                          double damp, double dt, bool advance)
{
  if (!c.active || !(c.fn > 0.0)) return 0.0;
  const Vec3 vrel = ((1.0 - c.xi) * v[0] + c.xi * v[1]) - ((1.0 - c.t) * v[2] + c.t * v[3]);
  double fn = c.fn;
  Vec3 ftot;
  if (damp > 0.0) {
    // normal dashpot per unit contact length, never pulling the chains together
    double fd = -damp * c.length * dot(vrel, c.normal);
    if (fd < -fn) fd = -fn;
    fn += fd;
    ftot += fd * c.normal;
  }
  double energy = 0.0;
  if (mu > 0.0) {
    const FrictionResult fr =
        friction_step(slip, c.normal, vrel, dt, kt * c.length, fn, mu, advance);
    ftot += fr.force;
    energy = fr.energy;
  }
  // applied at the contact points: A0 + xi (A1 - A0) on A, B0 + t (B1 - B0) on B
  c.f[0] += (1.0 - c.xi) * ftot;
  c.f[1] += c.xi * ftot;
  c.f[2] -= (1.0 - c.t) * ftot;
  c.f[3] -= c.t * ftot;
  return energy;
}

double contact_critical_dt(double mass, double kn, double length)
{
  if (!(mass > 0.0) || !(kn > 0.0) || !(length > 0.0)) return 0.0;
  return 2.0 * std::sqrt(mass / (kn * length));
}

}    // namespace NCF
