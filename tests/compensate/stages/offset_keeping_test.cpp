// The offset bookkeeping on its own: which blocks set an offset from the position, and how
// their words are moved so the offset comes out as the original's.
#include "compensate/offset_keeping.hpp"

#include <gtest/gtest.h>

#include "ccomp/gcode/writer.hpp"
#include "error_of.hpp"
#include "parsed_block.hpp"

namespace ccomp::compensate {
namespace {

using test::ParsedBlock;

TEST(OffsetKeeping, KnowsWhichBlocksSetAnOffsetFromThePosition) {
  EXPECT_TRUE(sets_offset_from_position(ParsedBlock("G92 X0 Y0").block));
  EXPECT_TRUE(sets_offset_from_position(ParsedBlock("G10 L20 P1 X0").block));
  EXPECT_TRUE(sets_offset_from_position(ParsedBlock("G10 L10 P1 Z0").block));
  EXPECT_TRUE(sets_offset_from_position(ParsedBlock("G10 L11 P1 Z0").block));
  EXPECT_TRUE(sets_offset_from_position(ParsedBlock("G10 L[#1] P1 X0").block));  // only the run shows it
  EXPECT_FALSE(sets_offset_from_position(ParsedBlock("G10 L2 P1 X0").block));    // a value, not a position
  EXPECT_FALSE(sets_offset_from_position(ParsedBlock("G1 X0").block));
}

/// The machine 3 um beyond the original's position in X, 2 um short in Z, program in mm.
struct Scene {
  gcode::Offsets offsets;
  gcode::Axes nominal_end{10, 20, 30};
  WrittenPosition written{{10.003, 20, 29.998}, {}};
  OffsetContext at(bool runs_again = false) const {
    return OffsetContext{offsets, gcode::Units::mm, nominal_end, written, runs_again, {}, "p.ngc"};
  }
};

TEST(OffsetKeeping, MovesEachValueByWhereTheMachineIsBeyondTheOriginal) {
  const Scene scene;
  const ParsedBlock b("G92 X0 Y5.5 Z1.000000");
  const std::vector<gcode::Edit> edits = offset_keeping_edits(b.block, scene.at());
  EXPECT_EQ(gcode::apply_edits(b.text, edits), "G92 X0.0030 Y5.5 Z0.998000");
}

TEST(OffsetKeeping, AnExpressionIsMovedAsWritten) {
  const Scene scene;
  const ParsedBlock b("G92 X[#1 * 2]");
  EXPECT_EQ(gcode::apply_edits(b.text, offset_keeping_edits(b.block, scene.at())), "G92 X[[#1 * 2] + 0.0030]");
}

TEST(OffsetKeeping, NothingChangesWhereTheMachineIsWhereTheOriginalHasIt) {
  Scene scene;
  scene.written.commanded = scene.nominal_end;
  const ParsedBlock b("G92 X0");
  EXPECT_TRUE(offset_keeping_edits(b.block, scene.at(true)).empty());  // even on a line that runs again
}

TEST(OffsetKeeping, RefusesWhatNoEditOfItsWordsCanKeep) {
  const Scene scene;
  const ParsedBlock again("G92 X0", 12);
  const Error e = test::error_of([&] { (void)offset_keeping_edits(again.block, scene.at(true)); }, "a loop's G92");
  EXPECT_EQ(e.kind(), ErrorKind::unsupported);
  EXPECT_EQ(e.where().line, 12U);
  EXPECT_NE(e.message().find("G92 sets an offset from where the machine is"), std::string::npos) << e.message();
  EXPECT_NE(e.message().find("3.00 um"), std::string::npos) << e.message();
  const ParsedBlock l11("G10 L11 P1 X0");
  EXPECT_EQ(test::error_of([&] { (void)offset_keeping_edits(l11.block, scene.at()); }, "L11 in X").kind(),
            ErrorKind::unsupported);
  const ParsedBlock rotated("G10 L20 P1 X0 R30");
  EXPECT_EQ(test::error_of([&] { (void)offset_keeping_edits(rotated.block, scene.at()); }, "L20 with R").kind(),
            ErrorKind::unsupported);
  const ParsedBlock in_force("G10 L20 P1 X0");
  EXPECT_EQ(gcode::apply_edits(in_force.text, offset_keeping_edits(in_force.block, scene.at())), "G10 L20 P1 X0.0030");
}

}  // namespace
}  // namespace ccomp::compensate
