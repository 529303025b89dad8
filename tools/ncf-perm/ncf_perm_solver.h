/* ncf-perm: permeability tensor of a periodic voxel grid (Stokes-Brinkman, FFT-preconditioned
   conjugate gradients on a staggered grid). Engine-free, no VTK: the grid arrives as plain arrays
   (tools/ncf-perm/ncf_perm.py reads the .vti with VTK and hands them over). doc/ncf_perm.md. */
#ifndef NCF_PERM_SOLVER_H
#define NCF_PERM_SOLVER_H

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace NCFPerm {

/* bad input: the message names the option or array and the value */
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string &m) : std::runtime_error(m) {}
};

enum class Medium {
  fibrous,    // vf = fibre volume fraction of filament bundles: Brinkman with Gebart's K
  solid    // vf = solid fraction of impermeable bodies: faces inside solid closed, sub-voxel walls
};
enum class Packing { square, hexagonal };

/* Gebart (1992): permeability of a unidirectional array of fibres of radius r at fibre volume
   fraction V, along the fibres (parallel) and across them (perpendicular); 0 at V >= Vmax */
double gebart_parallel(double V, double r, Packing pk);
double gebart_perpendicular(double V, double r, Packing pk);
double gebart_vmax(Packing pk);

struct Grid {
  int n[3] = {0, 0, 0};       // cells along x, y, z (one period)
  double h[3] = {0, 0, 0};    // spacing [m]
  std::vector<double> vf;     // per cell, x fastest (VTK order), 0..1
  std::vector<double> dir;    // optional, 3 per cell: fibre direction (need not be unit)
  size_t cells() const { return (size_t) n[0] * n[1] * n[2]; }
};

struct Options {
  Medium medium = Medium::fibrous;
  Packing packing = Packing::hexagonal;    // filament arrangement inside a chain (Gebart)
  double fibre_radius = 0.0;               // filament radius [m] (fibrous medium, 0 < vf < vmax)
  double solid_vf = -1.0;                  // fibrous: vf >= this is solid (default Gebart's Vmax)
  double penalty = 1e4;                    // resistance of solid faces, in units of 1/h_min^2
  double tol = 1e-6;                       // relative residual of the projected equation
  int max_iter = 20000;
  int threads = 1;
  bool measure_plans = false;    // FFTW_MEASURE instead of FFTW_ESTIMATE
  bool keep_fields = false;      // keep the velocity fields of the three loads
  bool verbose = true;
};

struct LoadResult {
  int iterations = 0;
  double residual = 0.0;    // final relative residual
  double seconds = 0.0;
  std::array<double, 3> mean_u{};    // mean velocity for a unit pressure gradient [m^2]
};

struct Result {
  double K[3][3] = {};          // [m^2], K[i][j] = <u_i> for a unit mean pressure gradient -e_j
  double symmetry_error = 0;    // |K - K^T| / |K| (Frobenius)
  std::array<LoadResult, 3> loads;
  size_t solid_cells = 0, brinkman_cells = 0, fluid_cells = 0;
  double fft_seconds = 0, total_seconds = 0;
  double bytes = 0;    // memory the solver allocated
  // with keep_fields: cell-centred velocity per load [load][component][cell]
  std::vector<double> field[3][3];
};

/* checks the grid (sizes, vf in 0..1, finite, not fully solid, fibre radius where needed);
   throws Error naming the array / option and the value */
void check_grid(const Grid &g, const Options &o);

/* the full tensor: three loads -e_x, -e_y, -e_z (mean pressure gradient), viscosity 1 */
Result permeability(const Grid &g, const Options &o);

/* only the loads in `which` (e.g. {true,false,false}); the other columns stay 0 */
Result permeability(const Grid &g, const Options &o, const std::array<bool, 3> &which);

}    // namespace NCFPerm

#endif
