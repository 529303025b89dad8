/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free material library: reads potentials/ncf.materials and turns filament or yarn data
   into the properties of one digital chain. No LAMMPS dependency.
------------------------------------------------------------------------- */

#ifndef NCF_MATERIAL_H
#define NCF_MATERIAL_H

#include "ncf_input_error.h"

#include <map>
#include <string>

namespace NCF {

// Packing coefficient of circular fibres in hexagonal packing, pi / (2 sqrt 3).
constexpr double HEXAGONAL_PACKING = 0.90689968211710892;

enum class MaterialKind { FILAMENT, YARN };

// Bulk data of one fibre material, SI units (UNITS: si on the file's first line).
struct Material {
  std::string name;
  MaterialKind kind = MaterialKind::FILAMENT;
  double modulus = 0.0;              // tensile modulus of the fibre material [Pa]
  double density = 0.0;              // density of the fibre material [kg/m^3]
  double filament_diameter = 0.0;    // diameter of one filament [m] (filaments)
  double linear_density =
      0.0;         // linear density of the whole yarn [kg/m] (yarns; 1 tex = 1e-6 kg/m)
  int line = 0;    // line of the file where it is defined
};

// Properties of one digital chain made of this material, SI units.
struct ChainProperties {
  double diameter = 0.0;           // chain (contact) diameter d_c [m]
  double packing = 0.0;            // packing coefficient phi (fibre volume fraction in the chain)
  double filaments = 0.0;          // filaments per chain n_f = phi d_c^2 / d_f^2 (filaments only)
  double modulus = 0.0;            // chain modulus E_c = phi E_f [Pa]
  double density = 0.0;            // chain density rho_c = phi rho_f [kg/m^3]
  double area = 0.0;               // chain cross-section pi d_c^2 / 4 [m^2]
  double ea = 0.0;                 // axial rigidity E_c A_c [N]
  double mass_per_length = 0.0;    // rho_c A_c [kg/m]
  double wave_speed = 0.0;         // sqrt(E_c / rho_c) [m/s]
  // bending rigidity of the chain as a bundle of n_f unbonded filaments, each bending about its
  // own axis: EI = n_f E_f pi d_f^4 / 64 [N m^2] (filaments only; 0 for a yarn chain). The
  // chains are stretch-only rods; this is only used where a card asks for 'bending bundle'.
  double bundle_ei = 0.0;
};

class MaterialLibrary {
 public:
  // Parse a materials file; throws InputError naming the file, line and problem.
  static MaterialLibrary read(const std::string &path);
  // Parse from text (path is only used in messages).
  static MaterialLibrary parse(const std::string &text, const std::string &path);

  const Material &get(const std::string &name) const;    // throws InputError if unknown
  bool has(const std::string &name) const { return materials_.count(name) > 0; }
  const std::map<std::string, Material> &all() const { return materials_; }
  const std::string &units() const { return units_; }

 private:
  std::string units_;
  std::map<std::string, Material> materials_;
};

// Filament chain (paper section 4.5): n_f = phi d_c^2 / d_f^2, E_c = phi E_f, rho_c = phi rho_f.
ChainProperties filament_chain(const Material &m, double chain_diameter, double packing);

// Stitching-yarn chain: one chain per yarn, its diameter from the linear density assuming the
// given packing (hexagonal by default): A_c = lambda / (rho_f phi), d_c = sqrt(4 A_c / pi).
ChainProperties yarn_chain(const Material &m, double packing = HEXAGONAL_PACKING);

}    // namespace NCF

#endif
