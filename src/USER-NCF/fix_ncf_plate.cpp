/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/plate (see fix_ncf_plate.h, doc/fix_ncf_plate.md)
------------------------------------------------------------------------- */

#include "fix_ncf_plate.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "input.h"
#include "memory.h"
#include "update.h"
#include "variable.h"

#include "lammps_ncf_args.h"
#include "lammps_ncf_compat.h"
#include "lammps_ncf_motion.h"
#include "ncf_contact.h"
#include "ncf_wall.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

static constexpr int NHIST = 6;
static constexpr int NTOT = 5;

/* ---------------------------------------------------------------------- */

FixNCFPlate::FixNCFPlate(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), slip(nullptr), use_history(0), energy(0.0), dt_contact(0.0), idx_l0(-1)
{
  scalar_flag = 1;
  vector_flag = 1;
  size_vector = 12;
  global_freq = 1;
  extscalar = 1;
  extvector = 0;
  energy_global_flag = 1;
  restart_global = 1;
  dynamic_group_allow = 1;
  zprev[0] = zprev[1] = 0.0;
  for (auto &t : totals)
    for (double &v : t) v = 0.0;

  diameter.assign(atom->ntypes + 1, 0.0);
  parse(narg, arg);
  clock.start(update);
  update_plates();
  for (int k = 0; k < 2; k++) zprev[k] = plate[k].z;

  // friction history only when the scene has friction
  use_history = (cc.mu > 0.0 && cc.kt > 0.0) ? 1 : 0;
  if (use_history) {
    restart_peratom = 1;
    FixNCFPlate::grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    atom->add_callback(Atom::RESTART);
    for (int i = 0; i < atom->nlocal; i++)
      for (int d = 0; d < NHIST; d++) slip[i][d] = 0.0;
  }
}

FixNCFPlate::~FixNCFPlate()
{
  if (use_history) {
    atom->delete_callback(id, Atom::GROW);
    atom->delete_callback(id, Atom::RESTART);
    memory->destroy(slip);
  }
}

/* ----------------------------------------------------------------------
   fix ID group ncf/plate kn KN [kt KT] [mu MU] [damp C] [diameter TYPES D ...]
                              [lower SPEC] [upper SPEC]
   SPEC: z Z | move Z0 V | target Z0 ZT V | v_NAME
   the contact keywords as in pair_coeff ncf/contact (kt a ratio of kn); the chain diameters
   those of pair ncf/contact unless given
------------------------------------------------------------------------- */

void FixNCFPlate::parse(int narg, char **arg)
{
  const std::string W = "fix ncf/plate";
  NCF_LMP::ContactReader reader(lmp, W, NCF_LMP::ContactReader::all_keys(),
                                {"diameter", "lower", "upper"});
  bool diameter_given = false;
  int iarg = 3;
  while (iarg < narg) {
    if (reader.read(iarg, narg, arg, cc)) continue;
    const std::string key = arg[iarg];
    reader.once(key);
    if (key == "lower" || key == "upper") {
      Plate &p = plate[key == "lower" ? 0 : 1];
      if (p.motion.kind != NCF::Motion::NONE)
        error->all(FLERR, "{}: keyword '{}' given twice (one plate of each)", W, key);
      iarg = NCF_LMP::parse_motion(lmp, "fix ncf/plate: '" + key, iarg + 1, narg, arg, p.motion,
                                   p.var, true);
    } else if (key == "diameter") {
      NCF_LMP::read_type_diameters(lmp, W, key, iarg, narg, arg, diameter);
      diameter_given = true;
    } else
      error->all(FLERR, "{}: unknown keyword '{}'", W, key);
  }
  if (!reader.has(NCF::ContactKey::KN))
    error->all(FLERR, "{}: keyword 'kn' (normal stiffness, Pa) is required", W);
  if (plate[0].motion.kind == NCF::Motion::NONE && plate[1].motion.kind == NCF::Motion::NONE)
    error->all(FLERR, "{}: define at least one plate with 'lower' or 'upper'", W);
  if (cc.mu > 0.0 && cc.kt == 0.0)
    error->all(FLERR, "{}: friction (mu {}) needs a tangential stiffness 'kt' > 0", W, cc.mu);
  NCF_LMP::pair_diameters(lmp, W, "diameter", diameter_given, diameter);
}

/* ---------------------------------------------------------------------- */

int FixNCFPlate::setmask()
{
  return POST_FORCE | MIN_POST_FORCE;
}

void FixNCFPlate::init()
{
  for (auto &p : plate)
    if (p.motion.kind == NCF::Motion::VARIABLE) {
      p.ivar = input->variable->find(p.var.c_str());
      if (p.ivar < 0) error->all(FLERR, "fix ncf/plate: variable '{}' does not exist", p.var);
    }
  int flag, cols;
  idx_l0 = atom->find_custom("ncf_l0", flag, cols);
  if (idx_l0 < 0)
    error->all(FLERR,
               "fix ncf/plate needs bond_style ncf/chain: the node contact force uses the "
               "elements' reference lengths (tributary length of each node)");
}

/* ---------------------------------------------------------------------- */

void FixNCFPlate::update_plates()
{
  const double t = clock.time(update);
  for (int k = 0; k < 2; k++) {
    Plate &p = plate[k];
    if (p.motion.kind == NCF::Motion::VARIABLE) {
      const double z = input->variable->compute_equal(p.ivar);
      if (p.ivar >= 0 && !std::isfinite(z))
        error->all(FLERR, "fix ncf/plate: variable '{}' gives the plate height {} at step {}",
                   p.var, z, update->ntimestep);
      p.vz = update->dt > 0.0 ? (z - zprev[k]) / update->dt : 0.0;
      zprev[k] = p.z = z;
    } else
      p.motion.at(t, p.z, p.vz);
  }
  // both plates: the lower one below the upper one, whatever moves them (checked at every step,
  // since a motion or a variable may bring them together later)
  // (a variable is looked up at init: not yet when the fix is defined)
  bool known = true;
  for (auto &p : plate)
    known &= p.motion.kind != NCF::Motion::NONE &&
        !(p.motion.kind == NCF::Motion::VARIABLE && p.ivar < 0);
  if (known && !(plate[0].z < plate[1].z))
    error->all(FLERR,
               "fix ncf/plate: the lower plate (z = {}) is not below the upper plate (z = {}) at "
               "step {}",
               plate[0].z, plate[1].z, update->ntimestep);
}

/* ----------------------------------------------------------------------
   half of each adjacent element (bond_style ncf/chain reference lengths)
------------------------------------------------------------------------- */

double FixNCFPlate::tributary_length(int i) const
{
  double **l0 = atom->darray[idx_l0];
  return 0.5 * (l0[i][0] + l0[i][1]);
}

void FixNCFPlate::check_nodes()
{
  int *mask = atom->mask, *type = atom->type;
  int bad = 0, badtype = 0;
  tagint badtag = 0;
  double dtmin = 1e300;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    if (diameter[type[i]] <= 0.0) badtype = type[i];
    const double l = tributary_length(i);
    if (!(l > 0.0)) {
      bad = 1;
      badtag = atom->tag[i];
      continue;
    }
    const double m = atom->rmass ? atom->rmass[i] : atom->mass[type[i]];
    dtmin = std::min(dtmin, 2.0 * sqrt(m / (cc.kn * l)));
  }
  int any = 0;
  MPI_Allreduce(&badtype, &any, 1, MPI_INT, MPI_MAX, world);
  if (any)
    error->all(FLERR, "fix ncf/plate: atom type {} in group {} has no 'diameter'", any,
               group->names[igroup]);
  MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, world);
  if (any && bad)
    error->one(FLERR, "fix ncf/plate: atom {} has no ncf/chain bond: no tributary length", badtag);
  if (any) error->all(FLERR, "fix ncf/plate: an atom of the group has no ncf/chain bond");
  MPI_Allreduce(&dtmin, &dt_contact, 1, MPI_DOUBLE, MPI_MIN, world);
  if (comm->me == 0 && update->whichflag == 1) {
    utils::logmesg(
        lmp,
        "fix ncf/plate: critical time step of the plate contacts {:.6g} (timestep {:.3g} of it)\n",
        dt_contact, update->dt / dt_contact);
  }
  // (an error before the run, naming kn: above it the contacts blow up within steps, and the run
  // would end in an error about something else, a segment longer than lmax or a bond atom missing)
  if (update->whichflag == 1 && update->dt > dt_contact)
    error->all(FLERR,
               "fix ncf/plate: timestep {:.6g} is above the critical time step {:.6g} of the "
               "plate contacts (kn {:.6g} Pa on the lightest node per tributary length); lower kn "
               "or the timestep, or scale the masses",
               update->dt, dt_contact, cc.kn);
}

/* ---------------------------------------------------------------------- */

void FixNCFPlate::setup(int vflag)
{
  check_nodes();
  post_force(vflag);
}

void FixNCFPlate::min_setup(int /*vflag*/)
{
  check_nodes();
  apply();
}

void FixNCFPlate::min_post_force(int /*vflag*/)
{
  apply();    // the plates stay where they are during a minimisation
}

/* ---------------------------------------------------------------------- */

void FixNCFPlate::post_force(int /*vflag*/)
{
  update_plates();
  apply();
}

void FixNCFPlate::apply()
{
  double **x = atom->x, **v = atom->v, **f = atom->f;
  int *mask = atom->mask, *type = atom->type;
  const int nlocal = atom->nlocal;
  const double dt = update->dt;
  const bool friction = use_history && update->whichflag == 1;
  // in the setup of a run the friction force of the stored slip, the slip left as it is (the
  // history advances in steps only, so that a run cut into pieces is the same run)
  const bool advance = !update->setupflag;

  double local[2][NTOT] = {{0.0}};
  double elocal = 0.0;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double radius = 0.5 * diameter[type[i]];
    for (int k = 0; k < 2; k++) {
      const Plate &p = plate[k];
      if (p.motion.kind == NCF::Motion::NONE) continue;
      const int side = k == 0 ? 1 : -1;
      double *s = use_history ? &slip[i][3 * k] : nullptr;
      // most nodes are far from both plates: their gap first (the test plane_contact makes), the
      // rest of the contact only for those that touch
      if (!(radius - side * (x[i][2] - p.z) > 0.0)) {
        if (s) s[0] = s[1] = s[2] = 0.0;
        continue;
      }
      const double l = tributary_length(i);
      const auto c =
          NCF::plane_contact(x[i][2], radius, p.z, side, cc.kn, l, cc.damp, v[i][2] - p.vz);
      f[i][2] += side * c.force;
      local[k][0] += side * c.force;
      local[k][3] += 1.0;
      local[k][4] = std::max(local[k][4], c.penetration);
      elocal += c.energy;
      if (friction) {
        NCF::Vec3 slipv{s[0], s[1], s[2]};
        const NCF::Vec3 n{0.0, 0.0, (double) side};
        const NCF::Vec3 vrel{v[i][0], v[i][1], v[i][2] - p.vz};
        const auto fr =
            NCF::friction_step(slipv, n, vrel, dt, cc.kt_stiffness() * l, c.force, cc.mu, advance);
        if (advance) {
          s[0] = slipv.x;
          s[1] = slipv.y;
          s[2] = slipv.z;
        }
        f[i][0] += fr.force.x;
        f[i][1] += fr.force.y;
        f[i][2] += fr.force.z;
        local[k][1] += fr.force.x;
        local[k][2] += fr.force.y;
        elocal += fr.energy;
      }
    }
  }
  double all[2 * NTOT + 1], mine[2 * NTOT + 1];
  for (int k = 0; k < 2; k++)
    for (int q = 0; q < NTOT; q++) mine[NTOT * k + q] = local[k][q];
  mine[2 * NTOT] = elocal;
  // (the sums and the energy in one reduction, the largest penetrations in another)
  MPI_Allreduce(mine, all, 2 * NTOT + 1, MPI_DOUBLE, MPI_SUM, world);
  energy = all[2 * NTOT];
  double pen[2] = {local[0][4], local[1][4]}, penall[2];
  MPI_Allreduce(pen, penall, 2, MPI_DOUBLE, MPI_MAX, world);
  for (int k = 0; k < 2; k++) {
    for (int q = 0; q < NTOT; q++) totals[k][q] = all[NTOT * k + q];
    totals[k][4] = penall[k];
  }
}

/* ---------------------------------------------------------------------- */

double FixNCFPlate::compute_scalar()
{
  return energy;
}

/* ----------------------------------------------------------------------
   1 lower z, 2 upper z, 3 force of the lower plate on the fabric (+z), 4 force of the upper plate
   on the fabric (-z, reported positive when pressing), 5 pressure of the upper plate (4 / area),
   6 pressure of the lower plate, 7 contacts lower, 8 contacts upper, 9 max penetration lower,
   10 max penetration upper, 11 tangential force of the lower plate in x, 12 in y (friction)
------------------------------------------------------------------------- */

double FixNCFPlate::compute_vector(int n)
{
  const double area = domain->xprd * domain->yprd;
  switch (n) {
    case 0:
      return plate[0].z;
    case 1:
      return plate[1].z;
    case 2:
      return totals[0][0];
    case 3:
      return -totals[1][0];
    case 4:
      return -totals[1][0] / area;
    case 5:
      return totals[0][0] / area;
    case 6:
      return totals[0][3];
    case 7:
      return totals[1][3];
    case 8:
      return totals[0][4];
    case 9:
      return totals[1][4];
    case 10:
      return totals[0][1] + totals[1][1];
    default:
      return totals[0][2] + totals[1][2];
  }
}

/* ----------------------------------------------------------------------
   restart: motion state; the friction history travels with the atoms
------------------------------------------------------------------------- */

void FixNCFPlate::write_restart(FILE *fp)
{
  if (comm->me != 0) return;
  // (a restart file written before the clock existed has the time origin in buf[0] and ends
  // after buf[10])
  double buf[1 + 2 * 5 + NCF_LMP::ToolClock::NPACK];
  buf[0] = NCF_LMP::ToolClock::MARK;
  for (int k = 0; k < 2; k++) {
    plate[k].motion.pack(&buf[1 + 5 * k]);
    buf[5 + 5 * k] = zprev[k];
  }
  clock.pack(&buf[11]);
  int size = sizeof(buf);
  fwrite(&size, sizeof(int), 1, fp);
  fwrite(buf, sizeof(double), sizeof(buf) / sizeof(double), fp);
}

void FixNCFPlate::restart(char *raw)
{
  auto *buf = (double *) raw;
  // the motion continues where it stopped only if the plates are defined the same way
  for (int k = 0; k < 2; k++) {
    NCF::Motion stored;
    stored.unpack(&buf[1 + 5 * k]);
    if (!stored.same_as(plate[k].motion)) {
      if (comm->me == 0)
        error->warning(FLERR,
                       "fix ncf/plate: the {} plate is defined differently from the restart "
                       "file: its motion starts anew",
                       k ? "upper" : "lower");
      return;
    }
  }
  if (buf[0] == NCF_LMP::ToolClock::MARK)
    clock.unpack(&buf[11]);
  else
    clock.resume_from_origin(update, buf[0]);
  zprev[0] = buf[5];
  zprev[1] = buf[10];
  update_plates();
  if (comm->me == 0)
    utils::logmesg(
        lmp, "fix ncf/plate: plate motion continued from the restart file (z = {:.6g}, {:.6g})\n",
        plate[0].z, plate[1].z);
}

/* ----------------------------------------------------------------------
   dump image ... fix ID type: each plate as two triangles over the box
------------------------------------------------------------------------- */

int FixNCFPlate::image(int *&ivec, double **&darray)
{
  imgtype.clear();
  imgbuf.clear();
  const double *lo = domain->boxlo, *hi = domain->boxhi;
  for (int k = 0; k < 2; k++) {
    if (plate[k].motion.kind == NCF::Motion::NONE) continue;
    const double z = plate[k].z;
    const double c[4][3] = {
        {lo[0], lo[1], z}, {hi[0], lo[1], z}, {hi[0], hi[1], z}, {lo[0], hi[1], z}};
    const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (auto &t : tri) {
      imgtype.push_back(NCF_COMPAT::ImageShape::TRI);
      imgbuf.push_back(k + 1);
      for (int q : t) imgbuf.insert(imgbuf.end(), c[q], c[q] + 3);
    }
  }
  imgrows.resize(imgtype.size());
  for (std::size_t r = 0; r < imgtype.size(); r++) imgrows[r] = &imgbuf[10 * r];
  ivec = imgtype.data();
  darray = imgrows.data();
  return (int) imgtype.size();
}

/* ----------------------------------------------------------------------
   per-atom friction history
------------------------------------------------------------------------- */

double FixNCFPlate::memory_usage()
{
  return use_history ? (double) atom->nmax * NHIST * sizeof(double) : 0.0;
}

void FixNCFPlate::grow_arrays(int nmax)
{
  memory->grow(slip, nmax, NHIST, "ncf/plate:slip");
}

void FixNCFPlate::copy_arrays(int i, int j, int /*delflag*/)
{
  for (int d = 0; d < NHIST; d++) slip[j][d] = slip[i][d];
}

int FixNCFPlate::pack_exchange(int i, double *buf)
{
  for (int d = 0; d < NHIST; d++) buf[d] = slip[i][d];
  return NHIST;
}

int FixNCFPlate::unpack_exchange(int nlocal, double *buf)
{
  for (int d = 0; d < NHIST; d++) slip[nlocal][d] = buf[d];
  return NHIST;
}

int FixNCFPlate::pack_restart(int i, double *buf)
{
  buf[0] = NHIST + 1;
  for (int d = 0; d < NHIST; d++) buf[d + 1] = slip[i][d];
  return NHIST + 1;
}

void FixNCFPlate::unpack_restart(int nlocal, int nth)
{
  // LAMMPS hands the stored rows to a fix of the same ID and style whatever its friction: the
  // plate defined again without friction (mu 0) keeps no history and drops them
  if (!use_history) return;
  double **extra = atom->extra;
  int m = 0;
  for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  for (int d = 0; d < NHIST; d++) slip[nlocal][d] = extra[nlocal][m++];
}

int FixNCFPlate::size_restart(int /*nlocal*/)
{
  return NHIST + 1;
}

int FixNCFPlate::maxsize_restart()
{
  return NHIST + 1;
}
