/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Boxes (segments or nodes) binned by their centres on a regular grid, for the candidate search of
   pair ncf/contact's list build (pair_ncf_contact_list.cpp). Engine-free: Key is the integer type
   of the keys an entry carries (LAMMPS's tagint there), tested in tests/unit/test_box_grid.cpp.

   Use: clear(), add() every box, bin(), then scan() any number of search boxes. The arrays are
   kept between builds (no allocation once they have grown). The entries are sorted by bin, one
   array per quantity, so that a search reads only what its tests need.
------------------------------------------------------------------------- */

#ifndef NCF_BOX_GRID_H
#define NCF_BOX_GRID_H

#include <cmath>
#include <vector>

namespace NCF {

template <class Key> struct BoxGrid {
  int nb[3];                         // bins per direction
  double lo[3], inv[3];              // lowest centre, 1 / bin size
  double hmax[3];                    // largest half extent of the entries
  std::vector<int> start;            // per bin: first entry (nbins + 1 values)
  std::vector<double> cx, cy, cz;    // centre of the box
  std::vector<double> hx, hy, hz;    // half extents
  std::vector<double> r;             // radius of the bounding sphere
  std::vector<Key> t0, t1, t2;       // three keys per entry (the caller's: segment, node)
  std::vector<int> i0, i1;           // two indices per entry (the caller's)
  // what the box test of scan reads, one record per entry (half a cache line with 4-byte keys):
  // centre relative to lo and half extents in single precision, and the first two keys
  struct Filter {
    float c[3], h[3];
    Key k0, k1;
  };
  std::vector<Filter> fb;
  float fslack;    // bound of the round-off of the single precision box test

  int size() const { return (int) cx.size(); }

  void clear()
  {
    for (std::vector<double> *v : {&cx, &cy, &cz, &hx, &hy, &hz, &r}) v->clear();
    for (std::vector<Key> *v : {&t0, &t1, &t2}) v->clear();
    i0.clear();
    i1.clear();
  }

  // a box of centre c, half extents h and bounding sphere radius rad, with its keys and indices
  void add(const double *c, const double *h, double rad, Key a, Key b, Key q, int j0, int j1)
  {
    cx.push_back(c[0]);
    cy.push_back(c[1]);
    cz.push_back(c[2]);
    hx.push_back(h[0]);
    hy.push_back(h[1]);
    hz.push_back(h[2]);
    r.push_back(rad);
    t0.push_back(a);
    t1.push_back(b);
    t2.push_back(q);
    i0.push_back(j0);
    i1.push_back(j1);
  }

  // bins c0..c1 (per direction) that hold every centre in the box lo_pos..hi_pos: the bin index
  // is monotonic in the position (clamped to the grid; no conversion of an out-of-range value to
  // int)
  void cells(const double *lo_pos, const double *hi_pos, int *c0, int *c1) const
  {
    for (int d = 0; d < 3; d++) {
      const double top = nb[d] - 1;
      double a = (lo_pos[d] - lo[d]) * inv[d], b = (hi_pos[d] - lo[d]) * inv[d];
      a = a < 0.0 ? 0.0 : (a > top ? top : a);
      b = b < 0.0 ? 0.0 : (b > top ? top : b);
      c0[d] = (int) a;
      c1[d] = (int) b;
    }
  }

  // Sort the entries by bin (a counting sort) and fill the bin index and the filter records.
  // Bins of about the largest half extent per direction: a search reaches over (own + largest)
  // half extent on either side, a few bins, and the rows it scans are not much longer than the
  // search box. Not more than 4 n + 1000 bins (larger bins where the entries are sparse).
  void bin()
  {
    const int n = size();
    const std::vector<double> *cen[3] = {&cx, &cy, &cz};
    const std::vector<double> *hal[3] = {&hx, &hy, &hz};
    double hi[3];
    for (int d = 0; d < 3; d++) {
      lo[d] = 1e300;
      hi[d] = -1e300;
      hmax[d] = 0.0;
      for (int k = 0; k < n; k++) {
        const double c = (*cen[d])[k], h = (*hal[d])[k];
        lo[d] = lo[d] < c ? lo[d] : c;
        hi[d] = hi[d] > c ? hi[d] : c;
        hmax[d] = hmax[d] > h ? hmax[d] : h;
      }
    }
    if (n == 0) {
      for (int d = 0; d < 3; d++) {
        nb[d] = 1;
        lo[d] = 0.0;
        inv[d] = 1.0;
      }
      start.assign(2, 0);
      fb.clear();
      fslack = 0.0f;
      return;
    }
    double bs[3];
    for (int d = 0; d < 3; d++) {
      const double floor_size = 1e-6 * (hi[d] - lo[d]);
      bs[d] = hmax[d] > floor_size ? hmax[d] : floor_size;
      if (!(bs[d] > 0.0)) bs[d] = 1.0;
    }
    for (;;) {
      double total = 1.0;
      for (int d = 0; d < 3; d++) {
        const double q = (hi[d] - lo[d]) / bs[d];
        nb[d] = (int) (q < 1e8 ? q : 1e8) + 1;
        total *= nb[d];
      }
      if (total <= 4.0 * n + 1000.0) break;
      for (int d = 0; d < 3; d++) bs[d] *= 1.5;
    }
    for (int d = 0; d < 3; d++) inv[d] = 1.0 / bs[d];
    const int nbins = nb[0] * nb[1] * nb[2];
    start.assign(nbins + 1, 0);
    binof.resize(n);
    for (int k = 0; k < n; k++) {
      const double c[3] = {cx[k], cy[k], cz[k]};
      int c0[3], c1[3];
      cells(c, c, c0, c1);
      binof[k] = (c0[2] * nb[1] + c0[1]) * nb[0] + c0[0];
      start[binof[k] + 1]++;
    }
    for (int b = 0; b < nbins; b++) start[b + 1] += start[b];
    fill.assign(start.begin(), start.end() - 1);
    // positions of the entries in bin order
    for (int k = 0; k < n; k++) binof[k] = fill[binof[k]]++;
    put(cx, tmpd);
    put(cy, tmpd);
    put(cz, tmpd);
    put(hx, tmpd);
    put(hy, tmpd);
    put(hz, tmpd);
    put(r, tmpd);
    put(t0, tmpk);
    put(t1, tmpk);
    put(t2, tmpk);
    put(i0, tmpi);
    put(i1, tmpi);

    // single precision copies for the box test: centres relative to lo. The round-off of a test
    // that holds exactly (a few roundings, relative 2^-24 each, of values below the span of the
    // grid plus the half extents of the two boxes) stays far below the slack of 1e-6 (span +
    // 2 hmax) plus 1e-6 times the half extents of the searching box added to its bound
    double big = 0.0;
    for (int d = 0; d < 3; d++) {
      const double s = (hi[d] - lo[d]) + 2.0 * hmax[d];
      big = big > s ? big : s;
    }
    fslack = (float) (1e-6 * big);
    fb.resize(n);
    for (int k = 0; k < n; k++) {
      Filter &f = fb[k];
      f.c[0] = (float) (cx[k] - lo[0]);
      f.c[1] = (float) (cy[k] - lo[1]);
      f.c[2] = (float) (cz[k] - lo[2]);
      f.h[0] = (float) hx[k];
      f.h[1] = (float) hy[k];
      f.h[2] = (float) hz[k];
      f.k0 = t0[k];
      f.k1 = t1[k];
    }
  }

  // The entries whose box overlaps the box of centre c and half extents h, with keep(filter
  // record) true, into cand (room for size() entries; returns their number), in bin order. The
  // tests run without branches (most entries of the scanned rows fail, unpredictably), in single
  // precision with the slack of the grid plus 1e-6 of the half extents: a superset of the exact
  // overlaps, by at most that slack. (bin() first.)
  template <class Keep> int scan(const double *c, const double *h, Keep keep, int *cand) const
  {
    double rlo[3], rhi[3];
    for (int d = 0; d < 3; d++) {
      rlo[d] = c[d] - (h[d] + hmax[d]);
      rhi[d] = c[d] + (h[d] + hmax[d]);
    }
    int c0[3], c1[3];
    cells(rlo, rhi, c0, c1);
    float fa[3], fh[3];
    const float fs = fslack + (float) (1e-6 * (h[0] + h[1] + h[2]));
    for (int d = 0; d < 3; d++) {
      fa[d] = (float) (c[d] - lo[d]);
      fh[d] = (float) h[d] + fs;
    }
    const Filter *f = fb.data();
    int nc = 0;
    for (int cz = c0[2]; cz <= c1[2]; cz++)
      for (int cy = c0[1]; cy <= c1[1]; cy++) {
        const int row = (cz * nb[1] + cy) * nb[0];
        const int nend = start[row + c1[0] + 1];
        for (int n = start[row + c0[0]]; n < nend; n++) {
          const Filter &b = f[n];
          cand[nc] = n;
          nc += keep(b) & (std::fabs(fa[0] - b.c[0]) <= fh[0] + b.h[0]) &
              (std::fabs(fa[1] - b.c[1]) <= fh[1] + b.h[1]) &
              (std::fabs(fa[2] - b.c[2]) <= fh[2] + b.h[2]);
        }
      }
    return nc;
  }

 private:
  // the scratch of bin(): bin and position of each entry, fill counters, the arrays being sorted
  std::vector<int> binof, fill, tmpi;
  std::vector<double> tmpd;
  std::vector<Key> tmpk;
  template <class T> void put(std::vector<T> &src, std::vector<T> &dst)
  {
    const int n = size();
    dst.resize(n);
    for (int k = 0; k < n; k++) dst[binof[k]] = src[k];
    src.swap(dst);
  }
};

}    // namespace NCF

#endif
