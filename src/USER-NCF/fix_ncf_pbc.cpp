/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/pbc: averaged periodic boundary conditions (see fix_ncf_pbc.h, doc/fix_ncf_pbc.md)

   For every group g of end nodes (cells of the boundary mesh, merged until each has nodes on
   both faces of its pair) the linear constraint

       C_g = sum_i w_i X_i - F D_g = 0,   w_i = +1/n_upper or -1/n_lower,  D_g = sum_i w_i X_i^ref

   holds, with X the unwrapped positions and F = h h_ref^-1 the in-plane deformation of the
   periodic box (identity in z). It is Eq. 2 of the paper applied to both reference points with
   ordinary periodicity between them. It is made exact after every step by constraint forces
   F_i = w_i lambda_g computed from the predicted (unconstrained) next positions, like SHAKE but
   in closed form because the constraints are linear and the groups disjoint: one MPI_Allreduce
   per step for all groups. Their weights sum to zero, so momentum is conserved.
------------------------------------------------------------------------- */

#include "fix_ncf_pbc.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "output.h"
#include "update.h"

#include "lammps_ncf_args.h"
#include "ncf_input_error.h"
#include "ncf_pbc.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
// face codes of the per-atom property (doc/ARCHITECTURE.md): 1 xlo, 2 xhi, 3 ylo, 4 yhi
constexpr int FACE_XLO = 1, FACE_XHI = 2, FACE_YLO = 3, FACE_YHI = 4;
// per group: predicted residual (3), current sum (3), sum w^2/m, sum w r of the node holds
constexpr int NVAL = 8;
// first number of the restart data (where a restart file without the multipliers of the last
// step held the node count): -2 with the group multipliers, -3 also with the reference origin
// and the multipliers of the node holds
constexpr double RESTART_MARK = -2.0;
constexpr double RESTART_MARK_NORMAL = -3.0;

// The shape of the box of the next step: the current box advanced by the rates of fix deform (zero
// without one), in whose metric a node's displacement of this step must have no normal part, so
// that a hold stays exact under a tilt that grows while the node slides along its face.
struct NextBox {
  double prd[3], xy;
};
NextBox next_box(const Domain *domain, double dt)
{
  NextBox b;
  for (int d = 0; d < 3; d++) b.prd[d] = domain->prd[d] + dt * domain->h_rate[d];
  b.xy = domain->triclinic ? domain->xy + dt * domain->h_rate[5] : 0.0;
  return b;
}

// the coupling a of a node hold on the faces of pair p (n = e_p + a e_u, ncf_pbc.h): the x faces of
// a box tilted by xy lean along y
double hold_coupling(int pair, const NextBox &b)
{
  return pair == 0 ? -b.xy / b.prd[1] : 0.0;
}

// in-plane deformation gradient F = h h_ref^-1 of the periodic box (x, y), identity in z
void deformation(const double *h, const double *href, double F[2][2])
{
  // h2 = [[xprd, xy], [0, yprd]]; inverse of the reference [[a, b], [0, d]] is [[1/a, -b/(a d)], [0, 1/d]]
  const double a = href[0], b = href[5], d = href[1];
  const double i00 = 1.0 / a, i01 = -b / (a * d), i11 = 1.0 / d;
  F[0][0] = h[0] * i00;
  F[0][1] = h[0] * i01 + h[5] * i11;
  F[1][0] = 0.0;
  F[1][1] = h[1] * i11;
}
}    // namespace

/* ---------------------------------------------------------------------- */

FixNCFPBC::FixNCFPBC(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), ngroups(0), residual_max(0.0), lambda_step(-1)
{
  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extscalar = 0;
  extvector = 0;
  restart_global = 1;
  // no virial: the constraint forces do no work under a box deformation (fix deform's remap
  // keeps every group's constraint and every hold as they are, so they are workless), and the
  // stress of the periodic fabric is the virial of its bonds and contacts alone; counted, they
  // would add the in-face offsets of the end nodes times their multipliers (doc/fix_ncf_pbc.md)
  dynamic_group_allow = 0;

  pair_on[0] = pair_on[1] = 1;
  for (int d = 0; d < 3; d++) loref[d] = domain->boxlo[d];
  faces_auto = 1;
  for (auto &p : user_cells) p[0] = p[1] = 0;
  for (auto &p : mesh_cells) p[0] = p[1] = 0;
  nmerged[0] = nmerged[1] = 0;
  endface_name = "ncf_end";
  parse(narg, arg);

  for (int p = 0; p < 2; p++)
    if (pair_on[p] && !domain->periodicity[p])
      error->all(FLERR, "fix ncf/pbc: faces {} need a periodic box in {}", p ? "y" : "x",
                 p ? "y" : "x");
  // the reference is captured in an orthogonal box; in a tilted one only a restart file can give
  // it (restart(), right after this constructor), otherwise init() stops
  tilted_at_definition =
      domain->triclinic && (domain->xy != 0.0 || domain->xz != 0.0 || domain->yz != 0.0);
  if (!from_id.empty())
    take_state_of(from_id);
  else if (!tilted_at_definition)
    capture_reference();
  if (normal_hold && comm->me == 0)
    utils::logmesg(lmp, "fix ncf/pbc: normal hold: every end node kept on its face\n");
}

/* ----------------------------------------------------------------------
   from FIXID: the reference state, groups and last multipliers of an existing fix ncf/pbc, so
   that a fix defined later in the same process can be moved before it (define the copy, then
   unfix the original) without capturing a new reference from the current positions
------------------------------------------------------------------------- */

void FixNCFPBC::take_state_of(const std::string &other_id)
{
  auto *f = modify->get_fix_by_id(other_id);
  if (!f) error->all(FLERR, "fix ncf/pbc: from '{}': no fix with this ID", other_id);
  auto *other = dynamic_cast<FixNCFPBC *>(f);
  if (!other || other == this)
    error->all(FLERR, "fix ncf/pbc: from '{}': fix {} is {}, not another fix ncf/pbc", other_id,
               other_id, f->style);
  if (other->igroup != igroup)
    error->all(FLERR,
               "fix ncf/pbc: from '{}': its group is {}, this fix's is {}; the state belongs to "
               "the end nodes of its group",
               other_id, group->names[other->igroup], group->names[igroup]);
  nodes = other->nodes;
  ngroups = other->ngroups;
  group_pair = other->group_pair;
  std::copy(other->href, other->href + 6, href);
  std::copy(other->loref, other->loref + 3, loref);
  if (!normal_given) normal_hold = other->normal_hold;
  endface_name = other->endface_name;
  faces_auto = other->faces_auto;
  for (int p = 0; p < 2; p++) {
    pair_on[p] = other->pair_on[p];
    nmerged[p] = other->nmerged[p];
    for (int k = 0; k < 2; k++) {
      user_cells[p][k] = other->user_cells[p][k];
      mesh_cells[p][k] = other->mesh_cells[p][k];
    }
  }
  lambda_last = other->lambda_last;
  lambda_step = other->lambda_step;
  node_lambda_last = other->node_lambda_last;
  node_lambda_step = other->node_lambda_step;
  tilted_at_definition = other->tilted_at_definition;
  finish_groups();
  if (comm->me == 0)
    utils::logmesg(lmp, "fix ncf/pbc: reference state and {} constraint groups taken from fix {}\n",
                   ngroups, other_id);
}

/* ----------------------------------------------------------------------
   fix ID group ncf/pbc [faces x|y|xy] [endface NAME|auto] [xcells NU NV] [ycells NU NV]
                        [normal hold|free] [from FIXID]
------------------------------------------------------------------------- */

void FixNCFPBC::parse(int narg, char **arg)
{
  int iarg = 3;
  std::string shape_keyword;    // the last keyword given that shapes the groups (faces, ...)
  NCF_LMP::KeywordsOnce once(lmp, "fix ncf/pbc");
  while (iarg < narg) {
    const std::string key = arg[iarg];
    once(key);
    auto need = [&](int n) {
      NCF_LMP::need_values(lmp, "fix ncf/pbc", key, iarg, narg, n);
    };
    if (key == "faces") {
      need(1);
      const std::string v = arg[iarg + 1];
      faces_auto = (v == "auto") ? 1 : 0;
      if (v == "auto") {
        pair_on[0] = pair_on[1] = 1;
      } else if (v == "x") {
        pair_on[0] = 1;
        pair_on[1] = 0;
      } else if (v == "y") {
        pair_on[0] = 0;
        pair_on[1] = 1;
      } else if (v == "xy") {
        pair_on[0] = pair_on[1] = 1;
      } else
        error->all(FLERR, "fix ncf/pbc: faces '{}' is not one of auto, x, y, xy", v);
      iarg += 2;
    } else if (key == "endface") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "auto")
        endface_name.clear();
      else if (utils::strmatch(v, "^i_"))
        endface_name = v.substr(2);
      else
        error->all(FLERR, "fix ncf/pbc: endface '{}' must be 'auto' or a per-atom integer i_NAME",
                   v);
      iarg += 2;
    } else if (key == "xcells" || key == "ycells") {
      need(2);
      const int p = key == "xcells" ? 0 : 1;
      for (int k = 0; k < 2; k++) {
        if (!utils::is_integer(arg[iarg + 1 + k]))
          error->all(FLERR, "fix ncf/pbc: value '{}' of '{}' is not an integer", arg[iarg + 1 + k],
                     key);
        const long long n =
            NCF_LMP::integer(lmp, "fix ncf/pbc", key, arg[iarg + 1 + k], LLONG_MIN, LLONG_MAX);
        if (n < 1) error->all(FLERR, "fix ncf/pbc: {} values must be >= 1, got {}", key, n);
        if (n > INT_MAX)
          error->all(FLERR, "fix ncf/pbc: {} values must be <= {}, got {}", key, INT_MAX,
                     arg[iarg + 1 + k]);
        user_cells[p][k] = n;
      }
      iarg += 3;
    } else if (key == "normal") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "hold")
        normal_hold = 1;
      else if (v == "free")
        normal_hold = 0;
      else
        error->all(FLERR, "fix ncf/pbc: normal '{}' is not one of hold, free", v);
      normal_given = true;
      iarg += 2;
    } else if (key == "from") {
      need(1);
      from_id = arg[iarg + 1];
      // (LAMMPS removes a fix of the same ID before it makes the new one: there is nothing left
      // to copy from)
      if (from_id == id)
        error->all(FLERR,
                   "fix ncf/pbc: 'from {}' names this fix itself: LAMMPS removes the fix {} "
                   "before the new one is made; define the new fix under another ID, then unfix "
                   "{} (doc/fix_ncf_pbc.md, \"Order of fixes\")",
                   from_id, from_id, from_id);
      iarg += 2;
    } else
      error->all(FLERR, "fix ncf/pbc: unknown keyword '{}'", key);
    if (key != "from" && key != "normal") shape_keyword = key;
  }
  // the copied state fixes the faces, cells and end-face codes: a keyword that would set them
  // too would be ignored
  if (!from_id.empty() && !shape_keyword.empty())
    error->all(FLERR,
               "fix ncf/pbc: keyword '{}' cannot be combined with 'from {}', which takes the "
               "faces, cells and end nodes of that fix",
               shape_keyword, from_id);
}

/* ----------------------------------------------------------------------
   reference state: every end node of the group with its face, unwrapped position, cell group
------------------------------------------------------------------------- */

void FixNCFPBC::capture_reference()
{
  const std::vector<double> all = gather_end_nodes();
  const int nend = (int) all.size() / 5;
  std::vector<int> order(nend);
  // sort by tag so that every rank builds the same list whatever the decomposition
  for (int k = 0; k < nend; k++) order[k] = k;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return all[5 * a] < all[5 * b];
  });

  for (int k = 0; k < 6; k++) href[k] = domain->h[k];
  for (int d = 0; d < 3; d++) loref[d] = domain->boxlo[d];
  nodes.clear();
  group_pair.clear();
  ngroups = 0;
  for (int p = 0; p < 2; p++)
    if (pair_on[p]) group_face_pair(p, all, order);
  if (nodes.empty())
    error->all(FLERR,
               "fix ncf/pbc: no end node of group {} lies on a periodic face (face codes "
               "of i_{} are all 0)",
               group->names[igroup], endface_name);
  finish_groups();
}

/* ----------------------------------------------------------------------
   the end nodes of the group on the constrained faces, of all ranks: per node its tag, face code
   and unwrapped position (5 values), in the order of the ranks
------------------------------------------------------------------------- */

std::vector<double> FixNCFPBC::gather_end_nodes()
{
  const int nlocal = atom->nlocal;
  int *mask = atom->mask;
  int *face = nullptr;
  if (!endface_name.empty()) {
    int flag, cols;
    const int idx = atom->find_custom(endface_name.c_str(), flag, cols);
    if (idx < 0 || flag != 0 || cols != 0)
      error->all(FLERR,
                 "fix ncf/pbc: no per-atom integer i_{} with the end-node face codes (read the "
                 "generator's NCF_NODE section, or use 'endface auto')",
                 endface_name);
    face = atom->ivector[idx];
  }

  // local end nodes: tag, face, unwrapped position
  std::vector<double> mine;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double xu[3];
    domain->unmap(atom->x[i], atom->image[i], xu);
    int code = 0;
    if (face) {
      code = face[i];
      if (code < 0 || code > 4)
        error->one(FLERR, "fix ncf/pbc: atom {} has face code {} (expected 0 to 4)", atom->tag[i],
                   code);
    } else {
      // auto: nearest of the constrained periodic faces
      double best = 1e300;
      for (int p = 0; p < 2; p++) {
        if (!pair_on[p]) continue;
        const double dlo = std::fabs(atom->x[i][p] - domain->boxlo[p]);
        const double dhi = std::fabs(domain->boxhi[p] - atom->x[i][p]);
        if (dlo < best) best = dlo, code = 2 * p + 1;
        if (dhi < best) best = dhi, code = 2 * p + 2;
      }
    }
    if (code == 0) continue;
    const int p = (code - 1) / 2;
    if (!pair_on[p]) continue;
    mine.insert(mine.end(), {(double) atom->tag[i], (double) code, xu[0], xu[1], xu[2]});
  }
  int n = (int) mine.size(), nprocs = comm->nprocs;
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int q = 1; q < nprocs; q++) displs[q] = displs[q - 1] + counts[q - 1];
  std::vector<double> all(displs[nprocs - 1] + counts[nprocs - 1]);
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE,
                 world);

  return all;
}

/* ----------------------------------------------------------------------
   the constraint groups of face pair p (x faces 0, y faces 1): the end nodes on its faces (all:
   the records of gather_end_nodes, order: by tag) meshed into cells, the cells grouped, the
   weights of the nodes; appended to nodes and group_pair
------------------------------------------------------------------------- */

void FixNCFPBC::group_face_pair(int p, const std::vector<double> &all,
                                const std::vector<int> &order)
{
  std::vector<NCF::FaceNode> fn;
  std::vector<int> which;
  double vlo = 1e300, vhi = -1e300;
  int nlow = 0, nup = 0;
  for (int k : order) {
    const int code = (int) all[5 * k + 1];
    if ((code - 1) / 2 != p) continue;
    NCF::FaceNode f;
    f.side = (code % 2 == 1) ? -1 : 1;
    // in-face coordinates: u along the other periodic direction, v = z
    f.u = all[5 * k + 2 + (1 - p)] - domain->boxlo[1 - p];
    f.v = all[5 * k + 4];
    vlo = std::min(vlo, f.v);
    vhi = std::max(vhi, f.v);
    (f.side < 0 ? nlow : nup)++;
    fn.push_back(f);
    which.push_back(k);
  }
  if (fn.empty() && faces_auto) {
    // faces auto: a face pair without end nodes (all chains cross the other way) is not tied
    pair_on[p] = 0;
    return;
  }
  if (fn.empty())
    error->all(FLERR, "fix ncf/pbc: no end node of group {} lies on the {} faces",
               group->names[igroup], p ? "y" : "x");
  const double lu = domain->prd[1 - p];
  NCF::FaceMesh mesh = NCF::auto_face_mesh(fn, lu);
  if (user_cells[p][0]) {
    // a mesh finer than 100 cells per end node only merges empty cells away, and an absurd
    // one would exhaust the memory before saying so
    const double cells = (double) user_cells[p][0] * user_cells[p][1];
    if (cells > 100.0 * (double) fn.size())
      error->all(FLERR,
                 "fix ncf/pbc: {}cells {} {} gives {:.3g} cells for the {} end nodes on the {} "
                 "faces; at most 100 cells per end node",
                 p ? "y" : "x", user_cells[p][0], user_cells[p][1], cells, fn.size(),
                 p ? "y" : "x");
    mesh = NCF::FaceMesh();
    mesh.lu = lu;
    mesh.vlo = vlo;
    mesh.vhi = vhi;
    mesh.nu = user_cells[p][0];
    mesh.nv = user_cells[p][1];
  }
  mesh_cells[p][0] = mesh.nu;
  mesh_cells[p][1] = mesh.nv;
  int ng = 0;
  std::vector<int> grp;
  try {
    grp = NCF::face_groups(mesh, fn, ng);
  } catch (NCF::InputError &e) {
    error->all(FLERR, "fix ncf/pbc: {} faces: {}", p ? "y" : "x", e.what());
  }
  auto w = NCF::face_weights(fn, grp, ng);
  int nonempty = 0;
  {
    std::vector<int> seen(mesh.nu * mesh.nv, 0);
    for (auto &f : fn) seen[mesh.cell_of(f.u, f.v)] = 1;
    for (int s : seen) nonempty += s;
  }
  nmerged[p] = nonempty - ng;
  for (std::size_t m = 0; m < fn.size(); m++) {
    const int k = which[m];
    EndNode e;
    e.tag = (tagint) all[5 * k];
    e.pair = p;
    e.group = ngroups + grp[m];
    e.weight = w[m];
    for (int d = 0; d < 3; d++) e.xref[d] = all[5 * k + 2 + d];
    nodes.push_back(e);
  }
  for (int g = 0; g < ng; g++) group_pair.push_back(p);
  ngroups += ng;
  if (comm->me == 0)
    utils::logmesg(lmp,
                   "fix ncf/pbc: {} faces: {} lower + {} upper end nodes, mesh {} x {} cells, "
                   "{} constraint groups ({} non-empty cells merged away)\n",
                   p ? "y" : "x", nlow, nup, mesh.nu, mesh.nv, ng, nmerged[p]);
}

/* ----------------------------------------------------------------------
   per-group constants derived from the node list
------------------------------------------------------------------------- */

void FixNCFPBC::finish_groups()
{
  mine_ncalls = -1;
  sum_w2.assign(ngroups, 0.0);
  dref.assign(3 * ngroups, 0.0);
  sref.resize(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); k++) {
    const EndNode &e = nodes[k];
    sum_w2[e.group] += e.weight * e.weight;
    for (int d = 0; d < 3; d++) dref[3 * e.group + d] += e.weight * e.xref[d];
    // reduced coordinate along the face normal in the reference box (lamda of LAMMPS)
    const int p = e.pair;
    double along = e.xref[p] - loref[p];
    if (p == 0) along -= href[5] / href[1] * (e.xref[1] - loref[1]);
    sref[k] = along / href[p];
  }
  node_lambda.assign(nodes.size(), 0.0);
}

/* ----------------------------------------------------------------------
   normal hold: n . x - b of node e at the unwrapped position xu in the current box,
   n = e_p + a e_u, b such that the node keeps its reduced coordinate along the normal
------------------------------------------------------------------------- */

double FixNCFPBC::hold_residual(const EndNode &e, const double *xu, const double *lo,
                                const double *prd, double a) const
{
  const int p = e.pair, u = 1 - p;
  const double s = sref[&e - nodes.data()];
  return (xu[p] - lo[p]) + a * (xu[u] - lo[u]) - prd[p] * s;
}

/* ---------------------------------------------------------------------- */

int FixNCFPBC::setmask()
{
  return POST_FORCE | MIN_POST_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixNCFPBC::init()
{
  if (tilted_at_definition)
    error->all(
        FLERR,
        "fix ncf/pbc: the box must be orthogonal when the fix is defined "
        "(a tilt may develop later, e.g. by fix deform; a restart file keeps the reference)");
  if (atom->map_style == Atom::MAP_NONE)
    error->all(FLERR, "fix ncf/pbc needs an atom map (atom_modify map array or hash)");
  for (auto &e : nodes)
    if (atom->map(e.tag) < 0 && comm->nprocs == 1)
      error->all(FLERR, "fix ncf/pbc: end node {} no longer exists", e.tag);
  check_fix_order();
}

/* ----------------------------------------------------------------------
   the constraint forces must be the last change of the forces in a step
------------------------------------------------------------------------- */

void FixNCFPBC::check_fix_order()
{
  bool after = false;
  for (auto &f : modify->get_fix_list()) {
    if (f == this) {
      after = true;
      continue;
    }
    if (after && (f->setmask() & POST_FORCE) && comm->me == 0)
      error->warning(FLERR,
                     "fix ncf/pbc: fix {} ({}) changes forces after fix ncf/pbc; define fix "
                     "ncf/pbc last so that the averaged periodic constraint sees the final forces",
                     f->id, f->style);
  }
}

/* ---------------------------------------------------------------------- */

void FixNCFPBC::setup(int vflag)
{
  post_force(vflag);
}

void FixNCFPBC::min_setup(int vflag)
{
  min_post_force(vflag);
}

/* ---------------------------------------------------------------------- */

void FixNCFPBC::find_mine()
{
  const int nlocal = atom->nlocal;
  // (LAMMPS resets ncalls at the setup of every run, after the build there: ago is 0 then)
  if (neighbor->ago != 0 && mine_ncalls == neighbor->ncalls && mine_nlocal == nlocal) return;
  mine.clear();
  for (int k = 0; k < (int) nodes.size(); k++) {
    const int i = atom->map(nodes[k].tag);
    if (i >= 0 && i < nlocal) mine.emplace_back(k, i);
  }
  mine_ncalls = neighbor->ncalls;
  mine_nlocal = nlocal;
}

/* ----------------------------------------------------------------------
   dynamics: constraint forces that make every C_g vanish at the next step
------------------------------------------------------------------------- */

void FixNCFPBC::post_force(int /*vflag*/)
{
  double **x = atom->x, **v = atom->v, **f = atom->f;
  imageint *image = atom->image;
  double *rmass = atom->rmass, *mass = atom->mass;
  int *type = atom->type;
  const double dt = update->dt;
  const double dt2 = dt * dt * force->ftm2v;
  const NextBox box1 = next_box(domain, dt);
  const double acoup[2] = {hold_coupling(0, box1), hold_coupling(1, box1)};
  const double acur[2] = {hold_coupling(0, next_box(domain, 0.0)), 0.0};

  find_mine();
  work.assign((std::size_t) NVAL * ngroups, 0.0);
  rnode.resize(mine.size());
  residual_node_local = 0.0;
  for (std::size_t q = 0; q < mine.size(); q++) {
    const auto &[k, i] = mine[q];
    const EndNode &e = nodes[k];
    const double m = rmass ? rmass[i] : mass[type[i]];
    double xu[3], pred[3];
    domain->unmap(x[i], image[i], xu);
    double *s = &work[(std::size_t) NVAL * e.group];
    for (int d = 0; d < 3; d++) {
      pred[d] = xu[d] + dt * v[i][d] + dt2 * f[i][d] / m;
      s[d] += e.weight * pred[d];
      s[3 + d] += e.weight * xu[d];
    }
    s[6] += e.weight * e.weight / m;
    if (normal_hold) {
      // the violation now plus the step's displacement along the normal of the next box: fix
      // deform's remap at the end of the step keeps the reduced coordinates of the positions
      // now, and the step's displacement adds to them in the next box's metric
      const int p = e.pair, u = 1 - p;
      const double now = hold_residual(e, xu, domain->boxlo, domain->prd, acur[p]);
      rnode[q] = now + (pred[p] - xu[p]) + acoup[p] * (pred[u] - xu[u]);
      s[7] += e.weight * rnode[q];
      residual_node_local = std::max(residual_node_local, std::fabs(now));
    }
  }
  sums.resize(work.size());
  MPI_Allreduce(work.data(), sums.data(), (int) work.size(), MPI_DOUBLE, MPI_SUM, world);

  // targets F D_g with the current box (fix deform's affine remap carries them along)
  double F[2][2];
  deformation(domain->h, href, F);
  lambda.assign(3 * ngroups, 0.0);
  residual_max = 0.0;
  for (int g = 0; g < ngroups; g++) {
    const double *s = &sums[(std::size_t) NVAL * g];
    const double *D = &dref[3 * g];
    const double target[3] = {F[0][0] * D[0] + F[0][1] * D[1], F[1][1] * D[1], D[2]};
    const int p = group_pair[g], u = 1 - p;
    for (int d = 0; d < 3; d++) {
      residual_max = std::max(residual_max, std::fabs(s[3 + d] - target[d]));
      if (normal_hold && d == p) continue;    // follows from the node holds
      if (normal_hold && d == u)
        lambda[3 * g + d] =
            NCF::held_group_multiplier(s[d] - target[d], s[7], acoup[p], dt2 * s[6]);
      else
        lambda[3 * g + d] = NCF::constraint_multiplier(s[d] - target[d], dt2 * s[6]);
    }
  }
  const bool reuse_nodes = normal_hold && update->setupflag &&
      node_lambda_step == update->ntimestep && node_lambda_last.size() == nodes.size();
  if (!update->setupflag) {
    lambda_last = lambda;
    lambda_step = update->ntimestep;
  } else if (lambda_step == update->ntimestep && lambda_last.size() == lambda.size()) {
    lambda = lambda_last;
  }

  if (normal_hold) std::fill(node_lambda.begin(), node_lambda.end(), 0.0);
  for (std::size_t q = 0; q < mine.size(); q++) {
    const auto &[k, i] = mine[q];
    const EndNode &e = nodes[k];
    double fc[3];
    for (int d = 0; d < 3; d++) fc[d] = e.weight * lambda[3 * e.group + d];
    if (normal_hold) {
      const int p = e.pair, u = 1 - p;
      const double m = rmass ? rmass[i] : mass[type[i]];
      const double lam = reuse_nodes
          ? node_lambda_last[k]
          : NCF::held_node_multiplier(rnode[q], e.weight, lambda[3 * e.group + u], acoup[p],
                                      m / dt2);
      node_lambda[k] = lam;
      fc[p] += lam;
      fc[u] += acoup[p] * lam;
    }
    for (int d = 0; d < 3; d++) f[i][d] += fc[d];
  }
  // the node multipliers of the last step of a run and of a restart-writing step, for the setup
  // of the next run (on whichever rank owns the node then)
  if (normal_hold && !update->setupflag &&
      (update->ntimestep == update->laststep ||
       (output->restart_flag && output->next_restart == update->ntimestep))) {
    node_lambda_last.resize(nodes.size());
    MPI_Allreduce(node_lambda.data(), node_lambda_last.data(), (int) nodes.size(), MPI_DOUBLE,
                  MPI_SUM, world);
    node_lambda_step = update->ntimestep;
  }
}

/* ----------------------------------------------------------------------
   minimisation: project the forces onto the constraint manifold (sum_i w_i f_i = 0 per group
   and component); line-search steps along projected directions keep every C_g unchanged
------------------------------------------------------------------------- */

void FixNCFPBC::min_post_force(int /*vflag*/)
{
  // (the expressions of the dynamics at m = dt = 1, with the forces as the predicted motion)
  double **f = atom->f;
  const NextBox box = next_box(domain, 0.0);
  const double acoup[2] = {hold_coupling(0, box), hold_coupling(1, box)};
  find_mine();
  work.assign((std::size_t) 4 * ngroups, 0.0);
  rnode.resize(mine.size());
  for (std::size_t q = 0; q < mine.size(); q++) {
    const auto &[k, i] = mine[q];
    const EndNode &e = nodes[k];
    for (int d = 0; d < 3; d++) work[4 * e.group + d] += e.weight * f[i][d];
    if (normal_hold) {
      const int p = e.pair;
      rnode[q] = f[i][p] + acoup[p] * f[i][1 - p];
      work[4 * e.group + 3] += e.weight * rnode[q];
    }
  }
  sums.resize(work.size());
  MPI_Allreduce(work.data(), sums.data(), (int) work.size(), MPI_DOUBLE, MPI_SUM, world);
  for (std::size_t q = 0; q < mine.size(); q++) {
    const auto &[k, i] = mine[q];
    const EndNode &e = nodes[k];
    const double *s = &sums[4 * e.group];
    const int p = e.pair, u = 1 - p;
    for (int d = 0; d < 3; d++) {
      if (normal_hold && d == p) continue;
      const double lam = normal_hold && d == u
          ? NCF::held_group_multiplier(s[d], s[3], acoup[p], sum_w2[e.group])
          : NCF::constraint_multiplier(s[d], sum_w2[e.group]);
      f[i][d] += e.weight * lam;
      if (normal_hold && d == u) {
        const double node = NCF::held_node_multiplier(rnode[q], e.weight, lam, acoup[p], 1.0);
        f[i][p] += node;
        f[i][u] += acoup[p] * node;
      }
    }
  }
}

/* ---------------------------------------------------------------------- */

double FixNCFPBC::compute_scalar()
{
  // (the node holds' largest residual of the last step on any rank, with the groups' one)
  double node = 0.0;
  MPI_Allreduce(&residual_node_local, &node, 1, MPI_DOUBLE, MPI_MAX, world);
  return std::max(residual_max, node);
}

double FixNCFPBC::compute_vector(int n)
{
  if (n == 0) return ngroups;
  if (n == 1) return (double) nodes.size();
  return compute_scalar();
}

/* ----------------------------------------------------------------------
   restart: reference state, groups and weights (the cell membership)
------------------------------------------------------------------------- */

void FixNCFPBC::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  std::vector<double> buf;
  // (a restart file written before the multipliers were kept starts with the node count)
  buf.push_back(RESTART_MARK_NORMAL);
  buf.push_back((double) nodes.size());
  buf.push_back(ngroups);
  for (int k = 0; k < 6; k++) buf.push_back(href[k]);
  for (int d = 0; d < 3; d++) buf.push_back(loref[d]);
  for (int p = 0; p < 2; p++)
    buf.insert(buf.end(),
               {(double) pair_on[p], (double) mesh_cells[p][0], (double) mesh_cells[p][1],
                (double) nmerged[p]});
  for (int g = 0; g < ngroups; g++) buf.push_back(group_pair[g]);
  for (auto &e : nodes)
    buf.insert(buf.end(),
               {(double) e.tag, (double) e.pair, (double) e.group, e.weight, e.xref[0], e.xref[1],
                e.xref[2]});
  buf.push_back((double) lambda_step);
  buf.push_back((double) lambda_last.size());
  buf.insert(buf.end(), lambda_last.begin(), lambda_last.end());
  buf.push_back((double) node_lambda_step);
  buf.push_back((double) node_lambda_last.size());
  buf.insert(buf.end(), node_lambda_last.begin(), node_lambda_last.end());
  int size = (int) (buf.size() * sizeof(double));
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(buf.data(), sizeof(double), buf.size(), fp);
}

void FixNCFPBC::restart(char *raw)
{
  auto *buf = (double *) raw;
  std::size_t m = 0;
  const bool with_normal = buf[0] == RESTART_MARK_NORMAL;
  const bool with_lambda = with_normal || buf[0] == RESTART_MARK;
  if (with_lambda) m++;
  const auto n = (std::size_t) buf[m++];
  ngroups = (int) buf[m++];
  for (int k = 0; k < 6; k++) href[k] = buf[m++];
  // (files without the reference origin: the box's origin now, which the fixes of a
  // manufacturing run leave where it was)
  for (int d = 0; d < 3; d++) loref[d] = with_normal ? buf[m++] : domain->boxlo[d];
  for (int p = 0; p < 2; p++) {
    pair_on[p] = (int) buf[m++];
    mesh_cells[p][0] = (int) buf[m++];
    mesh_cells[p][1] = (int) buf[m++];
    nmerged[p] = (int) buf[m++];
  }
  group_pair.resize(ngroups);
  for (int g = 0; g < ngroups; g++) group_pair[g] = (int) buf[m++];
  nodes.resize(n);
  for (auto &e : nodes) {
    e.tag = (tagint) buf[m++];
    e.pair = (int) buf[m++];
    e.group = (int) buf[m++];
    e.weight = buf[m++];
    for (double &xr : e.xref) xr = buf[m++];
  }
  if (with_lambda) {
    lambda_step = (bigint) buf[m++];
    lambda_last.resize((std::size_t) buf[m++]);
    for (double &l : lambda_last) l = buf[m++];
  }
  if (with_normal) {
    node_lambda_step = (bigint) buf[m++];
    node_lambda_last.resize((std::size_t) buf[m++]);
    for (double &l : node_lambda_last) l = buf[m++];
  }
  finish_groups();
  tilted_at_definition = false;
  if (comm->me == 0)
    utils::logmesg(
        lmp,
        "fix ncf/pbc: reference state and {} constraint groups restored from the restart file\n",
        ngroups);
}

/* ---------------------------------------------------------------------- */

double FixNCFPBC::memory_usage()
{
  return (double) nodes.size() * sizeof(EndNode) +
      (double) (work.size() + sums.size()) * sizeof(double);
}
