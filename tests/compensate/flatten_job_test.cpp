// The main job with --flatten: a program whose lines run several times (loops, subroutine
// calls) is compensated as it runs, each run of a line with its own correction, and what
// goes wrong is reported at the original's lines.
#include <gtest/gtest.h>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/error.hpp"
#include "error_of.hpp"
#include "job_runner.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

// Four holes of a bolt circle by a loop calling a subroutine, then G91 steps in a repeat.
const std::string kLoops =
    "G21 G90 G94 G54\n"
    "T1 M6\n"
    "G43 H1\n"
    "o100 sub\n"
    "  G0 X[#1] Y[#2] Z-95\n"
    "  G1 Z-100.5 F200\n"
    "  G1 X[#1 + 5] F400\n"
    "  G0 Z-95\n"
    "o100 endsub\n"
    "#1 = 0\n"
    "o1 while [#1 LT 4]\n"
    "  o100 call [80 * COS[#1 * 90]] [60 * SIN[#1 * 90]]\n"
    "  #1 = [#1 + 1]\n"
    "o1 endwhile\n"
    "G91 G1 X10 F500\n"
    "o2 repeat [3]\n"
    "  G1 X5 Y[#1]\n"
    "o2 endrepeat\n"
    "G90\n"
    "M30\n";

TEST(FlattenJob, ALoopIsRefusedWithoutItAndCompensatedRunByRunWithIt) {
  const Error e =
      test::error_of([&] { (void)compensate(kLoops, sample_machine("hmc-xyzb-geometric"), compensate::JobOptions{}); },
                     "a line run four times was compensated once");
  EXPECT_EQ(e.kind(), ErrorKind::unsupported);
  EXPECT_EQ(e.where().line, 5U);
  EXPECT_NE(e.message().find("--flatten"), std::string::npos) << e.message();
  compensate::JobOptions o;
  o.flatten = true;
  compensate::JobReport report;
  const std::string output = compensate(kLoops, sample_machine("hmc-xyzb-geometric"), o, &report);
  for (const char* gone : {"o100", "o1 ", "#1", "endwhile", "repeat"})
    EXPECT_EQ(output.find(gone), std::string::npos) << gone << " in\n" << output;
  EXPECT_EQ(report.compensated_moves, 4U * 4U + 1U + 3U);
  // Run through the machine model, the output follows what the original meant.
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  const model::ForwardModel m(mm);
  compensate::CheckOptions check;
  check.interpreter.tools.tools[1] = kTool1;
  gcode::LineSource original = gcode::LineSource::from_string(kLoops, "in.ngc");
  gcode::LineSource compensated = gcode::LineSource::from_string(output, "out.ngc");
  const compensate::PathError left = compensate::verify(original, compensated, m, check);
  gcode::LineSource again = gcode::LineSource::from_string(kLoops, "in.ngc");
  EXPECT_GT(compensate::predict(again, m, check).max, 0.010);
  EXPECT_GE(left.moves, 4U * 2U + 1U + 3U);
  EXPECT_LE(left.max, 0.001 + 1e-4) << left.max * 1000 << " um at line " << left.worst_line << " of\n" << output;
}

TEST(FlattenJob, AProgramWithoutLoopsComesOutTheSameEitherWay) {
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  compensate::JobOptions flat;
  flat.flatten = true;
  for (unsigned seed : {3U, 8U}) {
    const std::string program = random_program(seed);
    EXPECT_EQ(compensate(program, mm, flat), compensate(program, mm, compensate::JobOptions{})) << "seed " << seed;
  }
}

TEST(FlattenJob, ARefusalInASubroutineNamesTheOriginalLine) {
  // The third call sends X to 600 mm, beyond the sample machine's 500.
  const std::string program =
      "G21 G90\nT1 M6\nG43 H1\no7 sub\n  G0 X[#1] Y0 Z-95\no7 endsub\n"
      "o7 call [0]\no7 call [300]\no7 call [600]\nM30\n";
  compensate::JobOptions o;
  o.flatten = true;
  const Error e =
      test::error_of([&] { (void)compensate(program, sample_machine("hmc-xyzb-geometric"), o); }, "X600 was accepted");
  EXPECT_EQ(e.kind(), ErrorKind::safety);
  EXPECT_EQ(e.where().file, "in.ngc");
  EXPECT_EQ(e.where().line, 5U) << e.message();
  EXPECT_NE(e.message().find("600"), std::string::npos) << e.message();
}

TEST(FlattenJob, ASubroutineFileIsNotEditedInPlaceButFlattenedIn) {
  // The output is one program: a line of a file on the subroutine path cannot be rewritten
  // there (before, its offset was taken for one of the program's own lines).
  const std::string dir = temp_dir("flatten_sub_file");
  write_file(dir + "/hole.ngc", "o<hole> sub\n  G0 X[#1] Y0 Z-95\n  G1 Z-100 F200\no<hole> endsub\n");
  const std::string program =
      "G21 G90\nT1 M6\nG43 H1\nG0 X0 Y0 Z-90\nG1 X10 Y10 F500\no<hole> call [30]\nG0 Z-90\nM30\n";
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  compensate::JobOptions o;
  o.interpreter.subroutine_path = {dir};
  const Error e =
      test::error_of([&] { (void)compensate(program, mm, o); }, "a subroutine file's line was compensated in place");
  EXPECT_EQ(e.kind(), ErrorKind::unsupported);
  EXPECT_EQ(e.where().file, dir + "/hole.ngc");
  EXPECT_EQ(e.where().line, 2U);
  EXPECT_NE(e.message().find("--flatten"), std::string::npos) << e.message();
  o.flatten = true;
  const std::string output = compensate(program, mm, o);
  EXPECT_EQ(output.find("o<hole>"), std::string::npos) << output;
  const model::ForwardModel m(mm);
  compensate::CheckOptions check;
  check.interpreter.tools.tools[1] = kTool1;
  check.interpreter.subroutine_path = {dir};
  gcode::LineSource original = gcode::LineSource::from_string(program, "in.ngc");
  gcode::LineSource compensated = gcode::LineSource::from_string(output, "out.ngc");
  const compensate::PathError left = compensate::verify(original, compensated, m, check);
  EXPECT_EQ(left.moves, 2U) << "the G1 of the program and the subroutine's";
  EXPECT_LE(left.max, 0.001 + 1e-4) << output;
}

TEST(FlattenJob, WarningsNameTheOriginalLines) {
  compensate::JobOptions o;
  o.flatten = true;
  o.decimals = 3;  // warned of once, at the first move: line 5, the subroutine's first
  std::vector<std::uint32_t> lines;
  o.warning = [&lines](const std::string&, std::uint32_t line) { lines.push_back(line); };
  (void)compensate(kLoops, sample_machine("hmc-xyzb-geometric"), o);
  ASSERT_EQ(lines.size(), 1U);
  EXPECT_EQ(lines[0], 5U);
}

}  // namespace
}  // namespace ccomp::test
