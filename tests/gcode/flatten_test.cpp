// Flattening: a program written as it runs must make the same motions as the program, with
// every line run once, and say where each of its lines came from.
#include "ccomp/gcode/flatten.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "ccomp/gcode/dialect.hpp"
#include "ccomp/gcode/tool_table.hpp"
#include "error_of.hpp"
#include "linuxcnc_suite.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

struct Flat {
  std::string text;
  gcode::LineOrigins origins;
};

Flat flatten_source(gcode::LineSource& in, const gcode::InterpreterOptions& options) {
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  Flat f;
  try {
    f.origins = gcode::flatten(in, out, options);
  } catch (...) {
    std::fclose(out);
    std::free(buffer);
    throw;
  }
  std::fclose(out);
  f.text.assign(buffer, size);
  std::free(buffer);
  return f;
}

Flat flatten_text(const std::string& program, const gcode::InterpreterOptions& options = {}) {
  gcode::LineSource in = gcode::LineSource::from_string(program, "in.ngc");
  return flatten_source(in, options);
}

/// The motion calls of a trace, without the messages (a flattened (DEBUG,#1) prints a
/// parameter no line sets any more).
std::vector<std::string> motions_only(const TraceResult& t) {
  std::vector<std::string> calls;
  for (const std::string& c : motion_calls(t.lines))
    if (!c.starts_with("MESSAGE")) calls.push_back(c);
  return calls;
}

TEST(Flatten, LoopsAndSubroutinesUnrolledWithTheirValues) {
  const std::string program =
      "%\n"
      "(a bolt circle)\n"
      "G21 G90\n"
      "o100 sub\n"
      "  G0 X[#1] Y[#2] (over the hole)\n"
      "  G1 Z-1 F200\n"
      "o100 endsub\n"
      "#1 = 0\n"
      "o1 while [#1 LT 3]\n"
      "  o100 call [10 * #1] [#1 / 3]\n"
      "  #1 = [#1 + 1] (next)\n"
      "o1 endwhile\n"
      "N50 G91 G1 X#1 #2=7\n"
      "M2\n"
      "(not run)\n"
      "%\n";
  const Flat f = flatten_text(program);
  EXPECT_EQ(f.text,
            "%\n"
            "(a bolt circle)\n"
            "G21 G90\n"
            "  G0 X0.0 Y0.0 (over the hole)\n"
            "  G1 Z-1 F200\n"
            "  (next)\n"
            "  G0 X10.0 Y0.333333 (over the hole)\n"
            "  G1 Z-1 F200\n"
            "  (next)\n"
            "  G0 X20.0 Y0.666667 (over the hole)\n"
            "  G1 Z-1 F200\n"
            "  (next)\n"
            "N50 G91 G1 X3.0\n"
            "M2\n"
            "%\n");
  // Where each line came from: the sub's lines from lines 5 and 6, each time.
  EXPECT_EQ(f.origins.at(4).line, 5U);
  EXPECT_EQ(f.origins.at(4).file, "in.ngc");
  EXPECT_EQ(f.origins.at(8).line, 6U);
  EXPECT_EQ(f.origins.at(13).line, 13U);
  EXPECT_EQ(f.origins.at(15).line, 16U);
  EXPECT_TRUE(f.origins.at(99).file.empty());
}

TEST(Flatten, FanucSubprogramsAndTheirRepeats) {
  gcode::InterpreterOptions o;
  o.dialect = *gcode::dialect_named("fanuc");
  const std::string program =
      "%\nO0010 (MAIN)\nG21 G90 G0 X0 Y0\nM98 P20 L2\nN9 M98 P20\nG0 X5.\nM30\n"
      "O20 (SUB)\nG91 G1 X1. F100\nM99\n%\n";
  const Flat f = flatten_text(program, o);
  EXPECT_EQ(f.text,
            "%\nO0010 (MAIN)\nG21 G90 G0 X0 Y0\nG91 G1 X1. F100\nG91 G1 X1. F100\nG91 G1 X1. F100\nG0 X5.\nM30\n%\n");
  const auto calls = motions_only(trace_text(f.text, o));
  EXPECT_EQ(calls, motions_only(trace_text(program, o)));
}

TEST(Flatten, NumbersOfCodesAreWholeAndCoordinatesHaveAPoint) {
  EXPECT_EQ(gcode::flat_number('G', 1.0), "1");
  EXPECT_EQ(gcode::flat_number('G', 43.1), "43.1");
  EXPECT_EQ(gcode::flat_number('M', 3.0), "3");
  EXPECT_EQ(gcode::flat_number('X', 10.0), "10.0");
  EXPECT_EQ(gcode::flat_number('X', -1.0 / 3.0), "-0.333333");
  EXPECT_EQ(gcode::flat_number('Y', -1e-9), "0.0");
  EXPECT_EQ(gcode::flat_number('A', 51.428571428), "51.428571");
  EXPECT_EQ(gcode::flat_number('F', 250.0), "250.0");
  EXPECT_EQ(gcode::flat_number('S', 1200.0), "1200");
}

TEST(Flatten, BlockDeleteLinesAreNotRunSoNotWritten) {
  gcode::InterpreterOptions o;
  o.block_delete = true;
  EXPECT_EQ(flatten_text("G21 G0 X1\n/G0 X2\nG0 X3\nM2\n", o).text, "G21 G0 X1\nG0 X3\nM2\n");
  EXPECT_EQ(flatten_text("G21 G0 X1\n/G0 X2\nG0 X3\nM2\n").text, "G21 G0 X1\n/G0 X2\nG0 X3\nM2\n");
}

TEST(Flatten, AnEndlessLoopEndsAtTheBlockLimit) {
  gcode::InterpreterOptions o;
  o.max_blocks = 1000;
  const Error e = test::error_of([&] { (void)flatten_text("G21\no1 while [1]\nG0 X1\nG0 X2\no1 endwhile\nM2\n", o); },
                                 "an endless loop was flattened");
  EXPECT_NE(e.message().find("more than 1000 blocks executed"), std::string::npos) << e.message();
  EXPECT_LE(gcode::kFlattenMaxBlocks, gcode::InterpreterOptions{}.max_blocks);
}

// Every program of LinuxCNC's suite that ccomp runs: its flattened form makes the same motions.
class FlattenSuite : public ::testing::TestWithParam<SuiteProgram> {};

TEST_P(FlattenSuite, MakesTheSameMotions) {
  const fs::path path = fs::path(corpus_dir()) / "linuxcnc" / GetParam().path;
  gcode::InterpreterOptions o;
  o.machine_units = gcode::Units::inch;  // as the suite ran rs274
  o.subroutine_path.push_back(path.parent_path().string());
  if (fs::exists(path.parent_path() / "test.tbl"))
    o.tools = gcode::read_tool_table_file((path.parent_path() / "test.tbl").string());
  const TraceResult original = trace_file(path.string(), o);
  if (original.error) GTEST_SKIP() << "the interpreter refuses it: " << original.error->message();
  const std::vector<std::string> motions = motions_only(original);
  gcode::LineSource in = gcode::LineSource::open(path.string());
  const Flat f = flatten_source(in, o);
  const TraceResult flat = trace_text(f.text, o);
  ASSERT_FALSE(flat.error) << flat.error->message() << "\n" << f.text;
  if (const auto diff = compare_calls(motions_only(flat), motions, 1e-4)) FAIL() << *diff << "\n" << f.text;
}

INSTANTIATE_TEST_SUITE_P(Corpus, FlattenSuite, ::testing::ValuesIn(suite_programs()), suite_test_name);

}  // namespace
}  // namespace ccomp::test
