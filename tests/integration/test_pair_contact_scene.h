// Scenes for the pair ncf/contact tests: chains as polylines written to a LAMMPS data file
// (atom_style bond, molecule ID = chain ID, one bond type). Shared by the integration and mpi
// tests of pair ncf/contact (header only, not a test on its own).

#ifndef TEST_PAIR_CONTACT_SCENE_H
#define TEST_PAIR_CONTACT_SCENE_H

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

// writes the chains; masses per type (lumped: rho_a * mesh); ntypes >= max type
inline std::string write_data(const std::string &path, const std::vector<Chain> &chains,
                              const Box &box, double node_mass, int ntypes = 1)
{
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
      fprintf(fp, "%d %d %d %.17g %.17g %.17g %d %d %d\n", ++id, (int) c + 1, chains[c].type, q[0],
              q[1], q[2], img[0], img[1], img[2]);
    }
  fprintf(fp, "\nBonds\n\n");
  id = 0;
  int b = 0;
  for (const auto &c : chains) {
    for (size_t k = 0; k + 1 < c.x.size(); k++)
      fprintf(fp, "%d 1 %d %d\n", ++b, id + (int) k + 1, id + (int) k + 2);
    id += (int) c.x.size();
  }
  fclose(fp);
  return path;
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

}    // namespace contactscene

#endif
