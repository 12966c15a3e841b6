// The test oracle itself: the comparisons the LinuxCNC suite and the rs274 differential tests
// rest on must report a difference when there is one, or every test built on them passes.
#include "trace_capture.hpp"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

namespace ccomp::test {
namespace {

TEST(CompareCalls, AcceptsNumbersWithinTheToleranceOnly) {
  const std::vector<std::string> expected{"STRAIGHT_FEED(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)"};
  EXPECT_FALSE(compare_calls({"STRAIGHT_FEED(1.00005, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)"}, expected));
  const auto off = compare_calls({"STRAIGHT_FEED(1.0002, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)"}, expected);
  ASSERT_TRUE(off);
  EXPECT_NE(off->find("motion 1"), std::string::npos) << *off;
}

TEST(CompareCalls, ReportsADifferentCallOrAMissingOne) {
  const std::vector<std::string> expected{"STRAIGHT_FEED(1, 2, 3, 0, 0, 0)", "STRAIGHT_TRAVERSE(0, 0, 5, 0, 0, 0)"};
  EXPECT_TRUE(compare_calls({"STRAIGHT_TRAVERSE(1, 2, 3, 0, 0, 0)", expected[1]}, expected));
  const auto missing = compare_calls({expected[0]}, expected);
  ASSERT_TRUE(missing);
  EXPECT_NE(missing->find("first missing: STRAIGHT_TRAVERSE"), std::string::npos) << *missing;
  EXPECT_TRUE(compare_calls({expected[0], expected[1], expected[1]}, expected));
}

TEST(CompareCalls, ComparesMessagesWordByWordWithNumbersWithinTolerance) {
  EXPECT_FALSE(compare_calls({"PRINT x is 1.000000"}, {"PRINT x is 1.000001"}));
  EXPECT_FALSE(compare_calls({"PRINT x is -0.000000"}, {"PRINT x is 0.000000"}));
  EXPECT_TRUE(compare_calls({"PRINT x is 1.000000"}, {"PRINT y is 1.000000"}));
  EXPECT_TRUE(compare_calls({"PRINT x is 1.5"}, {"PRINT x is 1.0"}));
  EXPECT_TRUE(compare_calls({"PRINT x is"}, {"PRINT x is 1"}));
}

TEST(Observable, KeepsMotionsMessagesAndPrintedLinesAfterTheSuitesAwk) {
  const std::vector<std::string> trace{
      "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)",
      "    2 N..... STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
      "    3 N..... MESSAGE(\"x=2\")",
      "hello   world",
  };
  const std::vector<std::string> expected{"STRAIGHT_FEED(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
                                          "MESSAGE(\"x=2\")"};
  EXPECT_EQ(observable(trace, false), (std::vector<std::string>{expected[0], expected[1], "PRINT hello world"}));
  // The suite's awk drops the first field, so a printed line loses its first word.
  EXPECT_EQ(observable(trace, true), (std::vector<std::string>{expected[0], expected[1], "PRINT world"}));
}

TEST(RunProgram, RecordsTheMotionsOfAProgramAndRefusesABadOne) {
  const RunResult ok = run_program("G21 G90\nG0 X1 Y2\nG1 Z-3 F100\nM2\n");
  ASSERT_FALSE(ok.error);
  ASSERT_EQ(ok.motions.size(), 2u);
  const RunResult bad = run_program("G21\nG1 X1\nM2\n");  // a feed move without a feed rate
  EXPECT_TRUE(bad.error);
  EXPECT_DOUBLE_EQ(evaluate("[2 + 3] * 4"), 20.0);
}

TEST(TraceCapture, FileHelpersFailTheTestOnAMissingFile) {
  EXPECT_NONFATAL_FAILURE((void)read_file("/nonexistent/fixture.ngc"), "cannot read /nonexistent/fixture.ngc");
  EXPECT_NONFATAL_FAILURE((void)read_lines("/nonexistent/expected"), "cannot read");
  EXPECT_NONFATAL_FAILURE(write_file("/nonexistent/dir/out.ngc", "x"), "cannot write");
  const std::string path = temp_dir("helpers") + "/round.txt";
  write_file(path, "a\nb\n");
  EXPECT_EQ(read_file(path), "a\nb\n");
  EXPECT_EQ(read_lines(path), (std::vector<std::string>{"a", "b"}));
}

}  // namespace
}  // namespace ccomp::test
