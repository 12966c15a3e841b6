// LinuxCNC tool tables: what is read, and bad tables refused at their field (fuzzing's
// findings are kept here, minimised).
#include "ccomp/gcode/tool_table.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "ccomp/error.hpp"
#include "error_of.hpp"

namespace ccomp::gcode {
namespace {

ToolTable read(const std::string& text) {
  std::istringstream in(text);
  return read_tool_table(in, "t.tbl");
}

/// The error reading `text` gives (it must give one).
Error refusal(const std::string& text) {
  return test::error_of([&] { (void)read(text); }, text);
}

TEST(ToolTable, ReadsToolsPocketsOffsetsAndComments) {
  const ToolTable t = read("T1 P3 Z100.5 X-0.25 D10 ;end mill\r\n\nT7 P7 Z90 ;drill\n");
  ASSERT_EQ(t.tools.size(), 2U);
  const ToolEntry* one = t.find(1);
  ASSERT_NE(one, nullptr);
  EXPECT_EQ(one->pocket, 3);
  EXPECT_DOUBLE_EQ(one->offset[2], 100.5);
  EXPECT_DOUBLE_EQ(one->offset[0], -0.25);
  EXPECT_DOUBLE_EQ(one->diameter, 10.0);
  EXPECT_EQ(one->comment, "end mill");
  EXPECT_NE(t.find(7), nullptr);
  EXPECT_EQ(t.find(2), nullptr);
}

// Fuzzing (tools/fuzz.sh tool_table): a tool number beyond int was converted to int, which
// is undefined (UBSan: 1.1e96 is outside the range of int).
TEST(ToolTable, RefusesToolAndPocketNumbersBeyondInt) {
  for (const char* text : {"T1e96 P1 Z0\n", "T2147483648\n", "T-1 Z1\n", "T1 P1e300\n", "T3 P-2\n"}) {
    const Error e = refusal(text);
    EXPECT_EQ(e.kind(), ErrorKind::io) << text;
    EXPECT_NE(e.message().find("out of range"), std::string::npos) << e.message();
    EXPECT_EQ(e.where().file, "t.tbl");
    EXPECT_EQ(e.where().line, 1U);
  }
  EXPECT_EQ(refusal("T1\nT2 P99999999999\n").where().column, 4U) << "at the P field of line 2";
  EXPECT_EQ(refusal("T1\nT2 P99999999999\n").where().line, 2U);
  EXPECT_NE(read("T2147483647 P2147483647\n").find(2147483647), nullptr);
}

// A field written twice on a line (`Z1 Z2`) was read as the last; which one the operator
// meant is not for ccomp to guess.
TEST(ToolTable, RefusesAFieldWrittenTwice) {
  const Error e = refusal("T1 P1 Z1 D3 Z2\n");
  EXPECT_NE(e.message().find("'Z' is written twice"), std::string::npos) << e.message();
  EXPECT_EQ(e.where().column, 13U);
}

}  // namespace
}  // namespace ccomp::gcode
