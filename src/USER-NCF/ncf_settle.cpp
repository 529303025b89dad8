/* ----------------------------------------------------------------------
   USER-NCF: the quasi-static criterion of a hold (see ncf_settle.h)
------------------------------------------------------------------------- */

#include "ncf_settle.h"

#include "ncf_input_error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace NCF {

Settle::Settle(int window) : nwindow(window), nchecks(0)
{
  if (window < 1) throw InputError("the window of a quasi-static check must be >= 1 check");
}

void Settle::add(Kind kind, const std::string &name, double tol)
{
  if (!(tol >= 0.0) || !std::isfinite(tol))
    throw InputError("the tolerance of " + name + " must be a finite number >= 0");
  if (kind == STEADY && nwindow < 2)
    throw InputError("a steady criterion (" + name + ") needs a window of >= 2 checks");
  crit.push_back({kind, name, tol, {}, 0.0});
}

void Settle::reset()
{
  nchecks = 0;
  for (auto &c : crit) {
    c.last.clear();
    c.scale = 0.0;
  }
}

bool Settle::check(const std::vector<Sample> &samples)
{
  if (samples.size() != crit.size())
    throw InputError("a quasi-static check needs one sample per criterion");
  nchecks++;
  for (size_t k = 0; k < crit.size(); k++) {
    Criterion &c = crit[k];
    const Sample &s = samples[k];
    // (a sample that is not finite leaves the scale and fails while it is in the window)
    const double mag = std::fabs(c.kind == KE_RATIO ? s.ref : s.value);
    if (std::isfinite(mag)) c.scale = std::max(c.scale, mag);
    c.last.push_back(std::isfinite(mag) ? s.value : NAN);
    while ((int) c.last.size() > nwindow) c.last.pop_front();
  }
  bool all = !crit.empty();
  for (int k = 0; k < size(); k++) all = all && held(k);
  return all;
}

// |mean of the newer half - mean of the older half| of the window (the middle sample of an odd
// window in neither)
double Settle::drift(const Criterion &c) const
{
  const int n = (int) c.last.size();
  const int h = n / 2;
  if (h == 0) return NAN;
  double older = 0.0, newer = 0.0;
  for (int i = 0; i < h; i++) {
    older += c.last[i];
    newer += c.last[n - h + i];
  }
  return std::fabs(newer - older) / h;
}

double Settle::measure(int k) const
{
  const Criterion &c = crit[k];
  if (c.last.empty()) return NAN;
  if (c.kind == AT_MOST) return c.last.back();
  const double num = c.kind == KE_RATIO ? c.last.back() : drift(c);
  return c.scale > 0.0 ? num / c.scale : (num == 0.0 ? 0.0 : INFINITY);
}

bool Settle::held(int k) const
{
  const Criterion &c = crit[k];
  if (c.last.empty()) return false;
  if (c.kind != STEADY) {
    // at this check (the kinetic energy of the whole fabric does not dip for a moment; the
    // steady criteria give the window)
    const double v = c.last.back();
    return std::isfinite(v) && v <= (c.kind == KE_RATIO ? c.tol * c.scale : c.tol);
  }
  if ((int) c.last.size() < nwindow) return false;
  for (double v : c.last)
    if (!std::isfinite(v)) return false;
  return measure(k) <= c.tol;
}

std::string Settle::report() const
{
  std::string out;
  char buf[256];
  for (int k = 0; k < size(); k++) {
    const Criterion &c = crit[k];
    const double m = measure(k);
    const char *op = held(k) ? "<=" : ">";
    if (c.kind == STEADY)
      std::snprintf(buf, sizeof(buf), "%s drifted %.3g %% %s %.3g %% over %d checks",
                    c.name.c_str(), 100.0 * m, op, 100.0 * c.tol, (int) c.last.size());
    else
      std::snprintf(buf, sizeof(buf), "%s %.3g %s %.3g", c.name.c_str(), m, op, c.tol);
    if (!out.empty()) out += ", ";
    out += buf;
  }
  // (a steady criterion does not hold before `window` checks: say so rather than a bare '>')
  bool steady = false;
  for (const auto &c : crit) steady = steady || c.kind == STEADY;
  if (steady && nchecks < nwindow) {
    std::snprintf(buf, sizeof(buf), " (%d of the window's %d checks)", nchecks, nwindow);
    out += buf;
  }
  return out;
}

}    // namespace NCF
