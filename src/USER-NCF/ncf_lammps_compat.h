/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: the one place that knows about differences between the LAMMPS versions the package
   supports (2 Aug 2023 and later). Styles call these helpers instead of testing versions
   themselves, so that a future API change is mended here alone.

   Known differences handled here:
   - error->all(FLERR, iarg, ...) (pointing at the failing argument) exists only from 4 Feb 2025
     on: we never use it; every message names the style, keyword and value instead.
   - utils::print() is newer than fmt::print(FILE *, ...): output to files goes through
     NCF_COMPAT::print below.
------------------------------------------------------------------------- */

#ifndef NCF_LAMMPS_COMPAT_H
#define NCF_LAMMPS_COMPAT_H

#include "fmt/format.h"

#include <cstdio>
#include <string>

namespace NCF_COMPAT {

// Formatted write to a C stream (restart/data files, logs), identical in all supported versions.
template <typename... Args>
inline void print(FILE *fp, const std::string &format, const Args &...args)
{
  const std::string text = fmt::vformat(format, fmt::make_format_args(args...));
  fputs(text.c_str(), fp);
}

}    // namespace NCF_COMPAT

#endif
