/* ----------------------------------------------------------------------
   ncf-gen: USER-NCF fabric generator, command-line tool (see doc/ncf-gen.md).

     ncf-gen CARD [-o PREFIX] [-q]

   writes PREFIX.layers.data, .yarn.data, .needles, .settings.lmp, .yarn.lmp and .summary
   (PREFIX defaults to the card's 'name' in the current folder) and prints the summary.
------------------------------------------------------------------------- */

#include "ncfgen.h"

#include <cstdio>
#include <cstring>
#include <string>

int main(int argc, char **argv)
{
  std::string card, prefix;
  bool quiet = false;
  for (int i = 1; i < argc; i++) {
    if (!std::strcmp(argv[i], "-o") && i + 1 < argc) {
      prefix = argv[++i];
    } else if (!std::strcmp(argv[i], "-q")) {
      quiet = true;
    } else if (!std::strcmp(argv[i], "-h") || !std::strcmp(argv[i], "--help")) {
      std::printf("usage: ncf-gen CARD [-o PREFIX] [-q]\n"
                  "  writes PREFIX.layers.data PREFIX.yarn.data PREFIX.needles PREFIX.settings.lmp\n"
                  "  PREFIX.yarn.lmp PREFIX.summary (PREFIX defaults to the card's name)\n");
      return 0;
    } else if (argv[i][0] == '-' || !card.empty()) {
      std::fprintf(stderr, "ncf-gen: unexpected argument '%s' (usage: ncf-gen CARD [-o PREFIX] [-q])\n",
                   argv[i]);
      return 2;
    } else {
      card = argv[i];
    }
  }
  if (card.empty()) {
    std::fprintf(stderr, "usage: ncf-gen CARD [-o PREFIX] [-q]\n");
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
  if (!NCFGEN::generate(card, prefix, error, &summary)) {
    std::fprintf(stderr, "ncf-gen: ERROR: %s\n", error.c_str());
    return 1;
  }
  if (!quiet) std::fputs(summary.c_str(), stdout);
  return 0;
}
