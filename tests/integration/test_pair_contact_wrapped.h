// The scenes of the pair ncf/contact growth tests (integration and mpi): a thin chain wrapped 10
// times around a thick one (contactscene::wrapped), or thin chains crossing a thick one
// (contactscene::comb); the thick chain pulled along its axis at 0.5 m/s (fix move), the thin chain held where it is, friction on (nothing integrated but the fix move, so the time
// step checks of the styles are off). Header only.

#ifndef TEST_PAIR_CONTACT_WRAPPED_H
#define TEST_PAIR_CONTACT_WRAPPED_H

#include "ncf_lammps_test.h"
#include "test_pair_contact_scene.h"

#include "atom.h"
#include "fix.h"
#include "lammps.h"
#include "modify.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace wrappedscene {

using namespace contactscene;
using ncftest::Lammps;

const double DTHICK = 3e-4;
const double NODE_MASS = RHO_A * 1e-4;
const int NTHICK = 4;      // nodes of the thick chain (first in the chain list)
const int NATOMS = 125;    // and of both chains

inline Box wrapped_box()
{
  Box b;
  b.lo[0] = -2e-3;
  b.hi[0] = 2e-3;
  b.lo[1] = b.lo[2] = -0.5e-3;
  b.hi[1] = b.hi[2] = 0.5e-3;
  return b;
}

// the data file of the wrapped scene with the thick chain at x x0 .. x0 + 1.5 mm (default -1.6
// mm: its end cap reaches 11 segments of the helix, which begins at 0.05 mm); ids as write_data
inline std::string scene(const std::string &path, const std::vector<int> &ids = {},
                         double x0 = -1.6e-3)
{
  return write_data(path, wrapped(x0, DTHICK), wrapped_box(), NODE_MASS, 2, ids);
}

// the comb (contactscene::comb, thick chain first as there) at x0 = 0
const int NCOMB = 4 + 35 * 4;
inline std::string comb_scene(const std::string &path, const std::vector<int> &ids = {})
{
  Box b;
  b.lo[0] = -2.5e-3;
  b.hi[0] = 2.8e-3;
  b.lo[1] = b.lo[2] = -0.8e-3;
  b.hi[1] = b.hi[2] = 0.8e-3;
  return write_data(path, comb(0.0, DTHICK), b, NODE_MASS, 2, ids);
}

inline const char *STYLE = "pair_style ncf/contact dtcheck no";

// everything after read_data / read_restart
inline std::string settings(const std::string &style, double speed = 0.5)
{
  return "bond_coeff 1 modulus 120e9 diameter 69e-6\n" + style +
      "\npair_coeff * * kn 1e8 mu 0.3 kt 1.0 diameter 69e-6\n"
      "pair_coeff 2 2 kn 1e8 mu 0.3 kt 1.0 diameter 3e-4\n"
      "comm_modify vel yes\nneighbor 2e-5 bin\nneigh_modify every 1 delay 0 check yes\n"
      "group thick type 2\nfix move thick move linear " +
      std::to_string(speed) +
      " 0.0 0.0\ntimestep 1e-6\n"
      "compute pc all pair ncf/contact\nthermo_style custom step pe c_pc[1]\nthermo 0\n";
}

inline void define(Lammps &l, const std::string &data, const std::string &style = STYLE,
                   double speed = 0.5)
{
  l.cmds("units si\natom_style bond\natom_modify map array sort 0 0\nboundary f f f\n"
         "bond_style ncf/chain dtcheck no\nread_data " +
         data + "\n" + settings(style, speed));
}

// "slots" (per node) or "grows" of the history store, fix NCF_CONTACT_HISTORY (-1 without it)
inline int store_int(Lammps &l, const char *name)
{
  auto *f = l.lmp->modify->get_fix_by_id("NCF_CONTACT_HISTORY");
  if (!f) return -1;
  int dim = -1;
  auto *p = static_cast<int *>(f->extract(name, dim));
  return p ? *p : -1;
}

inline double largest(const std::vector<double> &v)
{
  double m = 0.0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

// per-atom values (3 each) of atoms numbered by `ids` (ids[k]: the ID of the k-th node in chain
// order, as write_data takes them), back in chain order
inline std::vector<double> in_chain_order(const std::vector<double> &f, const std::vector<int> &ids)
{
  std::vector<double> out(f.size());
  for (size_t k = 0; k < ids.size(); k++)
    for (int d = 0; d < 3; d++) out[3 * k + d] = f[3 * (ids[k] - 1) + d];
  return out;
}

// the friction history in the store (fix NCF_CONTACT_HISTORY, rows written at the end of every
// run) of the atoms of this rank: per contact (owner node ID, IDs of the other three nodes) its
// slip vector
using History = std::map<std::array<double, 4>, std::array<double, 3>>;
inline History history_of(Lammps &l)
{
  History h;
  auto *f = l.lmp->modify->get_fix_by_id("NCF_CONTACT_HISTORY");
  int dim = -1;
  auto **rows = f ? static_cast<double **>(f->extract("rows", dim)) : nullptr;
  if (!rows) return h;
  LAMMPS_NS::Atom *atom = l.lmp->atom;
  for (int i = 0; i < atom->nlocal; i++) {
    const double *r = rows[i];
    for (int k = 0; k < (int) r[0]; k++) {
      const double *s = r + 1 + 6 * k;
      h[{(double) atom->tag[i], s[0], s[1], s[2]}] = {s[3], s[4], s[5]};
    }
  }
  return h;
}

// the most contacts a node of this rank has in the store
inline int most_contacts(Lammps &l)
{
  std::map<double, int> n;
  for (const auto &kv : history_of(l)) n[kv.first[0]]++;
  int m = 0;
  for (const auto &kv : n) m = std::max(m, kv.second);
  return m;
}

// the IDs of the thin chains' nodes first, then the thick chain's (natoms nodes in all)
inline std::vector<int> thin_first_ids(int natoms)
{
  std::vector<int> ids(natoms);
  for (int k = 0; k < natoms; k++) ids[k] = k < NTHICK ? natoms - NTHICK + k + 1 : k - NTHICK + 1;
  return ids;
}

}    // namespace wrappedscene

#endif
