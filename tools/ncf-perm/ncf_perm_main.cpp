/* ncf-perm-solve: the FFTW solver of ncf-perm on a grid handed over as a raw file by the front-end
   tools/ncf-perm/ncf_perm.py (which reads the .vti with VTK). Not meant to be called by hand, but
   it can be:

     ncf-perm-solve GRID.raw [--medium fibrous|solid] [--packing hexagonal|square]
                    [--fibre-radius R] [--solid-vf V] [--penalty P] [--tol T] [--max-iter N]
                    [--threads N] [--plan estimate|measure] [--loads xyz] [--fields FILE]

   GRID.raw: one text line "NCFPERM 1 nx ny nz hx hy hz ndir" then nx*ny*nz doubles vf (x fastest)
   and, if ndir = 3, 3*nx*ny*nz doubles dir (little-endian, native). --fields writes the
   cell-centred velocity of every load (3 loads x 3 components x cells, doubles). The permeability
   tensor comes last, one row per line. doc/ncf_perm.md. */

#include "ncf_perm_solver.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

using namespace NCFPerm;

namespace {
double number(const char *opt, const char *v)
{
  char *end = nullptr;
  const double x = strtod(v, &end);
  if (!v[0] || *end || !std::isfinite(x))
    throw Error(std::string("ncf-perm: option ") + opt + ": value '" + v + "' is not a number");
  return x;
}
int integer(const char *opt, const char *v)
{
  char *end = nullptr;
  const long x = strtol(v, &end, 10);
  if (!v[0] || *end)
    throw Error(std::string("ncf-perm: option ") + opt + ": value '" + v + "' is not an integer");
  return (int) x;
}

Grid read_raw(const std::string &path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("ncf-perm: cannot read the grid file '" + path + "'");
  std::string line;
  std::getline(in, line);
  std::istringstream hs(line);
  std::string magic;
  int version = 0, ndir = 0;
  Grid g;
  hs >> magic >> version >> g.n[0] >> g.n[1] >> g.n[2] >> g.h[0] >> g.h[1] >> g.h[2] >> ndir;
  if (!hs || magic != "NCFPERM" || version != 1 || (ndir != 0 && ndir != 3))
    throw Error("ncf-perm: '" + path + "' is not a grid file of ncf_perm.py (header '" + line +
                "')");
  for (int d = 0; d < 3; ++d)
    if (g.n[d] < 1) throw Error("ncf-perm: '" + path + "': header '" + line + "': bad size");
  const size_t N = g.cells();
  g.vf.resize(N);
  in.read(reinterpret_cast<char *>(g.vf.data()), sizeof(double) * N);
  if (ndir == 3) {
    g.dir.resize(3 * N);
    in.read(reinterpret_cast<char *>(g.dir.data()), sizeof(double) * 3 * N);
  }
  if (!in) throw Error("ncf-perm: '" + path + "' is shorter than its header says");
  return g;
}
}    // namespace

int main(int argc, char **argv)
{
  try {
    if (argc < 2)
      throw Error("ncf-perm: usage: ncf-perm-solve GRID.raw [options] (doc/ncf_perm.md)");
    Options o;
    std::string grid_file, fields_file;
    std::array<bool, 3> which{true, true, true};
    for (int a = 1; a < argc; ++a) {
      const std::string s = argv[a];
      auto val = [&](void) -> const char * {
        if (a + 1 >= argc) throw Error("ncf-perm: option " + s + ": missing value");
        return argv[++a];
      };
      if (s == "--medium") {
        const std::string v = val();
        if (v == "fibrous")
          o.medium = Medium::fibrous;
        else if (v == "solid")
          o.medium = Medium::solid;
        else
          throw Error("ncf-perm: option --medium: value '" + v + "' (expected fibrous or solid)");
      } else if (s == "--packing") {
        const std::string v = val();
        if (v == "hexagonal" || v == "hex")
          o.packing = Packing::hexagonal;
        else if (v == "square")
          o.packing = Packing::square;
        else
          throw Error("ncf-perm: option --packing: value '" + v +
                      "' (expected hexagonal or square)");
      } else if (s == "--fibre-radius") {
        o.fibre_radius = number("--fibre-radius", val());
        if (!(o.fibre_radius > 0))
          throw Error("ncf-perm: option --fibre-radius: value " + std::string(argv[a]) +
                      " must be > 0");
      } else if (s == "--solid-vf") {
        o.solid_vf = number("--solid-vf", val());
        if (!(o.solid_vf > 0) || o.solid_vf > 1)
          throw Error("ncf-perm: option --solid-vf: value " + std::string(argv[a]) +
                      " must be in (0, 1]");
      } else if (s == "--penalty") {
        o.penalty = number("--penalty", val());
      } else if (s == "--tol") {
        o.tol = number("--tol", val());
      } else if (s == "--max-iter") {
        o.max_iter = integer("--max-iter", val());
      } else if (s == "--threads") {
        o.threads = integer("--threads", val());
        if (o.threads < 1)
          throw Error("ncf-perm: option --threads: value " + std::string(argv[a]) +
                      " must be >= 1");
      } else if (s == "--plan") {
        const std::string v = val();
        if (v == "estimate")
          o.measure_plans = false;
        else if (v == "measure")
          o.measure_plans = true;
        else
          throw Error("ncf-perm: option --plan: value '" + v + "' (expected estimate or measure)");
      } else if (s == "--loads") {
        const std::string v = val();
        which = {false, false, false};
        for (char c : v) {
          if (c < 'x' || c > 'z')
            throw Error("ncf-perm: option --loads: value '" + v + "' (letters of xyz)");
          which[c - 'x'] = true;
        }
        if (v.empty()) throw Error("ncf-perm: option --loads: empty value");
      } else if (s == "--fields") {
        fields_file = val();
        o.keep_fields = true;
      } else if (s == "--quiet") {
        o.verbose = false;
      } else if (!s.empty() && s[0] == '-') {
        throw Error("ncf-perm: unknown option '" + s + "'");
      } else if (grid_file.empty()) {
        grid_file = s;
      } else {
        throw Error("ncf-perm: a second grid file '" + s + "' (one grid per run)");
      }
    }
    const Grid g = read_raw(grid_file);
    Result r = permeability(g, o, which);
    printf("ncf-perm: cells: %zu fluid, %zu fibre bundles (Brinkman), %zu solid\n", r.fluid_cells,
           r.brinkman_cells, r.solid_cells);
    int total = 0;
    for (int l = 0; l < 3; ++l) total += which[l] ? r.loads[l].iterations : 0;
    printf("ncf-perm: iterations %d in all, %.3g s per iteration (%.0f%% in the transforms), "
           "memory %.1f MiB (%.0f bytes per cell)\n",
           total, total ? r.total_seconds / total : 0.0,
           r.total_seconds > 0 ? 100 * r.fft_seconds / r.total_seconds : 0.0, r.bytes / 1048576.0,
           r.bytes / (double) g.cells());
    double worst = 0;
    for (int l = 0; l < 3; ++l)
      if (which[l]) worst = std::max(worst, r.loads[l].residual);
    printf("ncf-perm: largest final residual %.3e (tolerance %.1e)%s\n", worst, o.tol,
           worst > o.tol ? "  NOT CONVERGED: raise --max-iter" : "");
    printf("ncf-perm: symmetry error |K - K^T| / |K| = %.3e\n", r.symmetry_error);
    if (!fields_file.empty()) {
      std::ofstream f(fields_file, std::ios::binary);
      for (int l = 0; l < 3; ++l)
        for (int d = 0; d < 3; ++d) {
          std::vector<double> zero;
          const std::vector<double> &v = r.field[l][d].empty() ? (zero.assign(g.cells(), 0.0), zero)
                                                               : r.field[l][d];
          f.write(reinterpret_cast<const char *>(v.data()), sizeof(double) * v.size());
        }
      if (!f) throw Error("ncf-perm: cannot write the fields file '" + fields_file + "'");
    }
    printf("ncf-perm: permeability tensor K [m^2], rows x y z (grid axes):\n");
    for (int i = 0; i < 3; ++i) printf("%.6e %.6e %.6e\n", r.K[i][0], r.K[i][1], r.K[i][2]);
    return worst > o.tol ? 2 : 0;
  } catch (const std::exception &e) {
    fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
