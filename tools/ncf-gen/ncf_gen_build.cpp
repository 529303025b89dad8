/* ----------------------------------------------------------------------
   USER-NCF fabric generator: geometry of the fibrous layers, the stitching yarn and the needles
   (paper sections 4.2, 4.4, 4.5; doc/ncf-gen.md).
------------------------------------------------------------------------- */

#include "ncf_gen.h"
#include "ncf_gen_geom.h"

#include "ncf_contact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>

namespace NCFGEN {

namespace {

  constexpr double PI = 3.14159265358979323846;
  constexpr double DEG = PI / 180.0;
  constexpr double INCH = 0.0254;
  constexpr double MARGIN = 1e-6;    // relative clearance margin above the contact diameter
  // relative clearance of the knitted loops' sides and levels (doc/ncf-gen.md)
  constexpr double LEVEL_MARGIN = 0.02;

  // ---------------------------------------------------------------- random numbers
  // mt19937_64 is specified bit for bit by the standard; the transforms below are our own, so a
  // seed gives the same fabric with any standard library.
  struct Rng {
    std::mt19937_64 g;
    explicit Rng(std::uint64_t seed) : g(seed) {}
    double uniform()    // in (0, 1)
    {
      return ((double) (g() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
    }
    int below(int n) { return std::min(n - 1, (int) (uniform() * n)); }
    double normal()    // Box-Muller, one value per call
    {
      const double u1 = uniform(), u2 = uniform();
      return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * PI * u2);
    }
  };

  // inverse of the standard normal CDF (Acklam's rational approximation, one Newton step on erfc)
  double normal_quantile(double p)
  {
    static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                               -2.759285104469687e+02, 1.383577518672690e+02,
                               -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                               -1.556989798598866e+02, 6.680131188771972e+01,
                               -1.328068155288572e+01};
    static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                               -2.400758277161838e+00, -2.549732539343734e+00,
                               4.374664141464968e+00,  2.938163982698783e+00};
    static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                               3.754408661907416e+00};
    const double plow = 0.02425;
    double x;
    if (p < plow) {
      const double q = std::sqrt(-2 * std::log(p));
      x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
          ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    } else if (p <= 1 - plow) {
      const double q = p - 0.5, r = q * q;
      x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
          (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
    } else {
      const double q = std::sqrt(-2 * std::log(1 - p));
      x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
          ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    }
    const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
    const double u = e * std::sqrt(2 * PI) * std::exp(x * x / 2);
    return x - u / (1 + x * u / 2);
  }

  // one straight chain of a layer before it gets its height
  struct Line {
    double p0[2], p1[2];    // first and last node (unwrapped)
    double bb[4];           // xmin xmax ymin ymax
    double z = 0.0;
  };

  // closest 2D distance of two lines, periodic images included
  double line_distance(const Line &a, const Line &b, double lx, double ly, double cut)
  {
    double best = 1e300;
    const int i0 = (int) std::ceil((a.bb[0] - b.bb[1] - cut) / lx);
    const int i1 = (int) std::floor((a.bb[1] - b.bb[0] + cut) / lx);
    const int j0 = (int) std::ceil((a.bb[2] - b.bb[3] - cut) / ly);
    const int j1 = (int) std::floor((a.bb[3] - b.bb[2] + cut) / ly);
    for (int i = i0; i <= i1; i++)
      for (int j = j0; j <= j1; j++) {
        const double q0[2] = {b.p0[0] + i * lx, b.p0[1] + j * ly};
        const double q1[2] = {b.p1[0] + i * lx, b.p1[1] + j * ly};
        best = std::min(best, segment_distance2<2>(a.p0, a.p1, q0, q1));
      }
    return std::sqrt(best);
  }

  // How far in from the main faces the end nodes of a straight chain must lie (at least e0) so
  // that its last node keeps the distance dmin from the first node of its own periodic image:
  // the chain (length len, unit direction dir, crossing main axis a) travels len dir[b] along
  // the other axis b (period period_b); its image across the main face starts offset by
  // delta = that travel less whole periods. Between the two end nodes v = 2e dir - delta e_b,
  // |v|^2 = 4e^2 - 4 e delta dir[b] + delta^2: at least dmin^2 for e >= (delta dir[b] +
  // sqrt(dmin^2 - delta^2 dir[a]^2)) / 2 when |delta dir[a]| < dmin (the segments, pointing away
  // from each other there, are then clear too); otherwise the two lines are a diameter apart
  double end_inset(double e0, double len, const double *dir, int a, double period_b, double dmin)
  {
    const int b = 1 - a;
    const double travel = len * dir[b];
    double e = e0;
    const double nlow = std::floor(travel / period_b);
    for (double n : {nlow, nlow + 1.0}) {
      const double delta = travel - n * period_b;
      const double across = delta * dir[a];
      if (std::fabs(across) >= dmin) continue;
      e = std::max(e, 0.5 * (delta * dir[b] + std::sqrt(dmin * dmin - across * across)));
    }
    return e;
  }

  int gcd(int a, int b)
  {
    return b ? gcd(b, a % b) : a;
  }

  std::string at(const std::string &path, int line)
  {
    return path + ":" + std::to_string(line);
  }

}    // namespace

// the most fibre nodes a card may ask for (about 1 GB of LAMMPS data; 200 times the paper's
// comparison RVEs)
constexpr double MAX_NODES = 2e7;
// the most chains of one layer: their placement compares every pair (the paper's RVEs have a few
// hundred per layer)
constexpr double MAX_CHAINS = 2e4;
// a layer's chain count is the nearest integer to width x chains per width: further than this
// from the target, the RVE is too narrow for the layer's areal weight
constexpr double MAX_CHAIN_ROUNDING = 0.1;

Fabric build_fabric(const Card &card_given, const NCF::MaterialLibrary &lib)
{
  Fabric f;
  // a mesh of the quality preset shorter than the diameter it discretises (a preset with a
  // thicker chain_diameter or yarn given on the card) is raised to that diameter, the finest
  // mesh allowed; a mesh given on the card is never changed (too short: an error below)
  Card card = card_given;
  if (!card.from_card("fibre_mesh") && card.fibre_mesh < card.chain_diameter) {
    f.fibre_mesh_preset_raised = card.fibre_mesh;
    card.fibre_mesh = card.chain_diameter;
  }
  f.card = card;
  f.course = card.stitch_length;
  f.needle_spacing = INCH / card.gauge;
  f.courses = card.pattern.repeat * card.r_l;
  f.lx = f.courses * f.course;
  f.ly = card.r_w * f.needle_spacing;
  const double lx = f.lx, ly = f.ly;

  auto line_of = [&](const char *key, const char *other) {
    auto it = card.key_line.find(key);
    if (it == card.key_line.end()) it = card.key_line.find(other);
    return it == card.key_line.end() ? 0 : it->second;
  };

  // ---------------------------------------------------------------- fibrous layers
  // elements at least one chain diameter long: non-neighbouring elements of one straight chain
  // then never touch (the contact acts between all segments that share no node)
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return std::string(buf);
  };
  if (card.fibre_mesh < card.chain_diameter)
    throw InputError(at(card.path, line_of("fibre_mesh", "chain_diameter")) +
                     ": key 'fibre_mesh': value " + num(card.fibre_mesh) +
                     " m is shorter than the chain diameter " + num(card.chain_diameter) + " m");
  // an RVE side shorter than two elements has no room for a chain; a course shorter than that is
  // a stitch length typed in the wrong unit
  if (lx < 2.0 * card.fibre_mesh)
    throw InputError(
        at(card.path, line_of("stitch_length", "pattern")) + ": key 'stitch_length': value " +
        num(card.stitch_length) + " m gives an RVE " + num(lx) +
        " m long, shorter than two fibre elements (fibre_mesh " + num(card.fibre_mesh) + " m)");
  if (ly < 2.0 * card.fibre_mesh)
    throw InputError(at(card.path, line_of("gauge", "rve")) + ": key 'gauge': value " +
                     num(card.gauge) + " gives an RVE " + num(ly) +
                     " m wide, shorter than two fibre elements (fibre_mesh " +
                     num(card.fibre_mesh) + " m)");
  double base = 0.0;    // bottom surface of the next layer
  int chain_id = 0;
  double nodes_estimate = 0.0;    // fibre nodes, summed over the layers before each is built
  double fibre_nodes = 0.0;       // fibre nodes, counted chain by chain before each is built
  const double dc = card.chain_diameter, rc = 0.5 * dc;
  for (std::size_t li = 0; li < card.layers.size(); li++) {
    const LayerSpec &spec = card.layers[li];
    const int layer = (int) li + 1;
    LayerInfo info;
    info.spec = spec;
    const NCF::Material *mat = nullptr;
    try {
      mat = &lib.get(spec.material);
      info.chain = NCF::filament_chain(*mat, dc, card.packing);
    } catch (InputError &e) {
      throw InputError(at(card.path, spec.material_line) + ": key 'material': value '" +
                       spec.material + "': " + e.what() + " (materials file " +
                       card.materials_file + ")");
    }
    info.filament_density = mat->density;
    info.t_l = spec.areal_weight / (card.v_l * mat->density);    // Eq. 1
    info.chains_per_width_target = spec.areal_weight / info.chain.mass_per_length;
    // chain length per RVE area is A / m'; refuse what no machine here could hold before
    // allocating it (the paper's comparison RVEs have about 1e5 nodes)
    nodes_estimate += info.chains_per_width_target * lx * ly / card.fibre_mesh;
    if (nodes_estimate > MAX_NODES)
      throw InputError(at(card.path, line_of("rve", "stitch_length")) +
                       ": the card asks for about " + std::to_string((long long) nodes_estimate) +
                       " fibre nodes (RVE " + num(lx) + " x " + num(ly) + " m, fibre_mesh " +
                       num(card.fibre_mesh) + " m), more than the limit of " +
                       std::to_string((long long) MAX_NODES) +
                       ": check the keys 'rve', 'stitch_length', 'gauge' and 'fibre_mesh'");

    // main axis: the face pair the chains cross once
    double theta = std::fmod(spec.angle, 180.0);    // fibres are lines: angle mod 180
    if (theta <= -90.0) theta += 180.0;
    if (theta > 90.0) theta -= 180.0;
    const double c = std::fabs(std::cos(theta * DEG)), s = std::fabs(std::sin(theta * DEG));
    if (c > s + 1e-12)
      info.main_axis = 0;
    else if (s > c + 1e-12)
      info.main_axis = 1;
    else
      info.main_axis = (lx / c <= ly / s) ? 0 : 1;    // 45 deg: the shorter chains
    // angle measured from the main axis' positive direction, in (-90, 90) for x, (0, 180) for y
    double nominal = theta;
    if (info.main_axis == 1 && nominal <= 0.0) nominal += 180.0;
    info.width = info.main_axis == 0 ? ly * c : lx * s;
    const double target_chains = info.width * info.chains_per_width_target;
    const std::string layer_is = at(card.path, spec.line) + ": layer " + std::to_string(layer) +
        " (areal_weight " + num(spec.areal_weight * 1e3) + " g/m^2)";
    if (!(target_chains <= MAX_CHAINS))
      throw InputError(layer_is + " needs " + num(target_chains) +
                       " chains across the RVE, more than the limit of " + num(MAX_CHAINS) +
                       " per layer: check the keys 'areal_weight', 'rve', 'gauge' and "
                       "'stitch_length'");
    const int n = std::max(1, (int) std::lround(target_chains));
    if (std::fabs(n / target_chains - 1.0) > MAX_CHAIN_ROUNDING)
      throw InputError(layer_is + " needs " + num(target_chains) + " chains across the RVE; the " +
                       std::to_string(n) + " whole chains that fit would give an areal weight " +
                       num(100.0 * (n / target_chains - 1.0)) + " % off (more than " +
                       num(100.0 * MAX_CHAIN_ROUNDING) +
                       " %): make the RVE wider with the key 'rve'");
    info.chains = n;

    // chain angles: Gaussian around the nominal angle
    Rng rng(card.seed * 0x9E3779B97F4A7C15ULL + 0x632BE59BD9B4E019ULL * (std::uint64_t) layer);
    std::vector<double> dev(n, 0.0);
    if (spec.sigma > 0.0) {
      if (card.stratified) {
        // one draw in each of n equal-probability strata, strata shuffled over the chains
        std::vector<int> perm(n);
        std::iota(perm.begin(), perm.end(), 0);
        for (int i = n - 1; i > 0; i--) std::swap(perm[i], perm[rng.below(i + 1)]);
        for (int k = 0; k < n; k++) dev[k] = normal_quantile((perm[k] + rng.uniform()) / n);
      } else {
        for (int k = 0; k < n; k++) dev[k] = rng.normal();
      }
      for (auto &d : dev) d *= spec.sigma;
    }

    // straight chains from the main face, start points evenly spaced on it
    std::vector<Line> lines(n);
    std::vector<std::vector<std::array<double, 2>>> pts(n);
    double mass = 0.0;
    for (int k = 0; k < n; k++) {
      const double a = (nominal + dev[k]) * DEG;
      double p0[2], dir[2] = {std::cos(a), std::sin(a)}, len;
      // a chain must cross its main axis at a reasonable angle (within 80 deg of it)
      if (dir[info.main_axis] < std::cos(80.0 * DEG))
        throw InputError(at(card.path, spec.line) + ": key 'sigma': value " +
                         std::to_string(spec.sigma) + " deg of layer " + std::to_string(layer) +
                         " gives a chain at " + std::to_string(spec.angle + dev[k]) +
                         " deg, more than 80 deg from the axis its chains cross (" +
                         (info.main_axis == 0 ? "x" : "y") + "): reduce sigma");
      if (info.main_axis == 0) {
        p0[0] = 0.0;
        p0[1] = (k + 0.5) * ly / n;
        len = lx / dir[0];
      } else {
        p0[0] = (k + 0.5) * lx / n;
        p0[1] = 0.0;
        len = ly / dir[1];
      }
      fibre_nodes += std::max(2.0, std::round(len / card.fibre_mesh));
      if (!(fibre_nodes <= MAX_NODES))
        throw InputError(at(card.path, line_of("fibre_mesh", "stitch_length")) +
                         ": the chains of layer " + std::to_string(layer) + " need more than " +
                         std::to_string((long long) MAX_NODES) + " nodes (RVE " + num(lx) + " x " +
                         num(ly) + " m, fibre_mesh " + num(card.fibre_mesh) +
                         " m): check the keys 'rve', 'stitch_length', 'gauge' and 'fibre_mesh'");
      int nseg = std::max(2, (int) std::lround(len / card.fibre_mesh));
      // the rounding may make the elements shorter than fibre_mesh: never shorter than the
      // chain diameter (elements i and i + 2 of a straight chain would touch), so that every
      // fibre_mesh >= chain_diameter works (the count changes only where that happened)
      while (nseg > 2 && len / nseg < dc * (1.0 + 1e-9)) nseg--;
      double h = len / nseg;
      // nodes half an element in from the main faces: the end caps of a chain and of its
      // continuation through the opposite face are one element apart. An inclined chain's
      // continuation is its own periodic image, offset across its axis by the chain's travel
      // along the face less whole periods; where that offset is below a diameter the end nodes
      // of the two would be closer than d_c (the height cannot separate a chain from itself), so
      // the ends move further in, just enough (end_inset)
      const double e = end_inset(0.5 * h, len, dir, info.main_axis, info.main_axis ? lx : ly,
                                 dc * (1.0 + MARGIN));
      const bool inset = e > 0.5 * h;
      if (inset) {
        while (nseg > 2 && (len - 2.0 * e) / (nseg - 1) < dc * (1.0 + 1e-9)) nseg--;
        h = (len - 2.0 * e) / (nseg - 1);
      }
      for (int j = 0; j < nseg; j++) {
        const double sj = inset ? e + j * h : (j + 0.5) * h;
        pts[k].push_back({p0[0] + sj * dir[0], p0[1] + sj * dir[1]});
      }
      // the line spans the chain with its end caps: pair ncf/contact extends a free end segment
      // by NCF::DEFAULT_ENDCAP diameters along its axis (pair_style default), so chains must also
      // keep clear of each other there
      Line &L = lines[k];
      for (int d = 0; d < 2; d++) {
        L.p0[d] = pts[k].front()[d] - NCF::DEFAULT_ENDCAP * dc * dir[d];
        L.p1[d] = pts[k].back()[d] + NCF::DEFAULT_ENDCAP * dc * dir[d];
      }
      L.bb[0] = std::min(L.p0[0], L.p1[0]);
      L.bb[1] = std::max(L.p0[0], L.p1[0]);
      L.bb[2] = std::min(L.p0[1], L.p1[1]);
      L.bb[3] = std::max(L.p0[1], L.p1[1]);
      mass += info.chain.mass_per_length * len;
      info.angles.push_back(spec.angle + dev[k]);
    }

    // heights
    const double r1 = rc * (1.0 + MARGIN);
    bool placed = false;
    if (spec.sigma == 0.0 && n > 1) {
      // homogeneous mat of thickness t_L: a rank-1 lattice in (offset across the fibres, z),
      // chain k at height index (k m mod n); m maximises the smallest distance of neighbours
      const double sp = info.width / n;    // spacing across the fibres
      const double dz = (info.t_l - 2.0 * r1) / (n - 1);
      if (dz > 0.0) {
        const int jmax = std::min(n - 1, (int) std::ceil(dc / sp));
        double best = -1.0;
        int best_m = 0;
        for (int m = 1; m < n; m++) {
          if (gcd(m, n) != 1) continue;
          double mind = 1e300;
          for (int j = 1; j <= jmax; j++) {
            const int jj = std::min(j, n - j);
            const int r = (int) (((long long) j * m) % n);
            const int rr = std::min(r, n - r);
            mind = std::min(mind, std::hypot(jj * sp, rr * dz));
          }
          if (mind > best) {
            best = mind;
            best_m = m;
          }
        }
        if (best >= dc * (1.0 + MARGIN)) {
          for (int k = 0; k < n; k++)
            lines[k].z = base + r1 + dz * (double) (((long long) k * best_m) % n);
          info.homogeneous = true;
          info.lattice_multiplier = best_m;
          placed = true;
        }
      }
    }
    if (!placed) {
      // first fit: each chain, in the order of its angle (nearly parallel chains first fill the
      // bottom like a mat; ties by start point), at the lowest height where it keeps the contact
      // diameter from every chain placed before it (this order gave stacks 10-25 % thinner than
      // the order of the start points or random orders; "gravity" sweeps dropping each chain
      // afterwards moved none). Conflicts (pairs closer than d_c in projection) are found once.
      const double zmin = base + r1;
      std::vector<std::vector<std::pair<int, double>>> conflicts(n);    // (other chain, half-gap)
      for (int k = 0; k < n; k++)
        for (int q = 0; q < k; q++) {
          const double d2d = line_distance(lines[k], lines[q], lx, ly, dc);
          if (d2d >= dc) continue;
          const double h = std::sqrt(dc * dc - d2d * d2d) * (1.0 + MARGIN) + MARGIN * dc;
          conflicts[k].emplace_back(q, h);
          conflicts[q].emplace_back(k, h);
        }
      std::vector<char> is_placed(n, 0);
      auto lowest = [&](int k) {
        std::vector<std::pair<double, double>> forbidden;
        for (auto &qh : conflicts[k])
          if (is_placed[qh.first])
            forbidden.emplace_back(lines[qh.first].z - qh.second, lines[qh.first].z + qh.second);
        std::sort(forbidden.begin(), forbidden.end());
        double z = zmin;
        for (auto &iv : forbidden) {
          if (iv.first >= z) break;
          if (iv.second > z) z = iv.second;
        }
        return z;
      };
      std::vector<int> order(n);
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return dev[a] < dev[b];
      });
      for (int k : order) {
        lines[k].z = lowest(k);
        is_placed[k] = 1;
      }
    }

    // nodes and bonds
    info.z_min = 1e300;
    info.z_max = -1e300;
    info.min_l0 = 1e300;
    info.max_l0 = 0.0;
    const int first_node = (int) f.fibres.nodes.size();
    double sum_l0 = 0.0;
    for (int k = 0; k < n; k++) {
      ++chain_id;
      f.fibres.diameter.push_back(dc);
      const int start = (int) f.fibres.nodes.size();
      const int m = (int) pts[k].size();
      for (int j = 0; j < m; j++) {
        Node nd;
        nd.x[0] = pts[k][j][0];
        nd.x[1] = pts[k][j][1];
        nd.x[2] = lines[k].z;
        nd.type = layer;
        nd.layer = layer;
        nd.chain = chain_id;
        if (j == 0) nd.end = info.main_axis == 0 ? XLO : YLO;
        if (j == m - 1) nd.end = info.main_axis == 0 ? XHI : YHI;
        f.fibres.nodes.push_back(nd);
        if (j > 0) {
          Bond b;
          b.i = start + j - 1;
          b.j = start + j;
          b.type = layer;
          const double *p = f.fibres.nodes[b.i].x, *q = f.fibres.nodes[b.j].x;
          b.l0 = std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                           (q[2] - p[2]) * (q[2] - p[2]));
          info.min_l0 = std::min(info.min_l0, b.l0);
          info.max_l0 = std::max(info.max_l0, b.l0);
          sum_l0 += b.l0;
          f.fibres.bonds.push_back(b);
          info.bonds++;
        }
        // bending: one angle per pair of consecutive bonds of the chain (none across the RVE
        // faces: the chain's ends there are tied by fix ncf/pbc, not bonded)
        if (card.bending && j > 1) {
          Angle a;
          a.i = start + j - 2;
          a.j = start + j - 1;
          a.k = start + j;
          a.type = layer;
          f.fibres.angles.push_back(a);
          info.bending_angles++;
        }
      }
      info.z_min = std::min(info.z_min, lines[k].z);
      info.z_max = std::max(info.z_max, lines[k].z);
    }
    info.nodes = (int) f.fibres.nodes.size() - first_node;
    info.mean_l0 = info.bonds ? sum_l0 / info.bonds : 0.0;
    // angle_style cosine, E = K (1 + cos theta) ~ K phi^2 / 2 for a kink phi = pi - theta: for a
    // chain of elements l0 this is the discrete Euler-Bernoulli beam with EI = K l0
    if (card.bending) info.bending_k = info.chain.bundle_ei / info.mean_l0;
    info.stack = info.z_max - info.z_min + dc;
    info.node_mass = card.mass_scaling * mass / info.nodes;
    info.dt_crit =
        info.min_l0 * std::sqrt(info.chain.density * card.mass_scaling / info.chain.modulus);
    if (!(std::isfinite(info.node_mass) && info.node_mass > 0.0 && std::isfinite(info.dt_crit) &&
          info.dt_crit > 0.0))
      throw InputError(at(card.path, line_of("mass_scaling", "fibre_mesh")) +
                       ": key 'mass_scaling': value " + num(card.mass_scaling) + " gives layer " +
                       std::to_string(layer) + " a node mass of " + num(info.node_mass) +
                       " kg and a critical time step of " + num(info.dt_crit) +
                       " s, not finite numbers > 0");
    double mean = 0.0, var = 0.0;
    for (double a : info.angles) mean += a;
    mean /= n;
    for (double a : info.angles) var += (a - mean) * (a - mean);
    info.angle_mean = mean;
    info.angle_std = n > 1 ? std::sqrt(var / (n - 1)) : 0.0;
    // the next layer starts above this one: t_L for a homogeneous mat, else the stack's top
    base = info.homogeneous ? base + info.t_l : info.z_max + rc * (1.0 + MARGIN);
    f.thickness += info.t_l;
    f.layers.push_back(info);
  }
  f.stack_top = base;

  // ---------------------------------------------------------------- stitching yarn
  YarnInfo &y = f.yarn;
  y.present = true;
  try {
    y.chain = NCF::yarn_chain(lib.get(card.yarn), card.yarn_packing);
  } catch (InputError &e) {
    throw InputError(at(card.path, card.yarn_line) + ": key 'yarn': value '" + card.yarn +
                     "': " + e.what() + " (materials file " + card.materials_file + ")");
  }
  const double dy = y.chain.diameter, ry = 0.5 * dy;
  // a yarn chain wider than the needle pitch cannot pass between two needles: a packing far off
  // (yarn_packing 1e-9 makes metres) or a yarn of another fabric; named before the checks of the
  // meshes and paths that it would fail
  if (dy >= f.needle_spacing) {
    if (card.from_card("yarn_packing"))
      throw InputError(at(card.path, line_of("yarn_packing", "yarn")) +
                       ": key 'yarn_packing': value " + num(card.yarn_packing) +
                       " gives the yarn '" + card.yarn + "' a diameter of " + num(dy) +
                       " m, not narrower than the needle pitch " + num(f.needle_spacing) + " m");
    throw InputError(at(card.path, card.yarn_line) + ": key 'yarn': value '" + card.yarn +
                     "': yarn diameter " + num(dy) + " m is not narrower than the needle pitch " +
                     num(f.needle_spacing) + " m (25.4 mm / gauge)");
  }
  if (!card.from_card("yarn_mesh") && card.yarn_mesh < dy) {
    f.yarn_mesh_preset_raised = card.yarn_mesh;
    card.yarn_mesh = f.card.yarn_mesh = dy;
  }
  if (card.yarn_mesh < dy)
    throw InputError(at(card.path, line_of("yarn_mesh", "yarn")) + ": key 'yarn_mesh': value " +
                     num(card.yarn_mesh) + " m is shorter than the yarn diameter " + num(dy) +
                     " m");
  // the yarn wraps the compacted mat 0 <= z <= sum t_L, touching its faces
  const double zb = -ry * (1.0 + MARGIN), zt = f.thickness + ry * (1.0 + MARGIN);
  const double zloop = card.loops_bottom ? zb : zt, zunder = card.loops_bottom ? zt : zb;
  y.z_bottom = zb;
  y.z_top = zt;
  const int kmax = card.pattern.max_underlap;
  if (card.knit) {
    // Warp knit (doc/ncf-gen.md "The idealised yarn path"): the two legs of a course pass through
    // their hole 2e apart along x, the loop runs out along +x at y - G, across its head at
    // x = next hole + h, and back at y + G. It leaves its hole at z_out, LEVEL_MARGIN clear below
    // the head of the loop before (which lies at z_loop, against the mat), and rises to z_loop at
    // its own head: the next course's legs pass through it there. All loops of a wale are the
    // same shape one course apart, so their sloped sides stay (1 + LEVEL_MARGIN) d_y apart in z.
    // The underlap runs on the other face from the up-leg to the next course's down-leg; the
    // holes are one course apart, so no underlap passes another hole.
    y.leg_offset = 0.5 * card.leg_gap * dy;
    y.loop_half_width = (1.0 + LEVEL_MARGIN) * dy;
    y.head_offset = y.leg_offset + (1.0 + LEVEL_MARGIN) * dy;
  } else {
    // Running stitch: an underlap over k needles runs from one hole's up-leg to the next course's
    // down-leg, 2e apart along x, so those of neighbouring yarns are parallel and 2e/k apart, and
    // an underlap crossing a hole passes between that hole's two legs: legs at least k yarn
    // diameters apart (plus the leg gap margin) keep wide underlaps (cord, satin) clear of each
    // other.
    y.leg_offset = 0.5 * card.leg_gap * dy * std::max(1, kmax);
  }
  const double e = y.leg_offset, G = y.loop_half_width, h = y.head_offset;
  const double loop_span = f.course + h + e;    // x extent of a knitted loop's outgoing side
  const double dz_loop = card.knit ? (1.0 + LEVEL_MARGIN) * dy * loop_span / f.course : 0.0;
  const double zout = zloop + (card.loops_bottom ? -dz_loop : dz_loop);
  y.z_loop = zloop;
  y.z_under = zunder;
  y.z_loop_out = zout;
  if (2.0 * e + dy >= f.course) {
    // the cause named: the card's leg_gap where the default gap would fit, a wide underlap of a
    // running stitch (its legs k yarn diameters apart) where one needle would, else the yarn
    const double course_mm = f.course * 1e3;
    const int k = card.knit ? 1 : std::max(1, kmax);
    const double e_default = 0.5 * 1.02 * dy * k;
    if (card.from_card("leg_gap") && 2.0 * e_default + dy < f.course)
      throw InputError(at(card.path, line_of("leg_gap", "yarn")) + ": key 'leg_gap': value " +
                       num(card.leg_gap) + " puts the two legs of a hole " + num(2.0 * e * 1e3) +
                       " mm apart, which with the yarn diameter " + num(dy * 1e3) +
                       " mm does not fit the course spacing " + num(course_mm) +
                       " mm (legs of neighbouring holes overlap)");
    if (k > 1 && 2.0 * 0.5 * card.leg_gap * dy + dy < f.course)
      throw InputError(at(card.path, card.pattern_line) + ": key 'pattern': value '" +
                       card.pattern.text + "': its underlap over " + std::to_string(k) +
                       " needles (running stitch) puts the two legs of a hole " +
                       num(2.0 * e * 1e3) + " mm apart, which does not fit the course spacing " +
                       num(course_mm) + " mm (legs of neighbouring holes overlap)");
    throw InputError(at(card.path, card.yarn_line) + ": key 'yarn': value '" + card.yarn +
                     "': yarn diameter " + num(dy) +
                     " m is too large for the stitch length (legs of neighbouring holes overlap)");
  }
  if (card.knit && 2.0 * G + (1.0 + LEVEL_MARGIN) * dy >= f.needle_spacing)
    throw InputError(at(card.path, card.yarn_line) + ": key 'yarn': value '" + card.yarn +
                     "': yarn diameter " + num(dy) +
                     " m is too large for the gauge (the loops of neighbouring needles overlap)");
  // the stitching points of two courses are a stitch length apart along x: the needles (narrower
  // than the needle pitch, read_card) must be narrower than that too
  if (card.needle_diameter >= f.course)
    throw InputError(at(card.path, line_of("needle_diameter", "stitch_length")) +
                     ": key 'needle_diameter': " + num(card.needle_diameter * 1e3) +
                     " mm is not narrower than the stitch length " + num(f.course * 1e3) +
                     " mm (the needles of two courses would overlap)");
  const std::vector<int> &needle = card.pattern.needle;
  const int p = card.pattern.repeat;
  // the yarn nodes and the needles, counted before any is made
  {
    const double legs = 2.0 * std::fabs(zout - zunder) / dy;
    const double loop = card.knit ? (2.0 * loop_span + 4.0 * G) / dy : (f.course - 2.0 * e) / dy;
    const double under = std::hypot(f.course, (double) kmax * f.needle_spacing) / dy;
    const double yarn_nodes = (double) card.r_w * f.courses * (legs + loop + under + 8.0);
    if (!(yarn_nodes <= MAX_NODES) || !((double) f.courses * card.r_w <= MAX_NODES))
      throw InputError(
          at(card.path, line_of("rve", "stitch_length")) + ": the stitching yarn needs about " +
          std::to_string((long long) std::min(yarn_nodes, 1e18)) + " nodes for " +
          std::to_string((long long) f.courses * card.r_w) + " stitches, more than the limit of " +
          std::to_string((long long) MAX_NODES) +
          ": check the keys 'rve', 'stitch_length', 'gauge' and 'pattern'");
  }
  y.yarns = card.r_w;
  double total_length = 0.0;    // of all yarns
  y.min_l0 = 1e300;
  for (int w = 0; w < card.r_w; w++) {
    std::vector<std::array<double, 3>> corners;
    for (int c = 0; c < f.courses; c++) {
      const double yn = (needle[c % p] + w + 0.5) * f.needle_spacing;
      const double xc = (c + 0.5) * f.course, xn = xc + f.course;
      if (card.knit) {
        // per course c at hole (c, n_c): down at x_c - e, out at y - G, rising to the head at
        // x_{c+1} + h, back at y + G, up at x_c + e; the underlap to the next course's down-leg
        corners.push_back({xc - e, yn, zunder});
        corners.push_back({xc - e, yn, zout});
        corners.push_back({xc - e, yn - G, zout});
        corners.push_back({xn + h, yn - G, zloop});
        corners.push_back({xn + h, yn + G, zloop});
        corners.push_back({xc + e, yn + G, zout});
        corners.push_back({xc + e, yn, zout});
        corners.push_back({xc + e, yn, zunder});
      } else {
        // per course c: down through the hole (c, n_c) just after its centre, the loop along +x
        // on the loop face, up through the hole (c+1, n_c) just before its centre, the underlap
        // on the other face to hole (c+1, n_c+1)
        corners.push_back({xc + e, yn, zunder});
        corners.push_back({xc + e, yn, zloop});
        corners.push_back({xn - e, yn, zloop});
        corners.push_back({xn - e, yn, zunder});
      }
    }
    // close the loop: the first corner of the next period, one RVE length further along x
    std::array<double, 3> closing = corners.front();
    closing[0] += lx;
    ++chain_id;
    const int chain = (int) (chain_id - f.fibres.diameter.size());    // ids from 1 in the yarn file
    f.stitch.diameter.push_back(dy);
    const int start = (int) f.stitch.nodes.size();
    for (std::size_t k = 0; k < corners.size(); k++) {
      const auto &a = corners[k];
      const auto &b = (k + 1 < corners.size()) ? corners[k + 1] : closing;
      const double len = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                   (b[2] - a[2]) * (b[2] - a[2]));
      total_length += len;
      // elements of at most yarn_mesh, but not shorter than the yarn diameter
      const int nseg = std::max(1,
                                std::min((int) std::ceil(len / card.yarn_mesh - 1e-9),
                                         (int) std::floor(len / dy + 1e-9)));
      for (int j = 0; j < nseg; j++) {
        Node nd;
        const double t = (double) j / nseg;
        for (int d = 0; d < 3; d++) nd.x[d] = a[d] + t * (b[d] - a[d]);
        nd.type = f.yarn_type();
        nd.layer = 0;
        nd.chain = chain;
        f.stitch.nodes.push_back(nd);
      }
    }
    const int end = (int) f.stitch.nodes.size();
    for (int i = start; i < end; i++) {
      Bond b;
      b.i = i;
      b.j = (i + 1 < end) ? i + 1 : start;
      b.type = f.yarn_type();
      double q[3];
      for (int d = 0; d < 3; d++) q[d] = f.stitch.nodes[b.j].x[d];
      if (b.j == start) q[0] += lx;    // the closing bond crosses the x face
      const double *pp = f.stitch.nodes[b.i].x;
      b.l0 = std::sqrt((q[0] - pp[0]) * (q[0] - pp[0]) + (q[1] - pp[1]) * (q[1] - pp[1]) +
                       (q[2] - pp[2]) * (q[2] - pp[2]));
      y.min_l0 = std::min(y.min_l0, b.l0);
      y.max_l0 = std::max(y.max_l0, b.l0);
      f.stitch.bonds.push_back(b);
    }
  }
  y.nodes = (int) f.stitch.nodes.size();
  y.bonds = (int) f.stitch.bonds.size();
  y.length_per_yarn = total_length / y.yarns;
  y.areal_weight = y.chain.mass_per_length * total_length / (lx * ly);
  y.node_mass = card.mass_scaling * y.chain.mass_per_length * total_length / y.nodes;
  y.dt_crit = y.min_l0 * std::sqrt(y.chain.density * card.mass_scaling / y.chain.modulus);
  if (!(std::isfinite(y.node_mass) && y.node_mass > 0.0 && std::isfinite(y.dt_crit) &&
        y.dt_crit > 0.0))
    throw InputError(
        at(card.path, line_of("mass_scaling", "yarn")) + ": key 'mass_scaling': value " +
        num(card.mass_scaling) + " gives the stitching yarn a node mass of " + num(y.node_mass) +
        " kg and a critical time step of " + num(y.dt_crit) + " s, not finite numbers > 0");

  // ---------------------------------------------------------------- needles: every stitching point
  for (int c = 0; c < f.courses; c++)
    for (int w = 0; w < card.r_w; w++)
      f.needles.emplace_back((c + 0.5) * f.course, (w + 0.5) * f.needle_spacing);

  // ---------------------------------------------------------------- box in z
  const double top = std::max(f.stack_top, std::max(zt, zout) + ry);
  const double bottom = std::min(0.0, std::min(zb, zout) - ry);
  const double pad = 0.5 * (top - bottom);
  f.zlo = bottom - pad;
  f.zhi = top + pad;

  // ---------------------------------------------------------------- the promise: no overlap
  const Clearance cl = min_clearance(part_segments(f.fibres, lx), lx, ly);
  const Clearance cy = min_clearance(part_segments(f.stitch, lx), lx, ly);
  f.fibre_gap = cl.gap;
  f.fibre_distance = cl.distance;
  f.yarn_gap = cy.gap;
  if (cl.gap < 0.0 || cy.gap < 0.0)
    throw InputError(card.path + ": internal check failed: generated " +
                     (cl.gap < 0.0 ? "chains" : "yarn segments") + " overlap by " +
                     num(-std::min(cl.gap, cy.gap)) +
                     " m; please report this card as a bug of ncf-gen");
  return f;
}

std::vector<Segment> part_segments(const Part &part, double lx)
{
  std::vector<Segment> out;
  for (const Bond &b : part.bonds) {
    Segment sg;
    for (int d = 0; d < 3; d++) {
      sg.a[d] = part.nodes[b.i].x[d];
      sg.b[d] = part.nodes[b.j].x[d];
    }
    // a closing bond of a yarn loop: its far end is one period further along x
    if (sg.b[0] < sg.a[0] - 0.5 * lx) sg.b[0] += lx;
    sg.chain = part.nodes[b.i].chain;
    sg.na = b.i;
    sg.nb = b.j;
    sg.radius = 0.5 * part.diameter[sg.chain - 1];
    out.push_back(sg);
  }
  return out;
}

}    // namespace NCFGEN
