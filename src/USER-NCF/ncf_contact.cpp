/* ----------------------------------------------------------------------
   USER-NCF: engine-free segment-segment contact law (see ncf_contact.h).
------------------------------------------------------------------------- */

#include "ncf_contact.h"

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

}    // namespace

SegmentContact segment_contact(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1,
                               double dc, double kn, double ramp)
{
  SegmentContact out;
  if (!(dc > 0.0) || !(ramp > 0.0)) return out;
  const Vec3 da = a1 - a0, u = b1 - b0;
  const double la = norm(da), lb = norm(u);
  if (!(la > MIN_LENGTH * dc) || !(lb > MIN_LENGTH * dc)) return out;
  const Vec3 ea = (1.0 / la) * da, eb = (1.0 / lb) * u;

  // along A: s(xi) = s0 + s1 xi (arc position on B's line), r(xi) = r0 + xi r1 (offset from it)
  const Vec3 w0 = a0 - b0;
  const double s0 = dot(w0, eb), s1 = dot(da, eb);
  const Vec3 r0 = w0 - s0 * eb, r1 = da - s1 * eb;
  const double d2 = dc * dc;

  double lo, hi;
  if (!negative_interval(norm2(r1), 2.0 * dot(r0, r1), norm2(r0) - d2, 1e-28 * la * la, lo, hi))
    return out;
  lo = std::max(lo, 0.0);
  hi = std::min(hi, 1.0);
  // where the weight W(s) is non-zero: -e < s < lb + e
  const double e = ramp;
  if (std::fabs(s1) > 1e-14 * la) {
    double x1 = (-e - s0) / s1, x2 = (lb + e - s0) / s1;
    if (x1 > x2) std::swap(x1, x2);
    lo = std::max(lo, x1);
    hi = std::min(hi, x2);
  } else if (s0 <= -e || s0 >= lb + e) {
    return out;
  }
  if (!(hi > lo)) return out;

  // break points of the piecewise polynomial integrand: ramp corners of W
  double brk[8] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  int nb = 0;
  brk[nb++] = lo;
  if (std::fabs(s1) > 1e-14 * la) {
    const double corners[5] = {-e, e, lb - e, lb + e, 0.5 * lb};
    for (double sc : corners) {
      const double x = (sc - s0) / s1;
      if (x > lo && x < hi) brk[nb++] = x;
    }
  }
  brk[nb++] = hi;
  for (int a = 1; a < nb; a++)    // insertion sort of at most 7 values
    for (int b = a; b > 0 && brk[b] < brk[b - 1]; b--) std::swap(brk[b], brk[b - 1]);

  static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
  static const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  const double inv2e = 0.5 / e;

  Vec3 g[4];    // dE/dx of A0, A1, B0, B1
  Vec3 fres;    // resultant normal force on A
  double energy = 0.0, length = 0.0, msum = 0.0, mxi = 0.0, ms = 0.0;

  for (int k = 0; k + 1 < nb; k++) {
    const double half = 0.5 * (brk[k + 1] - brk[k]);
    if (!(half > 0.0)) continue;
    const double mid = 0.5 * (brk[k + 1] + brk[k]);
    for (int q = 0; q < 3; q++) {
      const double xi = mid + half * gx[q];
      const double om = half * gw[q];
      const double s = s0 + s1 * xi;
      const Vec3 r = r0 + xi * r1;
      double h = (d2 - norm2(r)) / (2.0 * dc);
      if (h < 0.0) h = 0.0;
      // weight and the gradient of its active ramp variable
      const double wa = 0.5 + s * inv2e, wb = 0.5 + (lb - s) * inv2e;
      double w, wd = 0.0;
      Vec3 gp, gb0, gb1;    // d(sigma)/d(p, B0, B1) of the active ramp variable
      const Vec3 rl = (1.0 / lb) * r;
      if (wa <= wb) {
        w = wa;
        gp = eb;
        gb0 = -eb - rl;
        gb1 = rl;
      } else {
        w = wb;
        gp = -eb;
        gb0 = rl;
        gb1 = eb - rl;
      }
      if (w >= 1.0) {
        w = 1.0;
      } else if (w <= 0.0) {
        w = 0.0;
      } else {
        wd = inv2e;
      }
      if (w <= 0.0 && wd == 0.0) continue;
      const double t = s / lb;
      const double hh = 0.5 * h * h;
      energy += om * kn * la * hh * w;
      length += om * la * w;
      // dE/dx
      const Vec3 dpart = kn * la * (-(h * w / dc) * r + (hh * wd) * gp);    // through p
      const Vec3 lpart = (om * kn * hh * w) * ea;                             // through la
      g[0] += om * (1.0 - xi) * dpart - lpart;
      g[1] += om * xi * dpart + lpart;
      g[2] += (om * kn * la) * (((1.0 - t) * h * w / dc) * r + (hh * wd) * gb0);
      g[3] += (om * kn * la) * ((t * h * w / dc) * r + (hh * wd) * gb1);
      // normal resultant and its centroid
      const Vec3 fq = (om * kn * la * h * w / dc) * r;
      fres += fq;
      const double m = norm(fq);
      msum += m;
      mxi += m * xi;
      ms += m * s;
    }
  }
  if (!(energy > 0.0) && !(length > 0.0)) return out;

  out.active = true;
  out.energy = energy;
  for (int n = 0; n < 4; n++) out.f[n] = -g[n];
  out.length = length;
  if (msum > 0.0) {
    out.xi = mxi / msum;
    out.t = clamp01(ms / msum / lb);
  } else {
    out.xi = 0.5 * (lo + hi);
    out.t = clamp01((s0 + s1 * out.xi) / lb);
  }
  // normal direction: the offset from B's line of the point of A's line closest to it (the
  // common perpendicular of the two lines), that point being kept within one contact distance
  // of this pair's contact zone on A. Two pairs that share one contact (a crossing on a node of
  // A, or of B) therefore take the same normal and their normal forces add up without loss or
  // excess; for (nearly) parallel segments it is the offset at the end of the zone nearest to
  // B's line. Where the axes touch: the direction of the resultant.
  const double qa = norm2(r1);
  double xs = 0.5 * (lo + hi);
  if (qa > 1e-28 * la * la) {
    const double ext = dc / la;
    xs = std::min(hi + ext, std::max(lo - ext, -dot(r0, r1) / qa));
  }
  const Vec3 rs = r0 + xs * r1;
  const double rn = norm(rs), fr = norm(fres);
  if (rn > 1e-9 * dc) {
    out.normal = (1.0 / rn) * rs;
    out.fn = std::max(0.0, dot(fres, out.normal));
  } else if (fr > 0.0) {
    out.normal = (1.0 / fr) * fres;
    out.fn = fr;
  }
  const ClosestPoints cp = closest_points_segments(a0, a1, b0, b1);
  out.penetration = std::max(0.0, dc - std::sqrt(cp.dist2));
  return out;
}

FrictionResult friction_step(Vec3 &slip, const Vec3 &normal, const Vec3 &vrel, double dt,
                             double kt, double fn, double mu)
{
  FrictionResult out;
  if (!(kt > 0.0) || !(fn > 0.0) || !(mu > 0.0)) {
    slip = Vec3();
    return out;
  }
  // keep the stored slip in the current tangent plane, with its magnitude
  const double mag = norm(slip);
  slip -= dot(slip, normal) * normal;
  const double mag2 = norm(slip);
  slip = (mag2 > 0.0) ? (mag / mag2) * slip : Vec3();
  const Vec3 vt = vrel - dot(vrel, normal) * normal;
  slip += dt * vt;
  Vec3 f = -kt * slip;
  const double fm = norm(f), cap = mu * fn;
  if (fm > cap) {
    f = (cap / fm) * f;
    slip = (-1.0 / kt) * f;
    out.sliding = true;
  }
  out.force = f;
  out.energy = 0.5 * norm2(f) / kt;
  return out;
}

double contact_critical_dt(double mass, double kn, double length)
{
  if (!(mass > 0.0) || !(kn > 0.0) || !(length > 0.0)) return 0.0;
  return 2.0 * std::sqrt(mass / (kn * length));
}

}    // namespace NCF
