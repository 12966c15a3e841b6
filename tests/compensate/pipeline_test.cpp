// The main job on two threads (one compensates the moves, the other reads, interprets and
// writes the program) must write exactly what it writes on one, and report the first
// error in program order whichever thread met it first.
#include <gtest/gtest.h>

#include <utility>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"
#include "compensate/move_pipeline.hpp"
#include "job_runner.hpp"
#include "sample_models.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

/// A finishing pass long enough for several batches of moves: zig-zag rows (every row turns
/// X round, so the full model's reversals switch), an arc and a rapid now and then, the
/// table turned between the halves, a G93 4-axis stretch; then the random programs' mix.
std::string long_program() {
  std::string p = "G21 G90 G94 G54\nT1 M6\nG43 H1\nG0 X-60 Y-40 Z-90 B0\nG1 F1500\n";
  char line[160];
  for (int row = 0; row < 200; ++row) {
    const double y = -40 + row * 0.6;
    for (int k = 0; k <= 110; ++k) {
      const double x = (row % 2 == 0 ? -60 + k : 50 - k) + 0.013 * k;
      std::snprintf(line, sizeof line, "X%.4f Y%.4f Z%.4f\n", x, y, -90 + 2 * std::sin(0.05 * x + 0.1 * y));
      p += line;
    }
    if (row % 15 == 7) p += "G2 I-5 J0\nG1\n";  // a full circle back to the row's end
    if (row % 30 == 29) p += "G0 Z-60\nG0 B" + std::to_string(row) + "\nG0 Z-90\nG1\n";
  }
  p += "G93 G1 X20 Y10 Z-80 B30 F6\nG1 X30 B45 F8\nG94 F1500\n";
  std::string mix = random_program(3);
  mix.erase(mix.rfind("M30"));
  return p + mix + "M30\n";
}

compensate::JobOptions full_model_options(int threads) {
  compensate::JobOptions o;
  o.sensors = {{"bed", 24}, {"column", 23}, {"spindle", 31}};
  o.time = 3600;
  o.threads = threads;
  return o;
}

TEST(Pipeline, TwoThreadsWriteWhatOneWrites) {
  const model::MachineModel mm = sample_machine("hmc-xyzb");
  const std::string program = long_program();
  compensate::JobReport one, two;
  const std::string by_one = compensate(program, mm, full_model_options(1), &one);
  const std::string by_two = compensate(program, mm, full_model_options(2), &two);
  // More batches than the pipeline holds (four of 1,024 moves on two threads): its ring
  // goes round.
  ASSERT_GT(one.compensated_moves, 5U * compensate::MovePipeline::kThreaded.moves) << "several batches of moves";
  EXPECT_GT(one.take_up_moves, 0U) << "the rows' reversals are taken up";
  EXPECT_EQ(by_one, by_two);
  // What the report counts is what was written: the header's line, the program's, and
  // the added ones (a take-up too fine for the program's digits writes none).
  auto lines = [](const std::string& text) {
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  };
  EXPECT_EQ(lines(by_one), 1 + lines(program) + one.added_lines);
  EXPECT_EQ(one.compensated_moves, two.compensated_moves);
  EXPECT_EQ(one.added_lines, two.added_lines);
  EXPECT_EQ(one.take_up_moves, two.take_up_moves);
  EXPECT_EQ(one.max_error_before, two.max_error_before);
  EXPECT_EQ(one.max_error_after, two.max_error_after);
  EXPECT_EQ(one.max_correction, two.max_correction);
  EXPECT_EQ(one.max_orientation_error, two.max_orientation_error);
  EXPECT_GT(one.max_error_before, 0.02) << "the sample machine's error is tens of um";
  EXPECT_LT(one.max_error_after, 0.001);
}

TEST(Pipeline, WhicheverThreadTakesTheSharedWorkTheOutputIsTheSame) {
  // The moves' nominal end poses and the error before at their probes may be taken by the
  // reading thread or the worker (adaptive by default: batch by batch, whichever has time
  // to spare). Each split, on one thread and two, writes what the reading thread alone
  // writes, and reports the same figures to the bit: the error before's largest value
  // comes out the same though each side skips probes against a largest of its own.
  // Drilling cycles in the mix: their moves are solved, and their error before taken, on
  // the reading thread between batches the worker may have taken the probes of.
  const model::MachineModel mm = sample_machine("hmc-xyzb");
  std::string program = long_program();
  std::string cycles = random_program(5, true);
  ASSERT_NE(cycles.find(" G99 G8"), std::string::npos) << "drilling cycles among the moves";
  program.insert(program.rfind("M30"), cycles.substr(0, cycles.rfind("M30")));
  compensate::JobReport reference;
  compensate::JobOptions o = full_model_options(1);
  o.expand_cycles = true;
  o.split = compensate::WorkSplit::reader;
  const std::string expected = compensate(program, mm, o, &reference);
  ASSERT_GT(reference.max_error_before, 0.02) << "the sample machine's error is tens of um";
  using compensate::WorkSplit;
  for (const WorkSplit split : {WorkSplit::worker, WorkSplit::alternate, WorkSplit::adaptive, WorkSplit::reader})
    for (const int threads : {1, 2}) {
      if (split == WorkSplit::reader && threads == 1) continue;  // the reference
      o = full_model_options(threads);
      o.expand_cycles = true;
      o.split = split;
      compensate::JobReport report;
      const std::string written = compensate(program, mm, o, &report);
      const std::string what = "split " + std::to_string(static_cast<int>(split)) + ", " + std::to_string(threads) +
                               " thread(s)";
      EXPECT_EQ(written, expected) << what;
      EXPECT_EQ(report.max_error_before, reference.max_error_before) << what;
      EXPECT_EQ(report.max_error_after, reference.max_error_after) << what;
      EXPECT_EQ(report.max_correction, reference.max_correction) << what;
      EXPECT_EQ(report.max_orientation_error, reference.max_orientation_error) << what;
      EXPECT_EQ(report.added_lines, reference.added_lines) << what;
    }
}

TEST(Pipeline, BatchesOfBentMovesHoldFewerMoves) {
  // Full circles of 60 mm radius give about 500 chords each at 1 um: a batch passes on
  // after some 30 of them (its points, not its moves, are bounded), several times over
  // this program; the output must not depend on where the batches end.
  const model::MachineModel mm = sample_machine("hmc-xyzb");
  std::string program = "G21 G90 G94 G54\nT1 M6\nG43 H1\nG0 X60 Y0 Z-90 B0\nG1 F1500\n";
  for (int k = 0; k < 150; ++k) program += k % 2 ? "G2 X60 Y0 I-60 J0\n" : "G3 X60 Y0 Z-89.9 I-60 J0\n";
  program += "M30\n";
  compensate::JobReport one, two;
  const std::string by_one = compensate(program, mm, full_model_options(1), &one);
  const std::string by_two = compensate(program, mm, full_model_options(2), &two);
  ASSERT_GT(one.added_lines, 150U * 400U) << "hundreds of chords a circle";
  EXPECT_EQ(by_one, by_two);
  EXPECT_EQ(one.max_error_after, two.max_error_after);
  EXPECT_LT(one.max_error_after, 0.001);
}

/// The error the job stops with, on `threads` threads.
Error job_error(const std::string& program, const model::MachineModel& mm, int threads) {
  compensate::JobOptions o;
  o.threads = threads;
  try {
    (void)compensate(program, mm, o);
  } catch (const Error& e) {
    return e;
  }
  return Error(ErrorKind::internal, "accepted");
}

TEST(Pipeline, AnEarlierMovesRefusalComesBeforeALaterLinesError) {
  // The move on line 3 is refused when its correction is written (beyond a bound set tiny
  // here); the interpreter, running ahead, meets the bad line 5 first. Line 3's refusal is
  // the job's error.
  model::MachineModel mm = sample_machine("hmc-xyzb-geometric");
  mm.max_correction = 1e-6;
  const std::string program = "G21 G90 G54\nT1 M6 G43 H1\nG0 X10 Y10 Z-100\nG1 X20 F500\nG1 X[1+]\nM30\n";
  for (int threads : {1, 2}) {
    const Error e = job_error(program, mm, threads);
    EXPECT_EQ(e.kind(), ErrorKind::safety) << threads << " threads: " << e.message();
    EXPECT_EQ(e.where().line, 3U) << threads << " threads: " << e.message();
    EXPECT_NE(e.message().find("beyond the model's bound"), std::string::npos) << e.message();
  }
  // Without the refusal, the bad line is the error.
  mm.max_correction = 0.5;
  for (int threads : {1, 2}) {
    const Error e = job_error(program, mm, threads);
    EXPECT_EQ(e.kind(), ErrorKind::program) << threads << " threads: " << e.message();
    EXPECT_EQ(e.where().line, 5U) << threads << " threads: " << e.message();
  }
}

TEST(Pipeline, AnInverseThatCannotConvergeNamesItsBlock) {
  // X's positioning error cancels its travel beyond X = 0 (EXX = -x): no command reaches
  // X = 20, and the error names the block that asked for it, not where the reading was.
  // Where the error there is within max_correction, the solve is what failed; beyond it
  // (20 mm here, against the default 0.5 mm), the model is.
  const std::string terms = "terms:\n  - {name: EXX, form: polynomial, unit: um, coefficients: [0, -1000]}\n";
  std::string program = "G21 G90 G54\nT1 M6 G43 H1\nG0 X0 Y0 Z-100\nG1 X20 F500\n";
  for (int k = 0; k < 50; ++k) program += "G1 Y" + std::to_string(k) + "\n";
  program += "M30\n";
  for (const auto& [bound, says] : {std::pair{"max_correction: 100 mm\n", "did not converge"},
                                    std::pair{"", "the model's error here is 20 mm, beyond its bound"}}) {
    const model::MachineModel mm =
        model::parse_machine_model(std::string(kHmcChain) + bound + terms, "cancelling.yaml");
    for (int threads : {1, 2}) {
      const Error e = job_error(program, mm, threads);
      EXPECT_EQ(e.kind(), ErrorKind::safety) << threads << " threads: " << e.message();
      EXPECT_NE(e.message().find(says), std::string::npos) << e.message();
      EXPECT_EQ(e.where().line, 4U) << threads << " threads: " << e.message();
      EXPECT_EQ(e.source_line(), "G1 X20 F500");
    }
  }
}

}  // namespace
}  // namespace ccomp::test
