/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   The quasi-static criterion of a hold or a relaxation (engine-free; fix ncf/settle drives it,
   doc/fix_ncf_settle.md).

   A Settle holds a list of criteria and the samples of the last `window` checks of each. It is
   settled at a check when every criterion holds there:
     KE_RATIO  sample (KE, E): KE <= tol * max |E| since the reset (the run's scale: the energy
               it put in or had to dissipate), at this check
     AT_MOST   sample (value): value <= tol, at this check
     STEADY    sample (value), over the last `window` checks: the drift |mean of the window's
               newer half - mean of its older half| <= tol * max |value| since the reset (a
               drift, not the noise: the halves' means average the check-to-check scatter out)
   The samples of a check come in the order the criteria were added.
------------------------------------------------------------------------- */

#ifndef NCF_SETTLE_H
#define NCF_SETTLE_H

#include <deque>
#include <string>
#include <vector>

namespace NCF {

class Settle {
 public:
  enum Kind { KE_RATIO, AT_MOST, STEADY };
  struct Sample {
    double value;
    double ref = 0.0;    // KE_RATIO: the reference energy of this check
  };

  explicit Settle(int window);
  void add(Kind kind, const std::string &name, double tol);
  int size() const { return (int) crit.size(); }
  int window() const { return nwindow; }

  // forget the checks so far and the scales (a new run, or the check switched on again)
  void reset();
  // one check, one sample per criterion; true when settled. A sample that is not finite never
  // holds.
  bool check(const std::vector<Sample> &samples);
  // criterion k at the last check (a steady one: false before `window` checks)
  bool held(int k) const;
  // what criterion k compares with its tolerance at the last check: KE / max |E|, the value, or
  // the drift / max |value|
  double measure(int k) const;
  int checks() const { return nchecks; }

  // "KE / max v_work 2.1e-04 <= 0.001, v_p drifted 0.031 % <= 0.2 % over 10 checks, ..." for
  // the last check (criteria that do not hold say '>')
  std::string report() const;

 private:
  struct Criterion {
    Kind kind;
    std::string name;    // what the messages call the value ("KE / max v_work", "fmax", "v_p")
    double tol;
    std::deque<double> last;    // the measured values of the last `window` checks, newest last
    double scale;               // the largest magnitude since the reset
  };
  int nwindow;
  int nchecks;
  std::vector<Criterion> crit;
  double drift(const Criterion &c) const;
};

}    // namespace NCF

#endif
