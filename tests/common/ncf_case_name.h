// USER-NCF tests: the GoogleTest name of a case of a corpus (tests/bad_input): its name with every
// character that is not a letter or digit replaced by '_'. Engine-free, for unit and integration
// tests alike.
#ifndef NCF_CASE_NAME_H
#define NCF_CASE_NAME_H

#include <gtest/gtest.h>

#include <cctype>
#include <string>

namespace ncftest {

template <class Case> std::string case_test_name(const ::testing::TestParamInfo<Case> &info)
{
  std::string s;
  for (char c : info.param.name) s += std::isalnum((unsigned char) c) ? c : '_';
  return s;
}

}    // namespace ncftest

#endif
