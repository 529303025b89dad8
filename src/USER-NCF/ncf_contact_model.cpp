/* ----------------------------------------------------------------------
   USER-NCF: filament-scale virtual manufacturing of non-crimp fabrics.
   Engine-free contact model (see ncf_contact_model.h).
------------------------------------------------------------------------- */

#include "ncf_contact_model.h"

#include <algorithm>
#include <cmath>

namespace NCF {

// the contact keywords, their names and the coefficient each sets, once
namespace {
  const struct {
    ContactKey key;
    const char *name;
    double ContactCoeffs::*member;
  } KEYS[] = {{ContactKey::KN, "kn", &ContactCoeffs::kn},
              {ContactKey::KT, "kt", &ContactCoeffs::kt},
              {ContactKey::MU, "mu", &ContactCoeffs::mu},
              {ContactKey::DAMP, "damp", &ContactCoeffs::damp}};
}    // namespace

ContactKey contact_key(const std::string &key)
{
  for (const auto &k : KEYS)
    if (key == k.name) return k.key;
  return ContactKey::NONE;
}

const char *contact_key_name(ContactKey key)
{
  for (const auto &k : KEYS)
    if (k.key == key) return k.name;
  return "?";
}

std::string contact_value_error(ContactKey k, double v, const std::string &text)
{
  const std::string head = std::string(contact_key_name(k)) + " " + text + " must be ";
  if (k == ContactKey::KN) return v > 0.0 ? "" : head + "> 0";
  if (!(v >= 0.0)) return head + ">= 0";
  if (k == ContactKey::KT && v > KT_MAX)
    return head + "a ratio of kn in [0, " + std::to_string((int) KT_MAX) +
        "] (kt 1: the tangential stiffness equals kn); a value this large reads like a stiffness "
        "in Pa, the meaning fix ncf/plate's kt had before: give kt as a ratio";
  return "";
}

void set_contact_value(ContactCoeffs &c, ContactKey key, double v)
{
  for (const auto &k : KEYS)
    if (k.key == key) c.*k.member = v;
}

const char *invalid_coeff(const ContactCoeffs &c, double *value)
{
  for (const auto &k : KEYS) {
    const double v = c.*k.member;
    if (!std::isfinite(v) || (k.key == ContactKey::KN ? !(v > 0.0) : !(v >= 0.0))) {
      if (value) *value = v;
      return k.name;
    }
  }
  return nullptr;
}

ContactCoeffs mix(const ContactCoeffs &ii, const ContactCoeffs &jj)
{
  ContactCoeffs c;
  c.kn = 2.0 * ii.kn * jj.kn / (ii.kn + jj.kn);
  c.kt = 0.5 * (ii.kt + jj.kt);
  c.mu = std::sqrt(ii.mu * jj.mu);
  c.damp = std::sqrt(ii.damp * jj.damp);
  return c;
}

void ContactTable::resize(int ntypes)
{
  n = ntypes;
  const std::size_t m = (std::size_t) (n + 1) * (n + 1);
  for (int k = 0; k < 4; k++) {
    val[k].assign(m, 0.0);
    rows[k].resize(n + 1);
    for (int i = 0; i <= n; i++) rows[k][i] = val[k].data() + idx(i, 0);
  }
  given_.assign(m, 0);
  diam.assign(n + 1, 0.0);
  diamset.assign(n + 1, 0);
}

void ContactTable::set(int i, int j, const ContactCoeffs &c)
{
  const double cf[4] = {c.kn, c.kt, c.mu, c.damp};
  for (int k = 0; k < 4; k++) val[k][idx(i, j)] = val[k][idx(j, i)] = cf[k];
  given_[idx(i, j)] = given_[idx(j, i)] = 1;
}

ContactCoeffs ContactTable::coeffs(int i, int j) const
{
  ContactCoeffs c;
  c.kn = val[0][idx(i, j)];
  c.kt = val[1][idx(i, j)];
  c.mu = val[2][idx(i, j)];
  c.damp = val[3][idx(i, j)];
  return c;
}

bool ContactTable::resolve(int i, int j)
{
  ContactCoeffs c = coeffs(i, j);
  if (!given(i, j)) {
    if (!given(i, i) || !given(j, j)) return false;
    c = mix(coeffs(i, i), coeffs(j, j));
  }
  const double cf[4] = {c.kn, c.kt, c.mu, c.damp};
  for (int k = 0; k < 4; k++) val[k][idx(i, j)] = val[k][idx(j, i)] = cf[k];
  return true;
}

double ContactTable::kn_max_given() const
{
  double knmax = 0.0;
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++)
      if (given(i, j)) knmax = std::max(knmax, val[0][idx(i, j)]);
  return knmax;
}

void ContactTable::set_diameter(int t, double d)
{
  diam[t] = d;
  diamset[t] = 1;
}

}    // namespace NCF
