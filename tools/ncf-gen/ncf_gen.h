/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF fabric generator (ncf-gen): fabric card -> initial digital-chain model.
   Engine-free (no LAMMPS header). Paper sections 4.2, 4.4, 4.5; design.md section 5;
   doc/ncf-gen.md describes the card and the conventions.

   Conventions: SI units; x = machine direction (stitch courses follow each other along x, one
   stitch length apart), y = gauge direction (needles 25.4 mm / gauge apart), z = thickness.
   Atom and bond type i = layer i (from the bottom), the stitching yarn type is the last one.
------------------------------------------------------------------------- */

#ifndef NCFGEN_H
#define NCFGEN_H

#include "ncf_material.h"

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace NCFGEN {

using NCF::InputError;

// ------------------------------------------------------------------ card

struct LayerSpec {
  int line = 0;                  // card line of the 'layer' key (for messages)
  double angle = 0.0;            // nominal angle from the machine direction x [deg]
  double areal_weight = -1.0;    // fibre areal weight A [kg/m^2]
  std::string material;          // filament material name in the materials file
  int material_line = 0;
  double sigma = 0.0;    // standard deviation of the chain angles [deg]
};

struct Lapping {
  std::string text;                         // as written on the card (or the named pattern)
  std::vector<std::pair<int, int>> laps;    // overlap (a-b) of each course in the notation
  std::vector<int> needle;                  // needle of the loop of each course, min(a, b)
  int repeat = 0;                           // courses of the idealised path's repeat
  int max_underlap = 0;                     // widest underlap, in needles
};

// Parses warp-knitting lapping notation ("1-0/1-2//") or a named pattern (pillar, chain, tricot,
// tricot-chain). Throws InputError with 'where' as prefix.
Lapping parse_lapping(const std::string &text, const std::string &where);

// A quality preset (card key 'quality', doc/ncf-gen.md "Quality presets"): the resolution of the
// model and the run parameters of the stage scripts in one word. A resolution key given on the
// card wins over its preset value; the run parameters reach the stage scripts as defaults
// (settings variables ncf_dtfrac, ncf_pdyn, ncf_tau), which -var on the LAMMPS command line
// overrides.
struct QualityPreset {
  const char *name;
  double chain_diameter;    // d_c [m]
  double fibre_mesh;        // target element length of the filament chains [m]; raised to d_c
  double yarn_mesh;         // largest element length of the yarn [m]; raised to d_y
  double dtfrac;            // time step of the stages / critical step of the bonds [-]
  double pdyn;              // accepted dynamic pressure rho_mat v^2 of the compaction [Pa]
  double tau;               // viscous damping: velocity relaxation time [steps]
};

// draft, standard, fine (in that order)
const std::vector<QualityPreset> &quality_presets();
// the preset of that name, nullptr if there is none
const QualityPreset *find_quality(const std::string &name);

struct Card {
  std::string path;                       // the card file (messages, relative paths)
  std::map<std::string, int> key_line;    // line of each global key given on the card
  std::string name = "ncf";
  std::string materials_file;    // resolved path of the materials file
  int materials_line = 0;
  std::uint64_t seed = 1;
  int r_w = 1, r_l = 1;             // RVE repetitions across / along the machine direction
  double chain_diameter = 69e-6;    // d_c of the filament chains [m]
  double packing = 0.5;             // packing coefficient phi
  double fibre_mesh = 0.2e-3;       // target element length of the filament chains [m]
  double yarn_mesh = 0.1e-3;        // target element length of the yarn [m]
  double v_l = 0.20;                // initial fibre volume fraction V_L (Eq. 1)
  double mass_scaling = 1.0;        // factor on all node masses
  bool stratified = true;           // angle sampling: stratified Gaussian (default) or iid
  std::vector<LayerSpec> layers;    // bottom to top
  // stitching (one fully threaded guide bar)
  Lapping pattern;
  int pattern_line = 0;
  double gauge = 5.0;             // needles per inch
  double stitch_length = -1.0;    // course spacing [m]
  std::string yarn;               // yarn material name
  int yarn_line = 0;
  bool loops_bottom = true;    // loops on the bottom face (z < 0), underlaps on the top face
  double leg_gap = 1.02;       // distance of the two yarn legs at one hole / yarn diameter
  // the idealised yarn path: warp-knit loops (both legs through one hole, the loop out and back
  // on the loop face, its head around the next course's legs) or a running stitch (down through
  // one hole, along the loop face, up through the next; the path before the knit)
  bool knit = true;
  double yarn_packing = NCF::HEXAGONAL_PACKING;    // packing coefficient of the yarn chain
  // manufacturing (used by the stage scripts, written to the settings)
  double needle_diameter = 0.6e-3;    // needle shaft diameter [m]
  double needle_tip = 0.6e-3;         // length of the needle's conical point [m]
  double pretension = 0.16;           // shrink of the yarn's rest length in stage 4 [-]
  // chain bending (key 'bending'): none (the default: stretch-only chains, no angle terms) or
  // bundle (an angle per pair of consecutive bonds of every fibre chain, angle_style cosine with
  // K = EI / l0_mean, EI of the chain's n_f unbonded filaments; the stitching yarn gets none)
  bool bending = false;
  // the quality preset (no 'quality' key: standard); chain_diameter, fibre_mesh and yarn_mesh
  // above hold its values unless the card gives them (key_line tells which)
  std::string quality = "standard";
  double dtfrac = 0.5;    // run parameters of the stage scripts, from the preset
  double pdyn = 1e4;
  double tau = 2000.0;
  // whether a key's value came from the card (else from the quality preset)
  bool from_card(const std::string &key) const { return key_line.count(key) > 0; }
};

// Reads and checks a card; every error names the card file, the line, the key and the value.
Card read_card(const std::string &path);
Card parse_card(const std::string &text, const std::string &path);

// ------------------------------------------------------------------ generated model

enum EndFace { INTERIOR = 0, XLO = 1, XHI = 2, YLO = 3, YHI = 4 };

struct Node {
  double x[3];      // unwrapped position [m]
  int type = 1;     // atom type
  int layer = 0;    // layer index from 1, 0 = stitching yarn
  int end = 0;      // EndFace
  int chain = 0;    // chain (molecule) id within its data file, from 1
};

struct Bond {
  int i = 0, j = 0;    // node indices (0-based) within the same node list
  int type = 1;
  double l0 = 0.0;    // reference length = initial length [m]
};

struct Angle {                // i - j - k: two consecutive bonds of a chain, j the middle node
  int i = 0, j = 0, k = 0;    // node indices (0-based) within the same node list
  int type = 1;
};

struct Part {    // one data file's worth of nodes and bonds
  std::vector<Node> nodes;
  std::vector<Bond> bonds;
  std::vector<Angle> angles;       // only with 'bending bundle' (fibre chains)
  std::vector<double> diameter;    // contact diameter of each chain (index chain-1)
};

struct LayerInfo {
  LayerSpec spec;
  NCF::ChainProperties chain;
  double filament_density = 0.0;    // rho_f of the filament material [kg/m^3]
  double t_l = 0.0;                 // layer thickness before stitching, Eq. 1 [m]
  int main_axis = 0;                // 0: chains cross the RVE along x, 1: along y
  double width = 0.0;               // RVE width across the fibres counted on the main face [m]
  double chains_per_width_target = 0.0;    // A / (rho_c A_c) [1/m]
  int chains = 0;
  int nodes = 0, bonds = 0;
  double z_min = 0.0, z_max = 0.0;    // centre-line heights of the lowest / highest chain [m]
  double stack = 0.0;                 // generated thickness z_max - z_min + d_c [m]
  bool homogeneous = false;           // sigma = 0: mat of thickness t_L placed directly
  int lattice_multiplier = 0;         // rank-1 lattice multiplier of the homogeneous mat
  double angle_mean = 0.0, angle_std = 0.0;    // sample of the chain angles [deg]
  std::vector<double> angles;                  // chain angles [deg]
  double node_mass = 0.0;                      // lumped, mass scaling included [kg]
  double min_l0 = 0.0, max_l0 = 0.0;
  double mean_l0 = 0.0;    // mean element length of the layer [m]
  double dt_crit = 0.0;    // min L0 sqrt(rho_c ms / E_c) [s]
  // 'bending bundle': angles of the layer (bonds - chains), angle_style cosine's K = EI / mean_l0
  // with EI = chain.bundle_ei [J]; 0 with 'bending none'
  int bending_angles = 0;
  double bending_k = 0.0;
};

struct YarnInfo {
  bool present = false;
  NCF::ChainProperties chain;
  int yarns = 0, nodes = 0, bonds = 0;
  double length_per_yarn = 0.0;          // path length of one yarn in the RVE [m]
  double areal_weight = 0.0;             // yarn mass / RVE area [kg/m^2]
  double z_bottom = 0.0, z_top = 0.0;    // centre-line heights of the two faces [m]
  double z_loop = 0.0, z_under = 0.0;    // the loop face's and the underlap face's heights [m]
  // knit: the loops leave their hole at z_loop_out, a level further out than z_loop, and rise to
  // z_loop at their head, so that each loop passes outside the one before it near its hole
  // and inside it at its head (interlocked); running: z_loop [m]
  double z_loop_out = 0.0;
  double leg_offset = 0.0;         // x offset of each leg from its hole centre [m]
  double loop_half_width = 0.0;    // knit: half-width (y) of a loop [m]
  double head_offset = 0.0;        // knit: x of a loop's head beyond the next hole [m]
  double node_mass = 0.0;
  double min_l0 = 0.0, max_l0 = 0.0;
  double dt_crit = 0.0;
};

struct Fabric {
  Card card;
  double lx = 0.0, ly = 0.0;      // RVE size [m], box [0,lx] x [0,ly]
  double zlo = 0.0, zhi = 0.0;    // box in z (non-periodic)
  double course = 0.0;            // stitch length = course spacing [m]
  double needle_spacing = 0.0;    // 25.4 mm / gauge [m]
  int courses = 0;                // courses in the RVE
  double thickness = 0.0;         // sum of t_L: the compacted mat occupies 0 <= z <= thickness
  double stack_top = 0.0;         // top surface of the generated (uncompacted) stack [m]
  std::vector<LayerInfo> layers;
  YarnInfo yarn;
  Part fibres, stitch;
  std::vector<std::pair<double, double>> needles;    // stitching points (x, y) [m]
  // geometric check of the result: smallest distance minus contact diameter over all segment
  // pairs (periodic images included) of the layers and of the yarn [m], and the layers' distance
  double fibre_gap = 0.0, fibre_distance = 0.0, yarn_gap = 0.0;
  // a mesh of the quality preset shorter than the diameter is raised to it (card.fibre_mesh and
  // card.yarn_mesh then hold the raised values); the preset's value, 0 if not raised [m]
  double fibre_mesh_preset_raised = 0.0, yarn_mesh_preset_raised = 0.0;
  int atom_types() const { return (int) layers.size() + 1; }
  int yarn_type() const { return (int) layers.size() + 1; }
};

Fabric build_fabric(const Card &card, const NCF::MaterialLibrary &lib);

struct Segment;
// the bonds of a part as segments with unwrapped ends (a yarn's closing bond shifted by lx)
std::vector<Segment> part_segments(const Part &part, double lx);

// ------------------------------------------------------------------ outputs

struct Outputs {    // file suffix -> contents
  std::vector<std::pair<std::string, std::string>> files;
};

std::string layers_data(const Fabric &f);
std::string yarn_data(const Fabric &f);
std::string needles_text(const Fabric &f);
// the settings include file; `fabric` is its ncf_fabric (fabric_id(f) when empty)
std::string settings_text(const Fabric &f, const std::string &prefix,
                          const std::string &fabric = "");
// the fabric's identity written to its settings: a hash of its layers and yarn data files
std::string fabric_id(const Fabric &f);

std::string yarn_settings_text(const Fabric &f);
std::string summary_text(const Fabric &f);

// All outputs of one card, named <prefix>.layers.data, .yarn.data, .needles, .settings.lmp,
// .yarn.lmp, .summary. Nothing is written here.
Outputs make_outputs(const Fabric &f, const std::string &prefix);

// Command-line values that replace the card's (0 = keep the card's).
struct Overrides {
  int r_w = 0, r_l = 0;
  long long seed = -1;
};

// Reads the card and its materials, builds, then writes every file; on any error writes nothing
// and returns the message in 'error' (false returned).
bool generate(const std::string &card_path, const std::string &prefix, std::string &error,
              std::string *summary = nullptr, const Overrides *overrides = nullptr);

}    // namespace NCFGEN

#endif
