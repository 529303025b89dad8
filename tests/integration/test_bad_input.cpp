// The bad-input corpus of the LAMMPS styles (tests/bad_input/lammps.cases): every case is a short
// input that must stop with an error whose text holds the expected message (the style, the
// keyword and the value). Each case runs in a fresh LAMMPS instance, in-process.
//
// Corpus format (one case after the other; '#' lines outside a block are comments):
//   @file NAME ... @end         a file written to the scratch folder before the cases run; the
//                               cases name it as ${dir}/NAME (a LAMMPS string variable)
//   @prelude NAME ... @end      a block of LAMMPS commands that cases (and later preludes) can
//                               start with
//   @case NAME                  starts a case; then LAMMPS commands, '@use PRELUDE' lines, and
//   @expect TEXT                the end of the case: the error message must contain TEXT
//   @expect-ok                  the end of a check case: the input must run without error
// NCF_BAD_INPUT_SHOW=1 prints every case's message.

#include "ncf_case_name.h"
#include "ncf_lammps_test.h"

#include "fmt/format.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>

using namespace ncftest;
using ::testing::HasSubstr;

namespace {

struct Case {
  std::string name;
  int line = 0;                         // of '@case' in the corpus
  std::vector<std::string> commands;    // preludes expanded
  std::string expect;                   // "" with expect_ok
  bool expect_ok = false;
};

struct Corpus {
  std::map<std::string, std::string> files;
  std::vector<Case> cases;
};

const std::string CORPUS = "tests/bad_input/lammps.cases";

Corpus read_corpus()
{
  const std::string path = source_path(CORPUS);
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  Corpus corpus;
  std::map<std::string, std::vector<std::string>> preludes;
  std::string line, block_kind, block_name, block_text;
  std::vector<std::string> block_lines;
  Case current;
  bool in_case = false;
  int lineno = 0;
  auto fail = [&](const std::string &what) {
    throw std::runtime_error(fmt::format("{}:{}: {}", path, lineno, what));
  };
  while (std::getline(in, line)) {
    ++lineno;
    if (!block_kind.empty()) {
      if (line == "@end") {
        if (block_kind == "file")
          corpus.files[block_name] = block_text;
        else
          preludes[block_name] = block_lines;
        block_kind.clear();
      } else if (block_kind == "prelude" && line.rfind("@use ", 0) == 0) {
        // a prelude may start from another one
        auto it = preludes.find(line.substr(5));
        if (it == preludes.end()) fail("no prelude '" + line.substr(5) + "'");
        block_lines.insert(block_lines.end(), it->second.begin(), it->second.end());
      } else {
        block_text += line + "\n";
        const auto pos = line.find_first_not_of(" \t");
        if (pos != std::string::npos && line[pos] != '#') block_lines.push_back(line);
      }
      continue;
    }
    const auto pos = line.find_first_not_of(" \t");
    if (pos == std::string::npos || line[pos] == '#') continue;
    std::istringstream words(line);
    std::string word;
    words >> word;
    std::string rest;
    std::getline(words, rest);
    rest.erase(0, rest.find_first_not_of(" \t"));
    if (word == "@file" || word == "@prelude") {
      if (in_case) fail("a block inside a case");
      block_kind = word.substr(1);
      block_name = rest;
      block_text.clear();
      block_lines.clear();
    } else if (word == "@case") {
      if (in_case) fail("case " + current.name + " has no @expect");
      current = Case();
      current.name = rest;
      current.line = lineno;
      in_case = true;
    } else if (!in_case) {
      fail("'" + line + "' outside a case");
    } else if (word == "@use") {
      auto it = preludes.find(rest);
      if (it == preludes.end()) fail("no prelude '" + rest + "'");
      current.commands.insert(current.commands.end(), it->second.begin(), it->second.end());
    } else if (word == "@expect" || word == "@expect-ok") {
      current.expect_ok = word == "@expect-ok";
      current.expect = rest;
      if (!current.expect_ok && rest.empty()) fail("@expect needs a message");
      corpus.cases.push_back(current);
      in_case = false;
    } else if (word[0] == '@') {
      fail("unknown directive " + word);
    } else {
      current.commands.push_back(line);
    }
  }
  if (in_case) fail("case " + current.name + " has no @expect");
  if (!block_kind.empty()) fail("block " + block_name + " has no @end");
  return corpus;
}

const Corpus &corpus()
{
  static const Corpus c = read_corpus();
  return c;
}

std::string folder()
{
  static const std::string dir = [] {
    const std::string d = scratch_dir("bad_input");
    for (const auto &f : corpus().files) {
      FILE *fp = fopen((d + "/" + f.first).c_str(), "w");
      if (!fp) throw std::runtime_error("cannot write " + d + "/" + f.first);
      fputs(f.second.c_str(), fp);
      fclose(fp);
    }
    return d;
  }();
  return dir;
}

std::vector<Case> all_cases()
{
  try {
    return corpus().cases;
  } catch (std::exception &e) {
    // a broken corpus is one failing case, not a silent empty suite
    Case c;
    c.name = "corpus_unreadable";
    c.expect = e.what();
    return {c};
  }
}

// (gtest names a failing case by this, not by its bytes)
void PrintTo(const Case &c, std::ostream *os)
{
  *os << c.name;
}

class BadInput : public ::testing::TestWithParam<Case> {};

}    // namespace

TEST(BadInputCorpus, IsLargeAndNamesEveryCaseOnce)
{
  const auto &cases = corpus().cases;
  std::map<std::string, int> seen;
  int errors = 0;
  for (const auto &c : cases) {
    EXPECT_EQ(seen[c.name]++, 0) << "case name given twice: " << c.name;
    if (!c.expect_ok) errors++;
  }
  EXPECT_GE(errors, 200) << "the LAMMPS part of the bad-input corpus has shrunk";
}

TEST_P(BadInput, StopsWithItsMessage)
{
  const Case &c = GetParam();
  ASSERT_NE(c.name, "corpus_unreadable") << c.expect;
  const std::string dir = folder();
  std::string msg;
  {
    Lammps l;
    l.cmd("variable dir string " + dir);
    msg = error_of([&] {
      for (const auto &cmd : c.commands) l.cmd(cmd);
    });
  }
  if (getenv("NCF_BAD_INPUT_SHOW"))
    fprintf(stderr, "[%s] %s\n", c.name.c_str(), msg.empty() ? "(no error)" : msg.c_str());
  std::string script;
  for (const auto &cmd : c.commands) script += "    " + cmd + "\n";
  if (c.expect_ok)
    EXPECT_EQ(msg, "") << CORPUS << ":" << c.line << " case " << c.name << "\n" << script;
  else
    EXPECT_THAT(msg, HasSubstr(c.expect)) << CORPUS << ":" << c.line << " case " << c.name << "\n"
                                          << script;
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInput, ::testing::ValuesIn(all_cases()),
                         ncftest::case_test_name<Case>);
