/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: checked reading of style arguments (LAMMPS-side, included by styles only).

   Each reader takes `what`, the style as the user wrote it ("fix ncf/plate",
   "bond_coeff ncf/chain", ...), the keyword and the text of the value, and stops with
   error->all naming all three when the value is not what the keyword needs. The numbers go
   through utils::numeric/inumeric after the text has been checked, so that no message is the
   generic one of LAMMPS ("Expected floating point parameter ...") without the keyword.
------------------------------------------------------------------------- */

#ifndef LAMMPS_NCF_ARGS_H
#define LAMMPS_NCF_ARGS_H

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "lammps.h"
#include "pair.h"
#include "utils.h"

#include "ncf_contact_model.h"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace NCF_LMP {

// a finite number (is_double rejects words such as nan and inf; 1e999 reads as inf and is refused)
inline double number(LAMMPS_NS::LAMMPS *lmp, const std::string &what, const std::string &key,
                     const char *text)
{
  if (!LAMMPS_NS::utils::is_double(text))
    lmp->error->all(FLERR, "{}: value '{}' of '{}' is not a number", what, text, key);
  // (out of the range of a double: refused here, before utils::numeric gives its own message)
  if (!std::isfinite(std::strtod(text, nullptr)))
    lmp->error->all(FLERR, "{}: value '{}' of '{}' is not a finite number", what, text, key);
  return LAMMPS_NS::utils::numeric(FLERR, text, false, lmp);
}

// an integer in [lo, hi]
inline long long integer(LAMMPS_NS::LAMMPS *lmp, const std::string &what, const std::string &key,
                         const char *text, long long lo, long long hi)
{
  if (!LAMMPS_NS::utils::is_integer(text))
    lmp->error->all(FLERR, "{}: value '{}' of '{}' is not an integer", what, text, key);
  // (out of the range of a 64-bit integer: refused here, before utils::bnumeric's own message)
  errno = 0;
  const long long big = std::strtoll(text, nullptr, 10);
  if (errno == ERANGE || big < lo || big > hi)
    lmp->error->all(FLERR, "{}: value '{}' of '{}' must be an integer in [{}, {}]", what, text, key,
                    lo, hi);
  const long long v = LAMMPS_NS::utils::bnumeric(FLERR, text, false, lmp);
  if (v < lo || v > hi)
    lmp->error->all(FLERR, "{}: value '{}' of '{}' must be an integer in [{}, {}]", what, text, key,
                    lo, hi);
  return v;
}

// a chain's contact diameter smaller than the box's smallest edge: a diameter of the box's size
// (a length in mm given as metres) makes every node touch everything, and the ghost shell of the
// contacts spans thousands of periodic images (memory and time without end)
inline void diameter_in_box(LAMMPS_NS::LAMMPS *lmp, const std::string &what, const std::string &key,
                            const char *text, double d)
{
  const auto *dom = lmp->domain;
  if (!dom->box_exist) return;
  int dim = 0;
  for (int k = 1; k < 3; k++)
    if (dom->prd[k] < dom->prd[dim]) dim = k;
  if (d >= dom->prd[dim])
    lmp->error->all(FLERR,
                    "{}: {} {} is not smaller than the box's smallest edge {} (in {}): lengths are "
                    "in metres (69e-6 for a 69 um chain)",
                    what, key, text, dom->prd[dim], "xyz"[dim]);
}

// yes/no, on/off, true/false, 1/0
inline bool logical(LAMMPS_NS::LAMMPS *lmp, const std::string &what, const std::string &key,
                    const char *text)
{
  const std::string v = text;
  if (v != "yes" && v != "on" && v != "true" && v != "1" && v != "no" && v != "off" &&
      v != "false" && v != "0")
    lmp->error->all(FLERR, "{}: value '{}' of '{}' is not one of yes, no", what, text, key);
  return LAMMPS_NS::utils::logical(FLERR, text, false, lmp) != 0;
}

// a type or a range of types within 1..n: N, *, N*, *M, N*M (as utils::bounds, but the message
// names the style and the keyword)
inline void types(LAMMPS_NS::LAMMPS *lmp, const std::string &what, const std::string &key,
                  const char *text, int n, int &lo, int &hi)
{
  const std::string s = text;
  const auto star = s.find('*');
  auto part = [&](const std::string &p, int dflt, bool &ok) {
    if (p.empty()) return dflt;
    if (!LAMMPS_NS::utils::is_integer(p)) {
      ok = false;
      return 0;
    }
    errno = 0;
    if (std::strtoll(p.c_str(), nullptr, 10) < INT_MIN || errno == ERANGE ||
        std::strtoll(p.c_str(), nullptr, 10) > INT_MAX) {
      ok = false;
      return 0;
    }
    return (int) LAMMPS_NS::utils::bnumeric(FLERR, p, false, lmp);
  };
  bool ok = !s.empty();
  if (star == std::string::npos) {
    lo = hi = part(s, 0, ok);
    ok = ok && !s.empty();
  } else {
    if (s.find('*', star + 1) != std::string::npos) ok = false;
    lo = part(s.substr(0, star), 1, ok);
    hi = part(s.substr(star + 1), n, ok);
  }
  if (!ok || lo > hi)
    lmp->error->all(FLERR, "{}: {} '{}' is not a type or a range of types within 1-{}", what, key,
                    text, n);
  // (in the words of utils::bounds)
  if (lo < 1 || hi > n)
    lmp->error->all(FLERR, "{}: {} '{}': Numeric index {} is out of bounds (1-{})", what, key, text,
                    lo < 1 ? lo : hi, n);
}

// Each keyword of a style once: a keyword given twice would silently replace the first value, so
// it is an error naming the style and the keyword; `repeatable` lists the keywords that take one
// entry per use (a type range, a needle, a layer). Call it with every keyword as it is read.
class KeywordsOnce {
 public:
  KeywordsOnce(LAMMPS_NS::LAMMPS *lmp, const std::string &what,
               std::vector<std::string> repeatable = {}) :
      lmp(lmp),
      what(what), repeatable(std::move(repeatable))
  {
  }
  // `group`: the name under which the keyword counts (alternatives of one setting share it)
  void operator()(const std::string &key, const std::string &group = "")
  {
    for (const auto &r : repeatable)
      if (r == key) return;
    const std::string g = group.empty() ? key : group;
    for (const auto &s : seen)
      if (s.second == g)
        lmp->error->all(FLERR, "{}: keyword '{}' given twice{}", what, key,
                        s.first == key ? std::string()
                                       : " (as '" + s.first + "' and '" + key + "': one of them)");
    seen.emplace_back(key, g);
  }

 private:
  LAMMPS_NS::LAMMPS *lmp;
  std::string what;
  std::vector<std::string> repeatable;
  std::vector<std::pair<std::string, std::string>> seen;
};

// The look-ahead check of every style: keyword arg[iarg] needs n values after it. `values` names
// them when there is more than one ("an atom type range and a value").
inline void need_values(LAMMPS_NS::LAMMPS *lmp, const std::string &what, const std::string &key,
                        int iarg, int narg, int n, const char *values = nullptr)
{
  if (iarg + n < narg) return;
  if (values) lmp->error->all(FLERR, "{}: keyword '{}' needs {}", what, key, values);
  if (n > 1) lmp->error->all(FLERR, "{}: keyword '{}' needs {} values", what, key, n);
  lmp->error->all(FLERR, "{}: keyword '{}' needs a value", what, key);
}

// The contact keywords of every style (kn, kt, mu, damp; NCF::ContactCoeffs gives their meaning
// and unit), read in one way with one message form. `allowed` lists the keys a style takes (the
// needles are frictionless: kn only); each keyword once (`once` is shared with the style's other
// keywords).
class ContactReader {
 public:
  ContactReader(LAMMPS_NS::LAMMPS *lmp, const std::string &what,
                std::vector<NCF::ContactKey> allowed = {NCF::ContactKey::KN, NCF::ContactKey::KT,
                                                        NCF::ContactKey::MU, NCF::ContactKey::DAMP},
                std::vector<std::string> repeatable = {}) :
      lmp(lmp),
      what(what), allowed(std::move(allowed)), once(lmp, what, std::move(repeatable))
  {
  }
  static std::vector<NCF::ContactKey> all_keys()
  {
    return {NCF::ContactKey::KN, NCF::ContactKey::KT, NCF::ContactKey::MU, NCF::ContactKey::DAMP};
  }
  // reads the keyword at arg[iarg] into c and advances iarg past its value when it is a contact
  // keyword; false (iarg unchanged) when it is not one
  bool read(int &iarg, int narg, char **arg, NCF::ContactCoeffs &c)
  {
    const std::string key = arg[iarg];
    const NCF::ContactKey k = NCF::contact_key(key);
    if (k == NCF::ContactKey::NONE) return false;
    bool ok = false;
    for (auto a : allowed) ok |= a == k;
    if (!ok) {
      std::string list;
      for (auto a : allowed)
        list += std::string(list.empty() ? "" : ", ") + NCF::contact_key_name(a);
      lmp->error->all(FLERR, "{}: contact keyword '{}' is not one of this style's ({})", what, key,
                      list);
    }
    once(key);
    need_values(lmp, what, key, iarg, narg, 1);
    const double v = number(lmp, what, key, arg[iarg + 1]);
    const std::string bad = NCF::contact_value_error(k, v, arg[iarg + 1]);
    if (!bad.empty()) lmp->error->all(FLERR, "{}: {}", what, bad);
    NCF::set_contact_value(c, k, v);
    got.push_back(k);
    names.push_back(key);
    iarg += 2;
    return true;
  }
  bool has(NCF::ContactKey k) const
  {
    for (auto g : got)
      if (g == k) return true;
    return false;
  }
  // the contact keywords read, in order
  const std::vector<std::string> &keys() const { return names; }

 private:
  LAMMPS_NS::LAMMPS *lmp;
  std::string what;
  std::vector<NCF::ContactKey> allowed;

 public:
  KeywordsOnce once;    // every keyword of the style once (call it for the others too)

 private:
  std::vector<NCF::ContactKey> got;
  std::vector<std::string> names;
};

// `KEY TYPES D` at arg[iarg]: the chain diameter D [m] of the atom types TYPES (a type or a
// range); advances iarg past it
inline void read_type_diameters(LAMMPS_NS::LAMMPS *lmp, const std::string &what,
                                const std::string &key, int &iarg, int narg, char **arg,
                                std::vector<double> &diameter)
{
  need_values(lmp, what, key, iarg, narg, 2, "an atom type range and a diameter");
  int lo, hi;
  types(lmp, what, key, arg[iarg + 1], lmp->atom->ntypes, lo, hi);
  const double d = number(lmp, what, key, arg[iarg + 2]);
  if (!(d > 0.0)) lmp->error->all(FLERR, "{}: {} {} must be > 0", what, key, arg[iarg + 2]);
  diameter_in_box(lmp, what, key, arg[iarg + 2], d);
  for (int t = lo; t <= hi; t++) diameter[t] = d;
  iarg += 3;
}

// A chain's diameter is given once, in pair_coeff ncf/contact: a fix that did not get its own
// (`given` false) takes the pair's; one that did must agree with the pair where both have one.
// `only` (if given) restricts what is taken to the types it flags. Afterwards at least one type
// has a diameter.
inline void pair_diameters(LAMMPS_NS::LAMMPS *lmp, const std::string &what, const std::string &key,
                           bool given, std::vector<double> &diameter,
                           const std::vector<int> *only = nullptr)
{
  auto *pair = lmp->force->pair_match("ncf/contact", 1, 0);
  const double *pd = nullptr;
  if (pair) {
    int dim = 0;
    pd = static_cast<const double *>(pair->extract("diameter", dim));
  }
  const int n = (int) diameter.size() - 1;
  if (pd)
    for (int t = 1; t <= n; t++) {
      if (!(pd[t] > 0.0) || (only && !(*only)[t])) continue;
      if (!given)
        diameter[t] = pd[t];
      else if (diameter[t] > 0.0 && diameter[t] != pd[t])
        lmp->error->all(FLERR,
                        "{}: {} {} of atom type {} differs from pair ncf/contact's diameter {}: a "
                        "chain's diameter is given once (leave '{}' out to use the pair's)",
                        what, key, diameter[t], t, pd[t], key);
    }
  bool any = false;
  for (int t = 1; t <= n; t++) any |= diameter[t] > 0.0;
  if (!any)
    lmp->error->all(FLERR,
                    "{}: no chain diameter: define pair_style ncf/contact with its diameters "
                    "before this fix, or give '{} TYPES D'",
                    what, key);
}

// Needle positions in the plane, as the generator's PREFIX.needles lists them: one "x y" per line
// (lines up to 1023 characters), '#' comments. Every rank reads the small file.
inline void read_needles(LAMMPS_NS::LAMMPS *lmp, const std::string &what, const std::string &file,
                         std::vector<double> &x, std::vector<double> &y)
{
  FILE *fp = std::fopen(file.c_str(), "r");
  if (!fp) lmp->error->all(FLERR, "{}: cannot open needle file {}", what, file);
  char buf[1024];
  int lineno = 0;
  while (std::fgets(buf, sizeof(buf), fp)) {
    ++lineno;
    std::string line = LAMMPS_NS::utils::trim_comment(buf);
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
    const auto words = LAMMPS_NS::utils::split_words(line);
    if (words.empty()) continue;
    if (words.size() != 2 || !LAMMPS_NS::utils::is_double(words[0]) ||
        !LAMMPS_NS::utils::is_double(words[1])) {
      std::fclose(fp);
      lmp->error->all(FLERR, "{}: {}:{}: expected 'x y', got '{}'", what, file, lineno, line);
    }
    const double px = std::strtod(words[0].c_str(), nullptr);
    const double py = std::strtod(words[1].c_str(), nullptr);
    if (!std::isfinite(px) || !std::isfinite(py)) {
      std::fclose(fp);
      lmp->error->all(FLERR, "{}: {}:{}: needle position '{}' is not finite", what, file, lineno,
                      line);
    }
    x.push_back(px);
    y.push_back(py);
  }
  std::fclose(fp);
}

// Needles outside the box: in a periodic direction a needle acts through its periodic image, so
// it is wrapped into the box (inside the box nothing changes); in a direction that is not
// periodic, or farther than 100 box lengths (a typing mistake), it is an error.
inline void wrap_needles(LAMMPS_NS::LAMMPS *lmp, const std::string &what, std::vector<double> &x,
                         std::vector<double> &y)
{
  const auto *domain = lmp->domain;
  for (std::size_t k = 0; k < x.size(); k++) {
    double *xy[2] = {&x[k], &y[k]};
    for (int d = 0; d < 2; d++) {
      double &v = *xy[d];
      const double lo = domain->boxlo[d], hi = domain->boxhi[d], prd = hi - lo;
      if (v >= lo && v <= hi) continue;
      if (!domain->periodicity[d] || !(v > lo - 100.0 * prd && v < hi + 100.0 * prd))
        lmp->error->all(FLERR, "{}: needle {} at ({}, {}) lies outside the box in {} ([{}, {}]{})",
                        what, k + 1, x[k], y[k], d ? "y" : "x", lo, hi,
                        domain->periodicity[d] ? ", periodic, by more than 100 box lengths" : "");
      v -= prd * std::floor((v - lo) / prd);
    }
  }
}

}    // namespace NCF_LMP

#endif
