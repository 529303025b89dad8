/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF: the one place that knows about differences between the LAMMPS versions the package
   supports (tested: 4 Feb 2025 and 4 Jul 2026). Styles call these helpers instead of testing
   versions themselves, so that a future API change is mended here alone.

   LAMMPS has no version number usable by the preprocessor (version.h holds only a string), so
   each difference is detected by what the headers offer: a header that exists (__has_include) or
   a member function that can be called with given arguments (a C++17 detection trait).

   Known differences handled here:
   - error->all(FLERR, iarg, ...) (pointing at the failing argument) exists only from 4 Feb 2025
     on: we never use it; every message names the style, keyword and value instead.
   - utils::print() is newer than fmt::print(FILE *, ...): output to files goes through
     NCF_COMPAT::print below.
   - Domain::minimum_image(): (dx, dy, dz) up to 4 Feb 2025, (FLERR, dx, dy, dz) in 4 Jul 2026
     (it names the caller when the distance is too large): NCF_COMPAT::minimum_image below.
   - The shape codes a fix returns from Fix::image() for dump image: up to 4 Feb 2025 an enum
     { SPHERE, LINE, TRI } private to dump_image.cpp (no header has it); in 4 Jul 2026 the enum
     LAMMPS_NS::Graphics of graphics.h, { NONE, SPHERE, LINE, TRI, ... }, renumbered.
     NCF_COMPAT::ImageShape below takes them from graphics.h where it exists.
   - dump image itself (dump_image.cpp, image.cpp) moved into the optional GRAPHICS package in
     4 Jul 2026: a LAMMPS build for the examples needs PKG_GRAPHICS there (doc/build.md).
     Nothing in the plugin refers to it.
------------------------------------------------------------------------- */

#ifndef LAMMPS_NCF_COMPAT_H
#define LAMMPS_NCF_COMPAT_H

#include "fmt/format.h"

#include <cstdio>
#include <string>
#include <type_traits>
#include <utility>

#if __has_include("graphics.h")
#include "graphics.h"
#define NCF_COMPAT_HAVE_GRAPHICS_H 1
#endif

namespace NCF_COMPAT {

// Formatted write to a C stream (restart/data files, logs), identical in all supported versions.
template <typename... Args>
inline void print(FILE *fp, const std::string &format, const Args &...args)
{
  const std::string text = fmt::vformat(format, fmt::make_format_args(args...));
  fputs(text.c_str(), fp);
}

namespace detail {
  // true where Domain::minimum_image takes the caller's file and line first (4 Jul 2026)
  template <typename D, typename = void> struct minimum_image_takes_flerr : std::false_type {
  };
  template <typename D>
  struct minimum_image_takes_flerr<
      D,
      std::void_t<decltype(std::declval<const D &>().minimum_image(
          std::declval<const std::string &>(), 0, std::declval<double &>(),
          std::declval<double &>(), std::declval<double &>()))>> : std::true_type {
  };
}    // namespace detail

// domain->minimum_image(dx, dy, dz) in every version; call as
// NCF_COMPAT::minimum_image(domain, FLERR, dx, dy, dz)
template <typename D>
inline void minimum_image(const D *domain, const char *file, int line, double &dx, double &dy,
                          double &dz)
{
  if constexpr (detail::minimum_image_takes_flerr<D>::value) {
    domain->minimum_image(file, line, dx, dy, dz);
  } else {
    (void) file;
    (void) line;
    domain->minimum_image(dx, dy, dz);
  }
}

// Shape codes for Fix::image() (dump image ... fix ID ...). Both versions read a LINE row as
// (colour, x1 y1 z1, x2 y2 z2) and a TRI row as (colour, three corners).
struct ImageShape {
#ifdef NCF_COMPAT_HAVE_GRAPHICS_H
  static constexpr int LINE = LAMMPS_NS::Graphics::LINE;
  static constexpr int TRI = LAMMPS_NS::Graphics::TRI;
#else
  // up to 4 Feb 2025 the enum { SPHERE, LINE, TRI } lives in dump_image.cpp alone, so its
  // values are repeated here
  static constexpr int LINE = 1;
  static constexpr int TRI = 2;
#endif
};

}    // namespace NCF_COMPAT

#endif
