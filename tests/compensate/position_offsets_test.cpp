// Offsets set from where the machine is (G92, G10 L20) after a compensated move: the
// rewritten program leaves the machine off the nominal point by the correction, and the
// offset would take the correction in. The job moves the values given so the offset comes
// out as the original's; what it cannot rewrite so, it refuses. And a cut that starts
// where an uncompensated move (G53) left the machine begins off by the machine's error:
// the job goes to the compensated start first and says so.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/forward.hpp"
#include "error_of.hpp"
#include "job_runner.hpp"

namespace ccomp::test {
namespace {

/// A 20 mm square at the program origin, from (0, 0), depth Z-95 (tool H1, 100 mm).
constexpr const char* kSquare = "G1 Z-95 F300\nG1 X20\nG1 Y20\nG1 X0\nG1 Y0\nG0 Z-60\n";

compensate::PathError left_of(const std::string& program, const std::string& output, const model::MachineModel& mm) {
  const model::ForwardModel forward(mm);
  compensate::CheckOptions check;
  check.interpreter.tools.tools[1] = kTool1;
  gcode::LineSource a = gcode::LineSource::from_string(program, "in.ngc");
  gcode::LineSource b = gcode::LineSource::from_string(output, "out.ngc");
  return compensate::verify(a, b, forward, check);
}

TEST(PositionOffsets, ASecondPartPlacedWithG92OrG10L20IsCutWhereTheOriginalPutsIt) {
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  const std::string head = "G21 G90 G54 T1 M6 G43 H1\nG0 X-50 Y-40 Z-60\n";
  // After the first square the machine stands off its nominal end by the correction there;
  // the second square is placed 60 mm over by making that point read (-60, -40), or (the
  // same written as an expression and as G10 L20) by naming the point the machine is at.
  for (const std::string& place :
       {std::string("G0 X-50 Y-40\nG92 X-60 Y-40\n"), std::string("#1=-60\nG0 X-50 Y-40\nG92 X#1 Y[#1 + 20]\n"),
        std::string("G0 X-50 Y-40\nG10 L20 P0 X-60 Y-40\n"),
        // a touch-off: the tool's length set so the tip reads Z-95 (as it does)
        std::string("G0 X-50 Y-40\nG10 L10 P1 Z-60\nG43 H1\nG92 X-60 Y-40\n")}) {
    const std::string program = head + "G0 X0 Y0\n" + kSquare + place + "G0 X0 Y0\n" + kSquare + "M30\n";
    compensate::JobReport report;
    const std::string output = compensate(program, mm, 0.001, &report);
    const compensate::PathError left = left_of(program, output, mm);
    EXPECT_LE(left.max, 0.001 + 1e-4) << place << "worst at output line " << left.worst_line << "\n" << output;
    EXPECT_LT(left.uncut_length, 1e-6) << place;
    EXPECT_EQ(output.find(place.substr(place.find('\n') + 1)), std::string::npos)
        << "the offset's values are moved by the correction:\n"
        << output;
  }
}

TEST(PositionOffsets, WhatCannotBeRewrittenIsRefusedNamingTheLine) {
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  const std::string head = "G21 G90 G54 T1 M6 G43 H1\nG0 X-50 Y-40 Z-60\nG0 X0 Y0\n" + std::string(kSquare);
  for (const std::string& block : {std::string("G10 L11 P1 X0 Z100\n"), std::string("G10 L20 P0 X0 Y0 R30\n"),
                                   std::string("G10 L20 P2 X0 Y0\n")}) {
    const Error e =
        test::error_of([&] { (void)compensate(head + block + "M30\n", mm, 0.001); }, block, "was not refused");
    EXPECT_EQ(e.kind(), ErrorKind::unsupported) << e.what();
    EXPECT_EQ(e.where().line, 10U) << e.what();
    EXPECT_NE(e.message().find("sets an offset from where the machine is"), std::string::npos) << e.what();
  }
  // Before any compensated move the machine is where the original has it: nothing to do.
  const std::string early =
      "G21 G90 G54 T1 M6 G43 H1\nG10 L20 P2 X0 Y0 R30\nG0 X0 Y0 Z-60\n" + std::string(kSquare) + "M30\n";
  EXPECT_NO_THROW((void)compensate(early, mm, 0.001));
}

TEST(PositionOffsets, ACutFromWhereAMachineCoordinateMoveLeftTheMachineIsReported) {
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  // G53 puts the controlled point at machine (0, 0, -60): the program's (0, 0, -60) too
  // (G54 is zero here), uncompensated; the cut then starts from there.
  const std::string program = "G21 G90 G54 T1 M6 G43 H1\nG53 G0 X0 Y0 Z-160\nG1 X20 F300\nG1 Y20\nM30\n";
  compensate::JobOptions options;
  std::vector<std::string> warnings;
  options.warning = [&](const std::string& text, std::uint32_t line) {
    warnings.push_back(std::to_string(line) + ": " + text);
  };
  compensate::JobReport report;
  const std::string output = compensate(program, mm, options, &report);
  const compensate::PathError left = left_of(program, output, mm);
  ASSERT_EQ(warnings.size(), 1U);
  EXPECT_EQ(warnings[0].rfind("3: this cut starts where a move in machine coordinates", 0), 0U) << warnings[0];
  EXPECT_GT(left.max, 0.005) << "the machine's error where G53 left it";
  // The job's figure counts the start's error, from the start point (verify measures
  // from the path, which that error runs partly along): never less than verify's.
  EXPECT_GE(report.max_error_after, left.max - 1e-4);
  EXPECT_EQ(report.added_lines, 1U) << "the move to the compensated start\n" << output;
}

TEST(PositionOffsets, AMotionCodeBesideAReferenceReturnGetsNoWords) {
  // `G0 G28` without axis words: G28 returns to the reference point, the G0 moves nowhere.
  // Its correction written into the block ("G0 G28 X-0.0236 Y-0.0328 ...", found by the job
  // fuzzer) made G28's intermediate point of it, which the interpreter and LinuxCNC refuse:
  // two G codes that both use axis values.
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  const std::string program = "G21 G90 G54 T1 M6 G43 H1\nG0 X10 Y10 Z-60\nG0 G28\nG1 X20 F300\nM30\n";
  const std::string output = compensate(program, mm, 0.001);
  EXPECT_NE(output.find("\nG0 G28\n"), std::string::npos) << output;
  EXPECT_NO_THROW((void)left_of(program, output, mm)) << output;
}

}  // namespace
}  // namespace ccomp::test
