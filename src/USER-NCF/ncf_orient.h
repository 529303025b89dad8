/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free orientation statistics of chain segments (paper section 5.2, Fig. 10): every
   segment projected on the fabric plane, its deviation from the layer's nominal angle,
   length-weighted histogram (probability density), mean, standard deviation and the
   orientation tensor. No LAMMPS dependency (Eigen for the tensor's principal directions).
------------------------------------------------------------------------- */

#ifndef NCF_ORIENT_H
#define NCF_ORIENT_H

#include <vector>

namespace NCF {

// In-plane deviation of a segment (dx, dy) from the nominal angle (degrees), as an axis: the
// result is in (-90, 90] degrees (a segment and its reverse have the same orientation).
double axial_deviation(double dx, double dy, double nominal_deg);

// Length-weighted statistics of one layer's segments. The sums are plain numbers so that ranks
// can add them (MPI_Allreduce of data()).
class OrientStats {
 public:
  OrientStats(int nbins, double range_deg);

  // a segment (dx, dy, dz): its projection on the plane is weighted by its projected length
  void add(double dx, double dy, double dz, double nominal_deg);

  // raw sums: [0] weight, [1] sum w d, [2] sum w d^2, [3..8] sum w n_i n_j (xx yy zz xy xz yz of
  // the 3D unit vector, weighted by the 3D length), [9] outside the range, [10..] histogram
  std::vector<double> &data() { return sums; }
  const std::vector<double> &data() const { return sums; }
  int nbins() const { return nb; }
  double range() const { return range_deg; }

  double weight() const { return sums[0]; }
  double mean() const;                // mean deviation [deg]
  double stddev() const;              // standard deviation of the deviation [deg]
  double outside_fraction() const;    // weight outside +-range
  double bin_centre(int b) const;     // [deg]
  double density(int b) const;        // probability density [1/deg]
  // orientation tensor A = <n n> (3D, length-weighted) and its principal axis projected on the
  // plane: angle [deg] from +x, and the largest eigenvalue
  void tensor(double a[3][3]) const;
  double principal_angle() const;
  double principal_value() const;

 private:
  int nb;
  double range_deg;
  std::vector<double> sums;
};

}    // namespace NCF

#endif
