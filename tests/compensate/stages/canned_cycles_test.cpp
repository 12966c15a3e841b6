// Canned cycles on their own: the interpreter's cycle motions in, the cycle block's words (or
// its expanded moves) out, with the stages a cycle works with and nothing of the job around.
#include "compensate/canned_cycles.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <regex>

#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/compensate/machine_coordinates.hpp"
#include "error_of.hpp"
#include "job_runner.hpp"
#include "memory_file.hpp"

namespace ccomp::compensate {
namespace {

/// The stages a cycle needs, over a program in memory, and a sink that hands the cycle's
/// motions to CannedCycles and follows the others uncompensated.
class CycleRun : public gcode::CanonSink {
 public:
  CycleRun(const std::string& program, bool expand)
      : machine_(test::sample_machine("hmc-xyzb-geometric")),
        forward_(machine_),
        source_(gcode::LineSource::from_string(program, "p.ngc")),
        writer_(source_.another_reader(), out_.get(), "(header)"),
        solver_(forward_, {}),
        error_before_(forward_, {}),
        guards_(machine_, options_, report_, "p.ngc"),
        rewriter_(writer_, machine_, {}, report_, "p.ngc"),
        cycles_(CycleStages{solver_, error_before_, rewriter_, guards_, writer_, report_}, machine_, expand, "p.ngc") {}

  /// The program run through the cycles stage: its output.
  std::string run() {
    gcode::LineSource in = gcode::LineSource::from_string(source_text(), "p.ngc");
    gcode::Interpreter().run(in, *this);
    cycles_.finish();
    writer_.finish();
    return out_.text();
  }
  const JobReport& report() const { return report_; }

  void block(const gcode::Block& block, const gcode::SourceLine& line) override {
    cycles_.finish();
    cycles_.note_block(block);
    block_ = &block;
    line_ = line;
    repeated_ = line.offset < furthest_;
    furthest_ = std::max(furthest_, line.offset);
  }
  void motion(const gcode::Motion& m) override {
    if (m.source == gcode::MotionSource::canned_cycle) return cycles_.add(m, *block_, line_, repeated_);
    solver_.compensator.moved(compensate::chain_of(m.end, *m.offsets));
    rewriter_.position().commanded = m.end;
  }

 private:
  std::string source_text() {
    gcode::LineSource copy = source_.another_reader();
    std::string text;
    gcode::SourceLine l;
    while (copy.next(l)) text += std::string(l.text) + "\n";
    return text;
  }

  model::MachineModel machine_;
  model::ForwardModel forward_;
  gcode::LineSource source_;
  test::MemoryFile out_;
  gcode::ProgramWriter writer_;
  JobOptions options_;
  JobReport report_;
  MoveSolver solver_;
  Compensator error_before_;
  JobGuards guards_;
  MoveRewriter rewriter_;
  CannedCycles cycles_;
  const gcode::Block* block_ = nullptr;
  gcode::SourceLine line_;
  std::uint64_t furthest_ = 0;
  bool repeated_ = false;
};

const std::string kOneHole = "G17 G21 G90 G94\nG0 X10 Y10 Z-80\nG81 X20 Y15 Z-110 R-90 F100\nG80\nM30\n";

TEST(CannedCycles, KnowsTheCycleCodes) {
  for (double g : {73.0, 74.0, 76.0, 81.0, 85.0, 89.0}) EXPECT_TRUE(is_cycle_code(g)) << g;
  for (double g : {0.0, 1.0, 80.0, 90.0, 98.0}) EXPECT_FALSE(is_cycle_code(g)) << g;
}

TEST(CannedCycles, OneHoleIsCompensatedInItsBlocksWords) {
  CycleRun run(kOneHole, false);
  const std::string out = run.run();
  std::smatch hole;
  ASSERT_TRUE(std::regex_search(out, hole, std::regex(R"(\nG81 X(\S+) Y(\S+) Z(\S+) R(\S+) F100\n)"))) << out;
  // Moved by the model's correction: off the nominal by some um, and by less than its bound.
  const double nominal[] = {20, 15, -110, -90};
  for (int k = 0; k < 4; ++k) {
    const double off = std::abs(std::stod(hole[k + 1]) - nominal[k]);
    EXPECT_LT(off, 0.5) << hole[0];
  }
  EXPECT_NE(hole[0].str(), "\nG81 X20.0000 Y15.0000 Z-110.0000 R-90.0000 F100\n");
  EXPECT_EQ(run.report().compensated_moves, 1U);
  EXPECT_GT(run.report().max_error_before, 0.0);
}

TEST(CannedCycles, IncrementalRepeatsAreRefusedInWordsAndExpandedIntoMoves) {
  const std::string repeats = "G17 G21 G90 G94\nG0 X10 Y10 Z-80\nG91 G81 X5 Z-20 R-5 L3 F100\nG90 G80\nM30\n";
  CycleRun words(repeats, false);
  const Error e = test::error_of([&] { (void)words.run(); }, "a G91 cycle in its words");
  EXPECT_EQ(e.kind(), ErrorKind::unsupported);
  EXPECT_EQ(e.where().line, 3U);
  EXPECT_NE(e.message().find("incremental (G91) canned cycles"), std::string::npos) << e.message();
  EXPECT_NE(e.message().find("--expand-cycles"), std::string::npos) << e.message();
  CycleRun expanded(repeats, true);
  const std::string out = expanded.run();
  EXPECT_NE(out.find("\nG91\nG90 G80"), std::string::npos) << out;  // absolute moves, G91 restored after
  // header, five lines, G90 and G91 around the moves, and the moves
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 8 + static_cast<long>(expanded.report().added_lines)) << out;
  EXPECT_GE(expanded.report().added_lines, 9U) << out;  // three holes: to R, down, back up
}

TEST(CannedCycles, ACycleOnALineThatRunsAgainIsRefused) {
  CycleRun run(
      "G17 G21 G90 G94\nG0 X10 Y10 Z-80\n#1 = 0\no1 while [#1 LT 2]\nG81 X20 Y15 Z-110 R-90 F100\n"
      "#1 = [#1 + 1]\no1 endwhile\nG80\nM30\n",
      false);
  const Error e = test::error_of([&] { (void)run.run(); }, "a cycle in a loop");
  EXPECT_EQ(e.where().line, 5U);
  EXPECT_NE(e.message().find("runs more than once"), std::string::npos) << e.message();
}

}  // namespace
}  // namespace ccomp::compensate
