/* ----------------------------------------------------------------------
   ncf-gen: USER-NCF fabric generator, command-line tool (see doc/ncf-gen.md).

     ncf-gen CARD [-o PREFIX] [-rve R_W R_L] [-seed N] [-q]

   writes PREFIX.layers.data, .yarn.data, .needles, .settings.lmp, .yarn.lmp and .summary
   (PREFIX defaults to the card's 'name' in the current folder) and prints the summary.
------------------------------------------------------------------------- */

#include "ncf_gen.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

int main(int argc, char **argv)
{
  std::string card, prefix;
  bool quiet = false;
  NCFGEN::Overrides ov;
  auto positive_int = [](const char *s, long long &v) {
    char *end = nullptr;
    errno = 0;
    v = std::strtoll(s, &end, 10);
    // (out of the range of a 64-bit integer: refused, not clamped)
    return end != s && *end == '\0' && errno != ERANGE && v >= 0;
  };
  // an option at the end of the line without its value(s)
  auto needs = [&](int i, int n, const char *what) {
    if (i + n < argc) return true;
    std::fprintf(stderr, "ncf-gen: option %s needs %s\n", argv[i], what);
    return false;
  };
  std::string given;    // the options seen, " -o -rve ..."
  for (int i = 1; i < argc; i++) {
    for (const char *opt : {"-o", "-rve", "-seed"})
      if (!std::strcmp(argv[i], opt)) {
        if (given.find(std::string(" ") + opt + " ") != std::string::npos) {
          std::fprintf(stderr, "ncf-gen: option %s given twice\n", opt);
          return 2;
        }
        given += std::string(" ") + opt + " ";
      }
    if (!std::strcmp(argv[i], "-o") && !needs(i, 1, "a prefix (-o PREFIX)")) return 2;
    if (!std::strcmp(argv[i], "-o") && argv[i + 1][0] == '-') {
      // (an option where the prefix belongs: files named '-q.layers.data' are not wanted)
      std::fprintf(stderr, "ncf-gen: option -o needs a prefix, got the option '%s'\n", argv[i + 1]);
      return 2;
    }
    if (!std::strcmp(argv[i], "-rve") && !needs(i, 2, "two integers (-rve R_W R_L)")) return 2;
    if (!std::strcmp(argv[i], "-seed") && !needs(i, 1, "an integer (-seed N)")) return 2;
    if (!std::strcmp(argv[i], "-o") && i + 1 < argc) {
      prefix = argv[++i];
    } else if (!std::strcmp(argv[i], "-rve") && i + 2 < argc) {
      long long a, b;
      if (!positive_int(argv[i + 1], a) || !positive_int(argv[i + 2], b) || a < 1 || b < 1 ||
          a > 1000 || b > 1000) {
        std::fprintf(stderr, "ncf-gen: -rve needs two integers in 1..1000, got '%s %s'\n",
                     argv[i + 1], argv[i + 2]);
        return 2;
      }
      ov.r_w = (int) a;
      ov.r_l = (int) b;
      i += 2;
    } else if (!std::strcmp(argv[i], "-seed") && i + 1 < argc) {
      if (!positive_int(argv[i + 1], ov.seed)) {
        std::fprintf(stderr, "ncf-gen: -seed needs an integer >= 0, got '%s'\n", argv[i + 1]);
        return 2;
      }
      i++;
    } else if (!std::strcmp(argv[i], "-q")) {
      quiet = true;
    } else if (!std::strcmp(argv[i], "-h") || !std::strcmp(argv[i], "--help")) {
      std::printf(
          "usage: ncf-gen CARD [-o PREFIX] [-rve R_W R_L] [-seed N] [-q]\n"
          "  writes PREFIX.layers.data PREFIX.yarn.data PREFIX.needles PREFIX.settings.lmp\n"
          "  PREFIX.yarn.lmp PREFIX.summary (PREFIX defaults to the card's name);\n"
          "  -rve and -seed replace the card's values; -q prints no summary\n");
      return 0;
    } else if (argv[i][0] == '-' || !card.empty()) {
      std::fprintf(stderr,
                   "ncf-gen: unexpected argument '%s' (usage: ncf-gen CARD [-o PREFIX] [-rve R_W "
                   "R_L] [-seed N] [-q])\n",
                   argv[i]);
      return 2;
    } else {
      card = argv[i];
    }
  }
  if (card.empty()) {
    std::fprintf(stderr, "usage: ncf-gen CARD [-o PREFIX] [-rve R_W R_L] [-seed N] [-q]\n");
    return 2;
  }
  if (prefix.empty()) {
    try {
      prefix = NCFGEN::read_card(card).name;
    } catch (std::exception &e) {
      std::fprintf(stderr, "ncf-gen: ERROR: %s\n", e.what());
      return 1;
    }
  }
  std::string error, summary;
  if (!NCFGEN::generate(card, prefix, error, &summary, &ov)) {
    std::fprintf(stderr, "ncf-gen: ERROR: %s\n", error.c_str());
    return 1;
  }
  if (!quiet) std::fputs(summary.c_str(), stdout);
  return 0;
}
