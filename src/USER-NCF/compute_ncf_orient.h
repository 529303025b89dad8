/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   compute ncf/orient: in-plane orientation of the chain segments of each layer relative to the
   layer's nominal angle (histogram, mean, standard deviation, orientation tensor). Statistics
   in ncf_orient.h; see doc/compute_ncf_orient.md.
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(ncf/orient,ComputeNCFOrient);
// clang-format on
#else

#ifndef LMP_COMPUTE_NCF_ORIENT_H
#define LMP_COMPUTE_NCF_ORIENT_H

#include "compute.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class ComputeNCFOrient : public Compute {
 public:
  ComputeNCFOrient(class LAMMPS *, int, char **);
  ~ComputeNCFOrient() override;
  void init() override;
  void compute_vector() override;
  void compute_array() override;

 protected:
  std::vector<int> layers;        // layer indices (i_ncf_layer values)
  std::vector<double> nominal;    // nominal angle of each layer [deg]
  int nbins;
  double range;
  std::string layer_name;    // per-atom integer with the layer of each node
  int idx_layer;
  std::vector<double> sums;    // all layers' OrientStats sums, reduced over ranks

  void accumulate();
};

}    // namespace LAMMPS_NS

#endif
#endif
