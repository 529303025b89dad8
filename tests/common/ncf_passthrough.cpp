/* ----------------------------------------------------------------------
   USER-NCF tests: pass-through checker (see ncf_passthrough.h)
------------------------------------------------------------------------- */

#include "ncf_passthrough.h"

#include "ncf_geometry.h"

#include <algorithm>
#include <cmath>

namespace ncftest {

using NCF::Vec3;

PassThroughChecker::PassThroughChecker(std::vector<std::pair<int, int>> segs, double lx, double ly,
                                       double reach) :
    segs_(std::move(segs)),
    lx_(lx), ly_(ly), reach_(reach)
{
}

void PassThroughChecker::check(const std::vector<double> &x)
{
  auto image = [&](double d, double l) {
    return l > 0.0 ? d - l * std::round(d / l) : d;
  };
  const size_t n = segs_.size();
  // segments with minimum-image bonds, their midpoints wrapped into the periodic cell
  std::vector<Vec3> a(n), b(n), m(n);
  for (size_t s = 0; s < n; s++) {
    a[s] = Vec3(&x[3 * (size_t) segs_[s].first]);
    const Vec3 q(&x[3 * (size_t) segs_[s].second]);
    b[s] = a[s] + Vec3(image(q.x - a[s].x, lx_), image(q.y - a[s].y, ly_), q.z - a[s].z);
    m[s] = 0.5 * (a[s] + b[s]);
  }
  // cell list of the midpoints, cells at least `reach` wide; along a periodic direction the
  // cells tile the period (midpoints wrapped), so that neighbour cells wrap around
  const double period[3] = {lx_, ly_, 0.0};
  double lo[3] = {1e300, 1e300, 1e300}, len[3];
  int nc[3];
  for (int d = 0; d < 3; d++) {
    double hi = -1e300;
    for (const Vec3 &p : m) {
      lo[d] = std::min(lo[d], p[d]);
      hi = std::max(hi, p[d]);
    }
    if (period[d] > 0.0) {
      lo[d] = 0.0;
      len[d] = period[d];
    } else {
      len[d] = hi - lo[d] + 1e-300;
    }
    nc[d] = std::max(1, (int) (len[d] / reach_));
  }
  auto cell = [&](const Vec3 &p, int d) {
    double w = p[d] - lo[d];
    if (period[d] > 0.0) w -= period[d] * std::floor(w / period[d]);
    return std::min(nc[d] - 1, std::max(0, (int) (w / len[d] * nc[d])));
  };
  std::vector<std::vector<int>> bins((size_t) nc[0] * nc[1] * nc[2]);
  for (size_t s = 0; s < n; s++)
    bins[((size_t) cell(m[s], 2) * nc[1] + cell(m[s], 1)) * nc[0] + cell(m[s], 0)].push_back(
        (int) s);
  const bool px = lx_ > 0.0, py = ly_ > 0.0;
  std::vector<size_t> near;
  for (size_t s = 0; s < n; s++) {
    const int c0 = cell(m[s], 0), c1 = cell(m[s], 1), c2 = cell(m[s], 2);
    // the distinct neighbour bins (with fewer than 3 cells along a periodic direction the same
    // bin comes up more than once)
    near.clear();
    for (int dz = -1; dz <= 1; dz++)
      for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
          int k0 = c0 + dx, k1 = c1 + dy;
          const int k2 = c2 + dz;
          if (k2 < 0 || k2 >= nc[2]) continue;
          if (k0 < 0 || k0 >= nc[0]) {
            if (!px) continue;
            k0 = (k0 + nc[0]) % nc[0];
          }
          if (k1 < 0 || k1 >= nc[1]) {
            if (!py) continue;
            k1 = (k1 + nc[1]) % nc[1];
          }
          near.push_back(((size_t) k2 * nc[1] + k1) * nc[0] + k0);
        }
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    for (const size_t bin : near) {
      for (int t : bins[bin]) {
        if ((size_t) t <= s) continue;
        const auto &S = segs_[s], &T = segs_[t];
        if (S.first == T.first || S.first == T.second || S.second == T.first ||
            S.second == T.second)
          continue;
        const Vec3 sh(image(m[t].x - m[s].x, lx_) - (m[t].x - m[s].x),
                      image(m[t].y - m[s].y, ly_) - (m[t].y - m[s].y), 0.0);
        const Vec3 b0 = a[t] + sh, b1 = b[t] + sh;
        if (NCF::norm2(0.5 * (b0 + b1) - m[s]) > reach_ * reach_) continue;
        const NCF::ClosestPoints cp = NCF::closest_points_segments(a[s], b[s], b0, b1);
        closest = std::min(closest, std::sqrt(cp.dist2));
        const Vec3 nrm = NCF::cross(b[s] - a[s], b1 - b0);
        const std::uint64_t key = (std::uint64_t) s * n + (std::uint64_t) t;
        const bool interior = cp.s > 0.0 && cp.s < 1.0 && cp.t > 0.0 && cp.t < 1.0;
        if (!interior || NCF::norm(nrm) < 0.1 * NCF::norm(b[s] - a[s]) * NCF::norm(b1 - b0)) {
          side_.erase(key);
          continue;
        }
        const signed char now =
            NCF::dot(NCF::lerp(a[s], b[s], cp.s) - NCF::lerp(b0, b1, cp.t), nrm) > 0 ? 1 : -1;
        auto it = side_.find(key);
        if (it != side_.end()) {
          pairs_seen++;
          if (it->second != now) flips++;
          it->second = now;
        } else {
          side_.emplace(key, now);
        }
      }
    }
  }
}

}    // namespace ncftest
