/* ----------------------------------------------------------------------
   USER-NCF: batched evaluation of the segment-segment contact law (see ncf_contact.h).

   The same law and the same formulas as contact_of_segments in ncf_contact.cpp, restricted to
   the case where the integral along A has at most one piece per regime of B's weight (ramp at
   B0, plateau, ramp at B1) and no core boundary, written without branches: every lane computes everything and the case decisions
   become selects. The loop over the lanes is then one straight block that the compiler
   vectorises (compiled with -fno-math-errno -fno-trapping-math, so that the square roots and the
   divisions on either side of a select vectorise too). Lanes
   outside the case get status -1 and are left to segment_contact, which is the reference this
   code is tested against.
------------------------------------------------------------------------- */

#include "ncf_batch_second_pass.h"
#include "ncf_contact.h"

#include <cmath>

namespace NCF {

namespace {
  // The lanes of a batch. MULTI false: a zone within one regime of B's weight is one piece; a
  // zone across regimes gets status -2 (for the second pass). MULTI true: the three pieces.
  // (always inlined, so that each version of segment_contact_batch compiles it for its target)
  template <bool MULTI>
  inline __attribute__((always_inline)) void law_lanes(ContactBatch &b, double core)
  {
    const int n = b.n;
    const double kap = core;
    const double cf2 = CORE_FRACTION * CORE_FRACTION;
    for (int l = 0; l < n; l++) {
      const double ax0 = b.x[0][l], ay0 = b.x[1][l], az0 = b.x[2][l];
      const double dax = b.x[3][l] - ax0, day = b.x[4][l] - ay0, daz = b.x[5][l] - az0;
      const double bx0 = b.x[6][l], by0 = b.x[7][l], bz0 = b.x[8][l];
      const double ux = b.x[9][l] - bx0, uy = b.x[10][l] - by0, uz = b.x[11][l] - bz0;
      const double dc = b.dc[l], kn = b.kn[l], e = b.ramp[l];
      const double la2 = dax * dax + day * day + daz * daz, lb2 = ux * ux + uy * uy + uz * uz;
      const double lmin2 = MIN_LENGTH * MIN_LENGTH * dc * dc;
      const bool sizes = (la2 > lmin2) & (lb2 > lmin2);
      const double lb2s = sizes ? lb2 : 1.0, la2s = sizes ? la2 : 1.0;

      // A's line relative to B's: r(xi) = r0 + xi r1, r^2 = qa xi^2 + qb xi + qc
      const double inv_lb2 = 1.0 / lb2s;
      const double w0x = ax0 - bx0, w0y = ay0 - by0, w0z = az0 - bz0;
      const double t0 = (w0x * ux + w0y * uy + w0z * uz) * inv_lb2;
      const double t1 = (dax * ux + day * uy + daz * uz) * inv_lb2;
      const double r0x = w0x - t0 * ux, r0y = w0y - t0 * uy, r0z = w0z - t0 * uz;
      const double r1x = dax - t1 * ux, r1y = day - t1 * uy, r1z = daz - t1 * uz;
      const double d2 = dc * dc;
      const double qa = r1x * r1x + r1y * r1y + r1z * r1z;
      const double qb = 2.0 * (r0x * r1x + r0y * r1y + r0z * r1z);
      const double qc = r0x * r0x + r0y * r0y + r0z * r0z;
      const double qcp = qc - d2;
      // not within 1e-3 rad of parallel (qa = la^2 sin^2 of the angle)
      const bool crossing = qa > 1e-6 * la2s;
      // the zone follows from the quadratic (as in negative_interval) wherever the scalar law
      // takes it so, which is beyond 1e-28 la^2
      const bool quadratic = qa > 1e-28 * la2s;
      const double qas = quadratic ? qa : 1.0;

      // the zone r < D on A's line (negative_interval, quadratic case)
      const double disc = qb * qb - 4.0 * qa * qcp;
      const bool hit = disc > 0.0;
      const double sq = std::sqrt(hit ? disc : 0.0);
      const double qq0 = -0.5 * (qb + (qb >= 0.0 ? sq : -sq));
      const double qq = hit ? qq0 : 1.0;
      const double x1 = qq / qas, x2 = qcp / qq;
      const double rlo = x1 < x2 ? x1 : x2, rhi = x1 < x2 ? x2 : x1;
      const double xvert = 0.5 * (rlo + rhi);
      const double lo = rlo > 0.0 ? rlo : 0.0, hi = rhi < 1.0 ? rhi : 1.0;

      // arc position on B: s(xi) = s0 + s1 xi. The zone is cut into the parts where B's weight is
      // its ramp at B0 (-e < s < e), its plateau (e <= s <= lb - e) and its ramp at B1
      // (lb - e < s < lb + e): up to three pieces of the integral, each computed (an empty one has
      // zero width). The cut points are those of contact_of_segments ((c - s0) / s1).
      const double inv_lb = std::sqrt(inv_lb2), lb = lb2s * inv_lb, la = std::sqrt(la2s);
      const double s0 = t0 * lb, s1 = t1 * lb;
      const double stiny = 1e-14 * la;
      const bool sloped = (s1 > stiny) | (s1 < -stiny);
      const double inv_s1 = 1.0 / (sloped ? s1 : 1.0);
      const double xm_e = (-e - s0) * inv_s1, xp_e = (e - s0) * inv_s1;
      const double xm_l = (lb - e - s0) * inv_s1, xp_l = (lb + e - s0) * inv_s1;
      // the zone within the support of the weight (-e < s < lb + e)
      const double wlo = sloped ? (xm_e < xp_l ? xm_e : xp_l) : lo;
      const double whi = sloped ? (xm_e < xp_l ? xp_l : xm_e) : hi;
      const bool s0_in = (s0 > -e) & (s0 < lb + e);
      const double zlo = lo > wlo ? lo : wlo, zhi = hi < whi ? hi : whi;
      const bool outside = (sloped & !(zhi > zlo)) | (!sloped & !s0_in);    // W = 0 over the zone
      const bool long_b = lb >= 2.0 * e;
      // the core: the smallest r^2 over the zone must stay outside it
      const double xc = xvert < zlo ? zlo : (xvert > zhi ? zhi : xvert);
      const double r2min = (qa * xc + qb) * xc + qc;
      const bool clear_of_core = !(kap > 0.0) | (r2min >= cf2 * d2);

      // the pieces in closed form (as in contact_of_segments): on [plo, phi] the weight is
      // wm + wy y (y = xi - mid); ramp 1 or 2 adds the moments of hh W' to QA or QB
      const double inv2e = 0.5 / e;
      const double inv2d = 0.5 / dc, invd = 2.0 * inv2d;
      const double kd = inv2d * invd, bd = 0.5 * inv2d * inv2d;
      double C0 = 0.0, C1 = 0.0, C2 = 0.0, P0 = 0.0, L0 = 0.0;
      double QA0 = 0.0, QA1 = 0.0, QB0 = 0.0, QB1 = 0.0;
      auto piece = [&](double plo, double phi, double is1, double is2) {
        const double hw = phi > plo ? 0.5 * (phi - plo) : 0.0, mid = 0.5 * (phi + plo);
        const double sm = s0 + s1 * mid;
        const double wm = is1 > 0.0 ? 0.5 + sm * inv2e
                                    : (is2 > 0.0 ? 0.5 + (lb - sm) * inv2e : 1.0);
        const double wy = is1 > 0.0 ? s1 * inv2e : (is2 > 0.0 ? -s1 * inv2e : 0.0);
        const double r2m = (qa * mid + qb) * mid + qc;
        const double g0 = d2 - r2m, g1 = -(2.0 * qa * mid + qb), g2 = -qa;
        const double A0 = kd * g0, A1 = kd * g1, A2 = kd * g2;
        const double B0 = bd * g0 * g0, B1 = bd * 2.0 * g0 * g1,
                     B2 = bd * (g1 * g1 + 2.0 * g0 * g2), B3 = bd * 2.0 * g1 * g2,
                     B4 = bd * g2 * g2;
        const double hw2 = hw * hw;
        const double m0 = 2.0 * hw, m2 = m0 * hw2 * (1.0 / 3.0), m4 = m0 * hw2 * hw2 * 0.2;
        const double H0 = B0 * m0 + B2 * m2 + B4 * m4, H1 = B1 * m2 + B3 * m4;
        const double I0 = A0 * m0 + A2 * m2, I1 = A1 * m2, I2 = A0 * m2 + A2 * m4, I3 = A1 * m4;
        const double c0 = wm * I0 + wy * I1, c1 = wm * I1 + wy * I2, c2 = wm * I2 + wy * I3;
        L0 += wm * m0;
        P0 += wm * H0 + wy * H1;
        C0 += c0;
        C1 += mid * c0 + c1;
        C2 += mid * (mid * c0 + 2.0 * c1) + c2;
        const double Q0 = H0 * inv2e, Q1 = (mid * H0 + H1) * inv2e;
        QA0 += is1 > 0.0 ? Q0 : 0.0;
        QA1 += is1 > 0.0 ? Q1 : 0.0;
        QB0 += is2 > 0.0 ? Q0 : 0.0;
        QB1 += is2 > 0.0 ? Q1 : 0.0;
      };
      // the part of [zlo, zhi] between the cut points xa and xb (in either order); without slope
      // all of it in the regime of s0, none in the others
      auto lower = [&](double xa, double xb) {
        const double c = xa < xb ? xa : xb;
        return sloped ? (zlo > c ? zlo : c) : zlo;
      };
      auto upper = [&](double xa, double xb, double whole) {
        const double c = xa < xb ? xb : xa;
        return sloped ? (zhi < c ? zhi : c) : (whole > 0.0 ? zhi : zlo);
      };
      const double in1 = (s0 > -e) & (s0 < e) ? 1.0 : 0.0;
      const double in3 = (s0 >= e) & (s0 <= lb - e) ? 1.0 : 0.0;
      const double in2 = (s0 > lb - e) & (s0 < lb + e) ? 1.0 : 0.0;
      bool single = true;
      if constexpr (MULTI) {
        piece(lower(xm_e, xp_e), upper(xm_e, xp_e, in1), 1.0, 0.0);
        piece(lower(xp_e, xm_l), upper(xp_e, xm_l, in3), 0.0, 0.0);
        piece(lower(xm_l, xp_l), upper(xm_l, xp_l, in2), 0.0, 1.0);
      } else {
        // the regime holding the whole zone, if one does
        const double sa = s0 + s1 * zlo, sb = s0 + s1 * zhi;
        const double smin = sloped ? (sa < sb ? sa : sb) : s0,
                     smax = sloped ? (sa < sb ? sb : sa) : s0;
        const bool one3 = (smin >= e) & (smax <= lb - e);
        const bool one1 = !one3 & (smin >= -e) & (smax <= e);
        const bool one2 = !one3 & !one1 & (smin >= lb - e) & (smax <= lb + e);
        single = one1 | one2 | one3;
        piece(zlo, zhi, one1 ? 1.0 : 0.0, one2 ? 1.0 : 0.0);
      }
      const double mid = 0.5 * (zlo + zhi);
      const double energy = kn * la * P0, length = la * L0;
      const bool active = (energy > 0.0) | (length > 0.0);

      // gradient (as in contact_of_segments): g = alpha r0 + beta r1 + gamma eb + delta da
      const double ebx = inv_lb * ux, eby = inv_lb * uy, ebz = inv_lb * uz;
      const double inv_la = 1.0 / la;
      const double K = kn * la, lp = kn * P0 * inv_la;
      const double crx = C0 * r0x + C1 * r1x, cry = C0 * r0y + C1 * r1y, crz = C0 * r0z + C1 * r1z;
      const double cxx = C1 * r0x + C2 * r1x, cxy = C1 * r0y + C2 * r1y, cxz = C1 * r0z + C2 * r1z;
      const double ctx = inv_lb * (s0 * crx + s1 * cxx), cty = inv_lb * (s0 * cry + s1 * cxy),
                   ctz = inv_lb * (s0 * crz + s1 * cxz);
      const double qax = inv_lb * (QA0 * r0x + QA1 * r1x), qay = inv_lb * (QA0 * r0y + QA1 * r1y),
                   qaz = inv_lb * (QA0 * r0z + QA1 * r1z);
      const double qbx = inv_lb * (QB0 * r0x + QB1 * r1x), qby = inv_lb * (QB0 * r0y + QB1 * r1y),
                   qbz = inv_lb * (QB0 * r0z + QB1 * r1z);
      const double e0 = (QA0 - QA1) - (QB0 - QB1), e1 = QA1 - QB1;
      // forces -g on A0, A1, B0, B1
      b.f[0][l] = -(K * (e0 * ebx - (crx - cxx)) - lp * dax);
      b.f[1][l] = -(K * (e0 * eby - (cry - cxy)) - lp * day);
      b.f[2][l] = -(K * (e0 * ebz - (crz - cxz)) - lp * daz);
      b.f[3][l] = -(K * (e1 * ebx - cxx) + lp * dax);
      b.f[4][l] = -(K * (e1 * eby - cxy) + lp * day);
      b.f[5][l] = -(K * (e1 * ebz - cxz) + lp * daz);
      b.f[6][l] = -(K * ((crx - ctx) - QA0 * ebx - qax + qbx));
      b.f[7][l] = -(K * ((cry - cty) - QA0 * eby - qay + qby));
      b.f[8][l] = -(K * ((crz - ctz) - QA0 * ebz - qaz + qbz));
      b.f[9][l] = -(K * (ctx + qax + QB0 * ebx - qbx));
      b.f[10][l] = -(K * (cty + qay + QB0 * eby - qby));
      b.f[11][l] = -(K * (ctz + qaz + QB0 * ebz - qbz));

      // contact point (centroid of the penetration density) and normal (see contact_of_segments)
      const double xi = C0 > 0.0 ? C1 / (C0 > 0.0 ? C0 : 1.0) : mid;
      const double tt = (s0 + s1 * xi) * inv_lb;
      const double ext = dc * inv_la;
      const double xlo = zlo - ext, xhi = zhi + ext;
      const double xs = xvert < xlo ? xlo : (xvert > xhi ? xhi : xvert);
      const double rsx = r0x + xs * r1x, rsy = r0y + xs * r1y, rsz = r0z + xs * r1z;
      const double rn2 = rsx * rsx + rsy * rsy + rsz * rsz;
      const bool apart = rn2 > 1e-18 * d2;    // else the axes touch: left to segment_contact
      const double inv_rn = 1.0 / std::sqrt(apart ? rn2 : 1.0);
      const double nx = rsx * inv_rn, ny = rsy * inv_rn, nz = rsz * inv_rn;
      const double fdot = K * (crx * nx + cry * ny + crz * nz);

      b.energy[l] = energy;
      b.length[l] = length;
      b.xi[l] = xi;
      b.t[l] = tt < 0.0 ? 0.0 : (tt > 1.0 ? 1.0 : tt);
      b.normal[0][l] = nx;
      b.normal[1][l] = ny;
      b.normal[2][l] = nz;
      b.fn[l] = fdot > 0.0 ? fdot : 0.0;

      // status: the cases decided here; everything else goes to segment_contact. No zone on A
      // means no contact by the same test as the scalar law's, also for short, nearly parallel
      // segments (most pairs of a list are not in contact, and many of those are such)
      const bool no_zone = sizes & quadratic & (!hit | !(hi > lo));
      const bool in_case = sizes & crossing & long_b;
      const bool piecewise = clear_of_core & apart;
      // (a chain of two-way selects: one nested select of six cases does not vectorise)
      double st = active ? 1.0 : 0.0;
      st = single ? st : -2.0;
      st = piecewise ? st : -1.0;
      st = outside ? 0.0 : st;
      st = in_case ? st : -1.0;
      b.status[l] = no_zone ? 0.0 : st;
    }
  }
}    // namespace

// Compiled three times, for AVX-512 (x86-64-v4, 8 lanes per instruction), AVX2 (4 lanes) and the
// x86-64 baseline (SSE2, 2 lanes), chosen when the library is loaded. No FMA (-ffp-contract=off,
// CMakeLists.txt): every lane rounds exactly as the scalar law's operations do, whichever version
// runs. Most zones lie within one regime of B's weight: all
// lanes are first computed as one piece, the few across regimes again with three pieces.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#endif
void segment_contact_batch(ContactBatch &b, double core)
{
  law_lanes<false>(b, core);
  ContactBatch m;
  int lane[CONTACT_BATCH];
  if (gather_flagged_lanes<12>(b, m, lane) == 0) return;
  law_lanes<true>(m, core);
  for (int j = 0; j < m.n; j++) {
    const int l = lane[j];
    b.status[l] = m.status[j];
    b.energy[l] = m.energy[j];
    for (int k = 0; k < 12; k++) b.f[k][l] = m.f[k][j];
    b.fn[l] = m.fn[j];
    for (int k = 0; k < 3; k++) b.normal[k][l] = m.normal[k][j];
    b.xi[l] = m.xi[j];
    b.t[l] = m.t[j];
    b.length[l] = m.length[j];
  }
}

namespace {
  // the lanes of b (A against B) combined with those of s (B against A, B's nodes first) as
  // combine_both_ways does, with selects instead of branches
  inline __attribute__((always_inline)) void combine_lanes(ContactBatch &b, const ContactBatch &s)
  {
    for (int l = 0; l < b.n; l++) {
      const double sa = b.status[l], sb = s.status[l];
      const bool pa = sa > 0.0, pb = sb > 0.0;
      const double ea = pa ? b.energy[l] : 0.0, eb = pb ? s.energy[l] : 0.0;
      const double fa = pa ? b.fn[l] : 0.0, fb = pb ? s.fn[l] : 0.0;
      const double la = pa ? b.length[l] : 0.0, lb = pb ? s.length[l] : 0.0;
      b.energy[l] = 0.5 * (ea + eb);
      // (the force on A0 of B against A is its f[2], i.e. rows 6-8; written out, so that the
      // loop over the lanes vectorises)
      for (int k = 0; k < 6; k++) {
        const double ga = pa ? b.f[k][l] : 0.0, gb = pb ? s.f[k + 6][l] : 0.0;
        b.f[k][l] = 0.5 * (ga + gb);
      }
      for (int k = 6; k < 12; k++) {
        const double ga = pa ? b.f[k][l] : 0.0, gb = pb ? s.f[k - 6][l] : 0.0;
        b.f[k][l] = 0.5 * (ga + gb);
      }
      b.fn[l] = 0.5 * (fa + fb);
      b.length[l] = 0.5 * (la + lb);
      const double mx = fa * b.normal[0][l] - fb * s.normal[0][l];
      const double my = fa * b.normal[1][l] - fb * s.normal[1][l];
      const double mz = fa * b.normal[2][l] - fb * s.normal[2][l];
      const double m2 = mx * mx + my * my + mz * mz;
      const bool weighted = m2 > 0.0;
      const double im = 1.0 / std::sqrt(weighted ? m2 : 1.0);
      const double nx = pa ? b.normal[0][l] : -s.normal[0][l];
      const double ny = pa ? b.normal[1][l] : -s.normal[1][l];
      const double nz = pa ? b.normal[2][l] : -s.normal[2][l];
      b.normal[0][l] = weighted ? im * mx : nx;
      b.normal[1][l] = weighted ? im * my : ny;
      b.normal[2][l] = weighted ? im * mz : nz;
      const double w = fa + fb;
      const bool wpos = w > 0.0;
      const double ws = wpos ? w : 1.0;
      const double xa = b.xi[l], ta = b.t[l], xb = s.xi[l], tb = s.t[l];
      b.xi[l] = wpos ? (fa * xa + fb * tb) / ws : (pa ? xa : tb);
      b.t[l] = wpos ? (fa * ta + fb * xb) / ws : (pa ? ta : xb);
      const double st = (pa | pb) ? 1.0 : 0.0;
      b.status[l] = (sa < 0.0) | (sb < 0.0) ? -1.0 : st;
    }
  }
}    // namespace

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#endif
void chain_contact_batch(ContactBatch &b, double core)
{
  // B against A: the same lanes with B's nodes first
  ContactBatch s;
  s.n = b.n;
  for (int k = 0; k < 6; k++)
    for (int l = 0; l < b.n; l++) {
      s.x[k][l] = b.x[k + 6][l];
      s.x[k + 6][l] = b.x[k][l];
    }
  for (int l = 0; l < b.n; l++) {
    s.dc[l] = b.dc[l];
    s.kn[l] = b.kn[l];
    s.ramp[l] = b.ramp[l];
  }
  segment_contact_batch(b, core);
  segment_contact_batch(s, core);
  combine_lanes(b, s);
}

namespace {
  // friction_step (ncf_contact.cpp) for one lane; the branches of the scalar code become selects
  // whose unused side is computed but never used (a division by a zero t2 or fm2 goes to a dummy)
  struct FrictionLane {
    double fx, fy, fz, energy;
  };
  inline __attribute__((always_inline)) FrictionLane
  friction_lane(double &sx, double &sy, double &sz, double nx, double ny, double nz, double vx,
                double vy, double vz, double dt, double kt, double fn, double mu, bool adv)
  {
    const bool valid = (kt > 0.0) & (fn > 0.0) & (mu > 0.0);
    // keep the stored slip in the current tangent plane, with its magnitude
    const double sn = sx * nx + sy * ny + sz * nz;
    const double mag2 = sx * sx + sy * sy + sz * sz;
    const double px = sx - sn * nx, py = sy - sn * ny, pz = sz - sn * nz;
    const double t2 = px * px + py * py + pz * pz;
    const double rescale = std::sqrt(mag2 / (t2 > 0.0 ? t2 : 1.0));
    const double scale = sn != 0.0 ? (t2 > 0.0 ? rescale : 0.0) : 1.0;
    double qx = sn != 0.0 ? scale * px : sx;
    double qy = sn != 0.0 ? scale * py : sy;
    double qz = sn != 0.0 ? scale * pz : sz;
    // tangential relative velocity, slip update, elastic force capped at mu fn
    const double vn = vx * nx + vy * ny + vz * nz;
    qx += dt * (vx - vn * nx);
    qy += dt * (vy - vn * ny);
    qz += dt * (vz - vn * nz);
    // (in the setup of a run, adv false: the stored slip as it is)
    qx = adv ? qx : sx;
    qy = adv ? qy : sy;
    qz = adv ? qz : sz;
    const double mkt = -kt;
    double fx = mkt * qx, fy = mkt * qy, fz = mkt * qz;
    const double fm2 = fx * fx + fy * fy + fz * fz, cap = mu * fn;
    const bool sliding = adv & (fm2 > cap * cap);
    const double capf = cap / std::sqrt(sliding ? fm2 : 1.0);
    const double ikt = -1.0 / (valid ? kt : 1.0);
    qx = sliding ? ikt * (capf * fx) : qx;
    qy = sliding ? ikt * (capf * fy) : qy;
    qz = sliding ? ikt * (capf * fz) : qz;
    // the force of the slip as it is kept (friction_step)
    fx = mkt * qx;
    fy = mkt * qy;
    fz = mkt * qz;
    const double kts = valid ? kt : 1.0;
    const double energy = 0.5 * (fx * fx + fy * fy + fz * fz) / kts;
    sx = valid ? qx : 0.0;
    sy = valid ? qy : 0.0;
    sz = valid ? qz : 0.0;
    return {valid ? fx : 0.0, valid ? fy : 0.0, valid ? fz : 0.0, valid ? energy : 0.0};
  }
}    // namespace

namespace {
  typedef double v4d __attribute__((vector_size(32)));
  typedef long long v4i __attribute__((vector_size(32)));
  // the first three doubles of the rows r0..r3 (four lanes) into the lane arrays o[0..2] at l0
  inline __attribute__((always_inline)) void transpose_rows(const double *r0, const double *r1,
                                                            const double *r2, const double *r3,
                                                            double (*o)[CONTACT_BATCH], int l0)
  {
    v4d a, b, c, d;
    __builtin_memcpy(&a, r0, sizeof a);
    __builtin_memcpy(&b, r1, sizeof b);
    __builtin_memcpy(&c, r2, sizeof c);
    __builtin_memcpy(&d, r3, sizeof d);
    // (within 128-bit halves first, then across them: the shuffles x86 does in one instruction)
    const v4d ab0 = __builtin_shuffle(a, b, v4i{0, 4, 2, 6});    // x0 x1 z0 z1
    const v4d ab1 = __builtin_shuffle(a, b, v4i{1, 5, 3, 7});    // y0 y1 . .
    const v4d cd0 = __builtin_shuffle(c, d, v4i{0, 4, 2, 6});    // x2 x3 z2 z3
    const v4d cd1 = __builtin_shuffle(c, d, v4i{1, 5, 3, 7});    // y2 y3 . .
    const v4d x = __builtin_shuffle(ab0, cd0, v4i{0, 1, 4, 5});
    const v4d y = __builtin_shuffle(ab1, cd1, v4i{0, 1, 4, 5});
    const v4d z = __builtin_shuffle(ab0, cd0, v4i{2, 3, 6, 7});
    __builtin_memcpy(&o[0][l0], &x, sizeof x);
    __builtin_memcpy(&o[1][l0], &y, sizeof y);
    __builtin_memcpy(&o[2][l0], &z, sizeof z);
  }
}    // namespace

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#endif
void fill_lanes_from_rows(ContactBatch &b, TangentialBatch &t, const double *X,
                          const int (*idx)[4], bool velocities)
{
  const int n = b.n, n4 = n & ~3;
  auto row = [X](int k) {
    return X + 8 * (size_t) k;
  };
  for (int l = 0; l < n4; l += 4)
    for (int m = 0; m < 4; m++) {
      const double *r0 = row(idx[l][m]), *r1 = row(idx[l + 1][m]), *r2 = row(idx[l + 2][m]),
                   *r3 = row(idx[l + 3][m]);
      transpose_rows(r0, r1, r2, r3, b.x + 3 * m, l);
      if (velocities) transpose_rows(r0 + 4, r1 + 4, r2 + 4, r3 + 4, t.v + 3 * m, l);
    }
  for (int l = n4; l < n; l++)
    for (int m = 0; m < 4; m++) {
      const double *r = row(idx[l][m]);
      for (int d = 0; d < 3; d++) b.x[3 * m + d][l] = r[d];
      if (velocities)
        for (int d = 0; d < 3; d++) t.v[3 * m + d][l] = r[4 + d];
    }
}

// contact_tangential (ncf_contact.cpp) lane by lane, the same operations in the same order
// (__restrict: without it the compiler would have to check too many pairs of arrays for overlap
// at run time and gives up vectorising)
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#endif
void tangential_batch(ContactBatch &__restrict b, TangentialBatch &__restrict t, double dt,
                      bool advance)
{
  for (int l = 0; l < b.n; l++) {
    const double xi = b.xi[l], tt = b.t[l], len = b.length[l];
    const double nx = b.normal[0][l], ny = b.normal[1][l], nz = b.normal[2][l];
    // (one comparison: a bool combined from two keeps the loop from vectorising)
    const double fn_go = b.status[l] > 0.0 ? b.fn[l] : 0.0;
    const bool go = fn_go > 0.0;
    const double wa0 = 1.0 - xi, wb0 = 1.0 - tt;
    double vr[3];
    for (int d = 0; d < 3; d++)
      vr[d] = (wa0 * t.v[d][l] + xi * t.v[3 + d][l]) - (wb0 * t.v[6 + d][l] + tt * t.v[9 + d][l]);
    // normal dashpot
    double fn = b.fn[l];
    const double damp = t.damp[l];
    const bool damped = damp > 0.0;
    double fd = -damp * len * (vr[0] * nx + vr[1] * ny + vr[2] * nz);
    fd = fd < -fn ? -fn : fd;
    fn = damped ? fn + fd : fn;
    const double dx = damped ? 0.0 + fd * nx : 0.0, dy = damped ? 0.0 + fd * ny : 0.0,
                 dz = damped ? 0.0 + fd * nz : 0.0;
    // slip spring (no force and a zero slip without friction)
    double sx = t.slip[0][l], sy = t.slip[1][l], sz = t.slip[2][l];
    const FrictionLane r = friction_lane(sx, sy, sz, nx, ny, nz, vr[0], vr[1], vr[2], dt,
                                         t.kt[l] * len, fn, t.mu[l], advance);
    const bool fric = t.mu[l] > 0.0;
    const double gx = fric ? dx + r.fx : dx, gy = fric ? dy + r.fy : dy, gz = fric ? dz + r.fz : dz;
    const double fx = go ? gx : 0.0, fy = go ? gy : 0.0, fz = go ? gz : 0.0;
    t.slip[0][l] = sx;
    t.slip[1][l] = sy;
    t.slip[2][l] = sz;
    const double energy = fric ? r.energy : 0.0;
    t.energy[l] = go ? energy : 0.0;
    b.f[0][l] += wa0 * fx;
    b.f[1][l] += wa0 * fy;
    b.f[2][l] += wa0 * fz;
    b.f[3][l] += xi * fx;
    b.f[4][l] += xi * fy;
    b.f[5][l] += xi * fz;
    b.f[6][l] -= wb0 * fx;
    b.f[7][l] -= wb0 * fy;
    b.f[8][l] -= wb0 * fz;
    b.f[9][l] -= tt * fx;
    b.f[10][l] -= tt * fy;
    b.f[11][l] -= tt * fz;
  }
}

}    // namespace NCF
