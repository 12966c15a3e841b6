// Issue 49: lines are counted by what the interpreter reads, and read once where it can. A
// loop skipping the same false `if` rescanned it on every pass (quadratic: a 690 kB file ran
// half an hour) while the loop guard counted only what ran; a million blank lines in a row,
// where nothing goes back, were refused as an endless loop. And `flatten` is bounded by
// what it writes, not only by the blocks it runs (a loop of long lines headed for 340 GB).
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "ccomp/error.hpp"
#include "ccomp/gcode/flatten.hpp"
#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/gcode/source.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

/// Counts the blocks the interpreter hands its sink (every line it reads and announces).
class BlockCounter : public gcode::CanonSink {
 public:
  void block(const gcode::Block& /*block*/, const gcode::SourceLine& /*line*/) override { ++blocks; }
  void motion(const gcode::Motion& /*motion*/) override { ++motions; }
  std::uint64_t blocks = 0, motions = 0;
};

std::string lines(const std::string& line, int count) {
  std::string out;
  for (int i = 0; i < count; ++i) out += line;
  return out;
}

/// A loop of `passes` that moves once a pass and skips a false `if` of `skipped` lines.
std::string skipping_loop(int passes, int skipped, bool moves = true) {
  return "G21 G90 F100\n#1=0\nO1 repeat [" + std::to_string(passes) + "]\n" + (moves ? "G1 X[#1]\n" : "") +
         "#1=[#1+1]\nO2 if [#1 LT 0]\n" + lines("G1 X5 (never)\n", skipped) + "O2 endif\nO1 endrepeat\nM2\n";
}

TEST(SkipScan, AMillionBlankOrCommentLinesInARowAreNotALoop) {
  for (const char* filler : {"\n", "(a comment)\n", "; a comment\n"}) {
    const RunResult r = run_program("G21 G90\nG0 X1\n" + lines(filler, 1'100'000) + "G0 X2\nM2\n");
    EXPECT_FALSE(r.error) << filler << ": " << (r.error ? format_error(*r.error) : "");
    EXPECT_EQ(r.motions.size(), 2U) << filler;
  }
}

TEST(SkipScan, AStretchSkippedOnEveryPassIsReadOnce) {
  // 2,000 passes over a 5,000-line false `if`: read once, not 10 million times.
  const std::string program = skipping_loop(2000, 5000);
  gcode::LineSource source = gcode::LineSource::from_string(program, "loop.ngc");
  BlockCounter counter;
  gcode::Interpreter interpreter(gcode::InterpreterOptions{});
  interpreter.run(source, counter);
  EXPECT_EQ(counter.motions, 2000U);
  EXPECT_LT(counter.blocks, 5000U + 2000U * 8U);
}

TEST(SkipScan, SkippedLinesCountTowardsTheLimits) {
  // What is skipped counts as read: 200 passes over 5,000 skipped lines are over a million
  // blocks, past a limit of 500,000...
  gcode::InterpreterOptions o;
  o.max_blocks = 500'000;
  const RunResult over = run_program(skipping_loop(200, 5000), o);
  ASSERT_TRUE(over.error);
  EXPECT_NE(over.error->message().find("executed or skipped"), std::string::npos) << over.error->message();
  // ...and a loop that never moves, only skips, is endless after a million of them, not a
  // million passes (it ran for minutes).
  const RunResult endless =
      run_program("G21 G90\n#1=0\nO1 while [1]\nO2 if [#1 LT 0]\n" + lines("G1 X5\n", 1000) + "O2 endif\nO1 endwhile\nM2\n");
  ASSERT_TRUE(endless.error);
  EXPECT_NE(endless.error->message().find("without a move"), std::string::npos) << endless.error->message();
}

TEST(FlattenBound, AnUnrolledProgramBeyondItsSizeIsRefusedAtTheLine) {
  // A 7-line loop of long comment lines run 1,000 times: 1.4 MB unrolled, over a 64 kB cap
  // (the command's is 1 GiB), refused at the loop's line that passes it; within the cap the
  // same program is written whole.
  const std::string long_line = "G1 X1 (" + std::string(200, 'c') + ")\n";
  const std::string program = "G21 G90 F100\nO1 repeat [1000]\n" + lines(long_line, 7) + "O1 endrepeat\nM2\n";
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> spool(std::tmpfile(), &std::fclose);
  ASSERT_TRUE(spool);
  gcode::LineSource source = gcode::LineSource::from_string(program, "loop.ngc");
  try {
    (void)gcode::flatten(source, spool.get(), {}, 64 * 1024);
    ADD_FAILURE() << "not refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::program);
    EXPECT_EQ(e.where().file, "loop.ngc");
    EXPECT_GE(e.where().line, 3U);
    EXPECT_LE(e.where().line, 9U);
    EXPECT_NE(e.message().find("64 kB"), std::string::npos) << e.message();
    EXPECT_LE(std::ftell(spool.get()), 64 * 1024) << "nothing written past the cap";
  }
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> whole(std::tmpfile(), &std::fclose);
  gcode::LineSource again = gcode::LineSource::from_string(program, "loop.ngc");
  (void)gcode::flatten(again, whole.get(), {}, 2 * 1024 * 1024);
  EXPECT_GT(std::ftell(whole.get()), 1'400'000);
}

}  // namespace
}  // namespace ccomp::test
