// A move of more chords than a task holds (a helix of many turns) is compensated and
// written in parts: memory stays bounded, and the output must be what one task would
// write: one move, its block's words edited, its added lines in order, in G93 each
// keeping its share of the block's time, the same on one thread as on two.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/model/forward.hpp"
#include "job_runner.hpp"

namespace ccomp::test {
namespace {

TEST(LongMove, AHelixOfThousandsOfChordsIsWrittenInPartsAsOneMove) {
  // Radius 60 at 1 um: about 770 chords a turn, 40 turns: some 31,000 chords, several
  // parts. In inverse time F0.5 the block takes 2 minutes.
  const std::string program =
      "G21 G90 G17 G94\nG0 X60 Y0 Z0\nG93 G2 X60 Y0 Z-5 I-60 J0 P40 F0.5 (helix)\nG94 G0 Z10\nM2\n";
  const model::MachineModel mm = sample_machine("vmc-xyz");
  compensate::JobOptions options;
  compensate::JobReport one, two;
  options.threads = 1;
  const std::string by_one = compensate(program, mm, options, &one);
  options.threads = 2;
  const std::string by_two = compensate(program, mm, options, &two);
  EXPECT_EQ(by_one, by_two);
  EXPECT_EQ(one.compensated_moves, 3U) << "the helix is one move, however many parts";
  EXPECT_GT(one.added_lines, 20000U);

  // The helix' block and the lines after it, up to the next block of the program: their
  // durations (1/F minutes) add up to the block's.
  std::istringstream lines(by_one);
  std::string line;
  double minutes = 0;
  int helix_lines = 0;
  bool in_helix = false;
  while (std::getline(lines, line)) {
    if (line.find("(helix)") != std::string::npos)
      in_helix = true;
    else if (in_helix && line.rfind("G1 ", 0) != 0)
      break;
    if (!in_helix) continue;
    ++helix_lines;
    const auto f = line.find('F');
    ASSERT_NE(f, std::string::npos) << line;
    minutes += 1.0 / std::stod(line.substr(f + 1));
  }
  EXPECT_EQ(helix_lines, static_cast<int>(one.added_lines) + 1);
  EXPECT_NEAR(minutes, 2.0, 1e-6);

  const model::ForwardModel forward(mm);
  gcode::LineSource original = gcode::LineSource::from_string(program, "in.ngc");
  gcode::LineSource output = gcode::LineSource::from_string(by_one, "out.ngc");
  const compensate::PathError left = compensate::verify(original, output, forward, {});
  EXPECT_LE(left.max, 0.001 + 1e-4);
  EXPECT_LT(left.uncut_length, 1e-6);
}

}  // namespace
}  // namespace ccomp::test
