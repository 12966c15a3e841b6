// The number style on its own: how one compensated value is written.
#include "compensate/number_style.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <random>
#include <string>

#include "ccomp/gcode/parser.hpp"

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

TEST(NumberStyleAlone, AWordsStyleFromTheParserIsTheStyleOfItsText) {
  // What the parser counted of a word (gcode::Word::decimals, point_first) must give the
  // style its text gives, in every form a number takes, through both of the parser's paths.
  const std::string texts[] = {"1",    "12",        "-3",     "+7",      ".5",
                               "-.25", "+.125",     "0.0500", "-0.9975", "5.",
                               "-5.",  "12.123456", "0.0000", "1.",      "123456.1234567890123"};
  for (const bool fast_path : {true, false}) {
    gcode::Parser parser({}, fast_path);
    for (const std::string& number : texts) {
      gcode::Block block;
      const std::string line = "G1 X" + number;
      parser.parse(line, 1, "f", block);
      const gcode::Word* x = block.find('X');
      ASSERT_NE(x, nullptr) << line;
      for (const bool inch : {false, true})
        for (const bool rotary : {false, true})
          for (const int decimals : {-1, 3}) {
            const NumberStyle from_word = style_of(x, block.text, inch, rotary, decimals);
            const NumberStyle from_text = style_of(block.slice(x->value_span), inch, rotary, decimals);
            EXPECT_EQ(from_word.decimals, from_text.decimals) << line << (fast_path ? " fast" : " grammar");
            EXPECT_EQ(from_word.leading_zero, from_text.leading_zero) << line << (fast_path ? " fast" : " grammar");
          }
    }
  }
  // The fast path counts what it reads; a line it leaves to the grammar (an expression) is
  // styled from its text.
  gcode::Parser parser;
  gcode::Block block;
  parser.parse("G1 X-.25 Y12", 1, "f", block);
  EXPECT_EQ(int{block.find('X')->decimals}, 2);
  EXPECT_TRUE(block.find('X')->point_first);
  EXPECT_EQ(int{block.find('Y')->decimals}, 0);
  EXPECT_FALSE(block.find('Y')->point_first);
  parser.parse("G1 X-.25 Z[1.5 + 2]", 2, "f", block);
  EXPECT_EQ(int{block.find('X')->decimals}, -1);
  EXPECT_EQ(int{block.find('Z')->decimals}, -1);
  EXPECT_FALSE(style_of(block.find('X'), block.text, false, false, -1).leading_zero);
  EXPECT_EQ(style_of(nullptr, block.text, false, false, -1).decimals, kDefaultDecimals);
}

TEST(NumberStyleAlone, DefaultsDependOnUnitsAndAxisAndTheUserOverridesThem) {
  EXPECT_EQ(style_of("", true, false, -1).decimals, kDefaultInchDecimals);
  EXPECT_EQ(style_of("", false, true, -1).decimals, kDefaultRotaryDecimals);
  EXPECT_EQ(style_of("1.123456", false, false, 2).decimals, 2);  // fewer than the program wrote: asked for
  EXPECT_EQ(format_value(1.005, style_of("", false, false, 0)).text, "1");
}

TEST(NumberStyleAlone, WritesWhatFixedPointFormattingWritesInEveryStyle) {
  // Against fmt's correctly rounded fixed-point text (no "-0.000"; ".5" where the program
  // wrote no leading zero), on random coordinates of every size, halfway points among them,
  // and the number the text means.
  std::mt19937_64 random(23);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-6, 9);
  for (int n = 0; n < 40000; ++n) {
    double v = unit(random) * std::pow(10.0, exponent(random));
    const int decimals = n % 10;
    if (n % 7 == 0) v = (std::round(v * std::pow(10.0, decimals)) + 0.5) / std::pow(10.0, decimals);  // halfway
    for (const bool leading_zero : {true, false}) {
      std::string expected = fmt::format("{:.{}f}", v, decimals);
      if (expected.starts_with('-') && expected.find_first_not_of("0.", 1) == std::string::npos) expected.erase(0, 1);
      if (!leading_zero && decimals > 0) {
        if (expected.starts_with("0."))
          expected.erase(0, 1);
        else if (expected.starts_with("-0."))
          expected.erase(1, 1);
      }
      const WrittenValue written = format_value(v, NumberStyle{decimals, leading_zero});
      ASSERT_EQ(written.text, expected) << v << " to " << decimals << (leading_zero ? "" : " without the zero");
      double meant = 0.0;
      std::from_chars(expected.data(), expected.data() + expected.size(), meant);
      ASSERT_EQ(written.value, meant) << expected;
    }
  }
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
