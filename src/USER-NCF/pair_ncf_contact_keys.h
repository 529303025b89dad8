/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: pair_style ncf/contact, internal: the key of a chain segment (its two node tags, the
   lower first), shared by the list build and the friction history of the style. Not a style
   header; included by the pair_ncf_contact*.cpp files only.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_NCF_CONTACT_KEYS_H
#define LMP_PAIR_NCF_CONTACT_KEYS_H

#include "lmptype.h"

namespace NCF_PairContact {
using LAMMPS_NS::tagint;

struct SegKey {
  tagint lo, hi;
};
inline bool key_less(const SegKey &a, const SegKey &b)
{
  return a.lo < b.lo || (a.lo == b.lo && a.hi < b.hi);
}
inline bool share_node(const SegKey &a, const SegKey &b)
{
  return a.lo == b.lo || a.lo == b.hi || a.hi == b.lo || a.hi == b.hi;
}
inline SegKey make_key(tagint a, tagint b)
{
  return a < b ? SegKey{a, b} : SegKey{b, a};
}

}    // namespace NCF_PairContact

#endif
