// Rewriting on its own: a move's points as edits of its block and lines after it, the
// rounding of the written digits carried from word to word.
#include "compensate/move_rewriter.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "ccomp/gcode/dialect.hpp"
#include "ccomp/compensate/machine_coordinates.hpp"
#include "job_runner.hpp"
#include "memory_file.hpp"
#include "parsed_block.hpp"

namespace ccomp::compensate {
namespace {

using test::ParsedBlock;

/// A rewriter over a one-line program, its output in memory.
class Rewriting {
 public:
  explicit Rewriting(const std::string& program)
      : machine_(test::sample_machine("zero")),
        source_(gcode::LineSource::from_string(program, "p.ngc")),
        writer_(source_.another_reader(), out_.get(), "(header)"),
        rewriter_(writer_, machine_, {}, report_, "p.ngc") {}
  MoveRewriter& rewriter() { return rewriter_; }
  const JobReport& report() const { return report_; }
  std::string output() {
    writer_.finish();
    return out_.text();
  }

 private:
  model::MachineModel machine_;
  gcode::LineSource source_;
  test::MemoryFile out_;
  gcode::ProgramWriter writer_;
  JobReport report_;
  MoveRewriter rewriter_;
};

CompensatedPoint point_at(double s, const gcode::Axes& controlled, const gcode::Offsets& offsets,
                          bool take_up = false) {
  return CompensatedPoint{s, compensate::chain_of(controlled, offsets), take_up};
}

TEST(MoveRewriter, ASplitMoveKeepsItsLineForTheFirstPointAndAddsLinesForTheRest) {
  Rewriting r("G1 X10 Y5 F100 (cut)\n");
  const ParsedBlock b("G1 X10 Y5 F100 (cut)");
  const gcode::Offsets offsets;
  gcode::Motion m;
  m.kind = gcode::MotionKind::feed;
  m.offsets = &offsets;
  r.rewriter().position().commanded = {0, 5, 0};
  const std::vector<CompensatedPoint> points{point_at(0.5, {5.00012, 5, 0}, offsets),
                                             point_at(1.0, {10.00081, 5.00003, 0}, offsets)};
  r.rewriter().rewrite(m, b.block, points, 0, "\n");
  EXPECT_EQ(r.output(), "(header)\nG1 X5.0001 Y5.0000 F100 (cut)\nG1 X10.0008\n");
  EXPECT_EQ(r.report().added_lines, 1U);
}

TEST(MoveRewriter, ALoneLetterIsNoWordOfItsAxis) {
  // Fanuc-family dialects let a letter stand alone, ignored: `G0 X Y0 X1` moves X to 1. The
  // correction goes into X1; a value written into the lone X would make a second X word
  // (the job fuzzer found `g0xg0x0y0z` rewritten to `g0x-0.00093g0x0y-0.00129z-0.00176`,
  // which the interpreter then refuses).
  Rewriting r("G0 X Y0 X1 Z\n");
  const ParsedBlock b("G0 X Y0 X1 Z", 1, *gcode::dialect_named("fanuc"));
  const gcode::Offsets offsets;
  gcode::Motion m;
  m.kind = gcode::MotionKind::traverse;
  m.offsets = &offsets;
  r.rewriter().position().commanded = {0, 0, 0};
  r.rewriter().rewrite(m, b.block, {point_at(1.0, {1.00012, -0.00021, 0.00034}, offsets)}, 0, "\n");
  EXPECT_EQ(r.output(), "(header)\nG0 X Y-0.0002 X1.0001 Z Z0.0003\n");
}

TEST(MoveRewriter, IncrementalWordsCarryTheirRoundingInsteadOfSummingIt) {
  Rewriting r("G91 G1 X1\n");
  MoveRewriter& w = r.rewriter();
  // Three steps of 0.00004 mm: each rounds to nothing alone; carried, the second writes 0.0001.
  double sum = 0.0;
  for (int k = 1; k <= 3; ++k) {
    const double p = 0.00004 * k, last = 0.00004 * (k - 1);
    const auto word = w.axis_word(0, p, last, true, false, "1", false);
    if (word) sum += std::stod(*word);
    w.position().commanded[0] = p;  // the machine follows the command, as rewrite() does
  }
  EXPECT_DOUBLE_EQ(sum, 0.0001);
}

TEST(MoveRewriter, AnArcBlockBecomesALine) {
  const ParsedBlock arc("G2 X10 Y0 I5 J0 F200");
  std::vector<gcode::Edit> edits;
  arc_to_line_edits(arc.block, edits);
  EXPECT_EQ(gcode::apply_edits(arc.text, edits), "G1 X10 Y0 F200");
  const ParsedBlock modal("X0 Y10 R5");  // the arc modal: G1 written in front
  edits.clear();
  arc_to_line_edits(modal.block, edits);
  EXPECT_EQ(gcode::apply_edits(modal.text, edits), "G1 X0 Y10");
}

TEST(MoveRewriter, KnowsTheProgramStops) {
  for (const char* stop : {"M0", "M1", "M2", "M30", "M60", "G1 X1 M30"})
    EXPECT_TRUE(has_stop_code(ParsedBlock(stop).block)) << stop;
  for (const char* go_on : {"M3", "M5", "G1 X1", "M100"})
    EXPECT_FALSE(has_stop_code(ParsedBlock(go_on).block)) << go_on;
}

}  // namespace
}  // namespace ccomp::compensate
