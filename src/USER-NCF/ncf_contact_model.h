/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free contact model: the coefficients of a contact with the one meaning and unit each
   has in every style (pair ncf/contact, fix ncf/plate, fix ncf/needles), their checks, the
   per-type-pair table of the pair style with its mixing rule, and the table's restart layout.
   The contact laws themselves are in ncf_contact.h, ncf_wall.h and ncf_needle.h. No LAMMPS
   dependency; the styles read the keywords through NCF_LMP::read_contact (lammps_ncf_args.h).
------------------------------------------------------------------------- */

#ifndef NCF_CONTACT_MODEL_H
#define NCF_CONTACT_MODEL_H

#include <string>
#include <vector>

namespace NCF {

// The coefficients of one contact (a type pair, a chain type against a plate or a needle).
struct ContactCoeffs {
  double kn = 0.0;      // normal penalty stiffness per unit contact length [Pa = N/m per m]
  double kt = 1.0;      // tangential (friction spring) stiffness as a ratio of kn [-]
  double mu = 0.0;      // Coulomb friction coefficient [-]
  double damp = 0.0;    // normal dashpot per unit contact length [N s/m^2]
  // the tangential stiffness per unit contact length [Pa]
  double kt_stiffness() const { return kt * kn; }
};

// The contact keywords. kt is bounded: a ratio above KT_MAX is a stiffness in Pa written where a
// ratio is read (the meaning fix ncf/plate's kt had before the contact model was shared).
enum class ContactKey { KN, KT, MU, DAMP, NONE };
constexpr double KT_MAX = 10.0;
// the key of a keyword, NONE if it is not a contact keyword
ContactKey contact_key(const std::string &key);
const char *contact_key_name(ContactKey k);
// the reason value v (as written: text) is not valid for key k, empty if it is; the message
// form is "<key> <text> must be ..."
std::string contact_value_error(ContactKey k, double v, const std::string &text);
void set_contact_value(ContactCoeffs &c, ContactKey k, double v);
// the coefficient of c that is not valid (not finite, kn <= 0, another < 0), nullptr if none;
// its value in *value. For coefficients changed at run time (fix adapt), which no reader saw.
const char *invalid_coeff(const ContactCoeffs &c, double *value);

// Two types' coefficients mixed: springs in series for kn, the mean ratio kt, the geometric
// means of mu and damp.
ContactCoeffs mix(const ContactCoeffs &ii, const ContactCoeffs &jj);

// The coefficients of every pair of atom types 1..n (index 0 unused) and the chain diameter of
// every type. The tables kn, kt, mu and damp are double ** rows, so that fix adapt can change
// them through Pair::extract; entries that were not given hold the mixed values once resolve()
// ran.
class ContactTable {
 public:
  void resize(int ntypes);    // every pair and type unset
  int ntypes() const { return n; }

  void set(int i, int j, const ContactCoeffs &c);    // given (both orders)
  bool given(int i, int j) const { return given_[idx(i, j)] != 0; }
  // resolve i-j: a pair not given is mixed from i-i and j-j (both orders written); false if it
  // is neither given nor mixable
  bool resolve(int i, int j);
  ContactCoeffs coeffs(int i, int j) const;
  // the largest kn given
  double kn_max_given() const;

  void set_diameter(int t, double d);
  double diameter(int t) const { return diam[t]; }
  bool diameter_given(int t) const { return diamset[t] != 0; }
  double *diameters() { return diam.data(); }

  double **kn_rows() { return rows[0].data(); }
  double **kt_rows() { return rows[1].data(); }
  double **mu_rows() { return rows[2].data(); }
  double **damp_rows() { return rows[3].data(); }

  // restart: the table in the order of the pair style's restart files, through a writer or
  // reader with i(int) and d(double) (for each type i: diameter flag, diameter; for each j >= i:
  // given flag, then kn, kt, mu, damp if given)
  template <class W> void write(W &w) const
  {
    for (int i = 1; i <= n; i++) {
      w.i(diamset[i]);
      w.d(diam[i]);
      for (int j = i; j <= n; j++) {
        w.i(given_[idx(i, j)]);
        if (given_[idx(i, j)])
          for (int k = 0; k < 4; k++) w.d(val[k][idx(i, j)]);
      }
    }
  }
  template <class R> void read(R &r)
  {
    for (int i = 1; i <= n; i++) {
      diamset[i] = r.i();
      diam[i] = r.d();
      for (int j = i; j <= n; j++)
        if (r.i()) {
          ContactCoeffs c;
          c.kn = r.d();
          c.kt = r.d();
          c.mu = r.d();
          c.damp = r.d();
          set(i, j, c);
        }
    }
  }

 private:
  int n = 0;
  std::size_t idx(int i, int j) const { return (std::size_t) i * (n + 1) + j; }
  std::vector<double> val[4];    // kn, kt, mu, damp per (i, j)
  std::vector<double *> rows[4];
  std::vector<int> given_;
  std::vector<double> diam;
  std::vector<int> diamset;
};

}    // namespace NCF

#endif
