// The header that marks a compensated program: written, recognised, read back.
#include "ccomp/compensate/program_header.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "job_runner.hpp"

namespace ccomp::compensate {
namespace {

TEST(ProgramHeader, ReadsBackTheModelHashAndTheTolerance) {
  const model::MachineModel m = test::sample_machine("hmc-xyzb");
  const std::string line = header_line(m, 0.0025);
  ASSERT_TRUE(is_header_line(line)) << line;
  const auto facts = read_header(line);
  ASSERT_TRUE(facts);
  EXPECT_EQ(facts->model_sha256, m.sha256);
  EXPECT_DOUBLE_EQ(facts->tolerance, 0.0025);
}

TEST(ProgramHeader, IsRecognisedAfterABomAndBlanksAndNotInOtherComments) {
  EXPECT_TRUE(is_header_line("\xEF\xBB\xBF  (ccomp 1.0 compensated for machine 'x' model sha256:ab at 1 um)"));
  EXPECT_FALSE(is_header_line("(ccomp made this part)"));
  EXPECT_FALSE(is_header_line("G1 X1 (ccomp 1.0 compensated for machine 'x')"));
  EXPECT_FALSE(read_header("G1 X1"));
}

TEST(ProgramHeader, AnOlderHeaderWithoutTheToleranceReadsNaN) {
  const auto facts = read_header("(ccomp 0.9 compensated for machine 'x' model sha256:0a1b)");
  ASSERT_TRUE(facts);
  EXPECT_EQ(facts->model_sha256, "0a1b");
  EXPECT_TRUE(std::isnan(facts->tolerance));
}

TEST(ProgramHeader, AModelNameCannotCloseTheComment) {
  model::MachineModel m = test::sample_machine("zero");
  m.name = "a(b)c\nd";
  const std::string line = header_line(m, 0.001);
  EXPECT_NE(line.find("'a_b_c_d'"), std::string::npos) << line;
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_TRUE(is_header_line(line));
}

}  // namespace
}  // namespace ccomp::compensate
