/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   compute ncf/orient (see compute_ncf_orient.h, doc/compute_ncf_orient.md)
------------------------------------------------------------------------- */

#include "compute_ncf_orient.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "update.h"

#include "lammps_ncf_args.h"

#include "ncf_orient.h"

#include <climits>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;

static constexpr int NPER = 6;    // vector values per layer

/* ----------------------------------------------------------------------
   compute ID group ncf/orient layer L ANGLE [layer L ANGLE ...] [bins N] [range DEG]
                                [property i_NAME]
------------------------------------------------------------------------- */

ComputeNCFOrient::ComputeNCFOrient(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nbins(60), range(15.0), layer_name("ncf_layer"), idx_layer(-1)
{
  const std::string W = "compute ncf/orient";
  int iarg = 3;
  NCF_LMP::KeywordsOnce once(lmp, "compute ncf/orient", {"layer"});
  while (iarg < narg) {
    const std::string key = arg[iarg];
    once(key);
    if (key == "layer") {
      NCF_LMP::need_values(lmp, W, key, iarg, narg, 2, "a layer index and its angle");
      if (!utils::is_integer(arg[iarg + 1]))
        error->all(FLERR, "compute ncf/orient: layer index '{}' is not an integer", arg[iarg + 1]);
      const int l = (int) NCF_LMP::integer(lmp, W, key, arg[iarg + 1], INT_MIN, INT_MAX);
      if (l < 0) error->all(FLERR, "compute ncf/orient: layer index {} must be >= 0", l);
      for (int k : layers)
        if (k == l) error->all(FLERR, "compute ncf/orient: layer {} given twice", l);
      layers.push_back(l);
      nominal.push_back(NCF_LMP::number(lmp, W, "layer", arg[iarg + 2]));
      iarg += 3;
    } else if (key == "bins") {
      NCF_LMP::need_values(lmp, W, key, iarg, narg, 1);
      if (!utils::is_integer(arg[iarg + 1]))
        error->all(FLERR, "compute ncf/orient: value '{}' of 'bins' is not an integer",
                   arg[iarg + 1]);
      const long long nb = NCF_LMP::integer(lmp, W, key, arg[iarg + 1], LLONG_MIN, LLONG_MAX);
      if (nb < 1 || nb > 100000)
        error->all(FLERR, "compute ncf/orient: bins {} must be in [1, 100000]", arg[iarg + 1]);
      nbins = (int) nb;
      iarg += 2;
    } else if (key == "range") {
      NCF_LMP::need_values(lmp, W, key, iarg, narg, 1);
      range = NCF_LMP::number(lmp, W, key, arg[iarg + 1]);
      if (!(range > 0.0 && range <= 90.0))
        error->all(FLERR, "compute ncf/orient: range {} must be in (0, 90] degrees", range);
      iarg += 2;
    } else if (key == "property") {
      NCF_LMP::need_values(lmp, W, key, iarg, narg, 1);
      const std::string v = arg[iarg + 1];
      if (!utils::strmatch(v, "^i_"))
        error->all(FLERR, "compute ncf/orient: property '{}' must be a per-atom integer i_NAME", v);
      layer_name = v.substr(2);
      iarg += 2;
    } else
      error->all(FLERR, "compute ncf/orient: unknown keyword '{}'", key);
  }
  if (layers.empty())
    error->all(FLERR, "compute ncf/orient: name at least one layer: 'layer L ANGLE'");
  if (!atom->molecular) error->all(FLERR, "compute ncf/orient needs an atom style with bonds");

  const int nl = (int) layers.size();
  vector_flag = 1;
  size_vector = NPER * nl;
  array_flag = 1;
  size_array_rows = nbins;
  size_array_cols = 1 + nl;
  extvector = extarray = 0;
  vector = new double[size_vector];
  memory->create(array, nbins, 1 + nl, "ncf/orient:array");
}

ComputeNCFOrient::~ComputeNCFOrient()
{
  delete[] vector;
  memory->destroy(array);
}

void ComputeNCFOrient::init()
{
  int flag, cols;
  idx_layer = atom->find_custom(layer_name.c_str(), flag, cols);
  if (idx_layer < 0 || flag != 0 || cols != 0)
    error->all(FLERR, "compute ncf/orient: no per-atom integer i_{} with the layer of each node",
               layer_name);
  // a layer without a node in the group has no statistics: 0 +- 0 would look like a result
  const int *layer = atom->ivector[idx_layer];
  const int *mask = atom->mask;
  const int nl = (int) layers.size();
  std::vector<bigint> mine(nl, 0), all(nl, 0);
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & groupbit)
      for (int k = 0; k < nl; k++)
        if (layer[i] == layers[k]) mine[k]++;
  MPI_Allreduce(mine.data(), all.data(), nl, MPI_LMP_BIGINT, MPI_SUM, world);
  for (int k = 0; k < nl; k++)
    if (all[k] == 0)
      error->all(FLERR, "compute ncf/orient: layer {} has no atom in group {} (i_{} = {} nowhere)",
                 layers[k], group->names[igroup], layer_name, layers[k]);
}

/* ----------------------------------------------------------------------
   every bond of the group once: stored with an owned atom (twice with newton_bond off, then
   counted from its lower tag), partner at its closest image
------------------------------------------------------------------------- */

void ComputeNCFOrient::accumulate()
{
  std::vector<NCF::OrientStats> stats;
  for (std::size_t k = 0; k < layers.size(); k++) stats.emplace_back(nbins, range);
  double **x = atom->x;
  int *mask = atom->mask;
  tagint *tag = atom->tag;
  int *layer = atom->ivector[idx_layer];
  const int newton_bond = force->newton_bond;
  int missing = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    int k = -1;
    for (std::size_t q = 0; q < layers.size(); q++)
      if (layers[q] == layer[i]) k = (int) q;
    if (k < 0) continue;
    for (int m = 0; m < atom->num_bond[i]; m++) {
      if (atom->bond_type[i][m] <= 0) continue;
      const tagint partner = atom->bond_atom[i][m];
      if (!newton_bond && partner < tag[i]) continue;
      int j = atom->map(partner);
      if (j < 0) {
        missing++;
        continue;
      }
      j = domain->closest_image(i, j);
      if (!(mask[j] & groupbit)) continue;
      stats[k].add(x[j][0] - x[i][0], x[j][1] - x[i][1], x[j][2] - x[i][2], nominal[k]);
    }
  }
  int allmissing = 0;
  MPI_Allreduce(&missing, &allmissing, 1, MPI_INT, MPI_SUM, world);
  if (allmissing)
    error->all(FLERR,
               "compute ncf/orient: {} bond partner(s) missing on their ranks; increase the "
               "communication cutoff",
               allmissing);

  const std::size_t per = stats[0].data().size();
  std::vector<double> local(per * stats.size());
  for (std::size_t k = 0; k < stats.size(); k++)
    std::copy(stats[k].data().begin(), stats[k].data().end(), local.begin() + k * per);
  sums.resize(local.size());
  MPI_Allreduce(local.data(), sums.data(), (int) local.size(), MPI_DOUBLE, MPI_SUM, world);
}

/* ---------------------------------------------------------------------- */

void ComputeNCFOrient::compute_vector()
{
  invoked_vector = update->ntimestep;
  accumulate();
  NCF::OrientStats s(nbins, range);
  const std::size_t per = s.data().size();
  for (std::size_t k = 0; k < layers.size(); k++) {
    std::copy(sums.begin() + k * per, sums.begin() + (k + 1) * per, s.data().begin());
    double *v = vector + NPER * k;
    v[0] = s.mean();
    v[1] = s.stddev();
    v[2] = s.principal_angle();
    v[3] = s.principal_value();
    v[4] = s.outside_fraction();
    v[5] = s.weight();
  }
}

void ComputeNCFOrient::compute_array()
{
  invoked_array = update->ntimestep;
  accumulate();
  NCF::OrientStats s(nbins, range);
  const std::size_t per = s.data().size();
  for (int b = 0; b < nbins; b++) array[b][0] = s.bin_centre(b);
  for (std::size_t k = 0; k < layers.size(); k++) {
    std::copy(sums.begin() + k * per, sums.begin() + (k + 1) * per, s.data().begin());
    for (int b = 0; b < nbins; b++) array[b][1 + k] = s.density(b);
  }
}
