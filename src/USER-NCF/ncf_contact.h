/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free contact law between two chain segments (cylinders of diameters d_a, d_b around the
   axes A0-A1 and B0-B1). Shared by pair_style ncf/contact and the fixes (plates, needles);
   unit-tested directly. No LAMMPS dependency.

   Normal part: a line-to-line penalty, integrated along segment A against the axis of B

     E = (k_n / 2) * integral over A of  W(s) * h(x)^2  dx,       h = (D^2 - r^2) / (2 D) > 0

   with D = (d_a + d_b) / 2 the contact distance, r(x) the distance of the point x of axis A from
   the (infinite) line of B, s its arc-length position along B and W(s) a weight that is 1 on
   [e, L_B - e], 0 outside [-e, L_B + e] and linear in between (ramp half-width e). On a straight
   chain the ramps of two consecutive segments add up to 1, so the chain is covered exactly once
   and a contact whose closest point sits on a shared node is neither lost nor counted twice.
   h equals the penetration g = D - r to first order (h = g (1 - g / 2D)); the force per unit
   length k_n h r / D is largest at r = D / sqrt(3) (penetration 0.42 D), far beyond the working
   range of a penalty contact.

   Because h^2 is a polynomial of degree 4 along A and W is piecewise linear, the integral and
   its gradient are computed exactly (3-point Gauss on each smooth piece): the force is exactly
   -dE/dx, continuous in the angle between the segments (crossing, nearly parallel, parallel),
   and for parallel chains proportional to the overlap length independently of the mesh. The
   energy depends on distances only, so the force and moment of the four node forces balance.

   Units: k_n is a stiffness per unit contact length [N/m^2 = Pa]: two parallel cylinders
   pressed together over a length l with penetration g carry F = k_n g l.

   Tangential part (friction_step): an elastic slip spring at the contact point, stiffness
   k_t * l_c (k_t per unit contact length, l_c = integral of W over the contact), capped by
   mu * F_n (Coulomb), history = the slip vector, kept in the tangent plane.
------------------------------------------------------------------------- */

#ifndef NCF_CONTACT_H
#define NCF_CONTACT_H

#include "ncf_geometry.h"

namespace NCF {

// Options of the law beyond its three parameters (D, k_n, ramp); the defaults give the plain law.
//
// core: stiffness factor kappa of a stiff core. For r < D_c = CORE_FRACTION * D the energy
//   density gains the same term with D_c and kappa k_n:  (kappa k_n / 2) W h_c^2,
//   h_c = (D_c^2 - r^2) / (2 D_c). D_c = D / sqrt(3) is where the plain law's force per length
//   k_n h r / D peaks (0.19 k_n D at a penetration of 0.42 D): up to there nothing changes,
//   beyond it the force keeps rising instead of falling; with kappa = 10 it peaks at 1.26 k_n D
//   (penetration 0.66 D). This guards against chains pushed through each other where local loads
//   exceed the plain law's maximum; the force stays continuous (h_c starts with zero slope).
// ext: extension [m] of each segment beyond its nodes a0, a1, b0, b1 (0: none). A free chain end
//   (a node with one bond) is covered only half by the weight ramp and not at all beyond it;
//   extending the end segment along its own axis by ext covers it like an end cap. The extended
//   segment's contact is computed and its node forces are mapped back to the real nodes by the
//   chain rule (exact: force = -dE/dx, force and moment balance kept).
constexpr double CORE_FRACTION = 0.57735026918962576;    // 1 / sqrt(3)
constexpr double SQRT3 = 1.7320508075688772;
// pair_style ncf/contact defaults of the two options (the generator keeps chains clear of the
// end caps of this size)
constexpr double DEFAULT_CORE = 10.0;     // kappa
constexpr double DEFAULT_ENDCAP = 0.5;    // extension at a free end, in diameters of the chain
struct ContactOptions {
  double core = 0.0;
  double ext[4] = {0.0, 0.0, 0.0, 0.0};
};

struct SegmentContact {
  bool active = false;         // true if any part of A penetrates B's cylinder (within W > 0)
  double energy = 0.0;         // E [J]
  Vec3 f[4];                   // forces on A0, A1, B0, B1 [N] (= -dE/dx)
  double fn = 0.0;             // normal force on A along `normal` (>= 0) [N]
  Vec3 normal;                 // unit normal: from B's line to the point of A in contact closest to
                               // it; the direction of the resultant where the axes touch
  double xi = 0.0;             // contact point on A: A0 + xi (A1 - A0), centroid of the
                               // penetration density (h W along A)
  double t = 0.0;              // contact point on B: B0 + t (B1 - B0), in [0, 1] (with
                               // extensions: in [-ext_b0 / L_B, 1 + ext_b1 / L_B])
  double length = 0.0;         // contact length l_c = integral of W over the penetrated part [m]
  double penetration = 0.0;    // D - (distance of the closest points of the two segments) [m]
                               // (of the segments themselves, not of their extensions)
};

// Normal penalty contact of segment A (a0-a1) against segment B (b0-b1).
// dc: contact distance D = (d_a + d_b)/2 > 0; kn: normal stiffness per length [Pa];
// ramp: half-width e > 0 of the weight ramps at B's nodes [m].
// Segments shorter than MIN_LENGTH * D carry no contact (their neighbours do): the weight W
// depends on B's direction, so the force on a very short B grows like 1/L_B; below this length
// the contact is dropped instead. Never NaN.
// with_penetration false: `penetration` is left 0 (it costs a closest-point search and is only
// an output); everything else is the same.
constexpr double MIN_LENGTH = 1e-3;
SegmentContact segment_contact(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1,
                               double dc, double kn, double ramp, bool with_penetration = true,
                               const ContactOptions &opt = ContactOptions());

// The contact law of pair_style ncf/contact, the same whichever segment is A. segment_contact
// integrates along A, cut off at A's nodes, against the ramps at B's nodes; where a chain is kinked
// at a node in contact, or a contact straddles a node, A against B differs from B against A, and a
// pair style that takes the lower-numbered segment as A would make results depend on the atom
// numbering. The pair energy is therefore the mean of both ways,
//
//   E = (E_AB + E_BA) / 2,
//
// and the node forces are the means of theirs (so still exactly -dE/dx, balanced in force and
// moment). Each way leaves its own gaps at kinks of the other chain (the ramps at its nodes), so
// the node caps (node_contact), which fill them, enter with CAP_WEIGHT = 1/2. On straight chains
// both ways give the same energy, so nothing changes there. For the dashpot and friction the
// contact is described by combine_both_ways: normal force and contact length the means, normal
// direction and contact points the means weighted by each way's normal force (continuous when one
// way comes into contact before the other), penetration the larger. ext as for segment_contact.
// Twice the cost of segment_contact.
SegmentContact chain_contact(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1,
                             double dc, double kn, double ramp, bool with_penetration = true,
                             const ContactOptions &opt = ContactOptions());
// the combination of ab (A against B) and ba (B against A, computed with B's nodes first) that
// chain_contact returns; an inactive way counts as zero
SegmentContact combine_both_ways(const SegmentContact &ab, const SegmentContact &ba);
// the weight of the node caps in the symmetric law (chain_contact)
constexpr double CAP_WEIGHT = 0.5;

// A contact computed for the segments extended by ext[0..3] (extend_segment) mapped back to the
// real segments a0-a1, b0-b1: the node forces by the chain rule, the contact point parameters
// xi and t (what segment_contact does with ContactOptions::ext; penetration untouched)
void unextend_contact(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1,
                      const double *ext, SegmentContact &c);

// the end points of segment p0-p1 extended by e0 beyond p0 and e1 beyond p1 along its axis
inline void extend_segment(Vec3 &p0, Vec3 &p1, double e0, double e1)
{
  if (e0 == 0.0 && e1 == 0.0) return;
  const Vec3 u = p1 - p0;
  const double l = norm(u);
  if (!(l > 0.0)) return;
  const Vec3 eu = (1.0 / l) * u;
  p0 -= e0 * eu;
  p1 += e1 * eu;
}

// D minus the distance of the closest points of the two segments, 0 if apart (the penetration
// output of segment_contact)
inline double segment_penetration(const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1,
                                  double dc)
{
  return std::max(0.0, dc - std::sqrt(closest_points_segments(a0, a1, b0, b1).dist2));
}

// Batched evaluation of segment_contact for the common case, without branches, so that the
// compiler can put several pairs into one vector instruction: both segments without extensions
// and at least 2 ramp half-widths long, not within 1e-3 rad of parallel, axes not touching, and
// A's contact zone clear of the core (it may span the ramps and the plateau of B's weight: up to
// three pieces of the integral). A pair outside this case comes back with status -1, to be
// evaluated by segment_contact; otherwise the results equal segment_contact's to round-off
// (tested), with penetration left 0. Fill n lanes, call segment_contact_batch, read the lanes.
constexpr int CONTACT_BATCH = 32;
// (every per-lane array starts on a cache line, alignas(64), so that the vector loads and stores
// of the kernels never straddle two lines)
struct ContactBatch {
  int n = 0;
  // input per lane: a0, a1, b0, b1 (x, y, z each); contact distance, stiffness, ramp
  alignas(64) double x[12][CONTACT_BATCH];
  double dc[CONTACT_BATCH], kn[CONTACT_BATCH], ramp[CONTACT_BATCH];
  // output per lane: status 1 contact, 0 none, -1 not evaluated (use segment_contact)
  double status[CONTACT_BATCH];
  double energy[CONTACT_BATCH], f[12][CONTACT_BATCH], fn[CONTACT_BATCH], normal[3][CONTACT_BATCH];
  double xi[CONTACT_BATCH], t[CONTACT_BATCH], length[CONTACT_BATCH];
  void set(int lane, const Vec3 &a0, const Vec3 &a1, const Vec3 &b0, const Vec3 &b1, double d,
           double k, double e)
  {
    const Vec3 *p[4] = {&a0, &a1, &b0, &b1};
    for (int m = 0; m < 4; m++) {
      x[3 * m][lane] = p[m]->x;
      x[3 * m + 1][lane] = p[m]->y;
      x[3 * m + 2][lane] = p[m]->z;
    }
    dc[lane] = d;
    kn[lane] = k;
    ramp[lane] = e;
  }
  // the result of a lane with status 1 (or 0: inactive) as segment_contact returns it
  // (penetration 0)
  SegmentContact result(int lane) const
  {
    SegmentContact c;
    if (!(status[lane] > 0.0)) return c;
    c.active = true;
    c.energy = energy[lane];
    for (int m = 0; m < 4; m++)
      c.f[m] = Vec3(f[3 * m][lane], f[3 * m + 1][lane], f[3 * m + 2][lane]);
    c.fn = fn[lane];
    c.normal = Vec3(normal[0][lane], normal[1][lane], normal[2][lane]);
    c.xi = xi[lane];
    c.t = t[lane];
    c.length = length[lane];
    return c;
  }
};
// core: ContactOptions::core, the same for all lanes
void segment_contact_batch(ContactBatch &b, double core);
// chain_contact for the lanes of b: segment_contact_batch both ways, combined as
// combine_both_ways. A lane that either way leaves to the scalar law gets status -1 (evaluate it
// with chain_contact). Results equal chain_contact's to round-off (tested), penetration 0.
void chain_contact_batch(ContactBatch &b, double core);

// Exact and cheap prefilter of segment_contact: false when A stays at least dc away from B
// extended by the ramp half-width at both ends (closest points of the two segments); the contact
// law is zero there, since its weight vanishes beyond the extended segment and h vanishes beyond
// dc. True does not mean that the contact is active.
inline bool segment_contact_possible(Vec3 a0, Vec3 a1, Vec3 b0, Vec3 b1, double dc, double ramp,
                                     const double *ext = nullptr)
{
  if (ext) {
    extend_segment(a0, a1, ext[0], ext[1]);
    extend_segment(b0, b1, ext[2], ext[3]);
  }
  const Vec3 u = b1 - b0;
  const double lb2 = norm2(u);
  if (!(lb2 > 0.0)) return true;    // degenerate: let segment_contact decide
  const Vec3 bext = (ramp / std::sqrt(lb2)) * u;
  return closest_points_segments(a0, a1, b0 - bext, b1 + bext).dist2 < dc * dc;
}

// Contact of segment A (a0-a1) with the interior node n of another chain (neighbours p and q on
// that chain), filling the part of the node's sphere (radius D around n) that the ramps of the
// two segments p-n and n-q leave uncovered on the convex side of a kink:
//
//   E = (k_n / 2) * integral over A of  max(0, 1 - W_pn - W_nq)^2 * h_n(x)^2  dx,
//   h_n = (D^2 - |x - n|^2) / (2 D) > 0,
//
// with W_pn, W_nq the weights of segment_contact. Zero for a straight chain (the ramps add up to
// 1), so it only acts at kinks; the deficit enters squared so that the energy stays smooth when a
// chain passes through straight. Exact integral and gradient as in segment_contact.
// Forces: f[0], f[1] on a0, a1; f[2], f[3], f[4] on p, n, q. Normal part only (no friction).
struct NodeContact {
  bool active = false;
  double energy = 0.0;
  Vec3 f[5];
  double penetration = 0.0;    // D - distance of segment A from n [m]
};
// core: as ContactOptions::core (the same stiff core around the node, radius CORE_FRACTION D).
NodeContact node_contact(const Vec3 &a0, const Vec3 &a1, const Vec3 &p, const Vec3 &n,
                         const Vec3 &q, double dc, double kn, double ramp, double core = 0.0);
// the deficit 1 - W_pn - W_nq counts only beyond this tolerance (round-off of straight chains)
constexpr double NODE_DEFICIT_TOL = 1e-9;

// Batched evaluation of node_contact over caps (one lane per cap), without branches, so that the
// compiler puts several caps into one vector instruction: the common case where both chain
// segments p-n and n-q are at least D + e long (within D of n only their ramps at n act, as in
// node_contact's early exit on the concave side) and A is longer than MIN_LENGTH * D. A cap
// outside this case comes back with status -1, to be evaluated by node_contact; otherwise the
// results equal node_contact's to round-off (tested; status 0 where node_contact is inactive).
// Fill n lanes (set), call node_contact_batch, read the lanes.
constexpr int CAP_BATCH = 32;
struct CapBatch {
  int n = 0;
  // input per lane: a0, a1, p, n, q (x, y, z each); contact distance, stiffness, ramp
  alignas(64) double x[15][CAP_BATCH];    // (the arrays on cache lines, as ContactBatch's)
  double dc[CAP_BATCH], kn[CAP_BATCH], ramp[CAP_BATCH];
  // output per lane: status 1 contact, 0 none, -1 not evaluated (use node_contact); energy,
  // forces on a0, a1, p, n, q (x, y, z each), penetration
  double status[CAP_BATCH];
  double energy[CAP_BATCH], f[15][CAP_BATCH], penetration[CAP_BATCH];
  void set(int lane, const double *a0, const double *a1, const double *p, const double *nd,
           const double *q, double d, double k, double e)
  {
    const double *r[5] = {a0, a1, p, nd, q};
    for (int m = 0; m < 5; m++)
      for (int c = 0; c < 3; c++) x[3 * m + c][lane] = r[m][c];
    dc[lane] = d;
    kn[lane] = k;
    ramp[lane] = e;
  }
  // the result of a lane with status 1 (or 0: inactive) as node_contact returns it
  NodeContact result(int lane) const
  {
    NodeContact c;
    if (!(status[lane] > 0.0)) return c;
    c.active = true;
    c.energy = energy[lane];
    for (int m = 0; m < 5; m++)
      c.f[m] = Vec3(f[3 * m][lane], f[3 * m + 1][lane], f[3 * m + 2][lane]);
    c.penetration = penetration[lane];
    return c;
  }
};
// core: as node_contact's, the same for all lanes
void node_contact_batch(CapBatch &b, double core);

// One step of the Coulomb slip spring.
//   slip:   history, slip vector [m] (updated in place; rotated into the tangent plane)
//   normal: unit normal of the contact; vrel: velocity of A's contact point minus B's [m/s]
//   kt:     tangential stiffness of this contact [N/m]; fn: normal force [N]; mu: friction coeff.
//   advance: false in the setup of a run: the force of the stored slip, -kt slip, with the slip
//            left as it is (no rotation, no increment, no cap), which is the force the step that
//            stored it returned, bit for bit (so a run cut into pieces is the same run)
// Returns the tangential force on A (B gets the opposite), -kt slip with the updated slip,
// |F_t| <= mu fn (to round-off). A zero kt or fn gives zero force and a zero slip.
struct FrictionResult {
  Vec3 force;
  bool sliding = false;
  double energy = 0.0;    // elastic energy stored in the spring after the step [J]
};
FrictionResult friction_step(Vec3 &slip, const Vec3 &normal, const Vec3 &vrel, double dt, double kt,
                             double fn, double mu, bool advance = true);

// The tangential part of a contact computed by segment_contact (active, fn > 0; otherwise
// nothing happens): a normal dashpot (damp per unit contact length [N s/m^2]: force
// -damp l_c (v_rel . n), never pulling the chains together, i.e. not below -fn), then with
// mu > 0 the Coulomb slip spring (friction_step with stiffness kt l_c, kt per unit contact
// length [Pa], capped by mu times the normal force including the dashpot). Both act at the
// contact points (A0 + xi (A1 - A0) on A, B0 + t (B1 - B0) on B, the opposite force) and are
// added to c.f. v: velocities of A0, A1, B0, B1; slip: the history (updated if mu > 0).
// advance: as friction_step's (false: the force of the stored slip). Returns the spring energy.
double contact_tangential(SegmentContact &c, const Vec3 *v, Vec3 &slip, double kt, double mu,
                          double damp, double dt, bool advance = true);

// Batched contact_tangential on the lanes of a ContactBatch whose law has been evaluated: lanes
// with status 1 get the same results as contact_tangential (bitwise, the same operations), the
// others are left alone (their forces are then undefined). kt, mu, damp per lane as in
// contact_tangential; for a lane without friction (mu 0) the slip is not used.
struct TangentialBatch {
  alignas(64) double v[12][CONTACT_BATCH];    // velocities of A0, A1, B0, B1 (x, y, z each)
  double slip[3][CONTACT_BATCH];              // slip (updated)
  double kt[CONTACT_BATCH], mu[CONTACT_BATCH], damp[CONTACT_BATCH];
  double energy[CONTACT_BATCH];    // spring energy
};
void tangential_batch(ContactBatch &b, TangentialBatch &t, double dt, bool advance = true);

// The positions of the b.n lanes of b (and, with velocities, their velocities in t) copied from
// node rows of 8 doubles (x, y, z, any, vx, vy, vz, any; each row on 32 bytes): lane l takes the
// rows X + 8 idx[l][m] of its nodes m = A0, A1, B0, B1. Four lanes at a time are transposed in
// registers (rather than 24 scalar copies per lane).
void fill_lanes_from_rows(ContactBatch &b, TangentialBatch &t, const double *X, const int (*idx)[4],
                          bool velocities);

// Critical time step of a node of mass m pressed by a contact of stiffness kn over a length l:
// dt_c = 2 sqrt(m / (kn l)) (explicit central differences). See doc/pair_ncf_contact.md.
double contact_critical_dt(double mass, double kn, double length);

}    // namespace NCF

#endif
