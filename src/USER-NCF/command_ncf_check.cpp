/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   ncf/check (see command_ncf_check.h, doc/ncf_check.md)
------------------------------------------------------------------------- */

#include "command_ncf_check.h"

#include "domain.h"
#include "error.h"
#include "group.h"
#include "input.h"
#include "utils.h"
#include "variable.h"

#include <sys/stat.h>
#include <unistd.h>

#include "lammps_ncf_args.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

using namespace LAMMPS_NS;

namespace {

// the words from `from` on, joined by blanks
std::string join(const std::vector<std::string> &w, std::size_t from)
{
  std::string s;
  for (std::size_t i = from; i < w.size(); i++) s += (s.empty() ? "" : " ") + w[i];
  return s;
}

// a finite number written as one (is_double refuses nan, inf and words; 1e999 reads as inf)
bool finite_number(const std::string &text, double &v)
{
  if (!utils::is_double(text)) return false;
  v = std::strtod(text.c_str(), nullptr);
  return std::isfinite(v);
}

bool valid_name(const std::string &s)
{
  if (s.empty()) return false;
  for (char c : s)
    if (!(std::isalnum((unsigned char) c) || c == '_')) return false;
  return true;
}

}    // namespace

/* ----------------------------------------------------------------------
   ncf/check SCRIPT var NAME VALUE number|integer [OP BOUND ...] about TEXT ...
   ncf/check SCRIPT var NAME VALUE word W1 W2 ... about TEXT ...
   ncf/check SCRIPT required NAME about TEXT ...
   ncf/check SCRIPT file PATH about TEXT ...
   ncf/check SCRIPT folder NAME PATH about TEXT ...
   ncf/check SCRIPT settings FILE VAR1 VAR2 ...
   ncf/check SCRIPT restart FILE STAGE SETTINGS
   ncf/check SCRIPT needles FILE DIAMETER
   ncf/check SCRIPT mark STAGE FABRIC
   OP is one of > >= < <=
------------------------------------------------------------------------- */

void NCFCheck::command(int narg, char **arg)
{
  if (narg < 2)
    error->all(FLERR,
               "ncf/check: expected 'ncf/check SCRIPT var|required|file|settings|restart|mark "
               "...', got {} argument(s)",
               narg);
  script = arg[0];
  const std::string kind = arg[1];
  std::vector<std::string> w;
  for (int i = 2; i < narg; i++) w.emplace_back(arg[i]);
  if (kind == "var")
    check_var(w);
  else if (kind == "required")
    check_required(w);
  else if (kind == "file")
    check_file(w);
  else if (kind == "folder")
    check_folder(w);
  else if (kind == "settings")
    check_settings(w);
  else if (kind == "restart")
    check_restart(w);
  else if (kind == "needles")
    check_needles(w);
  else if (kind == "mark")
    mark(w);
  else
    error->all(FLERR,
               "ncf/check: {}: unknown check '{}' (expected var, required, file, folder, "
               "settings, restart, needles or mark)",
               script, kind);
}

/* ---------------------------------------------------------------------- */

void NCFCheck::check_var(const std::vector<std::string> &w)
{
  std::size_t about = 0;
  while (about < w.size() && w[about] != "about") about++;
  if (w.size() < 3 || about < 3 || about + 1 >= w.size())
    error->all(FLERR,
               "ncf/check: {}: expected 'var NAME VALUE number|integer|word ... about TEXT', got "
               "'{}'",
               script, join(w, 0));
  const std::string &name = w[0], &value = w[1], &type = w[2];
  const std::string what = join(w, about + 1);
  auto fail = [&](const std::string &must) {
    error->all(FLERR, "{}: variable {} = {}: {} ({})", script, name, value, must, what);
  };

  if (type == "word") {
    if (about == 3) error->all(FLERR, "ncf/check: {}: 'word' needs the words allowed", script);
    std::vector<std::string> allowed(w.begin() + 3, w.begin() + about);
    for (const auto &a : allowed)
      if (value == a) return;
    std::string list;
    for (const auto &a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail("must be one of " + list);
    return;
  }
  if (type != "number" && type != "integer")
    error->all(FLERR, "ncf/check: {}: unknown type '{}' (expected number, integer or word)", script,
               type);

  double v = 0.0;
  if (type == "integer") {
    if (!utils::is_integer(value)) fail("must be an integer");
    errno = 0;
    const long long big = std::strtoll(value.c_str(), nullptr, 10);
    if (errno == ERANGE) fail("must be an integer within the range of a 64-bit integer");
    v = (double) big;
  } else {
    if (!utils::is_double(value) && !utils::is_integer(value)) fail("must be a number");
    v = std::strtod(value.c_str(), nullptr);
    if (!std::isfinite(v)) fail("must be a finite number");
  }

  if ((about - 3) % 2 != 0)
    error->all(FLERR, "ncf/check: {}: expected pairs 'OP BOUND' after the type, got '{}'", script,
               join(std::vector<std::string>(w.begin() + 3, w.begin() + about), 0));
  for (std::size_t k = 3; k + 1 < about; k += 2) {
    const std::string &op = w[k], &btext = w[k + 1];
    double b = 0.0;
    if (!finite_number(btext, b))
      error->all(FLERR, "ncf/check: {}: bound '{}' of variable {} is not a finite number", script,
                 btext, name);
    bool ok = false;
    if (op == ">")
      ok = v > b;
    else if (op == ">=")
      ok = v >= b;
    else if (op == "<")
      ok = v < b;
    else if (op == "<=")
      ok = v <= b;
    else
      error->all(FLERR, "ncf/check: {}: unknown comparison '{}' (expected >, >=, <, <=)", script,
                 op);
    if (!ok) fail("must be " + op + " " + btext);
  }
}

/* ---------------------------------------------------------------------- */

void NCFCheck::check_required(const std::vector<std::string> &w)
{
  if (w.size() < 3 || w[1] != "about")
    error->all(FLERR, "ncf/check: {}: expected 'required NAME about TEXT', got '{}'", script,
               join(w, 0));
  if (input->variable->find(w[0].c_str()) < 0)
    error->all(FLERR, "{}: variable {} is not set: give it with -var {} VALUE ({})", script, w[0],
               w[0], join(w, 2));
}

/* ---------------------------------------------------------------------- */

void NCFCheck::check_file(const std::vector<std::string> &w)
{
  if (w.size() < 3 || w[1] != "about")
    error->all(FLERR, "ncf/check: {}: expected 'file PATH about TEXT', got '{}'", script,
               join(w, 0));
  FILE *fp = std::fopen(w[0].c_str(), "r");
  if (!fp)
    error->all(FLERR, "{}: cannot read file {}: {} ({})", script, w[0], utils::getsyserror(),
               join(w, 2));
  std::fclose(fp);
}

/* ----------------------------------------------------------------------
   an output folder given by the variable NAME: it must exist and be writable
------------------------------------------------------------------------- */

void NCFCheck::check_folder(const std::vector<std::string> &w)
{
  if (w.size() < 4 || w[2] != "about")
    error->all(FLERR, "ncf/check: {}: expected 'folder NAME PATH about TEXT', got '{}'", script,
               join(w, 0));
  struct stat st;
  if (stat(w[1].c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    error->all(FLERR, "{}: variable {} = {}: not an existing folder ({})", script, w[0], w[1],
               join(w, 3));
  if (access(w[1].c_str(), W_OK) != 0)
    error->all(FLERR, "{}: variable {} = {}: the folder is not writable ({})", script, w[0], w[1],
               join(w, 3));
}

/* ---------------------------------------------------------------------- */

bool NCFCheck::read_settings(const std::string &file, std::vector<std::string> &names,
                             std::string &fabric)
{
  FILE *fp = std::fopen(file.c_str(), "r");
  if (!fp) return false;
  char buf[4096];
  while (std::fgets(buf, sizeof(buf), fp)) {
    const auto words = utils::split_words(utils::trim_comment(buf));
    if (words.size() >= 2 && words[0] == "variable") {
      names.push_back(words[1]);
      if (words[1] == "ncf_fabric" && words.size() >= 4) fabric = words[3];
    }
  }
  std::fclose(fp);
  return true;
}

void NCFCheck::check_settings(const std::vector<std::string> &w)
{
  if (w.size() < 2)
    error->all(FLERR, "ncf/check: {}: expected 'settings FILE VAR ...', got '{}'", script,
               join(w, 0));
  std::vector<std::string> names;
  std::string fabric;
  if (!read_settings(w[0], names, fabric))
    error->all(FLERR,
               "{}: cannot read the settings file {}: {} (ncf-gen writes PREFIX.settings.lmp)",
               script, w[0], utils::getsyserror());
  std::vector<std::string> missing;
  for (std::size_t i = 1; i < w.size(); i++) {
    bool found = false;
    for (const auto &n : names) found = found || n == w[i];
    if (!found) missing.push_back(w[i]);
  }
  if (!missing.empty())
    error->all(FLERR,
               "{}: the settings file {} defines no variable {}: it was written by an older "
               "ncf-gen; generate the fabric again (ncf-gen CARD -o PREFIX)",
               script, w[0], join(missing, 0));
}

/* ---------------------------------------------------------------------- */

std::string NCFCheck::marker(const char *prefix)
{
  const std::size_t n = std::strlen(prefix);
  for (int g = 0; g < group->ngroup; g++)
    if (group->names[g] && std::strncmp(group->names[g], prefix, n) == 0)
      return std::string(group->names[g] + n);
  return "";
}

void NCFCheck::check_restart(const std::vector<std::string> &w)
{
  if (w.size() != 3)
    error->all(FLERR, "ncf/check: {}: expected 'restart FILE STAGE SETTINGS', got '{}'", script,
               join(w, 0));
  const std::string &file = w[0], &stage = w[1], &settings = w[2];
  const std::string found = marker(STAGE_GROUP);
  if (found.empty())
    error->all(FLERR,
               "{}: restart file {} carries no stage mark (group {}*): it was not written by a "
               "stage script of this version; {} continues from the restart of stage {} (in.{})",
               script, file, STAGE_GROUP, script, stage, stage);
  if (found != stage)
    error->all(FLERR,
               "{}: restart file {} was written by stage {} (in.{}); {} continues from the "
               "restart of stage {} (in.{}, PREFIX.{}.restart)",
               script, file, found, found, script, stage, stage, stage);
  std::vector<std::string> names;
  std::string fabric;
  if (!read_settings(settings, names, fabric))
    error->all(FLERR,
               "{}: cannot read the settings file {}: {} (ncf-gen writes PREFIX.settings.lmp)",
               script, settings, utils::getsyserror());
  if (fabric.empty())
    error->all(
        FLERR,
        "{}: the settings file {} defines no variable ncf_fabric: it was written by an older "
        "ncf-gen; generate the fabric again (ncf-gen CARD -o PREFIX)",
        script, settings);
  const std::string rfabric = marker(FABRIC_GROUP);
  if (rfabric != fabric)
    error->all(
        FLERR,
        "{}: restart file {} is of fabric {}, the settings file {} of fabric {} (ncf_fabric): "
        "give the prefix of the fabric the restart file was made from",
        script, file, rfabric.empty() ? "(none)" : rfabric, settings, fabric);
}

/* ----------------------------------------------------------------------
   the needle file of a stage: every needle inside the box (a needle file of another fabric lies
   partly outside it), none listed twice, no two shafts of diameter D overlapping (through the
   periodic faces too), none wider than the periodic box
------------------------------------------------------------------------- */

void NCFCheck::check_needles(const std::vector<std::string> &w)
{
  double dia = 0.0;
  if (w.size() != 2 || !finite_number(w[1], dia) || !(dia > 0.0))
    error->all(FLERR, "ncf/check: {}: expected 'needles FILE DIAMETER' (DIAMETER > 0), got '{}'",
               script, join(w, 0));
  if (!domain->box_exist)
    error->all(FLERR, "ncf/check: {}: 'needles' needs a box (after read_data or read_restart)",
               script);
  const std::string &file = w[0];
  std::vector<double> x, y;
  NCF_LMP::read_needles(lmp, script, file, x, y);
  if (x.empty()) error->all(FLERR, "{}: needle file {} lists no needle", script, file);
  const double *lo = domain->boxlo, *hi = domain->boxhi;
  for (std::size_t k = 0; k < x.size(); k++)
    if (x[k] < lo[0] || x[k] > hi[0] || y[k] < lo[1] || y[k] > hi[1])
      error->all(
          FLERR,
          "{}: needle file {}: needle {} at ({:.6g}, {:.6g}) lies outside the box (x {:.6g} .. "
          "{:.6g}, y {:.6g} .. {:.6g}): the needles of another fabric?",
          script, file, k + 1, x[k], y[k], lo[0], hi[0], lo[1], hi[1]);
  for (int d = 0; d < 2; d++)
    if (domain->periodicity[d] && dia >= hi[d] - lo[d])
      error->all(FLERR,
                 "{}: needle diameter {} is not smaller than the periodic box length {} in {}",
                 script, dia, hi[d] - lo[d], d ? "y" : "x");
  for (std::size_t a = 0; a < x.size(); a++)
    for (std::size_t b = a + 1; b < x.size(); b++) {
      double dxy[2] = {x[b] - x[a], y[b] - y[a]};
      for (int d = 0; d < 2; d++)
        if (domain->periodicity[d]) {
          const double prd = hi[d] - lo[d];
          dxy[d] -= prd * std::round(dxy[d] / prd);
        }
      const double dist = std::hypot(dxy[0], dxy[1]);
      if (dist == 0.0)
        error->all(FLERR,
                   "{}: needle file {}: needles {} and {} are the same needle, at ({:.6g}, {:.6g})",
                   script, file, a + 1, b + 1, x[a], y[a]);
      if (dist < dia)
        error->all(FLERR,
                   "{}: needle file {}: needles {} and {} at ({:.6g}, {:.6g}) and ({:.6g}, {:.6g}) "
                   "overlap: "
                   "their centres are {:.6g} apart, less than the needle diameter {}",
                   script, file, a + 1, b + 1, x[a], y[a], x[b], y[b], dist, dia);
    }
}

/* ---------------------------------------------------------------------- */

void NCFCheck::mark(const std::vector<std::string> &w)
{
  if (w.size() != 2 || !valid_name(w[0]) || !valid_name(w[1]))
    error->all(FLERR,
               "ncf/check: {}: expected 'mark STAGE FABRIC' (letters, digits, underscores), got "
               "'{}'",
               script, join(w, 0));
  // the earlier marks go (a stage continuing the previous one in the same process), then the
  // two empty groups that write_restart stores with the other groups
  for (const char *prefix : {STAGE_GROUP, FABRIC_GROUP}) {
    for (std::string old = marker(prefix); !old.empty(); old = marker(prefix))
      group->assign(std::string(prefix) + old + " delete");
  }
  group->assign(std::string(STAGE_GROUP) + w[0] + " empty");
  group->assign(std::string(FABRIC_GROUP) + w[1] + " empty");
}
