// The mat of the mpi tests of pair ncf/contact: five layers of ten chains in a periodic square,
// consecutive layers slightly pressed together, written once per test binary by rank 0 (header
// only, shared by test_pair_contact_ranks and test_split_runs_mpi).

#ifndef MPI_LAYERED_MAT_H
#define MPI_LAYERED_MAT_H

#include "../integration/test_pair_contact_scene.h"
#include "ncf_lammps_test.h"

#include <mpi.h>

#include <string>
#include <vector>

namespace mpimat {

const double SIDE = 1.5e-3;
const double DZ =
    0.97 * contactscene::DIAM;          // consecutive layers start slightly pressed together
const int NLAYER = 5, PERLAYER = 10;    // 50 chains

// the chains of the mat (every rank: the brute-force reference of the contacts needs them)
inline std::vector<contactscene::Chain> chains()
{
  return contactscene::layered_mat(NLAYER, PERLAYER, SIDE, 1e-4, DZ, 17);
}

// the data file of the mat in the test folder `name` (written on the first call)
inline std::string scene_data(const std::string &name)
{
  static std::string path;
  if (path.empty()) {
    auto dir = ncftest::scratch_dir(name);
    contactscene::Box box;
    box.lo[0] = box.lo[1] = 0.0;
    box.hi[0] = box.hi[1] = SIDE;
    box.lo[2] = -contactscene::DIAM;
    box.hi[2] = (NLAYER - 0.5) * DZ + 0.6 * contactscene::DIAM;
    path = dir + "/mat.data";
    if (ncftest::world_rank() == 0)
      contactscene::write_data(path, chains(), box, contactscene::RHO_A * 1e-4);
    MPI_Barrier(MPI_COMM_WORLD);
  }
  return path;
}

}    // namespace mpimat

#endif
