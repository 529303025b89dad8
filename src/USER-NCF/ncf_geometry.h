/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free geometry kernel: small 3-vector helpers and closest points of two segments,
   robust for parallel, crossing, touching and degenerate (zero-length) segments.
   No LAMMPS dependency: shared by pair_style ncf/contact, the fixes and the unit tests.
------------------------------------------------------------------------- */

#ifndef NCF_GEOMETRY_H
#define NCF_GEOMETRY_H

#include <algorithm>
#include <cmath>

namespace NCF {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
  Vec3() = default;
  Vec3(double a, double b, double c) : x(a), y(b), z(c) {}
  explicit Vec3(const double *p) : x(p[0]), y(p[1]), z(p[2]) {}
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

inline Vec3 operator+(const Vec3 &a, const Vec3 &b)
{
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(const Vec3 &a, const Vec3 &b)
{
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator-(const Vec3 &a)
{
  return {-a.x, -a.y, -a.z};
}
inline Vec3 operator*(double s, const Vec3 &a)
{
  return {s * a.x, s * a.y, s * a.z};
}
inline Vec3 operator*(const Vec3 &a, double s)
{
  return {s * a.x, s * a.y, s * a.z};
}
inline Vec3 &operator+=(Vec3 &a, const Vec3 &b)
{
  a.x += b.x;
  a.y += b.y;
  a.z += b.z;
  return a;
}
inline Vec3 &operator-=(Vec3 &a, const Vec3 &b)
{
  a.x -= b.x;
  a.y -= b.y;
  a.z -= b.z;
  return a;
}
inline double dot(const Vec3 &a, const Vec3 &b)
{
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(const Vec3 &a, const Vec3 &b)
{
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm2(const Vec3 &a)
{
  return dot(a, a);
}
inline double norm(const Vec3 &a)
{
  return std::sqrt(dot(a, a));
}
inline Vec3 lerp(const Vec3 &a, const Vec3 &b, double t)
{
  return a + t * (b - a);
}

// Closest points of segment P(s) = p0 + s (p1 - p0) and Q(t) = q0 + t (q1 - q0), s, t in [0, 1].
// dist2 is the squared distance of the closest points. For parallel segments the closest points
// are not unique: the middle of the overlap of the two projections is returned, so that the
// point moves continuously as the segments slide along each other. Zero-length segments are
// treated as points.
struct ClosestPoints {
  double s = 0.0, t = 0.0;
  double dist2 = 0.0;
  bool parallel = false;
};

inline double clamp01(double v)
{
  return v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
}

// squared distance of the point q from the segment p0-p1 (closest_points_segments with a point
// for the second segment, without its general cases)
inline double point_segment_dist2(const Vec3 &p0, const Vec3 &p1, const Vec3 &q)
{
  const Vec3 d = p1 - p0, w = q - p0;
  const double a = norm2(d);
  const double s = a > 0.0 ? clamp01(dot(d, w) / a) : 0.0;
  return norm2(w - s * d);
}

inline ClosestPoints closest_points_segments(const Vec3 &p0, const Vec3 &p1, const Vec3 &q0,
                                             const Vec3 &q1)
{
  ClosestPoints out;
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = norm2(d1), e = norm2(d2), f = dot(d2, r);
  const double scale = std::max(a, e);
  const double tiny = 1e-28 * (scale > 0.0 ? scale : 1.0);
  double s = 0.0, t = 0.0;
  if (a <= tiny && e <= tiny) {
    s = t = 0.0;
  } else if (a <= tiny) {
    t = clamp01(f / e);
  } else {
    const double c = dot(d1, r);
    if (e <= tiny) {
      s = clamp01(-c / a);
    } else {
      const double b = dot(d1, d2);
      const double denom = a * e - b * b;    // |d1 x d2|^2 >= 0
      if (denom <= 1e-12 * a * e) {
        // parallel (to round-off): middle of the overlap of the projections of Q on P
        out.parallel = true;
        const double sa = clamp01(-c / a), sb = clamp01((b - c) / a);
        const double lo = std::min(sa, sb), hi = std::max(sa, sb);
        s = 0.5 * (lo + hi);
        t = clamp01((b * s + f) / e);
      } else {
        s = clamp01((b * f - c * e) / denom);
        t = (b * s + f) / e;
        if (t < 0.0) {
          t = 0.0;
          s = clamp01(-c / a);
        } else if (t > 1.0) {
          t = 1.0;
          s = clamp01((b - c) / a);
        }
      }
    }
  }
  out.s = s;
  out.t = t;
  out.dist2 = norm2((p0 + s * d1) - (q0 + t * d2));
  return out;
}

}    // namespace NCF

#endif
