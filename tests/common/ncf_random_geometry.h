/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF tests: random geometry shared by the engine-free unit tests (no LAMMPS).
------------------------------------------------------------------------- */

#ifndef NCF_RANDOM_GEOMETRY_H
#define NCF_RANDOM_GEOMETRY_H

#include "ncf_geometry.h"

#include <cmath>
#include <random>

namespace NCF_TEST {

// a direction drawn uniformly on the unit sphere
inline NCF::Vec3 random_unit_vector(std::mt19937 &rng)
{
  std::normal_distribution<double> g(0.0, 1.0);
  NCF::Vec3 v;
  do v = NCF::Vec3(g(rng), g(rng), g(rng));
  while (NCF::norm(v) < 1e-3);
  return (1.0 / NCF::norm(v)) * v;
}

// a kink of the given angle at a node n of a chain p-n-q, in a random plane: the directions e1
// (p -> n) and e2 (n -> q), and bn, the unit normal to the chain's mean direction in the plane of
// the kink, pointing to its convex side
struct Kink {
  NCF::Vec3 e1, e2, bn;
};
inline Kink random_kink(std::mt19937 &rng, double angle)
{
  const NCF::Vec3 t = random_unit_vector(rng);
  const NCF::Vec3 v = random_unit_vector(rng), b = v - NCF::dot(v, t) * t;
  Kink k;
  k.bn = (1.0 / NCF::norm(b)) * b;
  k.e1 = std::cos(0.5 * angle) * t + std::sin(0.5 * angle) * k.bn;
  k.e2 = std::cos(0.5 * angle) * t - std::sin(0.5 * angle) * k.bn;
  return k;
}

}    // namespace NCF_TEST

#endif
