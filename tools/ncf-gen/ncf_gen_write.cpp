/* ----------------------------------------------------------------------
   USER-NCF fabric generator: output files (LAMMPS data files, needles, include files, summary).
   Numbers are written as the shortest text that reads back as the same double (std::to_chars),
   so the files are exact and the same card and seed give the same bytes.
------------------------------------------------------------------------- */

#include "ncf_gen.h"
#include "ncf_gen_geom.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>

namespace NCFGEN {

namespace {

  // shortest text that reads back as the same double
  std::string g(double v)
  {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof(buf), v);
    return std::string(buf, r.ptr);
  }

  std::string fmt(const char *f, double v)
  {
    char buf[64];
    std::snprintf(buf, sizeof(buf), f, v);
    return buf;
  }

  // wrapped coordinate in [0, len) and its image flag
  void wrap(double x, double len, double &w, int &image)
  {
    image = (int) std::floor(x / len);
    w = x - image * len;
    if (w >= len) {
      w -= len;
      image++;
    }
    if (w < 0.0) {
      w += len;
      image--;
    }
  }

  std::string data_file(const Fabric &f, const Part &part, const std::string &what)
  {
    const int ntypes = f.atom_types();
    // 'bending bundle': the fibre chains' angles (atom_style angle; one angle type per layer,
    // the yarn has none); without angles the file is atom_style bond as it always was
    const bool angles = !part.angles.empty();
    const std::string style = angles ? "angle" : "bond";
    std::string s;
    s += "LAMMPS data file: ncf-gen " + what + " of '" + f.card.name + "' (seed " +
        std::to_string(f.card.seed) + ", RVE " + std::to_string(f.card.r_w) + "x" +
        std::to_string(f.card.r_l) + "), units si, atom_style " + style + "\n\n";
    s += std::to_string(part.nodes.size()) + " atoms\n";
    s += std::to_string(ntypes) + " atom types\n";
    s += std::to_string(part.bonds.size()) + " bonds\n";
    s += std::to_string(ntypes) + " bond types\n";
    if (angles) {
      s += std::to_string(part.angles.size()) + " angles\n";
      s += std::to_string(f.layers.size()) + " angle types\n";
    }
    s += "\n";
    s += "0 " + g(f.lx) + " xlo xhi\n";
    s += "0 " + g(f.ly) + " ylo yhi\n";
    s += g(f.zlo) + " " + g(f.zhi) + " zlo zhi\n\n";
    s += "Masses\n\n";
    for (std::size_t i = 0; i < f.layers.size(); i++)
      s += std::to_string(i + 1) + " " + g(f.layers[i].node_mass) + "  # layer " +
          std::to_string(i + 1) + "\n";
    s += std::to_string(f.yarn_type()) + " " + g(f.yarn.node_mass) + "  # stitching yarn\n\n";
    s += "Atoms # " + style + "\n\n";
    for (std::size_t i = 0; i < part.nodes.size(); i++) {
      const Node &n = part.nodes[i];
      double x, y;
      int ix, iy;
      wrap(n.x[0], f.lx, x, ix);
      wrap(n.x[1], f.ly, y, iy);
      s += std::to_string(i + 1) + " " + std::to_string(n.chain) + " " + std::to_string(n.type) +
          " " + g(x) + " " + g(y) + " " + g(n.x[2]) + " " + std::to_string(ix) + " " +
          std::to_string(iy) + " 0\n";
    }
    s += "\nBonds\n\n";
    for (std::size_t b = 0; b < part.bonds.size(); b++) {
      const Bond &bd = part.bonds[b];
      s += std::to_string(b + 1) + " " + std::to_string(bd.type) + " " + std::to_string(bd.i + 1) +
          " " + std::to_string(bd.j + 1) + "\n";
    }
    if (angles) {
      s += "\nAngles\n\n";
      for (std::size_t a = 0; a < part.angles.size(); a++) {
        const Angle &an = part.angles[a];
        s += std::to_string(a + 1) + " " + std::to_string(an.type) + " " +
            std::to_string(an.i + 1) + " " + std::to_string(an.j + 1) + " " +
            std::to_string(an.k + 1) + "\n";
      }
    }
    // per-atom reference lengths: partner tag - own tag and L0, two slots (doc/ARCHITECTURE.md)
    std::vector<int> dt(2 * part.nodes.size(), 0);
    std::vector<double> l0(2 * part.nodes.size(), 0.0);
    auto put = [&](int a, int partner, double len) {
      const int slot = dt[2 * a] == 0 ? 0 : 1;
      dt[2 * a + slot] = partner - a;
      l0[2 * a + slot] = len;
    };
    for (const Bond &bd : part.bonds) {
      put(bd.i, bd.j, bd.l0);
      put(bd.j, bd.i, bd.l0);
    }
    s += "\nNCF_CHAIN_L0\n\n";
    for (std::size_t i = 0; i < part.nodes.size(); i++)
      s += std::to_string(i + 1) + " " + std::to_string(dt[2 * i]) + " " +
          std::to_string(dt[2 * i + 1]) + " " + g(l0[2 * i]) + " " + g(l0[2 * i + 1]) + "\n";
    s += "\nNCF_NODE\n\n";
    for (std::size_t i = 0; i < part.nodes.size(); i++)
      s += std::to_string(i + 1) + " " + std::to_string(part.nodes[i].layer) + " " +
          std::to_string(part.nodes[i].end) + "\n";
    return s;
  }

}    // namespace

std::string layers_data(const Fabric &f)
{
  return data_file(f, f.fibres, "fibrous layers");
}

std::string yarn_data(const Fabric &f)
{
  return data_file(f, f.stitch, "stitching yarn");
}

std::string needles_text(const Fabric &f)
{
  std::string s = "# ncf-gen needles of '" + f.card.name +
      "': " + std::to_string(f.needles.size()) +
      " stitching points, x y [m] (x machine direction, y gauge direction)\n";
  s += "# box 0 " + g(f.lx) + " 0 " + g(f.ly) + "\n";
  for (auto &n : f.needles) s += g(n.first) + " " + g(n.second) + "\n";
  return s;
}

std::string fabric_id(const Fabric &f)
{
  // FNV-1a (64 bit) of the two data files: two fabrics that differ in any node or bond differ
  std::uint64_t h = 1469598103934665603ULL;
  for (const std::string &t : {layers_data(f), yarn_data(f)})
    for (unsigned char c : t) h = (h ^ c) * 1099511628211ULL;
  char buf[24];
  std::snprintf(buf, sizeof(buf), "%016llx", (unsigned long long) h);
  return buf;
}

std::string settings_text(const Fabric &f, const std::string &prefix, const std::string &fabric)
{
  std::string s;
  const int nl = (int) f.layers.size(), yt = f.yarn_type();
  s += "# ncf-gen settings of '" + f.card.name + "' (card " + f.card.path + ", seed " +
      std::to_string(f.card.seed) + ").\n";
  s += "# Include after:\n";
  s += "#   units si\n#   atom_style " + std::string(f.card.bending ? "angle" : "bond") +
      "\n#   boundary p p f\n#   bond_style ncf/chain\n";
  s += "#   fix NCF_NODE all property/atom i_ncf_layer i_ncf_end ghost yes\n";
  s += "#   read_data " + prefix +
      ".layers.data fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0 fix NCF_NODE NULL NCF_NODE\n";
  s += "# The stitching yarn comes later with\n";
  s += "#   read_data " + prefix +
      ".yarn.data add append fix NCF_CHAIN_L0 NULL NCF_CHAIN_L0 fix NCF_NODE NULL NCF_NODE\n";
  s += "#   include " + prefix + ".yarn.lmp\n\n";
  s += "variable ncf_Lx equal " + g(f.lx) + "  # RVE length along the machine direction x [m]\n";
  s += "variable ncf_Ly equal " + g(f.ly) + "  # RVE width along the gauge direction y [m]\n";
  s += "variable ncf_thickness equal " + g(f.thickness) +
      "  # sum of t_L: compacted mat 0 <= z <= thickness [m]\n";
  s += "variable ncf_stack_top equal " + g(f.stack_top) + "  # top of the generated stack [m]\n";
  s += "variable ncf_nlayers equal " + std::to_string(nl) + "\n";
  s += "variable ncf_yarn_type equal " + std::to_string(yt) + "\n";
  for (int i = 0; i < nl; i++) {
    const LayerInfo &L = f.layers[i];
    const std::string n = std::to_string(i + 1);
    s += "variable ncf_tL_" + n + " equal " + g(L.t_l) + "  # layer " + n +
        " thickness, Eq. 1 [m]\n";
    s += "variable ncf_d_" + n + " equal " + g(L.chain.diameter) +
        "  # contact diameter of atom type " + n + " [m]\n";
  }
  s += "variable ncf_d_" + std::to_string(yt) + " equal " + g(f.yarn.chain.diameter) +
      "  # contact diameter of the stitching yarn [m]\n";
  // the same under names that do not depend on the number of layers (all filament chains of a
  // card share its chain_diameter), and the layers' nominal angles for compute ncf/orient
  s += "variable ncf_d_fibre equal " + g(f.layers.front().chain.diameter) +
      "  # contact diameter of every filament chain [m]\n";
  s += "variable ncf_d_yarn equal " + g(f.yarn.chain.diameter) +
      "  # contact diameter of the stitching yarn [m]\n";
  // the fibre volume fraction of the compacted mat and the filament modulus, for the virtual tests
  // (V_f = V_L sum(t_L) / thickness; Toll's law P = k E_f (V_f^n - V_0^n))
  s += "variable ncf_V_L equal " + g(f.card.v_l) +
      "  # fibre volume fraction of the mat at sum(t_L), Eq. 1 [-]\n";
  s += "variable ncf_E_fibre equal " +
      g(f.layers.front().chain.modulus / f.layers.front().chain.packing) +
      "  # filament modulus of layer 1 [Pa]\n";
  std::string orient;
  for (int i = 0; i < nl; i++)
    orient += (i ? " " : "") + std::string("layer ") + std::to_string(i + 1) + " " +
        g(f.layers[i].spec.angle);
  s += "variable ncf_orient_layers string \"" + orient + "\"  # arguments of compute ncf/orient\n";
  double dt = f.yarn.dt_crit;
  for (auto &L : f.layers) dt = std::min(dt, L.dt_crit);
  s += "variable ncf_dt_crit equal " + g(dt) + "  # min over bonds of L0 sqrt(rho/E) [s]\n";
  s += "variable ncf_needle_d equal " + g(f.card.needle_diameter) +
      "  # needle shaft diameter, stage 2 [m]\n";
  s += "variable ncf_needle_tip equal " + g(f.card.needle_tip) +
      "  # length of the needle's conical point, stages 2-3 [m]\n";
  s += "variable ncf_pretension equal " + g(f.card.pretension) +
      "  # shrink of the yarn's rest length, stage 4 [-]\n";
  s += "variable ncf_needle_pitch equal " + g(f.needle_spacing) +
      "  # needle spacing along the gauge direction, 25.4 mm / gauge [m]\n";
  // the fabric's identity: the stage scripts check that a restart file is of this fabric
  s += "variable ncf_fabric string " + (fabric.empty() ? fabric_id(f) : fabric) +
      "  # hash of the generated layers and yarn data [-]\n";
  // the run parameters of the quality preset: index variables, the defaults of the stage
  // scripts' dtfrac, pdyn and tau (-var on the command line wins over both)
  const Card &c = f.card;
  s += "variable ncf_quality string " + c.quality + "  # the card's quality preset\n";
  s += "variable ncf_dtfrac index " + g(c.dtfrac) +
      "  # time step / ncf_dt_crit of the stages (quality " + c.quality + ") [-]\n";
  s += "variable ncf_pdyn index " + g(c.pdyn) +
      "  # accepted dynamic pressure of the compaction (quality " + c.quality + ") [Pa]\n";
  s += "variable ncf_tau index " + g(c.tau) +
      "  # viscous damping relaxation time of the stages (quality " + c.quality + ") [steps]\n\n";
  for (int i = 0; i < nl; i++) {
    const LayerInfo &L = f.layers[i];
    s += "bond_coeff " + std::to_string(i + 1) + " ea " + g(L.chain.ea) + "  # layer " +
        std::to_string(i + 1) + ": E_c " + g(L.chain.modulus) + " Pa, d_c " + g(L.chain.diameter) +
        " m\n";
  }
  s += "bond_coeff " + std::to_string(yt) + " ea " + g(f.yarn.chain.ea) +
      "  # stitching yarn: E_c " + g(f.yarn.chain.modulus) + " Pa, d_c " +
      g(f.yarn.chain.diameter) + " m\n\n";
  // 'bending bundle': the layers' chains resist bending with the rigidity EI of their unbonded
  // filaments (angle_style cosine, E = K (1 + cos theta), K = EI / l0: the discrete
  // Euler-Bernoulli beam); the stitching yarn has no angles
  if (c.bending) {
    s += "angle_style cosine\n";
    for (int i = 0; i < nl; i++) {
      const LayerInfo &L = f.layers[i];
      s += "angle_coeff " + std::to_string(i + 1) + " " + g(L.bending_k) + "  # layer " +
          std::to_string(i + 1) + ": K = EI / l0 [J], EI " + g(L.chain.bundle_ei) + " N m^2 (" +
          g(L.chain.filaments) + " filaments), l0 " + g(L.mean_l0) + " m\n";
    }
    s += "\n";
  }
  std::string all;
  for (int i = 0; i < nl; i++) {
    s += "group ncf_layer" + std::to_string(i + 1) + " type " + std::to_string(i + 1) + "\n";
    all += " " + std::to_string(i + 1);
  }
  s += "group ncf_layers type" + all + "\n";
  s += "variable ncf_is_end atom i_ncf_end>0\n";
  s += "variable ncf_is_xend atom (i_ncf_end==1)||(i_ncf_end==2)\n";
  s += "variable ncf_is_yend atom (i_ncf_end==3)||(i_ncf_end==4)\n";
  s += "group ncf_ends variable ncf_is_end\n";
  s += "group ncf_ends_x variable ncf_is_xend\n";
  s += "group ncf_ends_y variable ncf_is_yend\n";
  return s;
}

std::string yarn_settings_text(const Fabric &f)
{
  std::string s = "# ncf-gen: groups of the stitching yarn of '" + f.card.name +
      "', include after read_data ... add append of the yarn data file\n";
  s += "group ncf_yarn type " + std::to_string(f.yarn_type()) + "\n";
  // the heights of the generated path, for the stitch stage's placement of the yarn
  s += "variable ncf_yarn_zloop equal " + g(f.yarn.z_loop) +
      "  # loop face, at the loops' heads [m]\n";
  s += "variable ncf_yarn_zunder equal " + g(f.yarn.z_under) + "  # underlap face [m]\n";
  s += "variable ncf_yarn_path string " + std::string(f.card.knit ? "knit" : "running") + "\n";
  return s;
}

std::string summary_text(const Fabric &f)
{
  const Card &c = f.card;
  std::string s;
  auto line = [&](const std::string &k, const std::string &v) {
    std::string key = k;
    if (key.size() < 36) key.resize(36, ' ');
    s += "  " + key + v + "\n";
  };
  s += "ncf-gen summary of '" + c.name + "' (card " + c.path + ")\n";
  s += "seed " + std::to_string(c.seed) + ", angle sampling " +
      (c.stratified ? "stratified" : "random") + ", materials " + c.materials_file + "\n\n";
  // the quality preset and, for each value it sets, where the value came from
  const std::string preset = "(quality " + c.quality + ")";
  auto origin = [&](const std::string &key) {
    return c.from_card(key) ? std::string("(card)") : preset;
  };
  s += "quality " + c.quality + "\n";
  line("chain_diameter", fmt("%g um  ", c.chain_diameter * 1e6) + origin("chain_diameter"));
  line("fibre_mesh",
       fmt("%g mm  ", c.fibre_mesh * 1e3) + origin("fibre_mesh") +
           (f.fibre_mesh_preset_raised > 0.0
                ? fmt(": the preset's %g mm raised to the chain diameter",
                      f.fibre_mesh_preset_raised * 1e3)
                : ""));
  line("yarn_mesh",
       fmt("%g mm  ", c.yarn_mesh * 1e3) + origin("yarn_mesh") +
           (f.yarn_mesh_preset_raised > 0.0
                ? fmt(": the preset's %g mm raised to the yarn diameter",
                      f.yarn_mesh_preset_raised * 1e3)
                : ""));
  // (the stage scripts take these as defaults: -var on the LAMMPS command line overrides them)
  const std::string run = "(quality " + c.quality + "; stage scripts' default)";
  line("dtfrac (time step / critical step)", fmt("%g  ", c.dtfrac) + run);
  line("pdyn (compaction dynamic pressure)", fmt("%g Pa  ", c.pdyn) + run);
  line("tau (damping time of the stages)", fmt("%g steps  ", c.tau) + run);
  s += "\n";
  s += "RVE\n";
  line("pattern",
       c.pattern.text + "  (repeat " + std::to_string(c.pattern.repeat) + " course" +
           (c.pattern.repeat > 1 ? "s" : "") + ")");
  line("gauge / needle spacing",
       fmt("%g npi", c.gauge) + " / " + fmt("%.4f mm", f.needle_spacing * 1e3));
  line("stitch length", fmt("%.4f mm", f.course * 1e3));
  line("repetitions r_W x r_L", std::to_string(c.r_w) + " x " + std::to_string(c.r_l));
  line("size Lx (machine) x Ly (gauge)",
       fmt("%.4f", f.lx * 1e3) + " x " + fmt("%.4f mm", f.ly * 1e3));
  line("courses, needles (stitching points)",
       std::to_string(f.courses) + ", " + std::to_string(f.needles.size()));
  line("sum of t_L (compacted mat)", fmt("%.4f mm", f.thickness * 1e3));
  line("generated stack top",
       fmt("%.4f mm", f.stack_top * 1e3) +
           fmt("  (%.2f x the compacted mat)", f.stack_top / f.thickness));
  line("box z", fmt("%.4f", f.zlo * 1e3) + " .. " + fmt("%.4f mm", f.zhi * 1e3));
  double minl0 = f.yarn.min_l0, dt = f.yarn.dt_crit;
  for (std::size_t i = 0; i < f.layers.size(); i++) {
    const LayerInfo &L = f.layers[i];
    minl0 = std::min(minl0, L.min_l0);
    dt = std::min(dt, L.dt_crit);
    s += "\nlayer " + std::to_string(i + 1) + " (atom/bond type " + std::to_string(i + 1) + ")\n";
    line("nominal angle, sigma", fmt("%g deg", L.spec.angle) + ", " + fmt("%g deg", L.spec.sigma));
    line("areal weight", fmt("%g g/m^2", L.spec.areal_weight * 1e3));
    line("material", L.spec.material + fmt("  (rho_f %g kg/m^3)", L.filament_density));
    line("chain d_c, packing", fmt("%g um", L.chain.diameter * 1e6) + fmt(", %g", L.chain.packing));
    line("filaments per chain", fmt("%.2f", L.chain.filaments));
    line("E_c, rho_c, EA",
         fmt("%.5g GPa", L.chain.modulus * 1e-9) + fmt(", %.5g kg/m^3", L.chain.density) +
             fmt(", %.5g N", L.chain.ea));
    line("fibre mass per chain length", fmt("%.5g kg/m", L.chain.mass_per_length));
    line("chains cross the RVE along",
         std::string(L.main_axis == 0 ? "x" : "y") +
             fmt("  (width across the fibres %.4f mm)", L.width * 1e3));
    line("chains per mm: target, generated",
         fmt("%.4f", L.chains_per_width_target * 1e-3) + fmt(", %.4f", L.chains / L.width * 1e-3) +
             fmt("  (%+.3f %%)", 100.0 * (L.chains / L.width / L.chains_per_width_target - 1.0)));
    line("chains, nodes, bonds",
         std::to_string(L.chains) + ", " + std::to_string(L.nodes) + ", " +
             std::to_string(L.bonds));
    line("element length min / max",
         fmt("%.5f", L.min_l0 * 1e3) + fmt(" / %.5f mm", L.max_l0 * 1e3));
    line("t_L = A / (V_L rho_f)", fmt("%.4f mm", L.t_l * 1e3) + fmt("  (V_L %g)", c.v_l));
    line("generated thickness",
         fmt("%.4f mm", L.stack * 1e3) +
             (L.homogeneous
                  ? fmt("  (homogeneous mat, lattice multiplier %g)", L.lattice_multiplier)
                  : fmt("  (first-fit stack, %.2f x t_L)", L.stack / L.t_l)));
    line("chain centres z", fmt("%.4f", L.z_min * 1e3) + fmt(" .. %.4f mm", L.z_max * 1e3));
    line("chain angles: mean, sample std",
         fmt("%.4f deg", L.angle_mean) + fmt(", %.4f deg", L.angle_std));
    line("bending",
         c.bending ? fmt("bundle: EI %.4g N m^2", L.chain.bundle_ei) +
                 fmt(" (%.2f unbonded filaments)", L.chain.filaments) +
                 fmt(", K = EI / l0 = %.4g J", L.bending_k) +
                 fmt(" (l0 %.5f mm), ", L.mean_l0 * 1e3) + std::to_string(L.bending_angles) +
                 " angles (angle_style cosine)"
                   : std::string("none (stretch-only chains)"));
    line("node mass (lumped, scaled)",
         fmt("%.5g kg", L.node_mass) + fmt("  (mass scaling %g)", c.mass_scaling));
    line("critical time step of the bonds", fmt("%.4g s", L.dt_crit));
  }
  const YarnInfo &y = f.yarn;
  s += "\nstitching yarn (atom/bond type " + std::to_string(f.yarn_type()) + ")\n";
  line("material", c.yarn);
  line("chain diameter, packing",
       fmt("%.2f um", y.chain.diameter * 1e6) + fmt(", %.4f", y.chain.packing));
  line("E_c, rho_c, EA",
       fmt("%.5g GPa", y.chain.modulus * 1e-9) + fmt(", %.5g kg/m^3", y.chain.density) +
           fmt(", %.5g N", y.chain.ea));
  line("yarns, nodes, bonds",
       std::to_string(y.yarns) + ", " + std::to_string(y.nodes) + ", " + std::to_string(y.bonds));
  if (c.bending)
    line("bending", "none (its tension sets its shape: bending length sqrt(EI/T) < d_y)");
  line("path length per yarn", fmt("%.4f mm", y.length_per_yarn * 1e3));
  line("yarn areal weight", fmt("%.3f g/m^2", y.areal_weight * 1e3));
  line("loops on / underlaps on",
       std::string(c.loops_bottom ? "bottom / top" : "top / bottom") +
           fmt("  (faces at z = %.4f", y.z_bottom * 1e3) + fmt(" and %.4f mm)", y.z_top * 1e3));
  line("yarn path",
       c.knit ? "warp knit (loops interlocked along the wale)"
              : "running stitch (one hole to the next)");
  line("legs: offset from the hole centre", fmt("%.4f mm", y.leg_offset * 1e3));
  if (c.knit)
    line("loops: half-width, head, z levels",
         fmt("%.4f mm", y.loop_half_width * 1e3) + fmt(", %.4f mm", y.head_offset * 1e3) +
             fmt(", z = %.4f", y.z_loop_out * 1e3) + fmt(" to %.4f mm", y.z_loop * 1e3));
  line("needle diameter, point length",
       fmt("%.4g mm", c.needle_diameter * 1e3) + fmt(", %.4g mm (stage 2)", c.needle_tip * 1e3));
  line("pretension (yarn shrink)", fmt("%.4g (stage 4)", c.pretension));
  line("element length min / max", fmt("%.5f", y.min_l0 * 1e3) + fmt(" / %.5f mm", y.max_l0 * 1e3));
  line("node mass (lumped, scaled)", fmt("%.5g kg", y.node_mass));
  line("critical time step of the bonds", fmt("%.4g s", y.dt_crit));
  // clearance of the generated layers (all segment pairs, periodic images included)

  s += "\nchecks\n";
  // (the layers are laid touching: their clearance is the generator's margin, 1e-6 d_c, shown
  // as a share of d_c rather than as a length of 1e-5 um that reads like an error)
  line("min clearance between fibre chains",
       fmt("%.2g x d_c", f.fibre_gap / f.card.chain_diameter) +
           fmt(" = %.3g nm  (chains laid touching, none overlapping)", f.fibre_gap * 1e9));
  line("min clearance within the yarn", fmt("%.4g um", f.yarn_gap * 1e6));
  line("total atoms, bonds",
       std::to_string(f.fibres.nodes.size() + f.stitch.nodes.size()) + ", " +
           std::to_string(f.fibres.bonds.size() + f.stitch.bonds.size()));
  line("critical time step (all bonds)",
       fmt("%.4g s", dt) + fmt("  (shortest element %.5f mm)", minl0 * 1e3));
  return s;
}

Outputs make_outputs(const Fabric &f, const std::string &prefix)
{
  Outputs o;
  std::string base = prefix;
  const auto slash = prefix.find_last_of('/');
  const std::string shown = slash == std::string::npos ? prefix : prefix.substr(slash + 1);
  o.files.emplace_back(base + ".layers.data", layers_data(f));
  o.files.emplace_back(base + ".yarn.data", yarn_data(f));
  o.files.emplace_back(base + ".needles", needles_text(f));
  o.files.emplace_back(base + ".settings.lmp", settings_text(f, shown, fabric_id(f)));
  o.files.emplace_back(base + ".yarn.lmp", yarn_settings_text(f));
  o.files.emplace_back(base + ".summary", summary_text(f));
  return o;
}

bool generate(const std::string &card_path, const std::string &prefix, std::string &error,
              std::string *summary, const Overrides *ov)
{
  Outputs out;
  try {
    Card card = read_card(card_path);
    if (ov && ov->r_w > 0) card.r_w = ov->r_w;
    if (ov && ov->r_l > 0) card.r_l = ov->r_l;
    if (ov && ov->seed >= 0) card.seed = (std::uint64_t) ov->seed;
    const NCF::MaterialLibrary lib = NCF::MaterialLibrary::read(card.materials_file);
    const Fabric f = build_fabric(card, lib);
    out = make_outputs(f, prefix);
  } catch (std::exception &e) {
    error = e.what();
    return false;
  }
  // everything is in memory: write every file under a temporary name next to its final one,
  // then rename them all; a failure on the way removes what was written, so that a failed run
  // leaves no output (and keeps the files of an earlier run intact until everything is ready)
  for (auto &file : out.files) {
    struct stat st;
    if (stat(file.first.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
      error = file.first +
          ": cannot write the output file: the name is a folder; nothing was "
          "written";
      return false;
    }
  }
  const std::string tmp_suffix = ".tmp-ncf-gen-" + std::to_string((long) getpid());
  std::vector<std::string> temps;
  auto remove_temps = [&]() {
    for (const auto &t : temps) std::remove(t.c_str());
  };
  for (auto &file : out.files) {
    const std::string tmp = file.first + tmp_suffix;
    FILE *fp = std::fopen(tmp.c_str(), "wb");
    if (fp) temps.push_back(tmp);
    const bool ok =
        fp && std::fwrite(file.second.data(), 1, file.second.size(), fp) == file.second.size();
    const bool closed = fp && std::fclose(fp) == 0;
    if (!ok || !closed) {
      const int err = errno;
      remove_temps();
      error = file.first + ": cannot write the output file (" + std::strerror(err) +
          "); nothing was written";
      return false;
    }
  }
  for (std::size_t k = 0; k < out.files.size(); k++) {
    if (std::rename(temps[k].c_str(), out.files[k].first.c_str()) != 0) {
      const int err = errno;
      for (std::size_t q = k; q < temps.size(); q++) std::remove(temps[q].c_str());
      error = out.files[k].first + ": cannot rename " + temps[k] + " to it (" + std::strerror(err) +
          ")" +
          (k ? "; the files before it in the list were already written" : "; nothing was written");
      return false;
    }
  }
  if (summary)
    for (auto &file : out.files)
      if (file.first == prefix + ".summary") *summary = file.second;
  return true;
}

}    // namespace NCFGEN
