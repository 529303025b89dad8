// The bad-input corpus of the fabric generator (tests/bad_input/cards.cases): every case is a
// card with one mistake, run through NCFGEN::generate as the ncf-gen tool runs it; the error
// must hold the expected message (the key and the value) and no output file may be left behind.
// Also: ncf-gen's outputs appear all together or not at all (temporary names, then renames).
//
// Corpus format ('#' lines outside a block are comments):
//   @base ... @end              the valid card every case starts from; @MATERIALS@ stands for
//                               the package's materials file
//   @file NAME ... @end         a file written next to the cards (e.g. a materials file)
//   @case NAME                  starts a case, then edits of the base card:
//     @set KEY VALUE...         the first line whose first word is KEY becomes "KEY VALUE..."
//                               (appended when there is none)
//     @drop KEY                 the first line whose first word is KEY goes
//     @add LINE                 LINE is appended
//     @empty                    the card starts empty instead
//   @expect TEXT                ends the case: generation fails with TEXT in the message
//   @expect-ok                  ends a check case: generation succeeds
// NCF_BAD_INPUT_SHOW=1 prints every case's message.

#include "ncf_case_name.h"
#include "ncf_gen.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>

using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

const std::string SRC = NCF_SOURCE_DIR;
const std::string CORPUS = "tests/bad_input/cards.cases";

struct Case {
  std::string name, card, expect;
  int line = 0;
  bool expect_ok = false;
};

struct Corpus {
  std::string base;
  std::map<std::string, std::string> files;
  std::vector<Case> cases;
};

std::vector<std::string> lines_of(const std::string &text)
{
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string l;
  while (std::getline(in, l)) out.push_back(l);
  return out;
}

std::string first_word(const std::string &line)
{
  std::istringstream in(line);
  std::string w;
  in >> w;
  return w;
}

Corpus read_corpus()
{
  const std::string path = SRC + "/" + CORPUS;
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  Corpus corpus;
  std::string line, block, block_name, text;
  std::vector<std::string> card;
  Case current;
  bool in_case = false;
  int lineno = 0;
  auto fail = [&](const std::string &what) {
    throw std::runtime_error(path + ":" + std::to_string(lineno) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++lineno;
    if (!block.empty()) {
      if (line == "@end") {
        if (block == "base")
          corpus.base = text;
        else
          corpus.files[block_name] = text;
        block.clear();
      } else
        text += line + "\n";
      continue;
    }
    const auto pos = line.find_first_not_of(" \t");
    if (pos == std::string::npos || line[pos] == '#') continue;
    const std::string word = first_word(line);
    std::string rest = line.substr(line.find(word) + word.size());
    rest.erase(0, rest.find_first_not_of(" \t"));
    if (word == "@base" || word == "@file") {
      if (in_case) fail("a block inside a case");
      block = word.substr(1);
      block_name = rest;
      text.clear();
    } else if (word == "@case") {
      if (in_case) fail("case " + current.name + " has no @expect");
      current = Case();
      current.name = rest;
      current.line = lineno;
      card = lines_of(corpus.base);
      in_case = true;
    } else if (!in_case) {
      fail("'" + line + "' outside a case");
    } else if (word == "@set" || word == "@drop") {
      const std::string key = first_word(rest);
      bool done = false;
      for (auto it = card.begin(); it != card.end() && !done; ++it)
        if (first_word(*it) == key) {
          if (word == "@set")
            *it = rest;
          else
            card.erase(it);
          done = true;
        }
      if (!done && word == "@drop") fail("no line with key '" + key + "' to drop");
      if (!done) card.push_back(rest);
    } else if (word == "@add") {
      card.push_back(rest);
    } else if (word == "@empty") {
      card.clear();
    } else if (word == "@expect" || word == "@expect-ok") {
      current.expect_ok = word == "@expect-ok";
      current.expect = rest;
      if (!current.expect_ok && rest.empty()) fail("@expect needs a message");
      for (auto &l : card) current.card += l + "\n";
      corpus.cases.push_back(current);
      in_case = false;
    } else {
      fail("unknown line '" + line + "'");
    }
  }
  if (in_case) fail("case " + current.name + " has no @expect");
  return corpus;
}

const Corpus &corpus()
{
  static const Corpus c = read_corpus();
  return c;
}

std::vector<Case> all_cases()
{
  try {
    return corpus().cases;
  } catch (std::exception &e) {
    Case c;
    c.name = "corpus_unreadable";
    c.expect = e.what();
    return {c};
  }
}

// a fresh folder for the cards under the build folder ($NCF_BUILD, which ctest sets; a test
// binary run by hand without it uses the system's temporary folder, never the source tree)
fs::path scratch(const std::string &name)
{
  const char *build = getenv("NCF_BUILD");
  const fs::path root = (build && *build) ? fs::path(build)
                                          : fs::temp_directory_path() / "ncf-test-output";
  fs::path p = root / "test-output" / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::string replace_all(std::string s, const std::string &from, const std::string &to)
{
  for (auto pos = s.find(from); pos != std::string::npos; pos = s.find(from, pos + to.size()))
    s.replace(pos, from.size(), to);
  return s;
}

void write(const fs::path &p, const std::string &text)
{
  FILE *fp = fopen(p.c_str(), "w");
  ASSERT_NE(fp, nullptr) << p;
  fputs(text.c_str(), fp);
  fclose(fp);
}

// every file in dir whose name starts with prefix
std::vector<std::string> files_starting(const fs::path &dir, const std::string &prefix)
{
  std::vector<std::string> out;
  for (auto &e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.rfind(prefix, 0) == 0) out.push_back(n);
  }
  return out;
}

// (gtest names a failing case by this, not by its bytes)
void PrintTo(const Case &c, std::ostream *os)
{
  *os << c.name;
}

class BadCard : public ::testing::TestWithParam<Case> {};

const std::string MATERIALS = SRC + "/potentials/ncf.materials";

}    // namespace

TEST(BadCardCorpus, IsLargeAndNamesEveryCaseOnce)
{
  std::map<std::string, int> seen;
  int errors = 0;
  for (const auto &c : corpus().cases) {
    EXPECT_EQ(seen[c.name]++, 0) << "case name given twice: " << c.name;
    if (!c.expect_ok) errors++;
  }
  EXPECT_GE(errors, 100) << "the card part of the bad-input corpus has shrunk";
}

TEST_P(BadCard, FailsWithItsMessageAndWritesNothing)
{
  const Case &c = GetParam();
  ASSERT_NE(c.name, "corpus_unreadable") << c.expect;
  static const fs::path dir = [] {
    fs::path d = scratch("bad_cards");
    for (auto &f : corpus().files) write(d / f.first, replace_all(f.second, "@DIR@", d.string()));
    return d;
  }();
  std::string safe = ncftest::case_test_name(::testing::TestParamInfo<Case>(c, 0));
  const fs::path card = dir / (safe + ".card");
  write(card, replace_all(replace_all(c.card, "@MATERIALS@", MATERIALS), "@DIR@", dir.string()));
  const std::string prefix = "out-" + safe;
  std::string err, summary;
  const bool ok = NCFGEN::generate(card.string(), (dir / prefix).string(), err, &summary);
  if (getenv("NCF_BAD_INPUT_SHOW"))
    fprintf(stderr, "[%s] %s\n", c.name.c_str(), ok ? "(no error)" : err.c_str());
  const std::string where =
      CORPUS + ":" + std::to_string(c.line) + " case " + c.name + "\n" + c.card;
  if (c.expect_ok) {
    EXPECT_TRUE(ok) << err << "\n" << where;
    EXPECT_EQ(files_starting(dir, prefix).size(), 6u) << where;
    for (auto &f : files_starting(dir, prefix)) fs::remove(dir / f);
    return;
  }
  EXPECT_FALSE(ok) << where;
  EXPECT_THAT(err, HasSubstr(c.expect)) << where;
  EXPECT_TRUE(files_starting(dir, prefix).empty()) << "output left behind\n" << where;
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadCard, ::testing::ValuesIn(all_cases()),
                         ncftest::case_test_name<Case>);

// ---------------------------------------------------------------------- atomic outputs

namespace {

const std::string GOOD_CARD = "name t\nmaterials " + MATERIALS +
    "\nseed 3\nlayer 0 deg\n  areal_weight 150 g/m^2\n  material SGL_Sigrafil_CT24-4.8/240\n"
    "  sigma 1 deg\npattern tricot\ngauge 5\nstitch_length 2.2 mm\nyarn PES_5.0tex\n";

std::string read(const fs::path &p)
{
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}    // namespace

TEST(GenAtomicOutputs, AFailedWriteLeavesNothingAndKeepsTheEarlierFiles)
{
  const fs::path dir = scratch("gen_atomic");
  write(dir / "a.card", GOOD_CARD);
  std::string err;
  ASSERT_TRUE(NCFGEN::generate((dir / "a.card").string(), (dir / "out").string(), err)) << err;
  auto before = files_starting(dir, "out.");
  ASSERT_EQ(before.size(), 6u);
  std::map<std::string, std::string> content;
  for (auto &f : before) content[f] = read(dir / f);

  // the last temporary file cannot be created (a folder holds its name): the run fails, the
  // five files it had written are gone, and the files of the first run are untouched
  const fs::path blocker = dir / ("out.summary.tmp-ncf-gen-" + std::to_string((long) getpid()));
  fs::create_directories(blocker);
  write(dir / "b.card", GOOD_CARD + "rve 2 1\n");
  EXPECT_FALSE(NCFGEN::generate((dir / "b.card").string(), (dir / "out").string(), err));
  EXPECT_THAT(err, HasSubstr("out.summary: cannot write the output file"));
  EXPECT_THAT(err, HasSubstr("nothing was written"));
  fs::remove(blocker);
  auto after = files_starting(dir, "out.");
  EXPECT_EQ(after, before);
  for (auto &f : after) EXPECT_EQ(read(dir / f), content[f]) << f << " changed";
}

TEST(GenAtomicOutputs, AnOutputNameTakenByAFolderWritesNothing)
{
  const fs::path dir = scratch("gen_atomic_folder");
  write(dir / "a.card", GOOD_CARD);
  // the last output's name is a folder: no output may be renamed into place
  fs::create_directories(dir / "out.summary" / "inside");
  std::string err;
  EXPECT_FALSE(NCFGEN::generate((dir / "a.card").string(), (dir / "out").string(), err));
  EXPECT_THAT(err, HasSubstr("out.summary"));
  EXPECT_THAT(err, HasSubstr("the name is a folder; nothing was written"));
  auto left = files_starting(dir, "out.");
  EXPECT_EQ(left, std::vector<std::string>{"out.summary"});
}

TEST(GenAtomicOutputs, AMissingFolderWritesNothing)
{
  const fs::path dir = scratch("gen_atomic_nofolder");
  write(dir / "a.card", GOOD_CARD);
  std::string err;
  EXPECT_FALSE(
      NCFGEN::generate((dir / "a.card").string(), (dir / "no" / "such" / "out").string(), err));
  EXPECT_THAT(err, HasSubstr("out.layers.data: cannot write the output file"));
  EXPECT_FALSE(fs::exists(dir / "no"));
}
