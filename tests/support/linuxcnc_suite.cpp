#include "linuxcnc_suite.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "trace_capture.hpp"

namespace ccomp::test {

namespace fs = std::filesystem;

std::ostream& operator<<(std::ostream& os, const SuiteProgram& p) {
  return os << p.path;
}

std::vector<SuiteProgram> suite_programs() {
  std::vector<SuiteProgram> programs;
  const fs::path root = fs::path(corpus_dir()) / "linuxcnc";
  if (!fs::exists(root)) return programs;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file() && e.path().extension() == ".ngc" && e.path().string().find("/bad/") == std::string::npos)
      programs.push_back({fs::relative(e.path(), root).string()});
  std::sort(programs.begin(), programs.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
  return programs;
}

std::string suite_test_name(const ::testing::TestParamInfo<SuiteProgram>& program) {
  std::string name = program.param.path;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

// The listing the parametrised suites are made of: were the corpus not found, they would
// have no cases and nothing to fail.
TEST(LinuxcncSuite, ListsTheCorpusProgramsButNotTheBadOnes) {
  const std::vector<SuiteProgram> programs = suite_programs();
  EXPECT_GE(programs.size(), 60U) << "corpus at " << corpus_dir();
  for (const SuiteProgram& p : programs) EXPECT_EQ(p.path.find("bad/"), std::string::npos) << p.path;
}

}  // namespace ccomp::test
