/* ----------------------------------------------------------------------
   USER-NCF: engine-free algebra of the averaged periodic boundary conditions (see ncf_pbc.h)
------------------------------------------------------------------------- */

#include "ncf_pbc.h"

#include "ncf_input_error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace NCF {

int FaceMesh::cell_of(double u, double v) const
{
  double uw = std::fmod(u - u0, lu);
  if (uw < 0.0) uw += lu;
  int iu = (int) std::floor(uw / lu * nu);
  iu = std::min(std::max(iu, 0), nu - 1);
  const double span = vhi - vlo;
  int iv = span > 0.0 ? (int) std::floor((v - vlo) / span * nv) : 0;
  iv = std::min(std::max(iv, 0), nv - 1);
  return iv * nu + iu;
}

double FaceMesh::cell_u(int cell) const
{
  return u0 + (cell % nu + 0.5) * lu / nu;
}

double FaceMesh::cell_v(int cell) const
{
  return vlo + (cell / nu + 0.5) * (vhi - vlo) / nv;
}

namespace {
  // sorted distinct values (within tol); periodic values are wrapped into [0, period) first
  std::vector<double> distinct(std::vector<double> vals, double tol)
  {
    std::sort(vals.begin(), vals.end());
    std::vector<double> out;
    for (double v : vals)
      if (out.empty() || v - out.back() > tol) out.push_back(v);
    return out;
  }

  bool evenly_spaced(const std::vector<double> &v, double step, double tol)
  {
    for (std::size_t k = 1; k < v.size(); k++)
      if (std::fabs(v[k] - v[k - 1] - step) > tol) return false;
    return true;
  }
}    // namespace

FaceMesh auto_face_mesh(const std::vector<FaceNode> &nodes, double lu)
{
  FaceMesh m;
  m.lu = lu;
  std::vector<double> us, vs;
  int nlow = 0, nup = 0;
  double vmin = std::numeric_limits<double>::max(), vmax = -vmin;
  for (const auto &f : nodes) {
    vmin = std::min(vmin, f.v);
    vmax = std::max(vmax, f.v);
    if (f.side < 0) {
      double uw = std::fmod(f.u, lu);
      if (uw < 0.0) uw += lu;
      us.push_back(uw);
      vs.push_back(f.v);
      nlow++;
    } else
      nup++;
  }
  if (nodes.empty() || lu <= 0.0) return m;
  m.vlo = vmin;
  m.vhi = vmax;

  // a regular lattice of end points (sigma = 0): one cell per lattice point
  const double tol = 1e-9 * std::max(lu, vmax - vmin);
  const auto cu = distinct(us, tol), cv = distinct(vs, tol);
  const int ncol = (int) cu.size(), nrow = (int) cv.size();
  const double du = lu / ncol, dv = nrow > 1 ? (cv.back() - cv.front()) / (nrow - 1) : 0.0;
  if (ncol * nrow == nlow && nup == nlow && evenly_spaced(cu, du, 1e-6 * du) &&
      (nrow == 1 || evenly_spaced(cv, dv, 1e-6 * dv))) {
    m.nu = ncol;
    m.nv = nrow;
    m.u0 = cu.front() - 0.5 * du;
    m.vlo = nrow > 1 ? cv.front() - 0.5 * dv : vmin - 0.5;
    m.vhi = nrow > 1 ? cv.back() + 0.5 * dv : vmax + 0.5;
    return m;
  }

  // otherwise square cells of area lu lv / n, n = nodes per face
  const int n = std::max(1, (nlow + nup + 1) / 2);
  const double lv = vmax - vmin;
  if (n == 1) return m;
  if (lv <= 0.0) {
    m.nu = n;
    return m;
  }
  const double h = std::sqrt(lu * lv / n);
  m.nu = std::max(1, (int) std::lround(lu / h));
  m.nv = std::max(1, (int) std::lround(lv / h));
  if (m.nv == 1) m.nu = n;    // a thin face: one row of n cells
  if (m.nu == 1) m.nv = n;
  return m;
}

std::vector<int> face_groups(const FaceMesh &mesh, const std::vector<FaceNode> &nodes, int &ngroups)
{
  const int ncell = mesh.nu * mesh.nv;
  std::vector<int> lower(ncell, 0), upper(ncell, 0);
  std::vector<int> cell(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); i++) {
    cell[i] = mesh.cell_of(nodes[i].u, nodes[i].v);
    if (nodes[i].side < 0)
      lower[cell[i]]++;
    else
      upper[cell[i]]++;
  }
  const int nlow = std::accumulate(lower.begin(), lower.end(), 0);
  const int nup = std::accumulate(upper.begin(), upper.end(), 0);
  if (nlow == 0 || nup == 0)
    throw InputError("averaged periodic boundary: no end node on the " +
                     std::string(nlow == 0 ? "lower" : "upper") + " face of a face pair (" +
                     std::to_string(nlow) + " lower, " + std::to_string(nup) + " upper)");

  // union of cells; a group's position is the mean of its cells' centres (u periodic)
  std::vector<int> owner(ncell);
  std::iota(owner.begin(), owner.end(), 0);
  auto root = [&](int c) {
    while (owner[c] != c) c = owner[c] = owner[owner[c]];
    return c;
  };
  std::vector<int> glow = lower, gup = upper;
  std::vector<double> su(ncell), sv(ncell), cnt(ncell, 1.0);
  // accumulate u on a circle so that merging across the periodic seam averages correctly
  std::vector<double> scos(ncell), ssin(ncell);
  for (int c = 0; c < ncell; c++) {
    const double phi = 2.0 * M_PI * mesh.cell_u(c) / mesh.lu;
    scos[c] = std::cos(phi);
    ssin[c] = std::sin(phi);
    sv[c] = mesh.cell_v(c);
  }
  auto centre_u = [&](int g) {
    double phi = std::atan2(ssin[g], scos[g]);
    if (phi < 0.0) phi += 2.0 * M_PI;
    return phi / (2.0 * M_PI) * mesh.lu;
  };
  auto distance2 = [&](int a, int b) {
    double du = std::fabs(centre_u(a) - centre_u(b));
    du = std::min(du, mesh.lu - du);
    const double dv = sv[a] / cnt[a] - sv[b] / cnt[b];
    return du * du + dv * dv;
  };

  // merge groups lacking a node on either face into their nearest non-empty neighbour, the one
  // with the fewest nodes first, until every group with nodes has nodes on both faces
  while (true) {
    int worst = -1;
    for (int c = 0; c < ncell; c++) {
      if (root(c) != c) continue;
      if (glow[c] + gup[c] == 0) continue;    // an empty cell constrains nothing
      if (glow[c] > 0 && gup[c] > 0) continue;
      if (worst < 0 || glow[c] + gup[c] < glow[worst] + gup[worst]) worst = c;
    }
    if (worst < 0) break;
    // a group with nodes on one face only joins its nearest neighbour with nodes
    int best = -1;
    double bestd = std::numeric_limits<double>::max();
    for (int c = 0; c < ncell; c++) {
      if (root(c) != c || c == worst) continue;
      if (glow[c] + gup[c] == 0) continue;
      const double d = distance2(worst, c);
      if (d < bestd) {
        bestd = d;
        best = c;
      }
    }
    if (best < 0) break;    // cannot happen: both faces have nodes somewhere
    owner[worst] = best;
    glow[best] += glow[worst];
    gup[best] += gup[worst];
    scos[best] += scos[worst];
    ssin[best] += ssin[worst];
    sv[best] += sv[worst];
    cnt[best] += cnt[worst];
  }

  // number the complete groups in order of their lowest cell
  std::vector<int> index(ncell, -1);
  ngroups = 0;
  for (int c = 0; c < ncell; c++) {
    const int r = root(c);
    if (index[r] < 0 && glow[r] > 0 && gup[r] > 0) index[r] = ngroups++;
  }
  std::vector<int> group(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); i++) group[i] = index[root(cell[i])];
  return group;
}

std::vector<double> face_weights(const std::vector<FaceNode> &nodes, const std::vector<int> &group,
                                 int ngroups)
{
  std::vector<int> nlow(ngroups, 0), nup(ngroups, 0);
  for (std::size_t i = 0; i < nodes.size(); i++) {
    if (nodes[i].side < 0)
      nlow[group[i]]++;
    else
      nup[group[i]]++;
  }
  std::vector<double> w(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); i++)
    w[i] = nodes[i].side < 0 ? -1.0 / nlow[group[i]] : 1.0 / nup[group[i]];
  return w;
}

}    // namespace NCF
