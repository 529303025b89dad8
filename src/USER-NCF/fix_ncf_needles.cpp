/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/needles (see fix_ncf_needles.h, doc/fix_ncf_needles.md)

   Every chain segment (bond) with both nodes in the group is tested against every needle at its
   closest periodic image. The contact is NCF::needle_contact of ncf_needle.h: a monotonic
   penalty on the horizontal penetration of the chain into the pointed needle (a body of
   revolution), integrated along the segment; conservative, continuous, pushing the chains out
   along the needle's normal (radially, plus the point's axial part) up to the axis itself.
   Segments are visited from both of their nodes (through the 1-2 special list), and each owner
   applies the force on its own node only: no ghost forces, no communication, every segment's
   force complete once.
------------------------------------------------------------------------- */

#include "fix_ncf_needles.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "input.h"
#include "neighbor.h"
#include "update.h"
#include "variable.h"

#include "lammps_ncf_args.h"
#include "lammps_ncf_compat.h"
#include "lammps_ncf_motion.h"
#include "ncf_needle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

/* ----------------------------------------------------------------------
   fix ID group ncf/needles diameter DN kn KN chain TYPES D [chain TYPES D ...]
       (file FILE | at X Y [at X Y ...]) MOTION [tip L] [length H] [direction down|up]
   MOTION: move Z0 V | target Z0 ZT V | v_NAME   (height of the tips)
------------------------------------------------------------------------- */

FixNCFNeedles::FixNCFNeedles(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), radius(0.0), tip(-1.0), length(-1.0), kn(0.0), direction(-1), ivar(-1),
    ztip(0.0), energy(0.0), maxpen(0.0), ncontact(0), nvisit(0)
{
  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 6;
  array_flag = 1;
  size_array_cols = 3;
  global_freq = 1;
  extscalar = 1;
  extvector = extarray = 0;
  energy_global_flag = 1;
  restart_global = 1;

  parse_args(narg, arg);
  set_needle_shape();
  if (!atom->molecular) error->all(FLERR, "fix ncf/needles needs an atom style with bonds");
  NCF_LMP::wrap_needles(lmp, "fix ncf/needles", nx, ny);
  check_needle_layout();
  size_array_rows = (int) nx.size();
  fneedle.assign(3 * nx.size(), 0.0);
  clock.start(update);
  update_tip();
}

FixNCFNeedles::~FixNCFNeedles() = default;

/* ----------------------------------------------------------------------
   the arguments: the keywords, the ones required, the chain diameters (from the pair unless
   given)
------------------------------------------------------------------------- */

void FixNCFNeedles::parse_args(int narg, char **arg)
{
  chain_d.assign(atom->ntypes + 1, 0.0);
  const std::string W = "fix ncf/needles";
  auto number = [&](int i, const char *key) {
    NCF_LMP::need_values(lmp, W, key, i - 1, narg, 1);
    return NCF_LMP::number(lmp, W, key, arg[i]);
  };
  // (the needles are frictionless: of the contact keywords only kn)
  NCF_LMP::ContactReader reader(lmp, W, {NCF::ContactKey::KN}, {"at", "chain"});
  NCF::ContactCoeffs cc;
  bool chain_given = false;
  int iarg = 3;
  while (iarg < narg) {
    if (reader.read(iarg, narg, arg, cc)) {
      kn = cc.kn;
      continue;
    }
    const std::string key = arg[iarg];
    reader.once(key,
                key == "move" || key == "target" || utils::strmatch(key, "^v_") ? "motion" : "");
    if (key == "diameter") {
      const double d = number(iarg + 1, "diameter");
      if (!(d > 0.0)) error->all(FLERR, "fix ncf/needles: diameter {} must be > 0", arg[iarg + 1]);
      radius = 0.5 * d;
      iarg += 2;
    } else if (key == "tip") {
      tip = number(iarg + 1, "tip");
      if (!(tip > 0.0)) error->all(FLERR, "fix ncf/needles: tip {} must be > 0", arg[iarg + 1]);
      iarg += 2;
    } else if (key == "length") {
      length = number(iarg + 1, "length");
      if (!(length > 0.0))
        error->all(FLERR, "fix ncf/needles: length {} must be > 0", arg[iarg + 1]);
      iarg += 2;
    } else if (key == "chain") {
      NCF_LMP::read_type_diameters(lmp, W, key, iarg, narg, arg, chain_d);
      chain_given = true;
    } else if (key == "at") {
      NCF_LMP::need_values(lmp, W, key, iarg, narg, 2, "two values, X Y");
      nx.push_back(number(iarg + 1, "at"));
      ny.push_back(number(iarg + 2, "at"));
      iarg += 3;
    } else if (key == "file") {
      NCF_LMP::need_values(lmp, W, key, iarg, narg, 1, "a file name");
      NCF_LMP::read_needles(lmp, "fix ncf/needles", arg[iarg + 1], nx, ny);
      iarg += 2;
    } else if (key == "direction") {
      NCF_LMP::need_values(lmp, W, key, iarg, narg, 1);
      const std::string v = arg[iarg + 1];
      if (v == "down")
        direction = -1;
      else if (v == "up")
        direction = 1;
      else
        error->all(FLERR, "fix ncf/needles: direction '{}' is not one of down, up", v);
      iarg += 2;
    } else if (key == "move" || key == "target" || utils::strmatch(key, "^v_")) {
      iarg =
          NCF_LMP::parse_motion(lmp, "fix ncf/needles: 'tips", iarg, narg, arg, motion, var, false);
    } else
      error->all(FLERR, "fix ncf/needles: unknown keyword '{}'", key);
  }
  if (radius == 0.0)
    error->all(FLERR, "fix ncf/needles: keyword 'diameter' (of the needles) is required");
  if (kn == 0.0)
    error->all(FLERR, "fix ncf/needles: keyword 'kn' (contact stiffness, Pa) is required");
  if (nx.empty()) error->all(FLERR, "fix ncf/needles: no needle: give 'file FILE' or 'at X Y'");
  if (motion.kind == NCF::Motion::NONE)
    error->all(FLERR, "fix ncf/needles: give the motion of the tips: move, target or v_NAME");
  {
    // (taken from the pair: the types of the group's nodes now, since the largest diameter
    // sizes the needles' reach)
    std::vector<int> mine(atom->ntypes + 1, 0), present(atom->ntypes + 1, 0);
    for (int i = 0; i < atom->nlocal; i++)
      if (atom->mask[i] & groupbit) mine[atom->type[i]] = 1;
    MPI_Allreduce(mine.data(), present.data(), atom->ntypes + 1, MPI_INT, MPI_MAX, world);
    NCF_LMP::pair_diameters(lmp, W, "chain", chain_given, chain_d, &present);
  }
}

/* ----------------------------------------------------------------------
   tip and length (defaults: the radius and the box height) and the reach of the needles' points
------------------------------------------------------------------------- */

void FixNCFNeedles::set_needle_shape()
{
  const bool tip_given = tip >= 0.0, length_given = length >= 0.0;
  if (tip < 0.0) tip = radius;
  // the largest z margin of a segment (see post_force): its contact radius rc plus the height of
  // the point's cone at rc from its surface, for the largest chain diameter
  double dmax = 0.0;
  for (double d : chain_d) dmax = std::max(dmax, d);
  margin_max = 0.5 * dmax * (1.0 + tip / radius);
  dmax_chain = dmax;
  if (length < 0.0) length = domain->boxhi[2] - domain->boxlo[2];
  if (length < NCF::needle_min_length(tip) && !tip_given && !length_given)
    // (neither was given: the diameter, whose half is the default point, is what is off)
    error->all(FLERR,
               "fix ncf/needles: diameter {} is too large for the box: its default point (tip, "
               "the radius {}) needs a needle of at least {}, longer than the box height {} (the "
               "default length)",
               2.0 * radius, radius, NCF::needle_min_length(tip), length);
  if (length < NCF::needle_min_length(tip))
    error->all(FLERR,
               "fix ncf/needles: length {} must be at least {} times tip {} (a point at each end "
               "and a shaft between)",
               length, NCF::needle_min_length(1.0), tip);
}

/* ----------------------------------------------------------------------
   the needles' positions: none listed twice, none overlapping another or its own periodic image
------------------------------------------------------------------------- */

void FixNCFNeedles::check_needle_layout()
{
  // a needle listed twice (a needle file given twice, 1 000 needles on one point) would act twice
  // on every chain it touches, two that overlap would press the chains between them from both
  // sides at once; in a periodic direction a needle must also clear its own image
  for (int d = 0; d < 2; d++) {
    const double prd = domain->boxhi[d] - domain->boxlo[d];
    if (domain->periodicity[d] && 2.0 * radius >= prd)
      error->all(
          FLERR,
          "fix ncf/needles: diameter {} is not smaller than the periodic box length {} in {}: "
          "a needle would overlap its own image",
          2.0 * radius, prd, d ? "y" : "x");
  }
  {
    std::vector<std::size_t> order(nx.size());
    for (std::size_t k = 0; k < order.size(); k++) order[k] = k;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return nx[a] < nx[b] || (nx[a] == nx[b] && (ny[a] < ny[b] || (ny[a] == ny[b] && a < b)));
    });
    for (std::size_t k = 1; k < order.size(); k++) {
      const std::size_t a = order[k - 1], b = order[k];
      if (nx[a] == nx[b] && ny[a] == ny[b])
        error->all(FLERR, "fix ncf/needles: needles {} and {} are the same needle, at ({}, {})",
                   std::min(a, b) + 1, std::max(a, b) + 1, nx[a], ny[a]);
    }
  }
  // (all pairs, through the periodic faces: a few hundred needles at most, once)
  for (std::size_t a = 0; a < nx.size(); a++)
    for (std::size_t b = a + 1; b < nx.size(); b++) {
      double d[3] = {nx[b] - nx[a], ny[b] - ny[a], 0.0};
      NCF_COMPAT::minimum_image(domain, FLERR, d[0], d[1], d[2]);
      const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1]);
      if (dist < 2.0 * radius)
        error->all(FLERR,
                   "fix ncf/needles: needles {} at ({}, {}) and {} at ({}, {}) overlap: their axes "
                   "are {:.6g} apart{}, less than the diameter {}",
                   a + 1, nx[a], ny[a], b + 1, nx[b], ny[b], dist,
                   std::fabs(d[0] - (nx[b] - nx[a])) + std::fabs(d[1] - (ny[b] - ny[a])) > 0.0
                       ? " through a periodic face"
                       : "",
                   2.0 * radius);
    }
}

int FixNCFNeedles::setmask()
{
  return POST_FORCE;
}

void FixNCFNeedles::init()
{
  if (motion.kind == NCF::Motion::VARIABLE) {
    ivar = input->variable->find(var.c_str());
    if (ivar < 0) error->all(FLERR, "fix ncf/needles: variable '{}' does not exist", var);
  }
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "fix ncf/needles needs an atom map (atom_modify map array or hash)");
  check_time_step();
}

/* ----------------------------------------------------------------------
   critical time step of the needle contacts, before a run: a node of mass m pressed against a
   needle over its tributary length l (half of each element, bond_style ncf/chain's reference
   lengths) has the stiffness kn l (1 + (R/tip)^2) at most (the point's slope adds its axial
   part), so dt_c = 2 sqrt(m / (kn l (1 + (R/tip)^2))). Above it the contacts blow up within a few
   steps, and the run would end in an error about something else (a segment longer than lmax, a
   bond atom missing): stopped here, naming kn. (Without bond_style ncf/chain there are no
   reference lengths: no check.)
------------------------------------------------------------------------- */

void FixNCFNeedles::check_time_step()
{
  int flag, cols;
  const int idx = atom->find_custom("ncf_l0", flag, cols);
  if (idx < 0 || update->whichflag != 1) return;
  double **l0 = atom->darray[idx];
  const int *mask = atom->mask, *type = atom->type;
  const double slope = radius / tip, kpoint = kn * (1.0 + slope * slope);
  double dtmin = 1e300;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit) || !(chain_d[type[i]] > 0.0)) continue;
    const double l = 0.5 * (l0[i][0] + l0[i][1]);
    if (!(l > 0.0)) continue;
    const double m = atom->rmass ? atom->rmass[i] : atom->mass[type[i]];
    dtmin = std::min(dtmin, 2.0 * std::sqrt(m / (kpoint * l)));
  }
  double all = 1e300;
  MPI_Allreduce(&dtmin, &all, 1, MPI_DOUBLE, MPI_MIN, world);
  if (update->dt > all)
    error->all(FLERR,
               "fix ncf/needles: timestep {:.6g} is above the critical time step {:.6g} of the "
               "needle contacts (kn {:.6g} Pa, the point's slope R/tip {:.3g}, on the lightest "
               "node per tributary length); lower kn or the timestep, or scale the masses",
               update->dt, all, kn, slope);
}

void FixNCFNeedles::update_tip()
{
  if (motion.kind == NCF::Motion::VARIABLE) {
    ztip = input->variable->compute_equal(ivar);
    // (a variable is looked up at init: not yet when the fix is defined)
    if (ivar >= 0 && !std::isfinite(ztip))
      error->all(FLERR, "fix ncf/needles: variable '{}' gives the tip height {} at step {}", var,
                 ztip, update->ntimestep);
    return;
  }
  double v;
  motion.at(clock.time(update), ztip, v);
}

void FixNCFNeedles::setup(int vflag)
{
  // (types, groups or bonds may have changed between runs)
  part_valid = false;
  post_force(vflag);
}

/* ----------------------------------------------------------------------
   the needles binned in the plane (their positions are fixed there), so that a segment tests
   only the needles of the cells within its reach: the cost of a step grows with the segments,
   not with segments times needles. Cells at least a needle diameter plus the thickest chain wide
   (one cell along a direction that is not periodic or in a triclinic box); binned again when the
   box changes
------------------------------------------------------------------------- */

void FixNCFNeedles::bin_needles()
{
  const double lo[2] = {domain->boxlo[0], domain->boxlo[1]};
  const double prd[2] = {domain->xprd, domain->yprd};
  if (!cell_first.empty() && lo[0] == cell_lo[0] && lo[1] == cell_lo[1] && prd[0] == cell_prd[0] &&
      prd[1] == cell_prd[1])
    return;
  const double want = 2.0 * radius + dmax_chain;
  for (int d = 0; d < 2; d++) {
    ncell[d] = 1;
    if (domain->periodicity[d] && !domain->triclinic && prd[d] > 0.0)
      ncell[d] = std::max(1, std::min(1024, (int) (prd[d] / want)));
    cell_lo[d] = lo[d];
    cell_prd[d] = prd[d];
    cell_size[d] = prd[d] / ncell[d];
  }
  const int nn = (int) nx.size(), ncells = ncell[0] * ncell[1];
  std::vector<int> of(nn);
  cell_first.assign(ncells + 1, 0);
  for (int k = 0; k < nn; k++) {
    int c[2];
    const double xy[2] = {nx[k], ny[k]};
    for (int d = 0; d < 2; d++) {
      double u = (xy[d] - lo[d]) / cell_size[d];
      if (ncell[d] > 1) u -= ncell[d] * std::floor(u / ncell[d]);    // wrapped into the box
      c[d] = std::min(ncell[d] - 1, std::max(0, (int) u));
    }
    of[k] = c[0] + ncell[0] * c[1];
    cell_first[of[k] + 1]++;
  }
  for (int c = 0; c < ncells; c++) cell_first[c + 1] += cell_first[c];
  cell_needle.assign(nn, 0);
  std::vector<int> next(cell_first.begin(), cell_first.end() - 1);
  for (int k = 0; k < nn; k++) cell_needle[next[of[k]]++] = k;
}

// a cell index wrapped into [0, n) (the common case, already inside, without a division)
static inline int wrap_cell(int c, int n)
{
  if (c >= 0 && c < n) return c;
  c %= n;
  return c < 0 ? c + n : c;
}

// the grid of the cells near a needle (near) for segments of half length up to half in the plane:
// a segment with its midpoint in a cell can touch a needle only if the needle's axis lies within
// half + radius + its contact radius of the midpoint, so a cell is flagged when a needle (or a
// periodic image) lies within that distance, for the thickest chain, of the cell's rectangle.
// Cells of about a quarter of that distance, at most 1024 per direction; along a direction that is
// not periodic the midpoints beyond the box are counted to its edge cells (farther from any
// needle than those)
void FixNCFNeedles::grid_near(double half)
{
  const double reach = half + radius + 0.5 * dmax_chain;
  const double lo[2] = {domain->boxlo[0], domain->boxlo[1]};
  const double prd[2] = {domain->xprd, domain->yprd};
  for (int d = 0; d < 2; d++) {
    near_n[d] = std::max(1, std::min(1024, (int) (prd[d] / (0.25 * reach))));
    near_lo[d] = lo[d];
    near_size[d] = prd[d] / near_n[d];
    near_inv[d] = 1.0 / near_size[d];
  }
  near.assign((size_t) near_n[0] * near_n[1], 0);
  const bool periodic[2] = {domain->periodicity[0] != 0, domain->periodicity[1] != 0};
  for (size_t k = 0; k < nx.size(); k++) {
    const double xy[2] = {nx[k], ny[k]};
    int c0[2], c1[2];
    for (int d = 0; d < 2; d++) {
      // (one cell more each side: the midpoints' cells are found by a multiplication)
      c0[d] = (int) std::floor((xy[d] - reach - near_lo[d]) * near_inv[d]) - 1;
      c1[d] = (int) std::floor((xy[d] + reach - near_lo[d]) * near_inv[d]) + 1;
      if (!periodic[d] || c1[d] - c0[d] + 1 >= near_n[d]) {
        c0[d] = periodic[d] ? 0 : std::max(0, c0[d]);
        c1[d] = periodic[d] ? near_n[d] - 1 : std::min(near_n[d] - 1, c1[d]);
      }
    }
    for (int cy = c0[1]; cy <= c1[1]; cy++)
      for (int cx = c0[0]; cx <= c1[0]; cx++)
        near[wrap_cell(cx, near_n[0]) + (size_t) near_n[0] * wrap_cell(cy, near_n[1])] = 1;
  }
  near_half = half;
  near_box[0] = lo[0];
  near_box[1] = lo[1];
  near_box[2] = prd[0];
  near_box[3] = prd[1];
}

// the bond partners of the owned nodes of the group with a chain diameter (closest images), once
// per reneighbouring: their indices do not change between
void FixNCFNeedles::find_partners()
{
  int *mask = atom->mask, *type = atom->type;
  tagint **special = atom->special;
  int **nspecial = atom->nspecial;
  const int nlocal = atom->nlocal;
  part_first.assign(nlocal + 1, 0);
  part_j.clear();
  int missing = 0;
  for (int i = 0; i < nlocal; i++) {
    part_first[i] = (int) part_j.size();
    if (!(mask[i] & groupbit) || chain_d[type[i]] <= 0.0) continue;
    for (int s = 0; s < nspecial[i][0]; s++) {
      int j = atom->map(special[i][s]);
      if (j < 0) {
        missing++;
        continue;
      }
      j = domain->closest_image(i, j);
      part_j.push_back((mask[j] & groupbit) && chain_d[type[j]] > 0.0 ? j : -1);
    }
  }
  part_first[nlocal] = (int) part_j.size();
  if (missing)
    error->one(FLERR, "fix ncf/needles: {} bond partner(s) of local nodes are missing", missing);
  part_ncalls = neighbor->ncalls;
  part_nlocal = nlocal;
  part_nall = nlocal + atom->nghost;
  part_valid = true;
  // the near grid for the segments as long as the longest here now, with a margin for stretching
  // (a longer segment later searches the needle cells itself)
  double **x = atom->x;
  double hmax = 0.0;
  for (int i = 0; i < nlocal; i++)
    for (int p = part_first[i]; p < part_first[i + 1]; p++) {
      const int j = part_j[p];
      if (j < 0) continue;
      const double dx = x[j][0] - x[i][0], dy = x[j][1] - x[i][1];
      hmax = std::max(hmax, 0.5 * std::sqrt(dx * dx + dy * dy));
    }
  grid_near(1.25 * hmax);
}

// contact of the segment a0-a1 (visited from its node i) with needle k at its closest image
void FixNCFNeedles::needle_segment(int k, int i, const NCF::Vec3 &a0, const NCF::Vec3 &a1,
                                   double rc, double half, NCF::Needle &needle,
                                   std::vector<double> &local, double &emine, double &penmine,
                                   int &cmine)
{
  double **f = atom->f;
  // the needle's closest image to the segment's midpoint
  double d[3] = {0.5 * (a0.x + a1.x) - nx[k], 0.5 * (a0.y + a1.y) - ny[k], 0.0};
  NCF_COMPAT::minimum_image(domain, FLERR, d[0], d[1], d[2]);
  if (d[0] * d[0] + d[1] * d[1] > (half + radius + rc) * (half + radius + rc)) return;
  needle.x = 0.5 * (a0.x + a1.x) - d[0];
  needle.y = 0.5 * (a0.y + a1.y) - d[1];
  const NCF::NeedleContact c = NCF::needle_contact(a0, a1, rc, needle, kn);
  if (!c.active) return;
  // visited from both nodes: each applies its own node's force, and half the energy
  f[i][0] += c.f[0].x;
  f[i][1] += c.f[0].y;
  f[i][2] += c.f[0].z;
  local[3 * k + 0] -= c.f[0].x;
  local[3 * k + 1] -= c.f[0].y;
  local[3 * k + 2] -= c.f[0].z;
  emine += 0.5 * c.energy;
  penmine = std::max(penmine, c.penetration);
  cmine++;
}

/* ---------------------------------------------------------------------- */

void FixNCFNeedles::post_force(int /*vflag*/)
{
  update_tip();
  bin_needles();
  double **x = atom->x;
  int *mask = atom->mask, *type = atom->type;
  int **nspecial = atom->nspecial;
  const int nlocal = atom->nlocal;
  const int nn = (int) nx.size();

  std::vector<double> local(3 * nn + 3, 0.0);    // needle forces, energy, contacts, visits
  double emine = 0.0, penmine = 0.0;
  int cmine = 0;
  NCF::Needle needle;
  needle.zapex = ztip;
  needle.direction = direction;
  needle.radius = radius;
  needle.tip = tip;
  needle.length = length;
  // needles out of reach of every chain node here (owned or ghost: the segments of the owned
  // nodes end at one of them) are out of reach of every segment: no per-segment work at all,
  // only this bound on the nodes' heights (the margin of the largest chain diameter, below)
  const double zb = ztip, ze = ztip - direction * length;
  const double nlo = std::min(zb, ze), nhi = std::max(zb, ze);
  const int nall = nlocal + atom->nghost;
  double zlo = 1e300, zhi = -1e300;
  for (int i = 0; i < nall; i++)
    if ((mask[i] & groupbit) && chain_d[type[i]] > 0.0) {
      zlo = std::min(zlo, x[i][2]);
      zhi = std::max(zhi, x[i][2]);
    }
  const bool reach = nhi >= zlo - margin_max && nlo <= zhi + margin_max;
  double visits = 0.0;
  const double cone = 1.0 + tip / radius;    // (z margin of a segment per unit contact radius)
  if (reach &&
      (!part_valid || neighbor->ncalls != part_ncalls || nlocal != part_nlocal ||
       nall != part_nall))
    find_partners();
  if (reach &&
      (near_box[0] != domain->boxlo[0] || near_box[1] != domain->boxlo[1] ||
       near_box[2] != domain->xprd || near_box[3] != domain->yprd))
    grid_near(near_half);    // (the box changed between reneighbourings)
  for (int i = 0; reach && i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double di = chain_d[type[i]];
    if (di <= 0.0) continue;
    visits += nspecial[i][0];
    for (int p = part_first[i]; p < part_first[i + 1]; p++) {
      const int j = part_j[p];
      if (j < 0) continue;
      const double dj = chain_d[type[j]];
      // the same radius from both nodes: the mean of the two types' diameters, halved
      const double rc = 0.25 * (di + dj);
      const NCF::Vec3 a0{x[i][0], x[i][1], x[i][2]}, a1{x[j][0], x[j][1], x[j][2]};
      // the segment's extent in z, to skip needles whose body does not reach it
      const double margin = rc * cone;
      const double zmin = std::min(a0.z, a1.z) - margin, zmax = std::max(a0.z, a1.z) + margin;
      if (nhi < zmin || nlo > zmax) continue;
      const double half = 0.5 * sqrt((a1.x - a0.x) * (a1.x - a0.x) + (a1.y - a0.y) * (a1.y - a0.y));
      const double mid[2] = {0.5 * (a0.x + a1.x), 0.5 * (a0.y + a1.y)};
      // most segments: no needle near the cell of the midpoint
      if (half <= near_half) {
        int c[2];
        for (int d = 0; d < 2; d++) {
          c[d] = (int) std::floor((mid[d] - near_lo[d]) * near_inv[d]);
          c[d] = domain->periodicity[d] ? wrap_cell(c[d], near_n[d])
                                        : std::max(0, std::min(near_n[d] - 1, c[d]));
        }
        if (!near[c[0] + (size_t) near_n[0] * c[1]]) continue;
      }
      // the needles of the cells within reach of the segment's midpoint (each cell once)
      const double reach = half + radius + rc;
      int c0[2], c1[2];
      for (int dd = 0; dd < 2; dd++) {
        c0[dd] = 0;
        c1[dd] = ncell[dd] - 1;
        if (ncell[dd] == 1) continue;
        const int lo = (int) std::floor((mid[dd] - reach - cell_lo[dd]) / cell_size[dd]);
        const int hi = (int) std::floor((mid[dd] + reach - cell_lo[dd]) / cell_size[dd]);
        if (hi - lo + 1 < ncell[dd]) c0[dd] = lo, c1[dd] = hi;
      }
      for (int cy = c0[1]; cy <= c1[1]; cy++)
        for (int cx = c0[0]; cx <= c1[0]; cx++) {
          const int cell = wrap_cell(cx, ncell[0]) + ncell[0] * wrap_cell(cy, ncell[1]);
          for (int q = cell_first[cell]; q < cell_first[cell + 1]; q++) {
            const int k = cell_needle[q];
            needle_segment(k, i, a0, a1, rc, half, needle, local, emine, penmine, cmine);
          }
        }
    }
  }
  local[3 * nn] = emine;
  local[3 * nn + 1] = cmine;
  local[3 * nn + 2] = visits;
  std::vector<double> all(local.size());
  MPI_Allreduce(local.data(), all.data(), (int) local.size(), MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&penmine, &maxpen, 1, MPI_DOUBLE, MPI_MAX, world);
  std::copy(all.begin(), all.begin() + 3 * nn, fneedle.begin());
  energy = all[3 * nn];
  ncontact = (int) std::lround(all[3 * nn + 1] / 2.0);    // each segment seen from both nodes
  nvisit = all[3 * nn + 2];
}

/* ---------------------------------------------------------------------- */

double FixNCFNeedles::compute_scalar()
{
  return energy;
}

// 1 tip height, 2 total force of the fabric on the needles along z, 3 segment-needle contacts,
// 4 largest penetration, 5 largest lateral force on one needle, 6 segment visits of the last step
double FixNCFNeedles::compute_vector(int n)
{
  const int nn = (int) nx.size();
  if (n == 0) return ztip;
  if (n == 5) return nvisit;
  if (n == 1) {
    double fz = 0.0;
    for (int k = 0; k < nn; k++) fz += fneedle[3 * k + 2];
    return fz;
  }
  if (n == 2) return ncontact;
  if (n == 3) return maxpen;
  double fmax = 0.0;
  for (int k = 0; k < nn; k++)
    fmax = std::max(
        fmax, std::sqrt(fneedle[3 * k] * fneedle[3 * k] + fneedle[3 * k + 1] * fneedle[3 * k + 1]));
  return fmax;
}

double FixNCFNeedles::compute_array(int i, int j)
{
  return fneedle[3 * i + j];
}

/* ---------------------------------------------------------------------- */

void FixNCFNeedles::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  // (a restart file written before the clock existed has the time origin in buf[0] and ends
  // after buf[4])
  double buf[5 + NCF_LMP::ToolClock::NPACK];
  buf[0] = NCF_LMP::ToolClock::MARK;
  motion.pack(&buf[1]);
  clock.pack(&buf[5]);
  int size = sizeof(buf);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(buf, sizeof(double), sizeof(buf) / sizeof(double), fp);
}

void FixNCFNeedles::restart(char *raw)
{
  auto *buf = (double *) raw;
  NCF::Motion stored;
  stored.unpack(&buf[1]);
  if (!stored.same_as(motion)) {
    if (comm->me == 0)
      error->warning(
          FLERR,
          "fix ncf/needles: motion defined differently from the restart file: it starts anew");
    return;
  }
  if (buf[0] == NCF_LMP::ToolClock::MARK)
    clock.unpack(&buf[5]);
  else
    clock.resume_from_origin(update, buf[0]);
  update_tip();
}

/* ----------------------------------------------------------------------
   dump image ... fix ID type: each needle as a line (cylinder) from its tip
------------------------------------------------------------------------- */

int FixNCFNeedles::image(int *&ivec, double **&darray)
{
  const int nn = (int) nx.size();
  imgtype.assign(nn, NCF_COMPAT::ImageShape::LINE);
  imgbuf.assign(7 * nn, 0.0);
  imgrows.resize(nn);
  for (int k = 0; k < nn; k++) {
    double *r = &imgbuf[7 * k];
    r[0] = 1;
    r[1] = nx[k];
    r[2] = ny[k];
    r[3] = ztip;
    r[4] = nx[k];
    r[5] = ny[k];
    r[6] = ztip - direction * length;
    imgrows[k] = r;
  }
  ivec = imgtype.data();
  darray = imgrows.data();
  return nn;
}
