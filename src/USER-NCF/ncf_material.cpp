/* ----------------------------------------------------------------------
   USER-NCF: engine-free material library (see ncf_material.h).
------------------------------------------------------------------------- */

#include "ncf_material.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

namespace NCF {

namespace {
  constexpr double PI = 3.14159265358979323846;

  std::vector<std::string> split_words(const std::string &line)
  {
    std::vector<std::string> words;
    std::istringstream in(line.substr(0, line.find('#')));
    std::string w;
    while (in >> w) words.push_back(w);
    return words;
  }

  [[noreturn]] void fail(const std::string &path, int line, const std::string &what)
  {
    throw InputError(path + ":" + std::to_string(line) + ": " + what);
  }

  double positive_number(const std::string &path, int line, const std::string &key,
                         const std::string &text)
  {
    const char *s = text.c_str();
    char *end = nullptr;
    errno = 0;
    const double v = std::strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !std::isfinite(v))
      fail(path, line, "value '" + text + "' of '" + key + "' is not a number");
    if (v <= 0.0) fail(path, line, "value '" + text + "' of '" + key + "' must be > 0");
    return v;
  }
}    // namespace

MaterialLibrary MaterialLibrary::read(const std::string &path)
{
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the materials file");
  std::stringstream buf;
  buf << in.rdbuf();
  return parse(buf.str(), path);
}

MaterialLibrary MaterialLibrary::parse(const std::string &text, const std::string &path)
{
  MaterialLibrary lib;
  std::istringstream in(text);
  std::string raw;
  int lineno = 0;
  bool have_units = false;
  while (std::getline(in, raw)) {
    ++lineno;
    auto words = split_words(raw);
    if (!have_units) {
      // the UNITS: line must come first (comments and blank lines may precede it)
      if (words.empty()) continue;
      if (words[0] != "UNITS:" || words.size() != 2)
        fail(path, lineno, "the first line must be 'UNITS: si'");
      if (words[1] != "si")
        fail(path, lineno, "units '" + words[1] + "' are not supported (only 'si')");
      lib.units_ = words[1];
      have_units = true;
      continue;
    }
    if (words.empty()) continue;
    if (words[0] != "filament" && words[0] != "yarn")
      fail(path, lineno, "unknown record '" + words[0] + "' (expected 'filament' or 'yarn')");
    if (words.size() < 2) fail(path, lineno, "record '" + words[0] + "' has no material name");
    Material m;
    m.kind = (words[0] == "filament") ? MaterialKind::FILAMENT : MaterialKind::YARN;
    m.name = words[1];
    m.line = lineno;
    if (lib.materials_.count(m.name))
      fail(path, lineno,
           "material '" + m.name + "' is defined twice (first on line " +
               std::to_string(lib.materials_[m.name].line) + ")");
    for (std::size_t i = 2; i < words.size(); i += 2) {
      const std::string &key = words[i];
      if (i + 1 >= words.size()) fail(path, lineno, "keyword '" + key + "' has no value");
      const double v = positive_number(path, lineno, key, words[i + 1]);
      if (key == "modulus")
        m.modulus = v;
      else if (key == "density")
        m.density = v;
      else if (key == "filament_diameter")
        m.filament_diameter = v;
      else if (key == "linear_density")
        m.linear_density = v;
      else
        fail(path, lineno, "unknown keyword '" + key + "' for material '" + m.name + "'");
    }
    if (m.modulus == 0.0) fail(path, lineno, "material '" + m.name + "' needs 'modulus'");
    if (m.density == 0.0) fail(path, lineno, "material '" + m.name + "' needs 'density'");
    if (m.kind == MaterialKind::FILAMENT && m.filament_diameter == 0.0)
      fail(path, lineno, "filament material '" + m.name + "' needs 'filament_diameter'");
    if (m.kind == MaterialKind::YARN && m.linear_density == 0.0)
      fail(path, lineno, "yarn material '" + m.name + "' needs 'linear_density'");
    lib.materials_[m.name] = m;
  }
  if (!have_units) fail(path, lineno, "the file has no 'UNITS: si' line");
  return lib;
}

const Material &MaterialLibrary::get(const std::string &name) const
{
  auto it = materials_.find(name);
  if (it == materials_.end()) {
    std::string known;
    for (const auto &kv : materials_) known += (known.empty() ? "" : ", ") + kv.first;
    throw InputError("unknown material '" + name + "' (known: " + known + ")");
  }
  return it->second;
}

static void finish(ChainProperties &c)
{
  c.area = 0.25 * PI * c.diameter * c.diameter;
  c.ea = c.modulus * c.area;
  c.mass_per_length = c.density * c.area;
  c.wave_speed = std::sqrt(c.modulus / c.density);
}

ChainProperties filament_chain(const Material &m, double chain_diameter, double packing)
{
  if (m.kind != MaterialKind::FILAMENT)
    throw InputError("material '" + m.name + "' is a yarn, not a filament material");
  if (!(chain_diameter > 0.0)) throw InputError("chain diameter must be > 0");
  if (!(packing > 0.0 && packing <= 1.0)) throw InputError("packing coefficient must be in (0, 1]");
  ChainProperties c;
  c.diameter = chain_diameter;
  c.packing = packing;
  c.filaments =
      packing * chain_diameter * chain_diameter / (m.filament_diameter * m.filament_diameter);
  c.modulus = packing * m.modulus;
  c.density = packing * m.density;
  const double df2 = m.filament_diameter * m.filament_diameter;
  c.bundle_ei = c.filaments * m.modulus * PI * df2 * df2 / 64.0;
  finish(c);
  return c;
}

ChainProperties yarn_chain(const Material &m, double packing)
{
  if (m.kind != MaterialKind::YARN)
    throw InputError("material '" + m.name + "' is a filament, not a yarn material");
  if (!(packing > 0.0 && packing <= 1.0)) throw InputError("packing coefficient must be in (0, 1]");
  ChainProperties c;
  c.packing = packing;
  const double area = m.linear_density / (m.density * packing);
  c.diameter = std::sqrt(4.0 * area / PI);
  c.filaments = 0.0;
  c.modulus = packing * m.modulus;
  c.density = packing * m.density;
  finish(c);
  return c;
}

}    // namespace NCF
