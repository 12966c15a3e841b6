// Issue 49: verify proves coverage. A full circle's end is its start, so an output that
// leaves the circle out still came to both of its ends: what counts is the angle the cut
// went round. And a table turning back while the tool moves on is cut to its end at any
// distance from the B axis (at 100 mm it was said to leave 9.8 mm uncut).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "ccomp/compensate/verify.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"
#include "job_runner.hpp"
#include "sample_models.hpp"

namespace ccomp::test {
namespace {

compensate::PathError verify_text(const std::string& original, const std::string& output,
                                  const model::MachineModel& mm) {
  gcode::LineSource a = gcode::LineSource::from_string(original, "in.ngc");
  gcode::LineSource b = gcode::LineSource::from_string(output, "out.ngc");
  return compensate::verify(a, b, model::ForwardModel(mm), {});
}

const model::MachineModel& exact_vmc() {
  static const model::MachineModel mm = model::parse_machine_model(kVmcChain, "exact.yaml");
  return mm;
}

TEST(VerifyCoverage, AFullCircleLeftOutIsUncut) {
  // A 50 mm circle between a lead-in and a lead-out: left out whole, 314 mm are uncut from
  // its line; a half of it left out is half that; the program against itself, nothing.
  const std::string head = "G21 G90 G17 F500\nG0 X0 Y0 Z0\nG1 X50\n";
  const std::string tail = "G1 X60\nG1 Y10\nM2\n";
  const std::string program = head + "G2 X50 Y0 I-50 J0\n" + tail;
  const std::string halves = head + "G2 X-50 Y0 I-50 J0\nG2 X50 Y0 I50 J0\n" + tail;
  const double circle = 2 * std::numbers::pi * 50.0;
  EXPECT_EQ(verify_text(program, program, exact_vmc()).uncut_length, 0.0);
  EXPECT_EQ(verify_text(program, halves, exact_vmc()).uncut_length, 0.0) << "the same circle in two halves";
  const compensate::PathError gone = verify_text(program, head + tail, exact_vmc());
  EXPECT_NEAR(gone.uncut_length, circle, 1e-6);
  EXPECT_EQ(gone.uncut_line, 4U);
  const compensate::PathError half = verify_text(halves, head + "G2 X-50 Y0 I-50 J0\nG0 X50 Y0\n" + tail, exact_vmc());
  EXPECT_NEAR(half.uncut_length, circle / 2, 1e-6);
  // Two turns in one block (P2): one left out is a turn uncut.
  const std::string twice = head + "G2 X50 Y0 I-50 J0 P2\n" + tail;
  EXPECT_EQ(verify_text(twice, twice, exact_vmc()).uncut_length, 0.0);
  EXPECT_NEAR(verify_text(twice, program, exact_vmc()).uncut_length, circle, 1e-6);
}

TEST(VerifyCoverage, AFullCircleCompensatedAsChordsIsCovered) {
  // The job writes the circle as chords on a machine with errors: covered to its end.
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  const std::string program = "G21 G90 G17 F500\nG0 X0 Y0 Z100 B0\nG1 X50\nG2 X50 Y0 I-50 J0\nG1 X60\nM2\n";
  const std::string out = compensate(program, mm, 0.001);
  const compensate::PathError e = verify_text(program, out, mm);
  EXPECT_EQ(e.uncut_length, 0.0) << "from line " << e.uncut_line;
  EXPECT_LE(e.max, 0.001);
}

TEST(VerifyCoverage, ATableTurningBackWhileTheToolMovesOnIsCutToItsEndAtAnyLever) {
  // B turns to 10 degrees, then back while X moves 10 mm; the output the program itself, or
  // with the way back in steps. At 100 mm from B's axis the way back starts 17 mm from where
  // the way out ends... both cut whole.
  const model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  for (const char* z : {"Z100", "Z50", "Z300"}) {
    const std::string head = std::string("G21 G90 G17 F500\nG0 X0 Y0 ") + z + " B0\nG1 B10\n";
    const std::string program = head + "G1 X10 B0\nM2\n";
    const std::string stepped = head + "G1 X0.01 B9.99\nG1 X0.05 B9.95\nG1 X10 B0\nM2\n";
    for (const std::string& output : {program, stepped}) {
      const compensate::PathError e = verify_text(program, output, mm);
      EXPECT_EQ(e.uncut_length, 0.0) << z << " from line " << e.uncut_line << "\n" << output;
    }
  }
}

}  // namespace
}  // namespace ccomp::test
