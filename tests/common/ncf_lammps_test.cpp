/* ----------------------------------------------------------------------
   USER-NCF test harness (see ncf_lammps_test.h)
------------------------------------------------------------------------- */

#include "ncf_lammps_test.h"

#include "atom.h"
#include "exceptions.h"
#include "input.h"
#include "lammps.h"
#include "library.h"
#include "variable.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace ncftest {

std::string source_path(const std::string &relative)
{
  return std::string(NCF_SOURCE_DIR) + "/" + relative;
}

std::string scratch_dir(const std::string &name)
{
  namespace fs = std::filesystem;
  // under the build folder ($NCF_BUILD, which ctest sets, else the one the tests were configured
  // in), never in the source tree or wherever the test binary was started
  const char *build = getenv("NCF_BUILD");
  const fs::path root = (build && *build) ? fs::path(build) : fs::path(NCF_BINARY_DIR);
  fs::path p = root / "test-output" / name;
  if (world_rank() == 0) {
    fs::remove_all(p);
    fs::create_directories(p);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return p.string();
}

Lammps::Lammps(MPI_Comm comm, const std::string &log)
{
  // the plugin is auto-loaded from LAMMPS_PLUGIN_PATH (ctest sets it); running a test binary by
  // hand works too
  if (!getenv("LAMMPS_PLUGIN_PATH")) {
    const std::string dir = std::filesystem::path(NCF_PLUGIN_FILE).parent_path().string();
    setenv("LAMMPS_PLUGIN_PATH", dir.c_str(), 1);
  }
  std::vector<std::string> args = {"ncftest", "-log",    log,    "-echo",
                                   "none",    "-screen", "none", "-nocite"};
  std::vector<char *> argv;
  for (auto &a : args) argv.push_back(a.data());
  lmp = new LAMMPS_NS::LAMMPS((int) argv.size(), argv.data(), comm);
}

Lammps::~Lammps()
{
  delete lmp;
}

void Lammps::cmd(const std::string &line)
{
  lmp->input->one(line);
}

void Lammps::cmds(const std::string &block)
{
  std::istringstream in(block);
  std::string line;
  while (std::getline(in, line)) {
    auto pos = line.find_first_not_of(" \t");
    if (pos == std::string::npos || line[pos] == '#') continue;
    cmd(line);
  }
}

double Lammps::value(const std::string &expression)
{
  return lmp->input->variable->compute_equal(expression);
}

std::vector<double> Lammps::gather3(const char *name, bool unwrap)
{
  const long natoms = (long) lammps_get_natoms(lmp);
  std::vector<double> out(3 * natoms);
  lammps_gather_atoms(lmp, name, 1, 3, out.data());
  if (unwrap) {
    std::vector<int> image(natoms);
    lammps_gather_atoms(lmp, "image", 0, 1, image.data());
    double lo[3], hi[3], xy, yz, xz;
    int pflags[3], boxflag;
    lammps_extract_box(lmp, lo, hi, &xy, &yz, &xz, pflags, &boxflag);
    for (long i = 0; i < natoms; i++) {
      const int img = image[i];
      const int ix = (img & 1023) - 512, iy = (img >> 10 & 1023) - 512, iz = (img >> 20) - 512;
      out[3 * i + 0] += ix * (hi[0] - lo[0]) + iy * xy + iz * xz;
      out[3 * i + 1] += iy * (hi[1] - lo[1]) + iz * yz;
      out[3 * i + 2] += iz * (hi[2] - lo[2]);
    }
  }
  return out;
}

std::vector<double> Lammps::positions()
{
  return gather3("x", true);
}
std::vector<double> Lammps::velocities()
{
  return gather3("v", false);
}
std::vector<double> Lammps::forces()
{
  return gather3("f", false);
}

double Lammps::energy_derivative(const std::string &energy, int id, int dim, double x, double h)
{
  auto place = [&](double at) {
    cmd(fmt::format("set atom {} {:c} {:.17g}", id, "xyz"[dim], at));
  };
  place(x + h);
  cmd("run 0");
  const double ep = value(energy);
  place(x - h);
  cmd("run 0");
  const double em = value(energy);
  place(x);
  return (ep - em) / (2 * h);
}

std::map<std::pair<long, long>, double> Lammps::reference_lengths()
{
  std::map<std::pair<long, long>, double> result;
  LAMMPS_NS::Atom *atom = lmp->atom;
  int flag, cols;
  const int idt = atom->find_custom("ncf_dtag", flag, cols);
  const int il0 = atom->find_custom("ncf_l0", flag, cols);
  if (idt < 0 || il0 < 0) return result;
  std::vector<double> mine;
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < cols; k++) {
      const int d = atom->iarray[idt][i][k];
      if (d == 0) continue;
      const long a = (long) atom->tag[i], b = a + d;
      mine.insert(mine.end(),
                  {(double) std::min(a, b), (double) std::max(a, b), atom->darray[il0][i][k]});
    }
  MPI_Comm comm = lmp->world;
  int nprocs;
  MPI_Comm_size(comm, &nprocs);
  int n = (int) mine.size();
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int p = 1; p < nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<double> all(displs[nprocs - 1] + counts[nprocs - 1]);
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE,
                 comm);
  for (std::size_t m = 0; m < all.size(); m += 3) {
    auto key = std::make_pair((long) all[m], (long) all[m + 1]);
    auto it = result.find(key);
    if (it != result.end() && it->second != all[m + 2])
      throw std::runtime_error("the two copies of L0 of bond " + std::to_string(key.first) + "-" +
                               std::to_string(key.second) + " differ");
    result[key] = all[m + 2];
  }
  return result;
}

std::string error_of(const std::function<void()> &f)
{
  try {
    f();
  } catch (LAMMPS_NS::LAMMPSAbortException &e) {
    return e.what();
  } catch (LAMMPS_NS::LAMMPSException &e) {
    return e.what();
  }
  return "";
}

double max_abs_diff(const std::vector<double> &a, const std::vector<double> &b)
{
  if (a.size() != b.size()) return INFINITY;
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); i++) m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

int world_rank()
{
  int r;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int world_size()
{
  int s;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

void on_ranks(int n, const std::function<void(MPI_Comm)> &f)
{
  MPI_Comm comm;
  MPI_Comm_split(MPI_COMM_WORLD, world_rank() < n ? 0 : MPI_UNDEFINED, world_rank(), &comm);
  if (comm != MPI_COMM_NULL) {
    // an error on some ranks must not leave the others waiting in the barrier below
    try {
      f(comm);
    } catch (LAMMPS_NS::LAMMPSAbortException &e) {
      // error->one: raised on some ranks of the instance only, while the others wait for them
      // in a collective call that never ends; stop the whole test at once (as LAMMPS does)
      int size;
      MPI_Comm_size(comm, &size);
      if (size > 1) {
        std::fprintf(
            stderr,
            "on %d rank(s), world rank %d: %s\n[aborting: the other ranks would wait forever]\n", n,
            world_rank(), e.what());
        std::fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, 1);
      }
      ADD_FAILURE() << "on " << n << " rank(s), world rank " << world_rank() << ": " << e.what();
    } catch (std::exception &e) {
      ADD_FAILURE() << "on " << n << " rank(s), world rank " << world_rank() << ": " << e.what();
    }
    MPI_Comm_free(&comm);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

}    // namespace ncftest
