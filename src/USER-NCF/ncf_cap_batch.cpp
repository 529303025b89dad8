/* ----------------------------------------------------------------------
   USER-NCF: batched evaluation of the node caps (node_contact, see ncf_contact.h) over caps,
   one lane per cap.

   The same law and the same formulas as node_contact in ncf_contact.cpp, restricted to the case
   where both chain segments p-n and n-q are at least D + e long. Within D of n only their ramps
   at n act there: W1 = c(z1), W2 = c(z2), c = clamp(., 0, 1), with z1 = 1/2 + (l1 - s1) / 2e
   and z2 = 1/2 + s2 / 2e linear along A. The positive part of the deficit then equals

     max(0, 1 - max(0, z1) - max(0, z2) - tol)

   (where z1 >= 1 or z2 >= 1 both sides are <= -tol), which is linear between the two points
   where z1 and z2 cross 0: the integrand's break points are A's entry into and exit from the
   node's sphere, these two corners, the core's boundary (two points) and the zero of the
   deficit. The four inner points are put in order by a sorting network; each of the five
   intervals between them is split at the zero of the deficit (as in node_contact) and its
   positive piece integrated with the 4-point Gauss rule (empty pieces contribute 0). Every lane
   computes everything and the case decisions become selects, so the loop over the lanes is one
   straight block that the compiler vectorises (compiled with -fno-math-errno
   -fno-trapping-math -ffp-contract=off, CMakeLists.txt). Lanes outside the case get status -1
   and are left to node_contact, which is the reference this code is tested against.
------------------------------------------------------------------------- */

#include "ncf_batch_second_pass.h"
#include "ncf_cap_integral_piece.h"
#include "ncf_contact.h"

#include <cmath>

namespace NCF {

namespace {
  // compare-exchange of a sorting network
  inline __attribute__((always_inline)) void cswap(double &a, double &b)
  {
    const double lo = a < b ? a : b, hi = a < b ? b : a;
    a = lo;
    b = hi;
  }

  // How cap_lanes computes the lanes of a batch: STATUS only the status of each lane, -1 outside
  // the case, 0 where node_contact returns early (A clear of the sphere, the concave side), -2
  // where the cap must be integrated and A's line does not cross the core's boundary, -3 where it
  // does (for the second pass); FULL everything; FULL_NO_CORE everything, for lanes that all have
  // status -2.
  enum CapMode { STATUS, FULL, FULL_NO_CORE };
  // (always inlined, so that each version of node_contact_batch compiles it for its target)
  template <CapMode MODE>
  inline __attribute__((always_inline)) void cap_lanes(CapBatch &__restrict b, double core)
  {
    const double kap = core > 0.0 ? core : 0.0;
    const double cf2 = CORE_FRACTION * CORE_FRACTION;
    const int n = b.n;
    for (int l = 0; l < n; l++) {
      const double a0x = b.x[0][l], a0y = b.x[1][l], a0z = b.x[2][l];
      const double dax = b.x[3][l] - a0x, day = b.x[4][l] - a0y, daz = b.x[5][l] - a0z;
      const double px = b.x[6][l], py = b.x[7][l], pz = b.x[8][l];
      const double nx = b.x[9][l], ny = b.x[10][l], nz = b.x[11][l];
      const double u1x = nx - px, u1y = ny - py, u1z = nz - pz;
      const double u2x = b.x[12][l] - nx, u2y = b.x[13][l] - ny, u2z = b.x[14][l] - nz;
      const double dc = b.dc[l], kn = b.kn[l], e = b.ramp[l];
      const double la2 = dax * dax + day * day + daz * daz;
      const double la = std::sqrt(la2);
      const double l1 = std::sqrt(u1x * u1x + u1y * u1y + u1z * u1z);
      const double l2 = std::sqrt(u2x * u2x + u2y * u2y + u2z * u2z);
      // the case: both chain segments long enough that only their ramps at n act within D of n
      const bool in_case =
          (dc > 0.0) & (e > 0.0) & (la > MIN_LENGTH * dc) & (l1 >= dc + e) & (l2 >= dc + e);
      const double las = in_case ? la : 1.0, la2s = in_case ? la2 : 1.0;
      const double dcs = in_case ? dc : 1.0, es = in_case ? e : 1.0;
      const double il1 = 1.0 / (in_case ? l1 : 1.0), il2 = 1.0 / (in_case ? l2 : 1.0);
      const double e1x = il1 * u1x, e1y = il1 * u1y, e1z = il1 * u1z;
      const double e2x = il2 * u2x, e2y = il2 * u2y, e2z = il2 * u2z;
      const double d2 = dcs * dcs;

      // |x(xi) - n|^2 < D^2 along A (negative_interval, quadratic case)
      const double w0x = a0x - nx, w0y = a0y - ny, w0z = a0z - nz;
      const double qb = 2.0 * (w0x * dax + w0y * day + w0z * daz);
      const double qc = w0x * w0x + w0y * w0y + w0z * w0z;
      const double qcp = qc - d2;
      const double disc = qb * qb - 4.0 * la2s * qcp;
      const bool hit = disc > 0.0;
      const double sq = std::sqrt(hit ? disc : 0.0);
      const double qq0 = -0.5 * (qb + (qb >= 0.0 ? sq : -sq));
      const double qq = hit ? qq0 : 1.0;
      const double x1 = qq / la2s, x2 = qcp / qq;
      const double rlo = x1 < x2 ? x1 : x2, rhi = x1 < x2 ? x2 : x1;
      const double lo0 = rlo > 0.0 ? rlo : 0.0, hi0 = rhi < 1.0 ? rhi : 1.0;
      const bool zone = hit & (hi0 > lo0);
      const double lo = zone ? lo0 : 0.0, hi = zone ? hi0 : 0.0;

      // node_contact's exact early exit on the concave side (no cap)
      const double dex = e1x - e2x, dey = e1y - e2y, dez = e1z - e2z;
      const double g0 = (w0x + lo * dax) * dex + (w0y + lo * day) * dey + (w0z + lo * daz) * dez;
      const double g1 = (w0x + hi * dax) * dex + (w0y + hi * day) * dey + (w0z + hi * daz) * dez;
      const double inv2e = 0.5 / es;
      const bool concave = (g0 > g1 ? g0 : g1) * inv2e <= NODE_DEFICIT_TOL;
      // the core's boundary |x - n| = D_c on A's line, if it is crossed
      const double qcc = qc - cf2 * d2;
      const double discc = qb * qb - 4.0 * la2s * qcc;
      const bool hitc = (kap > 0.0) & (discc > 0.0);
      if constexpr (MODE == STATUS) {
        const double st = zone & !concave ? (hitc ? -3.0 : -2.0) : 0.0;
        b.status[l] = in_case ? st : -1.0;
        continue;
      }

      // arc positions on the two segments: s1 = (x - p).e1, s2 = (x - n).e2, linear in xi
      const double apx = a0x - px, apy = a0y - py, apz = a0z - pz;
      const double s10 = apx * e1x + apy * e1y + apz * e1z, s11 = dax * e1x + day * e1y + daz * e1z;
      const double s20 = w0x * e2x + w0y * e2y + w0z * e2z, s21 = dax * e2x + day * e2y + daz * e2z;
      // the inner break points, each clamped to [lo, hi] (an empty interval where it is outside):
      // z1 = 0 (s1 = l1 + e), z2 = 0 (s2 = -e), none where s is constant along A (as node_contact)
      const double tiny = 1e-14 * las;
      const bool sl1 = (s11 > tiny) | (s11 < -tiny), sl2 = (s21 > tiny) | (s21 < -tiny);
      const double i11 = sl1 ? 1.0 / (sl1 ? s11 : 1.0) : 0.0;
      const double i21 = sl2 ? 1.0 / (sl2 ? s21 : 1.0) : 0.0;
      // (two-way selects only: nested ones keep the loop from being if-converted)
      auto clampz = [&](double x) {
        const double y = x > lo ? x : lo;
        return y < hi ? y : hi;
      };
      double c0 = clampz(((l1 + es) - s10) * i11);
      double c1 = clampz((-es - s20) * i21);
      // where the core's boundary is crossed (negative_interval, quadratic case)
      const double sqc = std::sqrt(hitc ? discc : 0.0);
      const double qqc0 = -0.5 * (qb + (qb >= 0.0 ? sqc : -sqc));
      const double qqc = hitc ? qqc0 : 1.0;
      const double y1 = qqc / la2s, y2 = qcc / qqc;
      const double ymin = y1 < y2 ? y1 : y2, ymax = y1 < y2 ? y2 : y1;
      double c2 = clampz(hitc ? ymin : lo);
      double c3 = clampz(hitc ? ymax : lo);
      // sorting network of four
      cswap(c0, c1);
      cswap(c2, c3);
      cswap(c0, c2);
      cswap(c1, c3);
      cswap(c1, c2);

      // |x - n|^2 from the point of A's line closest to n (no cancellation)
      const double xc = -0.5 * qb / la2s;
      const double rcx = w0x + xc * dax, rcy = w0y + xc * day, rcz = w0z + xc * daz;
      const double rc2 = rcx * rcx + rcy * rcy + rcz * rcz;
      const double inv2d = 0.5 / dcs, invd = 2.0 * inv2d;
      const double dcc2 = cf2 * d2, inv2c = SQRT3 * inv2d, invc = 2.0 * inv2c;
      const double kh = 0.5 * kap, kd = kap * invc;
      const CapProfile prof = {d2, inv2d, invd, dcc2, inv2c, kh, kd};

      // the moments (node_contact): alpha (1, xi, xi^2), eps, and per ramp sum sigma beta,
      // sigma^2 beta, sigma beta xi
      double sal = 0.0, sax = 0.0, saxx = 0.0, seps = 0.0;
      double sb1 = 0.0, sq1 = 0.0, sx1 = 0.0, sb2 = 0.0, sq2 = 0.0, sx2 = 0.0;
      auto interval = [&](double a, double bb) __attribute__((always_inline))
      {
        const double mf = 0.5 * (bb + a);
        // the ramps at n on the interval (at its middle; z1 and z2 keep their signs on it) and the
        // deficit there, linear on the interval
        const double s1m = s10 + s11 * mf, s2m = s20 + s21 * mf;
        const double z1 = 0.5 + (l1 - s1m) * inv2e, z2 = 0.5 + s2m * inv2e;
        const double sg1 = z1 > 0.0 ? -1.0 : 0.0, sg2 = z2 > 0.0 ? 1.0 : 0.0;
        const double dm = 1.0 - (z1 > 0.0 ? z1 : 0.0) - (z2 > 0.0 ? z2 : 0.0) - NODE_DEFICIT_TOL;
        const double dsl = -(sg1 * s11 + sg2 * s21) * inv2e;
        // its positive part, integrated (4-point Gauss: degree <= 7 on each piece)
        const CapPiece pc = cap_piece(a, bb, dm, dsl, xc, rc2, la2s, prof);
        sal += pc.al;
        sax += pc.ax;
        saxx += pc.axx;
        seps += pc.ep;
        const double b1 = sg1 * pc.bt, b2 = sg2 * pc.bt;
        sb1 += b1;
        sq1 += sg1 * b1;
        sx1 += sg1 * pc.bx;
        sb2 += b2;
        sq2 += sg2 * b2;
        sx2 += sg2 * pc.bx;
      };
      // (without a crossing of the core, c2 = c3 = lo before the sorting: the first two
      // intervals are [lo, lo], which add zeros, i.e. change no sum)
      if constexpr (MODE == FULL) {
        interval(lo, c0);
        interval(c0, c1);
      }
      interval(c1, c2);
      interval(c2, c3);
      interval(c3, hi);

      // the forces -dE/dx (node_contact)
      const double energy = kn * las * seps;
      const double K = kn * las, kr = K * (2.0 * inv2e), lp = kn * seps / las;
      const double A0 = sal, A1 = sax, A2 = saxx;
      const double S1 = kr * sb1, S1x = kr * sx1, B1a = 0.5 * (kr * sq1 + S1);
      const double S2 = kr * sb2, S2x = kr * sx2, B2b = 0.5 * (kr * sq2 - S2);
      const double c1a = S1 * il1, c1d = S1x * il1, c1e = B1a - (S1 * s10 + S1x * s11) * il1;
      const double c2w = S2 * il2, c2d = S2x * il2, c2e = B2b - (S2 * s20 + S2x * s21) * il2;
      const double fw0 = K * (A0 - A1), fd0 = K * (A1 - A2) + lp, fe10 = S1 - S1x, fe20 = S2 - S2x;
      const double fw1 = K * A1, fd1 = K * A2 - lp;
      const double f0x = fw0 * w0x + fd0 * dax + fe10 * e1x + fe20 * e2x;
      const double f0y = fw0 * w0y + fd0 * day + fe10 * e1y + fe20 * e2y;
      const double f0z = fw0 * w0z + fd0 * daz + fe10 * e1z + fe20 * e2z;
      const double f1x = fw1 * w0x + fd1 * dax + S1x * e1x + S2x * e2x;
      const double f1y = fw1 * w0y + fd1 * day + S1x * e1y + S2x * e2y;
      const double f1z = fw1 * w0z + fd1 * daz + S1x * e1z + S2x * e2z;
      const double f2x = -(c1a * apx + c1d * dax + c1e * e1x);
      const double f2y = -(c1a * apy + c1d * day + c1e * e1y);
      const double f2z = -(c1a * apz + c1d * daz + c1e * e1z);
      const double f4x = c2w * w0x + c2d * dax + c2e * e2x;
      const double f4y = c2w * w0y + c2d * day + c2e * e2y;
      const double f4z = c2w * w0z + c2d * daz + c2e * e2z;
      b.f[0][l] = f0x;
      b.f[1][l] = f0y;
      b.f[2][l] = f0z;
      b.f[3][l] = f1x;
      b.f[4][l] = f1y;
      b.f[5][l] = f1z;
      b.f[6][l] = f2x;
      b.f[7][l] = f2y;
      b.f[8][l] = f2z;
      b.f[9][l] = -(f0x + f1x + f2x + f4x);
      b.f[10][l] = -(f0y + f1y + f2y + f4y);
      b.f[11][l] = -(f0z + f1z + f2z + f4z);
      b.f[12][l] = f4x;
      b.f[13][l] = f4y;
      b.f[14][l] = f4z;
      b.energy[l] = energy;
      // penetration: D - the distance of n from segment A
      const double xn0 = xc > 0.0 ? xc : 0.0;
      const double xn = xn0 < 1.0 ? xn0 : 1.0;
      const double pnx = w0x + xn * dax, pny = w0y + xn * day, pnz = w0z + xn * daz;
      const double pen = dc - std::sqrt(pnx * pnx + pny * pny + pnz * pnz);
      b.penetration[l] = pen > 0.0 ? pen : 0.0;
      // status (a chain of two-way selects, as in segment_contact_batch)
      double st = energy > 0.0 ? 1.0 : 0.0;
      st = concave ? 0.0 : st;
      st = zone ? st : 0.0;
      b.status[l] = in_case ? st : -1.0;
    }
  }
}    // namespace

// Compiled for AVX-512 (x86-64-v4), AVX2 and the x86-64 baseline, chosen when the library is
// loaded; no FMA (-ffp-contract=off), so every version gives the same bits. About half of the
// caps in reach end at node_contact's early exits (A clear of the sphere, the concave side): all
// lanes first get their status only, and the caps to integrate are gathered and integrated in a
// second pass, so that the lanes of its vector instructions are not spent on caps without
// contact.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#endif
void node_contact_batch(CapBatch &b, double core)
{
  cap_lanes<STATUS>(b, core);
  CapBatch m;
  int lane[CAP_BATCH];
  if (gather_flagged_lanes<15>(b, m, lane) == 0) return;
  // (on a compacted mat A's line seldom crosses a core: most batches without)
  bool core_crossed = false;
  for (int j = 0; j < m.n; j++) core_crossed |= m.status[j] == -3.0;
  if (core_crossed)
    cap_lanes<FULL>(m, core);
  else
    cap_lanes<FULL_NO_CORE>(m, core);
  for (int j = 0; j < m.n; j++) {
    const int l = lane[j];
    b.status[l] = m.status[j];
    b.energy[l] = m.energy[j];
    for (int k = 0; k < 15; k++) b.f[k][l] = m.f[k][j];
    b.penetration[l] = m.penetration[j];
  }
}

}    // namespace NCF
