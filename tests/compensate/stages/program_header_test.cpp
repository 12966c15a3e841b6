// The header that marks a compensated program: written, recognised, read back.
#include "ccomp/compensate/program_header.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>

#include "ccomp/error.hpp"

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

TEST(ProgramHeader, IsRecognisedByContentAsAControlOrATransferKeepsIt) {
  // Issue 49: upper-cased (Fanuc, DNC), respaced, `( ccomp`, a `;` comment: compensated
  // twice before (X10 -> 9.9986 -> 9.9972).
  const model::MachineModel m = test::sample_machine("hmc-xyzb");
  std::string upper = header_line(m, 0.001);
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const std::string& line : {upper, std::string("( ccomp 0.1.0  compensated for machine 'x' model sha256:ab at 1 um)"),
                                  std::string("; ccomp 0.1.0 compensated for machine 'x'"),
                                  std::string("\t(CCOMP 0.1.0 COMPENSATED FOR\tMACHINE 'X')")})
    EXPECT_TRUE(is_header_line(line)) << line;
  const auto facts = read_header(upper);
  ASSERT_TRUE(facts);
  EXPECT_EQ(facts->model_sha256, m.sha256) << "the hash read in any case";
  EXPECT_DOUBLE_EQ(facts->tolerance, 0.001);
  EXPECT_FALSE(is_header_line("(CCOMP MADE THIS PART)"));
  EXPECT_FALSE(is_header_line("G1 X1 ; ccomp 1.0 compensated for machine 'x'"));

  // The job refuses it a few lines down, after a tape's `%`, a program number and a comment.
  const std::string program = "%\nO1234\n(PART 7)\n" + upper + "\nG21 G90\nG0 X10 Y0 Z-100 B0\nM2\n%\n";
  try {
    (void)test::compensate(program, m, 0.001);
    ADD_FAILURE() << "compensated twice";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::safety);
    EXPECT_EQ(e.where().line, 4U);
  }
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
