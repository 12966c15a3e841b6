#pragma once
// Test support: the programs of LinuxCNC's interpreter test suite in the corpus
// (corpus/linuxcnc, without its bad/ folder of programs meant to fail), for tests that run
// over all of them, and what ccomp must do with each (the cases' table).
#include <gtest/gtest.h>

#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace ccomp::test {

struct SuiteProgram {
  std::string path;  ///< relative to corpus/linuxcnc
};
std::ostream& operator<<(std::ostream& os, const SuiteProgram& p);

enum class Expect {
  same_motions,   ///< motions equal to `expected`
  same_messages,  ///< (DEBUG,...) messages equal to `expected` (test.sh keeps only those)
  accepted,       ///< accepted, no motion in `expected` to compare
  rejected,       ///< the interpreter must refuse the program
  out_of_scope,
};

struct SuiteCase {
  const char* name;     ///< test name
  const char* program;  ///< relative to corpus/linuxcnc
  Expect expect;
  const char* expected = "";  ///< relative to the program's folder; default `expected`
  const char* tool_table = "";
  const char* sub_path = "";
  const char* param = "";   ///< NAME=VALUE
  const char* reason = "";  ///< why out of scope
  bool awk = true;          ///< test.sh pipes rs274 through awk '{$1=""; print}'
};

std::ostream& operator<<(std::ostream& os, const SuiteCase& c);

/// What ccomp must do with each program of the suite, as LinuxCNC's own tests expect.
const std::vector<SuiteCase>& suite_cases();
/// The case of a program (path relative to corpus/linuxcnc), or nullptr for one not listed.
const SuiteCase* suite_case(std::string_view program);

/// Every .ngc of the suite, sorted by path.
std::vector<SuiteProgram> suite_programs();
/// A test name made of the path.
std::string suite_test_name(const ::testing::TestParamInfo<SuiteProgram>& program);

}  // namespace ccomp::test
