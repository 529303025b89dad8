/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF test scenes shared by the integration and mpi tests
------------------------------------------------------------------------- */

#ifndef NCF_SCENES_H
#define NCF_SCENES_H

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace ncftest {

// a mat of chains crossing a 2.0 x 1.6 x 1.0 mm box once along x
constexpr double MAT_LX = 2.0e-3, MAT_LY = 1.6e-3, MAT_LZ = 1.0e-3;

struct Mat {
  std::string path, masses;    // data file; LAMMPS commands setting the lumped node masses
  int nchain = 0, nper = 0;    // nodes per chain (open chains: nel+1 nodes, both ends on faces)
};

// Chains crossing the box once along x at angles drawn from N(0, sigma), with their end nodes on
// the x faces (face codes in an NCF_NODE section: i_ncf_layer i_ncf_end). ring = true closes the
// same chains across the x boundary instead (ordinary periodicity, one node fewer per chain).
// Needs per-atom masses (fix property/atom rmass) and reads with "fix NCF_NODE NULL NCF_NODE".
Mat write_mat(const std::string &dir, double sigma_deg, unsigned seed, bool ring = false,
              int ny = 8, int nz = 3, int nel = 10);

// face code of every atom of a mat, in tag order
std::vector<int> face_codes(const Mat &mat, bool ring = false);

class Lammps;
// Reads a mat into an empty LAMMPS instance (units si, bond ncf/chain with the CT24 chain,
// lumped per-atom masses, p p f box) and defines the group "ends" of its end nodes.
void load_mat(Lammps &l, const Mat &mat);

// The same scene for every rank count: the data file names of a mat written by rank 0 into dir.
Mat mat_files(const std::string &dir, bool ring = false);

// The same mat scene on 1, 2 and 4 ranks (the mpi tests): rank 0 writes the mat into dir, every
// sub-communicator loads it, runs `commands` and reports the positions before and after and the
// value of `expression` at the end. Results are valid on world rank 0.
struct RankRun {
  int nprocs = 0;
  double value = 0.0;
  std::vector<double> x0, x;
};
std::vector<RankRun> mat_on_1_2_4_ranks(const std::string &dir, unsigned seed,
                                        const std::string &commands, const std::string &expression);

// Checks on world rank 0 that the runs used 1, 2 and 4 ranks, that the scene moved by more than
// `moved` and that 2 and 4 ranks agree with 1 rank to `tol` (absolute, m); prints the differences
void expect_same_on_ranks(const std::vector<RankRun> &r, double moved, double tol,
                          const char *what);

// A LAMMPS data file written by ncf-gen, read back: counts, bonds (tags as in the file) with their
// reference lengths (NCF_CHAIN_L0 section), atom types, layer and end face codes (NCF_NODE).
struct Data {
  long atoms = 0, bonds = 0;
  std::vector<std::pair<long, long>> bond;    // tags as in the file
  std::vector<double> l0;                     // per bond
  std::map<long, int> type, end, layer;
  long ends = 0;
};
Data read_data_file(const std::string &path);

// LAMMPS commands before reading a generator's data file (atom style, box, bond style, the node
// properties), and the read_data keywords that take its NCF_CHAIN_L0 and NCF_NODE sections:
//   l.cmds(GENERATED_SETUP); l.cmd("read_data " + prefix + ".layers.data" + GENERATED_READ_FIXES);
extern const char *const GENERATED_SETUP;
extern const char *const GENERATED_READ_FIXES;

// Runs the ncf-gen tool of the build (NCF_BUILD) on a card; returns the output prefix.
std::string generate(const std::string &card, const std::string &prefix);

}    // namespace ncftest

#endif
