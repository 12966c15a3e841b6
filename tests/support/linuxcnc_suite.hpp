#pragma once
// Test support: the programs of LinuxCNC's interpreter test suite in the corpus
// (corpus/linuxcnc, without its bad/ folder of programs meant to fail), for tests that run
// over all of them.
#include <gtest/gtest.h>

#include <ostream>
#include <string>
#include <vector>

namespace ccomp::test {

struct SuiteProgram {
  std::string path;  ///< relative to corpus/linuxcnc
};
std::ostream& operator<<(std::ostream& os, const SuiteProgram& p);

/// Every .ngc of the suite, sorted by path.
std::vector<SuiteProgram> suite_programs();
/// A test name made of the path.
std::string suite_test_name(const ::testing::TestParamInfo<SuiteProgram>& program);

}  // namespace ccomp::test
