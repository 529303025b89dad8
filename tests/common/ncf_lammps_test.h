/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF test harness: a LAMMPS instance driven through its C++ library interface, with the
   plugin auto-loaded from LAMMPS_PLUGIN_PATH (set by ctest to the build folder).
------------------------------------------------------------------------- */

#ifndef NCF_LAMMPS_TEST_H
#define NCF_LAMMPS_TEST_H

#include <mpi.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace ncftest {

// Path of a file in the source tree (e.g. "potentials/ncf.materials").
std::string source_path(const std::string &relative);

// A fresh, empty folder for one test's files: <build folder>/test-output/<name> (the build folder
// is $NCF_BUILD, else the one CMake configured; never the source tree nor the working
// directory). Removed by nobody: it lives in the build tree.
std::string scratch_dir(const std::string &name);

class Lammps {
 public:
  // comm: the ranks that run this instance (MPI_COMM_WORLD or a split of it)
  explicit Lammps(MPI_Comm comm = MPI_COMM_WORLD, const std::string &log = "none");
  ~Lammps();
  Lammps(const Lammps &) = delete;
  Lammps &operator=(const Lammps &) = delete;

  // run LAMMPS commands: one line, or a block of lines
  void cmd(const std::string &line);
  void cmds(const std::string &block);

  // thermo keyword or equal-style expression evaluated now, e.g. value("pe"), value("v_x")
  double value(const std::string &expression);

  // all atoms, ordered by tag (tags must be 1..N): unwrapped positions, velocities, forces
  std::vector<double> positions();
  std::vector<double> velocities();
  std::vector<double> forces();

  // d(energy)/d(coordinate dim of atom id) by central differences of step h around its current
  // value x (run 0 at x + h and x - h, then the atom put back at x); energy: a thermo keyword
  double energy_derivative(const std::string &energy, int id, int dim, double x, double h);

  // per-bond reference lengths stored by bond ncf/chain, keyed by (lower tag, higher tag), all ranks
  std::map<std::pair<long, long>, double> reference_lengths();

  LAMMPS_NS::LAMMPS *lmp = nullptr;

 private:
  std::vector<double> gather3(const char *name, bool unwrap);
};

// Runs f and returns the text of the LAMMPS error it raised ("" if none).
std::string error_of(const std::function<void()> &f);

// max_i |a_i - b_i|
double max_abs_diff(const std::vector<double> &a, const std::vector<double> &b);

// MPI helpers for the mpi tests
int world_rank();
int world_size();

// Runs f on a communicator of the first n ranks of MPI_COMM_WORLD (the other ranks wait), then
// a barrier: the way the mpi tests run one scene on 1, 2 and 4 ranks.
void on_ranks(int n, const std::function<void(MPI_Comm)> &f);

}    // namespace ncftest

#endif
