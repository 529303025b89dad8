// Scenes for the pair ncf/contact tests: chains as polylines written to a LAMMPS data file
// (atom_style bond, molecule ID = chain ID, one bond type), and a brute-force evaluation of the
// contact law over all pairs of a scene. Shared by the integration and mpi
// tests of pair ncf/contact (header only, not a test on its own).

#ifndef TEST_PAIR_CONTACT_SCENE_H
#define TEST_PAIR_CONTACT_SCENE_H

#include "ncf_contact.h"
#include "ncf_geometry.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace contactscene {

struct Chain {
  std::vector<std::array<double, 3>> x;
  int type = 1;
};

struct Box {
  double lo[3] = {-1e-3, -1e-3, -1e-3}, hi[3] = {1e-3, 1e-3, 1e-3};
};

// node mass of a 69 um chain of carbon (phi = 0.5, rho_c = 890 kg/m^3) per 0.2 mm
constexpr double DIAM = 69e-6;
constexpr double RHO_A = 890.0 * M_PI * 0.25 * DIAM * DIAM;    // mass per length [kg/m]

inline Chain straight(std::array<double, 3> a, std::array<double, 3> b, int nseg, int type = 1)
{
  Chain c;
  c.type = type;
  for (int k = 0; k <= nseg; k++) {
    const double t = double(k) / nseg;
    c.x.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])});
  }
  return c;
}

// writes the chains; masses per type (lumped: rho_a * mesh); ntypes >= max type. ids: the atom ID
// of each node, in the order of the chains and their nodes (default 1, 2, ...: chain after chain)
inline std::string write_data(const std::string &path, const std::vector<Chain> &chains,
                              const Box &box, double node_mass, int ntypes = 1,
                              const std::vector<int> &ids = {})
{
  auto id_of = [&ids](int k) {
    return ids.empty() ? k + 1 : ids[k];
  };
  FILE *fp = fopen(path.c_str(), "w");
  int natoms = 0, nbonds = 0;
  for (const auto &c : chains) {
    natoms += (int) c.x.size();
    nbonds += (int) c.x.size() - 1;
  }
  fprintf(fp, "contact scene\n\n%d atoms\n%d atom types\n%d bonds\n1 bond types\n\n", natoms,
          ntypes, nbonds);
  fprintf(fp, "%.17g %.17g xlo xhi\n%.17g %.17g ylo yhi\n%.17g %.17g zlo zhi\n\n", box.lo[0],
          box.hi[0], box.lo[1], box.hi[1], box.lo[2], box.hi[2]);
  fprintf(fp, "Masses\n\n");
  for (int t = 1; t <= ntypes; t++) fprintf(fp, "%d %.17g\n", t, node_mass);
  fprintf(fp, "\nAtoms # bond\n\n");
  int id = 0;
  for (size_t c = 0; c < chains.size(); c++)
    for (const auto &p : chains[c].x) {
      // wrap into a periodic box (the bond across the boundary is fine)
      double q[3];
      int img[3];
      for (int d = 0; d < 3; d++) {
        const double len = box.hi[d] - box.lo[d];
        img[d] = (int) std::floor((p[d] - box.lo[d]) / len);
        q[d] = p[d] - img[d] * len;
      }
      fprintf(fp, "%d %d %d %.17g %.17g %.17g %d %d %d\n", id_of(id++), (int) c + 1, chains[c].type,
              q[0], q[1], q[2], img[0], img[1], img[2]);
    }
  fprintf(fp, "\nBonds\n\n");
  id = 0;
  int b = 0;
  for (const auto &c : chains) {
    for (size_t k = 0; k + 1 < c.x.size(); k++)
      fprintf(fp, "%d 1 %d %d\n", ++b, id_of(id + (int) k), id_of(id + (int) k + 1));
    id += (int) c.x.size();
  }
  fclose(fp);
  return path;
}

// a thin chain wrapped around a thick one (thick: type 2, first in the list): the thick chain
// straight along x from x0 to x0 + 1.5 mm in 3 segments of 0.5 mm, the thin one (type 1) a helix
// around the x axis from x 0.05 to 1.05 mm, pitch 0.1 mm, 12 segments per turn (120 in all),
// of radius 0.9 times the contact distance of the two (thick diameter dthick, thin DIAM): every
// thin segment beside a thick one touches it, up to 60 on one thick segment
inline std::vector<Chain> wrapped(double x0, double dthick)
{
  Chain thick = straight({x0, 0.0, 0.0}, {x0 + 1.5e-3, 0.0, 0.0}, 3, 2);
  Chain thin;
  thin.type = 1;
  const double r = 0.9 * 0.5 * (dthick + DIAM), pitch = 1e-4;
  for (int k = 0; k <= 120; k++) {
    const double a = 2.0 * M_PI * k / 12.0;
    thin.x.push_back({0.05e-3 + pitch * k / 12.0, r * std::cos(a), r * std::sin(a)});
  }
  return {thick, thin};
}

// thin chains (type 1) crossing a thick one (type 2, first in the list) at right angles, every
// contact inside a segment of both (so that the contact law is the same whichever segment is A):
// the thick chain along x through x0 + (-2, -1.5, 1.5, 2) mm (a middle segment of 3 mm), 35 thin
// chains at x = -1.2, -1.125, ... 1.35 mm, each 1.2 mm long in 3 segments, in turn above (along
// y), beside (along z), below and on the other side of it, their axes 0.9 times the contact
// distance of the two from its axis (thick diameter dthick, thin DIAM): the middle segment of the
// thick chain touches the middle segments of all 35
inline std::vector<Chain> comb(double x0, double dthick)
{
  std::vector<Chain> out;
  Chain thick;
  thick.type = 2;
  for (double x : {-2e-3, -1.5e-3, 1.5e-3, 2e-3}) thick.x.push_back({x0 + x, 0.0, 0.0});
  out.push_back(thick);
  const double r = 0.9 * 0.5 * (dthick + DIAM), h = 0.6e-3;
  for (int j = 0; j < 35; j++) {
    const double x = -1.2e-3 + 0.075e-3 * j, side = (j % 4) < 2 ? r : -r;
    if (j % 2 == 0)
      out.push_back(straight({x, -h, side}, {x, h, side}, 3));
    else
      out.push_back(straight({x, side, -h}, {x, side, h}, 3));
  }
  return out;
}

// a random mat: nlayers layers of chains with random in-plane angles, periodic in x and y
// (box side `side`), layer spacing `dz` (< DIAM: the layers start slightly pressed together)
inline std::vector<Chain> random_mat(int nchains, int nlayers, double side, double mesh, double dz,
                                     unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Chain> out;
  const double len = 0.8 * side;
  const int nseg = (int) std::lround(len / mesh);
  for (int c = 0; c < nchains; c++) {
    const int layer = c % nlayers;
    const double ang = M_PI * u(rng);
    const double cx = side * u(rng), cy = side * u(rng);
    const double z = (layer + 0.5) * dz;
    const double ex = 0.5 * len * std::cos(ang), ey = 0.5 * len * std::sin(ang);
    out.push_back(straight({cx - ex, cy - ey, z}, {cx + ex, cy + ey, z}, nseg));
  }
  return out;
}

// a layered mat: nlayers layers of `per_layer` parallel chains each (layer angle random), chains
// of one layer at least 1.5 diameters apart in the plane (periodic images included), layer
// spacing dz; periodic in x and y with box side `side`, chains 0.8 side long
inline std::vector<Chain> layered_mat(int nlayers, int per_layer, double side, double mesh,
                                      double dz, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Chain> out;
  const double len = 0.8 * side;
  const int nseg = (int) std::lround(len / mesh);
  for (int layer = 0; layer < nlayers; layer++) {
    const double ang = M_PI * u(rng);
    const double ex = 0.5 * len * std::cos(ang), ey = 0.5 * len * std::sin(ang);
    const double z = (layer + 0.5) * dz;
    std::vector<std::array<double, 4>> placed;    // 2D ends of the chains of this layer
    int tries = 0;
    while ((int) placed.size() < per_layer && tries++ < 100000) {
      const double cx = side * u(rng), cy = side * u(rng);
      const NCF::Vec3 p0(cx - ex, cy - ey, 0), p1(cx + ex, cy + ey, 0);
      bool ok = true;
      for (const auto &q : placed)
        for (int ix = -1; ix <= 1 && ok; ix++)
          for (int iy = -1; iy <= 1 && ok; iy++) {
            const NCF::Vec3 sh(ix * side, iy * side, 0);
            auto cp = NCF::closest_points_segments(p0 + sh, p1 + sh, NCF::Vec3(q[0], q[1], 0),
                                                   NCF::Vec3(q[2], q[3], 0));
            if (cp.dist2 < 1.44 * DIAM * DIAM) ok = false;
          }
      if (!ok) continue;
      placed.push_back({p0.x, p0.y, p1.x, p1.y});
      out.push_back(straight({p0.x, p0.y, z}, {p1.x, p1.y, z}, nseg));
    }
  }
  return out;
}

// A brute-force reference of pair ncf/contact (no list, no cutoff, no ranks), with the pair
// style's defaults: ramp, core, end cap
inline constexpr double RAMP_FRAC = 0.25;
inline constexpr double CORE = NCF::DEFAULT_CORE;
inline constexpr double ENDCAP_FRAC = NCF::DEFAULT_ENDCAP;

struct Brute {
  int contacts = 0, caps = 0;
  double energy = 0.0;    // frictionless contact energy
  double pensum = 0.0;    // sum of the penetrations of the segment pairs
};

// every segment pair (A, B) of the chains that shares no node, key(A) < key(B), B's periodic
// image nearest to A (x and y periodic with period `side`); and every cap of an interior node n
// (chain neighbours p, q) with a segment A that touches neither of n's segments
inline Brute brute_force(const std::vector<Chain> &chains, const std::vector<double> &x,
                         double side, double kn)
{
  struct Seg {
    int a0, a1;    // node indices (0-based, = tag - 1); a0 < a1
  };
  std::vector<Seg> segs;
  std::vector<std::array<int, 3>> interior;    // p, n, q
  std::vector<bool> free_end;                  // per node: one bond only
  int id = 0;
  for (const auto &c : chains) {
    const int n = (int) c.x.size();
    for (int k = 0; k < n; k++) free_end.push_back(k == 0 || k == n - 1);
    for (int k = 0; k + 1 < n; k++) segs.push_back({id + k, id + k + 1});
    for (int k = 1; k + 1 < n; k++) interior.push_back({id + k - 1, id + k, id + k + 1});
    id += n;
  }
  auto P = [&](int n) {
    return NCF::Vec3(&x[3 * n]);
  };
  // shift that brings the point b next to the point a
  auto image = [&](const NCF::Vec3 &a, const NCF::Vec3 &b) {
    return NCF::Vec3(-side * std::round((b.x - a.x) / side), -side * std::round((b.y - a.y) / side),
                     0.0);
  };
  const double dc = DIAM, e = RAMP_FRAC * DIAM;
  Brute out;
  for (size_t i = 0; i < segs.size(); i++) {
    const NCF::Vec3 a0 = P(segs[i].a0), a1 = P(segs[i].a1);
    for (size_t j = i + 1; j < segs.size(); j++) {
      const Seg &A = segs[i], &B = segs[j];    // keys ascend with the index
      if (A.a0 == B.a0 || A.a0 == B.a1 || A.a1 == B.a0 || A.a1 == B.a1) continue;
      const NCF::Vec3 sh = image(a0, P(B.a0));
      NCF::ContactOptions opt;
      opt.core = CORE;
      const int nodes[4] = {A.a0, A.a1, B.a0, B.a1};
      for (int k = 0; k < 4; k++) opt.ext[k] = free_end[nodes[k]] ? ENDCAP_FRAC * dc : 0.0;
      const auto c = NCF::chain_contact(a0, a1, P(B.a0) + sh, P(B.a1) + sh, dc, kn, e, true, opt);
      if (!c.active) continue;
      out.contacts++;
      out.energy += c.energy;
      out.pensum += c.penetration;
    }
    for (const auto &pnq : interior) {
      const Seg &A = segs[i];
      bool excluded = false;
      for (int m : pnq) excluded = excluded || m == A.a0 || m == A.a1;
      if (excluded) continue;
      const NCF::Vec3 sh = image(a0, P(pnq[1]));
      const auto c = NCF::node_contact(a0, a1, P(pnq[0]) + sh, P(pnq[1]) + sh, P(pnq[2]) + sh, dc,
                                       NCF::CAP_WEIGHT * kn, e, CORE);
      if (!c.active) continue;
      out.caps++;
      out.energy += c.energy;
    }
  }
  return out;
}

}    // namespace contactscene

#endif
