/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   fix ncf/needles: needle indenters at the stitching points, moving along z, in contact with
   chain *segments* (a needle can pass between two nodes). Contact law: NCF::needle_contact of
   ncf_needle.h (pointed body of revolution, monotonic penalty); see doc/fix_ncf_needles.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(ncf/needles,FixNCFNeedles);
// clang-format on
#else

#ifndef LMP_FIX_NCF_NEEDLES_H
#define LMP_FIX_NCF_NEEDLES_H

#include "fix.h"
#include "lammps_ncf_clock.h"
#include "ncf_motion.h"
#include "ncf_needle.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixNCFNeedles : public Fix {
 public:
  FixNCFNeedles(class LAMMPS *, int, char **);
  ~FixNCFNeedles() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void post_force(int) override;
  double compute_scalar() override;
  double compute_vector(int) override;
  double compute_array(int, int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  int image(int *&, double **&) override;

 protected:
  // the constructor's steps
  void parse_args(int narg, char **arg);
  void set_needle_shape();
  void check_needle_layout();
  void check_time_step();

  std::vector<double> nx, ny;    // needle axes
  double radius;                 // needle radius
  double tip;                    // length of the conical point
  double length;                 // needle length from the tip
  double kn;
  int direction;                  // -1: tip points down (shaft above), +1: tip points up
  std::vector<double> chain_d;    // chain diameter per atom type (0 = not in contact)
  NCF::Motion motion;             // of the tips (ncf_motion.h)
  NCF_LMP::ToolClock clock;       // time of the motion since the fix definition
  std::string var;
  int ivar;
  double ztip;

  std::vector<double> fneedle;    // per needle: force of the fabric on the needle (3), reduced
  double energy, maxpen;
  int ncontact;
  double nvisit;        // segment visits (node, bond partner) of the last step, all ranks
  double margin_max;    // largest z margin of a segment from its nodes' heights
  double dmax_chain;    // largest chain diameter

  // the needles binned in the plane (bin_needles)
  int ncell[2] = {1, 1};
  double cell_lo[2] = {0.0, 0.0}, cell_size[2] = {1.0, 1.0}, cell_prd[2] = {0.0, 0.0};
  std::vector<int> cell_first, cell_needle;
  // a finer grid in the plane, per cell 1 if a needle may touch a segment of half length (in the
  // plane) up to near_half whose midpoint is in the cell; the segments whose midpoint is in a cell
  // without one skip the needle search (most segments of a mat are far from every needle)
  std::vector<char> near;
  int near_n[2] = {1, 1};
  double near_lo[2] = {0.0, 0.0}, near_size[2] = {1.0, 1.0}, near_inv[2] = {1.0, 1.0};
  double near_half = -1.0;    // (< 0: no grid yet)
  double near_box[4] = {0.0, 0.0, 0.0, 0.0};
  void grid_near(double half);

  // the bond partners of the owned nodes (closest images, -1 skipped), in the order of their
  // special lists, kept between reneighbourings (the atom indices are stable then)
  std::vector<int> part_first, part_j;
  bigint part_ncalls = -1;
  int part_nlocal = -1, part_nall = -1;
  bool part_valid = false;
  void find_partners();

  std::vector<int> imgtype;
  std::vector<double> imgbuf;
  std::vector<double *> imgrows;

  void bin_needles();
  void needle_segment(int k, int i, const NCF::Vec3 &a0, const NCF::Vec3 &a1, double rc,
                      double half, NCF::Needle &needle, std::vector<double> &local, double &emine,
                      double &penmine, int &cmine);
  void update_tip();
};

}    // namespace LAMMPS_NS

#endif
#endif
