/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF fabric generator: header-only geometry used by the generator and by the tests
   (closest distance of two segments, 2D and 3D, and a cell-list clearance check of chain
   segments in a box periodic in x and y). Engine-free.
------------------------------------------------------------------------- */

#ifndef NCFGEN_GEOM_H
#define NCFGEN_GEOM_H

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace NCFGEN {

// Squared closest distance of segments p0-p1 and q0-q1 in D dimensions (Ericson, Real-Time
// Collision Detection, 5.1.9), robust for parallel and degenerate segments.
template <int D>
inline double segment_distance2(const double *p0, const double *p1, const double *q0,
                                const double *q1)
{
  double d1[D], d2[D], r[D];
  double a = 0.0, e = 0.0, f = 0.0, c = 0.0, b = 0.0;
  for (int k = 0; k < D; k++) {
    d1[k] = p1[k] - p0[k];
    d2[k] = q1[k] - q0[k];
    r[k] = p0[k] - q0[k];
    a += d1[k] * d1[k];
    e += d2[k] * d2[k];
    f += d2[k] * r[k];
    c += d1[k] * r[k];
    b += d1[k] * d2[k];
  }
  const double eps = 1e-300;
  double s = 0.0, t = 0.0;
  if (a <= eps && e <= eps) {
    s = t = 0.0;
  } else if (a <= eps) {
    s = 0.0;
    t = std::clamp(f / e, 0.0, 1.0);
  } else if (e <= eps) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else {
    const double denom = a * e - b * b;
    s = (denom > 1e-14 * a * e) ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
    t = (b * s + f) / e;
    if (t < 0.0) {
      t = 0.0;
      s = std::clamp(-c / a, 0.0, 1.0);
    } else if (t > 1.0) {
      t = 1.0;
      s = std::clamp((b - c) / a, 0.0, 1.0);
    }
  }
  double d = 0.0;
  for (int k = 0; k < D; k++) {
    const double dk = r[k] + d1[k] * s - d2[k] * t;
    d += dk * dk;
  }
  return d;
}

// One straight segment of a chain (unwrapped end points), its chain and end-node ids.
struct Segment {
  double a[3], b[3];
  int chain;        // segments of one chain share this id
  int na, nb;       // node ids of the ends (segments sharing a node are never a contact)
  double radius;    // contact radius
};

struct Clearance {
  double gap = std::numeric_limits<double>::infinity();    // min distance - (r_i + r_j)
  double distance = 0.0;
  int s1 = -1, s2 = -1;    // the segments
  long pairs = 0;          // segment pairs closer than their cell-list cut-off that were measured
};

// Smallest clearance (distance minus the sum of contact radii) over all pairs of segments that
// share no node, periodic images in x (period lx) and y (period ly) included, z open.
// Pairs of segments that are both chain-end segments across a main face are measured too.
inline Clearance min_clearance(const std::vector<Segment> &segs, double lx, double ly)
{
  Clearance out;
  if (segs.empty()) return out;
  double maxlen = 0.0, maxr = 0.0, zmin = 1e300, zmax = -1e300;
  std::vector<double> mid(3 * segs.size());
  for (std::size_t i = 0; i < segs.size(); i++) {
    double l2 = 0.0;
    for (int k = 0; k < 3; k++) {
      const double d = segs[i].b[k] - segs[i].a[k];
      l2 += d * d;
      mid[3 * i + k] = 0.5 * (segs[i].a[k] + segs[i].b[k]);
    }
    // wrap the midpoint into the box in x and y
    mid[3 * i + 0] -= lx * std::floor(mid[3 * i + 0] / lx);
    mid[3 * i + 1] -= ly * std::floor(mid[3 * i + 1] / ly);
    maxlen = std::max(maxlen, std::sqrt(l2));
    maxr = std::max(maxr, segs[i].radius);
    zmin = std::min(zmin, mid[3 * i + 2]);
    zmax = std::max(zmax, mid[3 * i + 2]);
  }
  const double cut = maxlen + 2.0 * maxr + 1e-12;    // midpoints of touching segments are closer
  const int nx = std::max(1, (int) std::floor(lx / cut));
  const int ny = std::max(1, (int) std::floor(ly / cut));
  const int nz = std::max(1, (int) std::floor((zmax - zmin) / cut) + 1);
  const double cx = lx / nx, cy = ly / ny;
  auto cell_of = [&](std::size_t i, int &ix, int &iy, int &iz) {
    ix = std::min(nx - 1, (int) (mid[3 * i] / cx));
    iy = std::min(ny - 1, (int) (mid[3 * i + 1] / cy));
    iz = std::min(nz - 1, (int) ((mid[3 * i + 2] - zmin) / cut));
  };
  std::vector<std::vector<int>> cells((std::size_t) nx * ny * nz);
  for (std::size_t i = 0; i < segs.size(); i++) {
    int ix, iy, iz;
    cell_of(i, ix, iy, iz);
    cells[((std::size_t) iz * ny + iy) * nx + ix].push_back((int) i);
  }
  for (std::size_t i = 0; i < segs.size(); i++) {
    int ix, iy, iz;
    cell_of(i, ix, iy, iz);
    // neighbour cells; with fewer than 3 cells in a direction each one is visited once
    std::vector<int> xs, ys;
    for (int d = -1; d <= 1; d++) {
      int v = ((ix + d) % nx + nx) % nx;
      if (std::find(xs.begin(), xs.end(), v) == xs.end()) xs.push_back(v);
      v = ((iy + d) % ny + ny) % ny;
      if (std::find(ys.begin(), ys.end(), v) == ys.end()) ys.push_back(v);
    }
    for (int jz = std::max(0, iz - 1); jz <= std::min(nz - 1, iz + 1); jz++)
      for (int jy : ys)
        for (int jx : xs)
          for (int j : cells[((std::size_t) jz * ny + jy) * nx + jx]) {
            if (j <= (int) i) continue;
            const Segment &p = segs[i], &q = segs[j];
            if (p.na == q.na || p.na == q.nb || p.nb == q.na || p.nb == q.nb) continue;
            // the periodic image of q nearest to p (segments are short against the box)
            double shift[3] = {0.0, 0.0, 0.0};
            const double dx = mid[3 * j] - mid[3 * i], dy = mid[3 * j + 1] - mid[3 * i + 1];
            const double pa = 0.5 * (p.a[0] + p.b[0]), qa = 0.5 * (q.a[0] + q.b[0]);
            const double pb = 0.5 * (p.a[1] + p.b[1]), qb = 0.5 * (q.a[1] + q.b[1]);
            shift[0] = (pa + dx - std::round(dx / lx) * lx) - qa;
            shift[1] = (pb + dy - std::round(dy / ly) * ly) - qb;
            double q0[3], q1[3];
            for (int k = 0; k < 3; k++) {
              q0[k] = q.a[k] + shift[k];
              q1[k] = q.b[k] + shift[k];
            }
            const double d = std::sqrt(segment_distance2<3>(p.a, p.b, q0, q1));
            out.pairs++;
            const double gap = d - (p.radius + q.radius);
            if (gap < out.gap) {
              out.gap = gap;
              out.distance = d;
              out.s1 = (int) i;
              out.s2 = j;
            }
          }
  }
  return out;
}

}    // namespace NCFGEN

#endif
