/* ----------------------------------------------------------------------
   USER-NCF fabric generator: the fabric card and the lapping notation (see ncf_gen.h and
   doc/ncf-gen.md). Every error names the card, the line, the key and the value.
------------------------------------------------------------------------- */

#include "ncf_gen.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

namespace NCFGEN {

namespace {

  [[noreturn]] void fail(const std::string &where, const std::string &what)
  {
    throw InputError(where + ": " + what);
  }

  std::string num(double v)
  {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%g", v);
    return buf;
  }

  std::string at(const std::string &path, int line)
  {
    return path + ":" + std::to_string(line);
  }

  // physical dimension of a key's value and the unit words accepted for it
  enum Dim { NONE, LENGTH, AREAL, ANGLE };

  double unit_factor(Dim dim, const std::string &unit, const std::string &where,
                     const std::string &key)
  {
    static const std::map<std::string, double> length = {
        {"m", 1.0}, {"mm", 1e-3}, {"um", 1e-6}, {"micron", 1e-6}};
    static const std::map<std::string, double> areal = {
        {"kg/m^2", 1.0}, {"g/m^2", 1e-3}, {"gsm", 1e-3}};
    static const std::map<std::string, double> angle = {{"deg", 1.0},
                                                        {"rad", 180.0 / 3.14159265358979323846}};
    const std::map<std::string, double> *table = nullptr;
    std::string known;
    if (dim == LENGTH) table = &length;
    if (dim == AREAL) table = &areal;
    if (dim == ANGLE) table = &angle;
    if (table) {
      auto it = table->find(unit);
      if (it != table->end()) return it->second;
      for (const auto &kv : *table) known += (known.empty() ? "" : ", ") + kv.first;
      fail(where,
           "key '" + key + "': unknown unit '" + unit + "' (expected one of: " + known + ")");
    }
    fail(where, "key '" + key + "' takes no unit, got '" + unit + "'");
  }

  double number(const std::string &text, const std::string &where, const std::string &key)
  {
    const char *s = text.c_str();
    char *end = nullptr;
    errno = 0;
    const double v = std::strtod(s, &end);
    if (end == s || *end != '\0' || (errno != ERANGE && !std::isfinite(v)))
      fail(where, "key '" + key + "': value '" + text + "' is not a number");
    if (errno == ERANGE)
      fail(where, "key '" + key + "': value '" + text + "' is out of the range of a double");
    return v;
  }

  long integer(const std::string &text, const std::string &where, const std::string &key)
  {
    const char *s = text.c_str();
    char *end = nullptr;
    errno = 0;
    const long v = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno == ERANGE)
      fail(where, "key '" + key + "': value '" + text + "' is not an integer");
    return v;
  }

  std::vector<std::string> words_of(const std::string &line)
  {
    std::vector<std::string> words;
    std::istringstream in(line.substr(0, line.find('#')));
    std::string w;
    while (in >> w) words.push_back(w);
    return words;
  }

  std::string dirname_of(const std::string &path)
  {
    const auto slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
  }

  bool file_exists(const std::string &path)
  {
    std::ifstream in(path);
    return (bool) in;
  }

}    // namespace

// ---------------------------------------------------------------------- lapping notation

Lapping parse_lapping(const std::string &text, const std::string &where)
{
  static const std::map<std::string, std::string> named = {
      {"pillar", "1-0/0-1//"},
      {"chain", "1-0/0-1//"},
      {"tricot", "1-0/1-2//"},
      {"tricot-chain", "1-0/0-1/1-2/2-1//"},
  };
  Lapping lap;
  lap.text = text;
  std::string notation = text;
  auto it = named.find(text);
  if (it != named.end()) notation = it->second;

  // "a-b/a-b/.../a-b//": courses separated by '/', the repeat closed by '//' (optional)
  std::string body = notation;
  if (body.size() >= 2 && body.compare(body.size() - 2, 2, "//") == 0)
    body = body.substr(0, body.size() - 2);
  const std::string bad = "key 'pattern': value '" + text +
      "' is neither a known pattern (pillar, chain, tricot, tricot-chain) nor lapping notation "
      "like 1-0/1-2//";
  if (body.empty()) fail(where, bad);
  std::size_t pos = 0;
  while (pos <= body.size()) {
    const auto slash = body.find('/', pos);
    const std::string course =
        body.substr(pos, slash == std::string::npos ? std::string::npos : slash - pos);
    const auto dash = course.find('-');
    if (dash == std::string::npos || dash == 0 || dash + 1 >= course.size()) fail(where, bad);
    const std::string sa = course.substr(0, dash), sb = course.substr(dash + 1);
    for (char c : sa + sb)
      if (c < '0' || c > '9') fail(where, bad);
    // (a lapping number counts needle spaces: more than a few digits is a typing mistake, and
    // would overflow; the card's check compares the span with the gauge)
    for (const std::string &sn : {sa, sb})
      if (sn.size() > 4)
        fail(where,
             "key 'pattern': lapping number '" + sn + "' in '" + text +
                 "' is beyond any gauge (at most 9999 needle spaces)");
    const int a = std::atoi(sa.c_str()), b = std::atoi(sb.c_str());
    if (std::abs(a - b) != 1)
      fail(where,
           "key 'pattern': overlap '" + course + "' in '" + text +
               "' does not lap exactly one needle (|a - b| must be 1; overlaps over several "
               "needles and courses without a loop are not supported)");
    lap.laps.emplace_back(a, b);
    if (slash == std::string::npos) break;
    pos = slash + 1;
  }
  // the needle of each loop: the guide swings between spaces a and b around needle min(a, b)
  int lowest = 1 << 30;
  for (auto &ab : lap.laps) lowest = std::min(lowest, std::min(ab.first, ab.second));
  for (auto &ab : lap.laps) lap.needle.push_back(std::min(ab.first, ab.second) - lowest);
  // repeat of the idealised path: the shortest period of the needle sequence (the direction of
  // the overlap, open or closed loop, is not part of the idealised path)
  const int n = (int) lap.needle.size();
  for (int p = 1; p <= n; p++) {
    if (n % p) continue;
    bool ok = true;
    for (int c = 0; c < n && ok; c++) ok = lap.needle[c] == lap.needle[(c + p) % n];
    if (ok) {
      lap.repeat = p;
      break;
    }
  }
  lap.needle.resize(lap.repeat);
  // widest underlap (from the loop of one course to the next), in needles: underlaps over two or
  // more needles get a sloped path in the generator so that those of neighbouring yarns stack
  lap.max_underlap = 0;
  for (int c = 0; c < lap.repeat; c++)
    lap.max_underlap =
        std::max(lap.max_underlap, std::abs(lap.needle[(c + 1) % lap.repeat] - lap.needle[c]));
  return lap;
}

// ---------------------------------------------------------------------- quality presets

// Resolution: standard is the paper's compromise (Table 3, section 4.5: 69 um chains, 0.2 mm
// fibre mesh, 0.1 mm yarn mesh); draft and fine are one step of sqrt(2) in the chain diameter and
// of 2 in the meshes to either side. Run parameters: standard is what the stage scripts were
// tuned with (half the critical step, 1e4 Pa, 2000 steps); draft takes a larger part of the
// critical step, a faster plate and a stronger damping, fine a smaller part of the critical step
// and a slower plate. Their accuracy and cost: doc/accuracy_cost.md.
const std::vector<QualityPreset> &quality_presets()
{
  static const std::vector<QualityPreset> presets = {
      {"draft", 98e-6, 0.4e-3, 0.2e-3, 0.7, 4e4, 1000.0},
      {"standard", 69e-6, 0.2e-3, 0.1e-3, 0.5, 1e4, 2000.0},
      {"fine", 49e-6, 0.1e-3, 0.05e-3, 0.4, 5e3, 2000.0},
  };
  return presets;
}

const QualityPreset *find_quality(const std::string &name)
{
  for (const auto &q : quality_presets())
    if (name == q.name) return &q;
  return nullptr;
}

// ---------------------------------------------------------------------- the card

Card read_card(const std::string &path)
{
  struct stat st;
  if (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    throw InputError(path + ": is a folder, not a fabric card");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the fabric card");
  std::stringstream buf;
  buf << in.rdbuf();
  return parse_card(buf.str(), path);
}

Card parse_card(const std::string &text, const std::string &path)
{
  Card card;
  card.path = path;
  // a UTF-8 byte-order mark (some editors write one) is not part of the first key
  const std::string bom = "\xEF\xBB\xBF";
  std::istringstream in(text.compare(0, bom.size(), bom) == 0 ? text.substr(bom.size()) : text);
  std::string raw;
  int lineno = 0;
  std::map<std::string, int> seen;    // global keys given, with their line
  bool have_pattern = false, have_seed = false;
  std::string materials_given;

  // keys of a layer block and of the whole card
  static const std::map<std::string, Dim> layer_keys = {
      {"areal_weight", AREAL}, {"material", NONE}, {"sigma", ANGLE}};
  static const std::map<std::string, Dim> global_keys = {{"name", NONE},
                                                         {"materials", NONE},
                                                         {"seed", NONE},
                                                         {"rve", NONE},
                                                         {"chain_diameter", LENGTH},
                                                         {"packing", NONE},
                                                         {"fibre_mesh", LENGTH},
                                                         {"yarn_mesh", LENGTH},
                                                         {"V_L", NONE},
                                                         {"mass_scaling", NONE},
                                                         {"sampling", NONE},
                                                         {"pattern", NONE},
                                                         {"gauge", NONE},
                                                         {"stitch_length", LENGTH},
                                                         {"yarn", NONE},
                                                         {"loops", NONE},
                                                         {"leg_gap", NONE},
                                                         {"layer", ANGLE},
                                                         {"needle_diameter", LENGTH},
                                                         {"needle_tip", LENGTH},
                                                         {"pretension", NONE},
                                                         {"quality", NONE},
                                                         {"yarn_packing", NONE},
                                                         {"yarn_path", NONE},
                                                         {"bending", NONE}};

  while (std::getline(in, raw)) {
    ++lineno;
    const auto w = words_of(raw);
    if (w.empty()) continue;
    const std::string where = at(path, lineno);
    const std::string &key = w[0];
    const bool is_layer_key = layer_keys.count(key) > 0;
    if (!is_layer_key && !global_keys.count(key)) {
      std::string known;
      for (const auto &kv : global_keys) known += (known.empty() ? "" : " ") + kv.first;
      for (const auto &kv : layer_keys) known += " " + kv.first;
      fail(where, "unknown key '" + key + "' (known keys: " + known + ")");
    }
    if (w.size() < 2) fail(where, "key '" + key + "' has no value");
    const Dim dim = is_layer_key ? layer_keys.at(key) : global_keys.at(key);
    const std::string &val = w[1];

    // value with an optional unit word; 'rve' takes two integers
    double scale = 1.0;
    if (key == "rve") {
      if (w.size() != 3)
        fail(where,
             "key 'rve' needs two integers r_W r_L, got " + std::to_string(w.size() - 1) +
                 " value(s)");
    } else if (w.size() > 3) {
      fail(where, "key '" + key + "': unexpected '" + w[3] + "' after the value");
    } else if (w.size() == 3) {
      scale = unit_factor(dim, w[2], where, key);
    } else if (dim == LENGTH) {
      // a length without its unit is a factor 1 000 or 10^6 away from what was meant as often as
      // not (0.6 for 0.6 mm): refused rather than read in metres
      fail(where,
           "key '" + key + "': value '" + val + "' needs a unit (one of: m, micron, mm, um)");
    }
    auto positive = [&](const std::string &k) {
      const double v = number(val, where, k) * scale;
      if (!(v > 0.0)) fail(where, "key '" + k + "': value '" + val + "' must be > 0");
      return v;
    };

    if (!is_layer_key && key != "layer") {
      if (seen.count(key))
        fail(where,
             "key '" + key + "' given twice (first on line " + std::to_string(seen[key]) + ")");
      seen[key] = lineno;
    }

    if (key == "layer") {
      LayerSpec L;
      L.line = lineno;
      L.angle = number(val, where, key) * scale;
      if (!(std::fabs(L.angle) <= 360.0))
        fail(where,
             "key 'layer': angle '" + val + (w.size() == 3 ? " " + w[2] : std::string()) +
                 "' is beyond +-360 deg");
      card.layers.push_back(L);
    } else if (is_layer_key) {
      if (card.layers.empty())
        fail(where, "key '" + key + "' outside a layer block (start one with 'layer ANGLE')");
      LayerSpec &L = card.layers.back();
      if (key == "areal_weight") {
        L.areal_weight = positive(key);
      } else if (key == "material") {
        L.material = val;
        L.material_line = lineno;
      } else if (key == "sigma") {
        const double v = number(val, where, key) * scale;
        if (v < 0.0) fail(where, "key 'sigma': value '" + val + "' must be >= 0");
        if (v >= 20.0)
          fail(where, "key 'sigma': value '" + val + "' is too large (must be < 20 deg)");
        L.sigma = v;
      }
    } else if (key == "name") {
      for (char c : val)
        if (!(std::isalnum((unsigned char) c) || c == '_' || c == '-' || c == '.'))
          fail(where, "key 'name': value '" + val + "' may hold only letters, digits, _ - .");
      card.name = val;
    } else if (key == "materials") {
      materials_given = val;
      card.materials_line = lineno;
    } else if (key == "seed") {
      const long v = integer(val, where, key);
      if (v < 0) fail(where, "key 'seed': value '" + val + "' must be >= 0");
      card.seed = (std::uint64_t) v;
      have_seed = true;
    } else if (key == "rve") {
      const long a = integer(w[1], where, key), b = integer(w[2], where, key);
      if (a < 1 || b < 1 || a > 1000 || b > 1000)
        fail(where, "key 'rve': values '" + w[1] + " " + w[2] + "' must be integers in 1..1000");
      card.r_w = (int) a;
      card.r_l = (int) b;
    } else if (key == "chain_diameter") {
      card.chain_diameter = positive(key);
    } else if (key == "packing") {
      card.packing = positive(key);
      if (card.packing > 1.0) fail(where, "key 'packing': value '" + val + "' must be <= 1");
    } else if (key == "fibre_mesh") {
      card.fibre_mesh = positive(key);
    } else if (key == "yarn_mesh") {
      card.yarn_mesh = positive(key);
    } else if (key == "V_L") {
      card.v_l = positive(key);
      if (card.v_l >= 1.0) fail(where, "key 'V_L': value '" + val + "' must be < 1");
    } else if (key == "mass_scaling") {
      card.mass_scaling = positive(key);
    } else if (key == "sampling") {
      if (val == "stratified")
        card.stratified = true;
      else if (val == "random")
        card.stratified = false;
      else
        fail(where, "key 'sampling': value '" + val + "' must be 'stratified' or 'random'");
    } else if (key == "pattern") {
      card.pattern = parse_lapping(val, where);
      card.pattern_line = lineno;
      have_pattern = true;
    } else if (key == "gauge") {
      card.gauge = positive(key);
    } else if (key == "stitch_length") {
      card.stitch_length = positive(key);
    } else if (key == "yarn") {
      card.yarn = val;
      card.yarn_line = lineno;
    } else if (key == "loops") {
      if (val == "bottom")
        card.loops_bottom = true;
      else if (val == "top")
        card.loops_bottom = false;
      else
        fail(where, "key 'loops': value '" + val + "' must be 'bottom' or 'top'");
    } else if (key == "yarn_path") {
      if (val == "knit")
        card.knit = true;
      else if (val == "running")
        card.knit = false;
      else
        fail(where, "key 'yarn_path': value '" + val + "' must be 'knit' or 'running'");
    } else if (key == "bending") {
      if (val == "none")
        card.bending = false;
      else if (val == "bundle")
        card.bending = true;
      else
        fail(where,
             "key 'bending': value '" + val +
                 "' must be 'none' (stretch-only chains) or 'bundle' (the bending rigidity of "
                 "the chain's unbonded filaments)");
    } else if (key == "yarn_packing") {
      card.yarn_packing = positive(key);
      if (card.yarn_packing > 1.0)
        fail(where, "key 'yarn_packing': value '" + val + "' must be <= 1");
    } else if (key == "leg_gap") {
      card.leg_gap = positive(key);
      if (card.leg_gap < 1.0)
        fail(where, "key 'leg_gap': value '" + val + "' must be >= 1 (legs would overlap)");
    } else if (key == "needle_diameter") {
      card.needle_diameter = positive(key);
    } else if (key == "needle_tip") {
      card.needle_tip = positive(key);
    } else if (key == "quality") {
      if (!find_quality(val)) {
        std::string known;
        for (const auto &q : quality_presets())
          known += std::string(known.empty() ? "" : ", ") + q.name;
        fail(where,
             "key 'quality': value '" + val +
                 "' is not a quality preset (expected one of: " + known + ")");
      }
      card.quality = val;
    } else if (key == "pretension") {
      card.pretension = number(val, where, key) * scale;
      if (!(card.pretension >= 0.0 && card.pretension < 1.0))
        fail(where, "key 'pretension': value '" + val + "' must be in [0, 1)");
    }
  }

  // the quality preset: its resolution where the card gives none, and the run parameters
  const QualityPreset &q = *find_quality(card.quality);
  if (!seen.count("chain_diameter")) card.chain_diameter = q.chain_diameter;
  if (!seen.count("fibre_mesh")) card.fibre_mesh = q.fibre_mesh;
  if (!seen.count("yarn_mesh")) card.yarn_mesh = q.yarn_mesh;
  card.dtfrac = q.dtfrac;
  card.pdyn = q.pdyn;
  card.tau = q.tau;

  // completeness
  if (card.layers.empty()) fail(at(path, lineno), "the card has no 'layer' block");
  for (std::size_t i = 0; i < card.layers.size(); i++) {
    const LayerSpec &L = card.layers[i];
    const std::string where = at(path, L.line);
    if (L.areal_weight < 0.0)
      fail(where,
           "layer " + std::to_string(i + 1) + " (key 'layer' " + std::to_string(L.angle) +
               " deg) has no 'areal_weight'");
    if (L.material.empty())
      fail(where,
           "layer " + std::to_string(i + 1) + " (key 'layer' " + std::to_string(L.angle) +
               " deg) has no 'material'");
  }
  if (!have_pattern) fail(at(path, lineno), "the card has no 'pattern' (stitching pattern)");
  if (card.stitch_length < 0.0) fail(at(path, lineno), "the card has no 'stitch_length'");
  if (card.yarn.empty()) fail(at(path, lineno), "the card has no 'yarn' (stitching yarn material)");
  (void) have_seed;

  // plausibility of the sizes that a wrong unit or a typing mistake puts far off: the needle
  // must fit between its neighbours (the needle pitch 25.4 mm / gauge), and the lapping must
  // not span more needles than one inch of the machine holds (the gauge)
  const double pitch = 25.4e-3 / card.gauge;
  if (card.needle_diameter >= pitch) {
    const int line = seen.count("needle_diameter") ? seen["needle_diameter"] : lineno;
    fail(at(path, line),
         "key 'needle_diameter': " + num(card.needle_diameter * 1e3) +
             " mm is not narrower than the needle pitch " + num(pitch * 1e3) +
             " mm (25.4 mm / gauge " + num(card.gauge) + ")");
  }
  {
    int lo = 1 << 30, hi = -1;
    for (auto &ab : card.pattern.laps) {
      lo = std::min({lo, ab.first, ab.second});
      hi = std::max({hi, ab.first, ab.second});
    }
    if (hi >= 0 && hi - lo >= card.gauge)
      fail(at(path, card.pattern_line),
           "key 'pattern': the lapping numbers of '" + card.pattern.text + "' span " +
               std::to_string(hi - lo) + " needles, beyond the gauge (" + num(card.gauge) +
               " needles per inch)");
  }

  // the materials file: relative to the card's folder, else to $NCF_ROOT, else the default
  std::string m = materials_given.empty() ? "potentials/ncf.materials" : materials_given;
  if (!m.empty() && m[0] != '/') {
    const std::string local = dirname_of(path) + "/" + m;
    const char *root = std::getenv("NCF_ROOT");
    if (file_exists(local))
      m = local;
    else if (root && file_exists(std::string(root) + "/" + m))
      m = std::string(root) + "/" + m;
    else
      m = local;
  }
  if (!file_exists(m))
    fail(at(path, card.materials_line ? card.materials_line : lineno),
         "key 'materials': value '" +
             (materials_given.empty() ? std::string("(default)") : materials_given) +
             "': cannot open '" + m + "'");
  card.materials_file = m;
  card.key_line = seen;
  return card;
}

}    // namespace NCFGEN
