/* ncf-perm solver: Stokes-Brinkman flow on a periodic staggered (MAC) voxel grid.

   Unknowns: the velocity components on the cell faces (u_x on the x faces, ...), pressure in the
   cells. For a mean pressure gradient -G (viscosity 1) the discrete problem is

     -lap(u) + R u + grad(p) = G,   div(u) = 0,   periodic,

   with lap, grad and div the second-order staggered differences. R is the Brinkman resistance
   (1 / permeability) of the fibre voxels (Gebart, transversely isotropic about the voxel's fibre
   direction) and a penalty in solid voxels. In Fourier space the staggered differences are
   diagonal, so the divergence-free projection P and the constant-coefficient part are exact there:
   the solver runs conjugate gradients on P (-lap + R) P u = G, preconditioned by
   P (-lap + alpha)^-1 P (one forward and one backward real-to-complex transform of the three
   components per iteration, FFTW plans made once and reused, threads). This is the
   Fourier-preconditioned Krylov form of the FFT-based Stokes-Brinkman homogenisation
   (Mezhoud, Monchiet, Bonnet, Grande 2020; the staggered differences as in Wiegmann's voxel
   solvers), chosen because the resistance contrast of a fabric (fluid, Brinkman, solid) makes
   the plain fixed-point Lippmann-Schwinger iteration slow. doc/ncf_perm.md. */

#include "ncf_perm_solver.h"

#include <fftw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sstream>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace NCFPerm {

namespace {
  const double PI = 3.14159265358979323846;

  std::string num(double v)
  {
    char b[64];
    snprintf(b, sizeof b, "%.6g", v);
    return b;
  }

  double now()
  {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
  }

  struct FreeFFTW {
    void operator()(void *p) const { fftw_free(p); }
  };
  template <typename T> using fbuf = std::unique_ptr<T[], FreeFFTW>;
  template <typename T> fbuf<T> alloc(size_t n)
  {
    T *p = static_cast<T *>(fftw_malloc(sizeof(T) * std::max<size_t>(n, 1)));
    if (!p) throw Error("ncf-perm: out of memory (" + num(sizeof(T) * (double) n) + " bytes)");
    return fbuf<T>(p);
  }
}    // namespace

double gebart_vmax(Packing pk)
{
  return pk == Packing::square ? PI / 4.0 : PI / (2.0 * std::sqrt(3.0));
}

double gebart_parallel(double V, double r, Packing pk)
{
  if (V <= 0) return INFINITY;
  if (V >= 1) return 0.0;
  const double c = pk == Packing::square ? 57.0 : 53.0;
  return 8.0 * r * r / c * (1 - V) * (1 - V) * (1 - V) / (V * V);
}

double gebart_perpendicular(double V, double r, Packing pk)
{
  if (V <= 0) return INFINITY;
  const double vmax = gebart_vmax(pk);
  if (V >= vmax) return 0.0;
  const double C1 = pk == Packing::square ? 16.0 / (9.0 * PI * std::sqrt(2.0))
                                          : 16.0 / (9.0 * PI * std::sqrt(6.0));
  return C1 * std::pow(std::sqrt(vmax / V) - 1.0, 2.5) * r * r;
}

void check_grid(const Grid &g, const Options &o)
{
  const char *ax = "xyz";
  for (int d = 0; d < 3; ++d) {
    if (g.n[d] < 1)
      throw Error("ncf-perm: grid: " + std::to_string(g.n[d]) + " cells along " + ax[d] +
                  " (need at least 1)");
    if (!(g.h[d] > 0) || !std::isfinite(g.h[d]))
      throw Error(std::string("ncf-perm: grid: spacing along ") + ax[d] + " is " + num(g.h[d]) +
                  " (must be > 0)");
  }
  const size_t N = g.cells();
  if (g.vf.size() != N)
    throw Error("ncf-perm: array 'vf': " + std::to_string(g.vf.size()) + " values for " +
                std::to_string(N) + " cells");
  if (!g.dir.empty() && g.dir.size() != 3 * N)
    throw Error("ncf-perm: array 'dir': " + std::to_string(g.dir.size()) + " values for " +
                std::to_string(N) + " cells (need 3 per cell)");
  const double svf = o.solid_vf > 0 ? o.solid_vf : gebart_vmax(o.packing);
  size_t solid = 0, brink = 0;
  for (size_t c = 0; c < N; ++c) {
    const double v = g.vf[c];
    if (!std::isfinite(v) || v < 0 || v > 1) {
      const size_t i = c % g.n[0], j = (c / g.n[0]) % g.n[1], k = c / ((size_t) g.n[0] * g.n[1]);
      throw Error("ncf-perm: array 'vf': value " + num(v) + " at cell (" + std::to_string(i) + "," +
                  std::to_string(j) + "," + std::to_string(k) + ") is outside 0..1");
    }
    if (o.medium == Medium::fibrous) {
      if (v >= svf)
        ++solid;
      else if (v > 0)
        ++brink;
    } else if (v >= 0.5) {
      ++solid;
    }
  }
  if (solid == N)
    throw Error("ncf-perm: array 'vf': every cell is solid (vf >= " +
                num(o.medium == Medium::fibrous ? svf : 0.5) + "): no flow, no permeability");
  if (brink > 0 && !(o.fibre_radius > 0))
    throw Error("ncf-perm: option --fibre-radius: " + std::to_string(brink) +
                " cells are fibre bundles (0 < vf < " + num(svf) +
                ") and need the filament radius for Gebart's permeability (value " +
                num(o.fibre_radius) + ")");
  if (!(o.tol > 0) || o.tol >= 1)
    throw Error("ncf-perm: option --tol: value " + num(o.tol) + " must be in (0, 1)");
  if (o.max_iter < 1)
    throw Error("ncf-perm: option --max-iter: value " + std::to_string(o.max_iter) +
                " must be >= 1");
  if (!(o.penalty > 0))
    throw Error("ncf-perm: option --penalty: value " + num(o.penalty) + " must be > 0");
}

namespace {

  /* everything one solve needs, allocated once for the three loads */
  struct Solver {
    int nx, ny, nz;
    size_t N, Nc;    // real cells, complex cells (nx/2+1 in x)
    double h[3];
    std::vector<double> beta[3];    // face resistance, face j of cell c between c and c+e_j
    std::vector<double> roff;       // per cell 3 off-diagonal resistances (xy, xz, yz), or empty
    double alpha = 0;               // preconditioner shift
    std::vector<double> lapk[3];    // 4 sin^2(theta/2)/h^2 along each axis, per wave index
    fbuf<double> rbuf;              // real scratch for the transforms
    fbuf<fftw_complex> cbuf[3];
    fftw_plan fwd = nullptr, bwd = nullptr;
    double fft_seconds = 0;

    size_t idx(int i, int j, int k) const
    {
      return (size_t) i + (size_t) nx * (j + (size_t) ny * k);
    }

    ~Solver()
    {
      if (fwd) fftw_destroy_plan(fwd);
      if (bwd) fftw_destroy_plan(bwd);
    }

    /* y = A x: -lap x + R x (x, y: 3 face components, each N) */
    void apply(const std::vector<double> *x, std::vector<double> *y) const
    {
      const double ih2[3] = {1 / (h[0] * h[0]), 1 / (h[1] * h[1]), 1 / (h[2] * h[2])};
      for (int comp = 0; comp < 3; ++comp) {
        const double *u = x[comp].data();
        double *v = y[comp].data();
        const double *b = beta[comp].data();
#pragma omp parallel for collapse(2) schedule(static)
        for (int k = 0; k < nz; ++k)
          for (int j = 0; j < ny; ++j) {
            const int jm = j == 0 ? ny - 1 : j - 1, jp = j == ny - 1 ? 0 : j + 1;
            const int km = k == 0 ? nz - 1 : k - 1, kp = k == nz - 1 ? 0 : k + 1;
            const size_t row = idx(0, j, k);
            const double *ujm = u + idx(0, jm, k), *ujp = u + idx(0, jp, k);
            const double *ukm = u + idx(0, j, km), *ukp = u + idx(0, j, kp);
            for (int i = 0; i < nx; ++i) {
              const int im = i == 0 ? nx - 1 : i - 1, ip = i == nx - 1 ? 0 : i + 1;
              const double c = u[row + i];
              double lap = (u[row + ip] - 2 * c + u[row + im]) * ih2[0];
              lap += (ujp[i] - 2 * c + ujm[i]) * ih2[1];
              lap += (ukp[i] - 2 * c + ukm[i]) * ih2[2];
              v[row + i] = -lap + b[row + i] * c;
            }
          }
      }
      if (roff.empty()) return;
      /* off-diagonal Brinkman resistance through the cell centres: the face values averaged to
         the centre, times the cell's off-diagonal tensor, half back onto each face (C^T R C) */
      for (int comp = 0; comp < 3; ++comp) {
        const int o1 = comp == 0 ? 1 : 0, o2 = comp == 2 ? 1 : 2;    // the other two components
        double *v = y[comp].data();
#pragma omp parallel for collapse(2) schedule(static)
        for (int k = 0; k < nz; ++k)
          for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
              // the two cells of face (comp) of cell c: c and c + e_comp
              int ii[2] = {i, i}, jj[2] = {j, j}, kk[2] = {k, k};
              if (comp == 0) ii[1] = i == nx - 1 ? 0 : i + 1;
              if (comp == 1) jj[1] = j == ny - 1 ? 0 : j + 1;
              if (comp == 2) kk[1] = k == nz - 1 ? 0 : k + 1;
              double acc = 0;
              for (int s = 0; s < 2; ++s) {
                const size_t cc = idx(ii[s], jj[s], kk[s]);
                const double *R = &roff[3 * cc];
                // centre values of the other two components in cell cc
                double uc[3] = {0, 0, 0};
                for (int oc : {o1, o2}) {
                  size_t prev;
                  if (oc == 0)
                    prev = idx(ii[s] == 0 ? nx - 1 : ii[s] - 1, jj[s], kk[s]);
                  else if (oc == 1)
                    prev = idx(ii[s], jj[s] == 0 ? ny - 1 : jj[s] - 1, kk[s]);
                  else
                    prev = idx(ii[s], jj[s], kk[s] == 0 ? nz - 1 : kk[s] - 1);
                  uc[oc] = 0.5 * (x[oc][cc] + x[oc][prev]);
                }
                // row comp of the off-diagonal tensor: xy=R[0], xz=R[1], yz=R[2]
                double f = 0;
                if (comp == 0)
                  f = R[0] * uc[1] + R[1] * uc[2];
                else if (comp == 1)
                  f = R[0] * uc[0] + R[2] * uc[2];
                else
                  f = R[1] * uc[0] + R[2] * uc[1];
                acc += 0.5 * f;
              }
              v[idx(i, j, k)] += acc;
            }
      }
    }

    /* z = P (-lap + alpha)^-1 P r; returns |P r|^2 (real-space norm) */
    double precondition(const std::vector<double> *r, std::vector<double> *z)
    {
      const double t0 = now();
      for (int comp = 0; comp < 3; ++comp) {
        std::memcpy(rbuf.get(), r[comp].data(), sizeof(double) * N);
        fftw_execute_dft_r2c(fwd, rbuf.get(), cbuf[comp].get());
      }
      fft_seconds += now() - t0;
      const int nxc = nx / 2 + 1;
      double norm2 = 0;
#pragma omp parallel for collapse(2) schedule(static) reduction(+ : norm2)
      for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nxc; ++i) {
            const size_t q = (size_t) i + (size_t) nxc * (j + (size_t) ny * k);
            const double th[3] = {2 * PI * i / nx, 2 * PI * j / ny, 2 * PI * k / nz};
            std::complex<double> gv[3], u[3];
            double g2 = 0;
            for (int d = 0; d < 3; ++d) {
              gv[d] = std::complex<double>(std::cos(th[d]) - 1, std::sin(th[d])) / h[d];
              g2 += std::norm(gv[d]);
              u[d] = std::complex<double>(cbuf[d][q][0], cbuf[d][q][1]);
            }
            if (g2 > 0) {
              std::complex<double> s = 0;
              for (int d = 0; d < 3; ++d) s += std::conj(gv[d]) * u[d];
              s /= g2;
              for (int d = 0; d < 3; ++d) u[d] -= gv[d] * s;
            }
            const double w = (i == 0 || (nx % 2 == 0 && i == nx / 2)) ? 1.0 : 2.0;
            for (int d = 0; d < 3; ++d) norm2 += w * std::norm(u[d]);
            const double m = 1.0 / ((lapk[0][i] + lapk[1][j] + lapk[2][k] + alpha) * (double) N);
            for (int d = 0; d < 3; ++d) {
              cbuf[d][q][0] = u[d].real() * m;
              cbuf[d][q][1] = u[d].imag() * m;
            }
          }
      const double t1 = now();
      for (int comp = 0; comp < 3; ++comp) {
        fftw_execute_dft_c2r(bwd, cbuf[comp].get(), rbuf.get());
        std::memcpy(z[comp].data(), rbuf.get(), sizeof(double) * N);
      }
      fft_seconds += now() - t1;
      return norm2 / (double) N;
    }
  };

  double dot3(const std::vector<double> *a, const std::vector<double> *b, size_t N)
  {
    double s = 0;
    for (int c = 0; c < 3; ++c) {
      const double *x = a[c].data(), *y = b[c].data();
#pragma omp parallel for reduction(+ : s) schedule(static)
      for (long long i = 0; i < (long long) N; ++i) s += x[i] * y[i];
    }
    return s;
  }

}    // namespace

Result permeability(const Grid &g, const Options &o)
{
  return permeability(g, o, {true, true, true});
}

Result permeability(const Grid &g, const Options &o, const std::array<bool, 3> &which)
{
  check_grid(g, o);
  const double t_start = now();
  Result res;
#ifdef _OPENMP
  omp_set_num_threads(std::max(1, o.threads));
#endif
  static bool threads_ready = false;
  if (!threads_ready) {
    fftw_init_threads();
    threads_ready = true;
  }
  fftw_plan_with_nthreads(std::max(1, o.threads));

  Solver S;
  S.nx = g.n[0];
  S.ny = g.n[1];
  S.nz = g.n[2];
  S.N = g.cells();
  S.Nc = (size_t) (S.nx / 2 + 1) * S.ny * S.nz;
  for (int d = 0; d < 3; ++d) S.h[d] = g.h[d];
  const size_t N = S.N;
  const double hmin = std::min({g.h[0], g.h[1], g.h[2]});
  const double bsolid = o.penalty / (hmin * hmin);
  const double svf = o.solid_vf > 0 ? o.solid_vf : gebart_vmax(o.packing);

  /* per-cell resistance tensor (fibrous) or solid fraction (solid medium) */
  std::vector<double> rdiag(3 * N, 0.0);
  bool aniso = false;
  std::vector<double> roff;
  if (o.medium == Medium::fibrous) {
    roff.assign(3 * N, 0.0);
    for (size_t c = 0; c < N; ++c) {
      const double v = g.vf[c];
      if (v >= svf) {
        for (int d = 0; d < 3; ++d) rdiag[3 * c + d] = bsolid;
        ++res.solid_cells;
      } else if (v > 0) {
        ++res.brinkman_cells;
        const double rperp =
            std::min(bsolid, 1.0 / gebart_perpendicular(v, o.fibre_radius, o.packing));
        const double rpar = std::min(bsolid, 1.0 / gebart_parallel(v, o.fibre_radius, o.packing));
        double t[3] = {0, 0, 0}, tn = 0;
        if (!g.dir.empty()) {
          for (int d = 0; d < 3; ++d) t[d] = g.dir[3 * c + d];
          tn = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        }
        if (tn > 0 && std::isfinite(tn)) {
          for (int d = 0; d < 3; ++d) t[d] /= tn;
          // R = rperp (I - t t) + rpar t t
          const double dr = rpar - rperp;
          for (int d = 0; d < 3; ++d) rdiag[3 * c + d] = rperp + dr * t[d] * t[d];
          roff[3 * c + 0] = dr * t[0] * t[1];
          roff[3 * c + 1] = dr * t[0] * t[2];
          roff[3 * c + 2] = dr * t[1] * t[2];
          if (roff[3 * c] != 0 || roff[3 * c + 1] != 0 || roff[3 * c + 2] != 0) aniso = true;
        } else {
          for (int d = 0; d < 3; ++d)
            rdiag[3 * c + d] = rperp;    // no direction: isotropic, across
        }
      } else {
        ++res.fluid_cells;
      }
    }
    if (aniso) S.roff.swap(roff);
  } else {
    for (size_t c = 0; c < N; ++c) {
      if (g.vf[c] >= 0.5)
        ++res.solid_cells;
      else
        ++res.fluid_cells;
    }
  }

  /* face resistances */
  for (int comp = 0; comp < 3; ++comp) {
    S.beta[comp].assign(N, 0.0);
    for (int k = 0; k < S.nz; ++k)
      for (int j = 0; j < S.ny; ++j)
        for (int i = 0; i < S.nx; ++i) {
          const size_t c = S.idx(i, j, k);
          const size_t c2 = S.idx(comp == 0 ? (i + 1) % S.nx : i, comp == 1 ? (j + 1) % S.ny : j,
                                  comp == 2 ? (k + 1) % S.nz : k);
          if (o.medium == Medium::fibrous)
            S.beta[comp][c] = 0.5 * (rdiag[3 * c + comp] + rdiag[3 * c2 + comp]);
          else
            S.beta[comp][c] = 0.5 * (g.vf[c] + g.vf[c2]) >= 0.5 ? bsolid : 0.0;
        }
  }
  if (o.medium == Medium::solid) {
    /* sub-voxel no-slip: a face next to a solid face (across its component) sees the wall at the
       distance the solid fractions give, d = h (3/2 - s_f - s_g) for a plane wall; the ghost value
       of the linear profile through u = 0 there adds (h - d) / (d h^2) to its resistance */
    for (int comp = 0; comp < 3; ++comp) {
      std::vector<double> sf(N);
      for (int k = 0; k < S.nz; ++k)
        for (int j = 0; j < S.ny; ++j)
          for (int i = 0; i < S.nx; ++i) {
            const size_t c = S.idx(i, j, k);
            const size_t c2 = S.idx(comp == 0 ? (i + 1) % S.nx : i, comp == 1 ? (j + 1) % S.ny : j,
                                    comp == 2 ? (k + 1) % S.nz : k);
            sf[c] = 0.5 * (g.vf[c] + g.vf[c2]);
          }
      std::vector<double> extra(N, 0.0);
      for (int ax = 0; ax < 3; ++ax) {
        if (ax == comp || g.n[ax] == 1) continue;
        const double hk = g.h[ax];
        for (int k = 0; k < S.nz; ++k)
          for (int j = 0; j < S.ny; ++j)
            for (int i = 0; i < S.nx; ++i) {
              const size_t c = S.idx(i, j, k);
              if (S.beta[comp][c] >= bsolid) continue;
              for (int sgn = -1; sgn <= 1; sgn += 2) {
                int q[3] = {i, j, k};
                q[ax] = (q[ax] + sgn + g.n[ax]) % g.n[ax];
                const size_t nb = S.idx(q[0], q[1], q[2]);
                if (S.beta[comp][nb] < bsolid) continue;
                double d = hk * (1.5 - sf[c] - sf[nb]);
                d = std::max(d, 1e-3 * hk);
                if (d < hk) extra[c] += (hk - d) / (d * hk * hk);
              }
            }
      }
      for (size_t c = 0; c < N; ++c) S.beta[comp][c] = std::min(bsolid, S.beta[comp][c] + extra[c]);
    }
  }

  /* preconditioner shift: the volume mean of the face resistances (measured on cylinder arrays:
     fewer iterations than a shift 10-10^4 times smaller, for the same result) */
  {
    double sum = 0;
    for (int comp = 0; comp < 3; ++comp)
      for (size_t c = 0; c < N; ++c) sum += S.beta[comp][c];
    S.alpha = sum / (3.0 * N);
    if (!(S.alpha > 0)) S.alpha = bsolid * 1e-12;
  }
  for (int d = 0; d < 3; ++d) {
    S.lapk[d].resize(g.n[d]);
    for (int m = 0; m < g.n[d]; ++m) {
      const double s = std::sin(PI * m / g.n[d]);
      S.lapk[d][m] = 4 * s * s / (g.h[d] * g.h[d]);
    }
  }

  /* transforms: one plan each way, reused for every component and iteration */
  S.rbuf = alloc<double>(N);
  for (int d = 0; d < 3; ++d) S.cbuf[d] = alloc<fftw_complex>(S.Nc);
  const unsigned flags = o.measure_plans ? FFTW_MEASURE : FFTW_ESTIMATE;
  S.fwd = fftw_plan_dft_r2c_3d(S.nz, S.ny, S.nx, S.rbuf.get(), S.cbuf[0].get(), flags);
  S.bwd = fftw_plan_dft_c2r_3d(S.nz, S.ny, S.nx, S.cbuf[0].get(), S.rbuf.get(), flags);
  if (!S.fwd || !S.bwd)
    throw Error("ncf-perm: FFTW could not plan a " + std::to_string(S.nx) + "x" +
                std::to_string(S.ny) + "x" + std::to_string(S.nz) + " transform");

  std::vector<double> x[3], r[3], p[3], q[3], z[3];
  for (int d = 0; d < 3; ++d) {
    x[d].resize(N);
    r[d].resize(N);
    p[d].resize(N);
    q[d].resize(N);
    z[d].resize(N);
  }
  res.bytes = (15.0 + 3.0 + (S.roff.empty() ? 0.0 : 3.0) + 1.0) * 8.0 * N + 3.0 * 16.0 * S.Nc;

  for (int load = 0; load < 3; ++load) {
    if (!which[load]) continue;
    const double t0 = now();
    LoadResult &L = res.loads[load];
    for (int d = 0; d < 3; ++d) {
      std::fill(x[d].begin(), x[d].end(), 0.0);
      std::fill(r[d].begin(), r[d].end(), d == load ? 1.0 : 0.0);    // b = G (div-free)
    }
    const double bnorm = std::sqrt((double) N);
    double rn2 = S.precondition(r, z);
    for (int d = 0; d < 3; ++d) p[d] = z[d];
    double rz = dot3(r, z, N);
    int it = 0;
    double rel = std::sqrt(rn2) / bnorm;
    while (rel > o.tol && it < o.max_iter) {
      S.apply(p, q);
      const double pq = dot3(p, q, N);
      if (!(pq > 0)) break;
      const double a = rz / pq;
      for (int d = 0; d < 3; ++d) {
        double *xd = x[d].data(), *rd = r[d].data();
        const double *pd = p[d].data(), *qd = q[d].data();
#pragma omp parallel for schedule(static)
        for (long long c = 0; c < (long long) N; ++c) {
          xd[c] += a * pd[c];
          rd[c] -= a * qd[c];
        }
      }
      rn2 = S.precondition(r, z);
      const double rz_new = dot3(r, z, N);
      const double b = rz_new / rz;
      rz = rz_new;
      for (int d = 0; d < 3; ++d) {
        double *pd = p[d].data();
        const double *zd = z[d].data();
#pragma omp parallel for schedule(static)
        for (long long c = 0; c < (long long) N; ++c) pd[c] = zd[c] + b * pd[c];
      }
      ++it;
      rel = std::sqrt(rn2) / bnorm;
      if (o.verbose && (it % 200 == 0))
        fprintf(stdout, "ncf-perm:   load %c iteration %d residual %.3e\n", "xyz"[load], it, rel);
    }
    L.iterations = it;
    L.residual = rel;
    for (int d = 0; d < 3; ++d) {
      double s = 0;
      for (size_t c = 0; c < N; ++c) s += x[d][c];
      L.mean_u[d] = s / (double) N;
      res.K[d][load] = L.mean_u[d];
    }
    if (o.keep_fields) {
      for (int d = 0; d < 3; ++d) {
        res.field[load][d].resize(N);
        // cell-centred: mean of the two faces of the cell along d
        for (int k = 0; k < S.nz; ++k)
          for (int j = 0; j < S.ny; ++j)
            for (int i = 0; i < S.nx; ++i) {
              const size_t c = S.idx(i, j, k);
              const size_t pv =
                  S.idx(d == 0 ? (i + S.nx - 1) % S.nx : i, d == 1 ? (j + S.ny - 1) % S.ny : j,
                        d == 2 ? (k + S.nz - 1) % S.nz : k);
              res.field[load][d][c] = 0.5 * (x[d][c] + x[d][pv]);
            }
      }
    }
    L.seconds = now() - t0;
    if (o.verbose)
      fprintf(stdout, "ncf-perm: load %c: %d iterations, residual %.3e, %.2f s\n", "xyz"[load], it,
              rel, L.seconds);
  }
  double a = 0, s = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      a += res.K[i][j] * res.K[i][j];
      const double dd = res.K[i][j] - res.K[j][i];
      s += dd * dd;
    }
  res.symmetry_error = a > 0 ? std::sqrt(s / a) : 0.0;
  res.fft_seconds = S.fft_seconds;
  res.total_seconds = now() - t_start;
  return res;
}

}    // namespace NCFPerm
