// The number style on its own: how one compensated value is written.
#include "compensate/number_style.hpp"

#include <gtest/gtest.h>

namespace ccomp::compensate {
namespace {

TEST(NumberStyleAlone, TakesTheDecimalsAndLeadingZeroOfTheWordItReplaces) {
  const NumberStyle bare = style_of(".5", false, false, -1);
  EXPECT_EQ(bare.decimals, kDefaultDecimals);
  EXPECT_FALSE(bare.leading_zero);
  EXPECT_EQ(format_value(0.25, bare).text, ".2500");
  EXPECT_EQ(format_value(-0.25, bare).text, "-.2500");
  EXPECT_EQ(style_of("12.123456", false, false, -1).decimals, 6);
  EXPECT_EQ(style_of("12", false, false, -1).decimals, kDefaultDecimals);
  EXPECT_TRUE(style_of("12", false, false, -1).leading_zero);
}

TEST(NumberStyleAlone, DefaultsDependOnUnitsAndAxisAndTheUserOverridesThem) {
  EXPECT_EQ(style_of("", true, false, -1).decimals, kDefaultInchDecimals);
  EXPECT_EQ(style_of("", false, true, -1).decimals, kDefaultRotaryDecimals);
  EXPECT_EQ(style_of("1.123456", false, false, 2).decimals, 2);  // fewer than the program wrote: asked for
  EXPECT_EQ(format_value(1.005, style_of("", false, false, 0)).text, "1");
}

TEST(NumberStyleAlone, NeverWritesMinusZeroAndTellsTheValueTheTextMeans) {
  const NumberStyle four{4, true};
  EXPECT_EQ(format_value(-0.00001, four).text, "0.0000");
  const WrittenValue w = format_value(1.23456789, four);
  EXPECT_EQ(w.text, "1.2346");
  EXPECT_DOUBLE_EQ(w.value, 1.2346);
  EXPECT_EQ(format_value(-12.5, NumberStyle{1, true}).text, "-12.5");
}

TEST(NumberStyleAlone, WrittenAlikeComparesTheRoundedDigits) {
  const NumberStyle four{4, true};
  EXPECT_TRUE(written_alike(1.00004, 1.0, four));
  EXPECT_FALSE(written_alike(1.00006, 1.0, four));
  EXPECT_TRUE(written_alike(-0.00001, 0.0, four));  // "-0.0000" is written "0.0000"
  EXPECT_FALSE(written_alike(0.0, 0.001, NumberStyle{3, true}));
}

}  // namespace
}  // namespace ccomp::compensate
