// Decimal numbers read and written exactly: what std::from_chars and std::to_chars give,
// on random coordinates, halfway points, long digit strings and the forms G-code allows.
#include "ccomp/gcode/number.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace ccomp::gcode {
namespace {

/// Random coordinates of every size the programs carry, values on and next to the halfway
/// points of each precision (exact binary ties like 0.125, and the decimal ones like
/// 0.00005 that binary can only come near), and signed zeros: each with a precision.
template <class Check>
void for_each_coordinate(Check check) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> exponent(-8, 12);
  for (int k = 0; k < 200000; ++k) {
    const double v = unit(rng) * std::pow(10.0, exponent(rng));
    for (int decimals : {0, 3, 4, 5, 6, 9}) check(v, decimals);
  }
  for (int decimals = 0; decimals <= 9; ++decimals) {
    for (long long m = -3000; m <= 3000; ++m) {
      const double halfway = (static_cast<double>(m) + 0.5) / std::pow(10.0, decimals);
      for (double v : {halfway, std::nextafter(halfway, 1e300), std::nextafter(halfway, -1e300),
                       static_cast<double>(m) / 8.0, static_cast<double>(m) / 1024.0})
        check(v, decimals);
    }
  }
  for (double v : {0.0, -0.0, -1e-12, 1e-12, 1e14 + 0.5, -9.99995e8, 123456789.0125})
    for (int decimals = 0; decimals <= 12; ++decimals) check(v, decimals);
}

std::string to_chars_fixed(double v, int decimals) {
  char text[400];
  const auto end = std::to_chars(text, text + sizeof text, v, std::chars_format::fixed, decimals).ptr;
  return {text, static_cast<std::size_t>(end - text)};
}

TEST(Number, FormatFixedWritesWhatToCharsWrites) {
  for_each_coordinate([](double v, int decimals) {
    char ours[40];
    const std::size_t n = format_fixed(v, decimals, ours);
    ASSERT_EQ(std::string_view(ours, n), to_chars_fixed(v, decimals))
        << std::hexfloat << v << " with " << decimals << " decimals";
  });
  char out[40];
  EXPECT_EQ(format_fixed(1e300, 4, out), 0U) << "does not fit: the caller formats it otherwise";
}

TEST(Number, FormatUnitsWritesEveryIntegerWithItsPoint) {
  // Units of every length to 19 digits and the extremes, against their digits as to_chars
  // writes the integer, the point put in (zeros before it where the digits are fewer).
  auto expected = [](std::int64_t units, int decimals) {
    const std::uint64_t magnitude =
        units < 0 ? 0 - static_cast<std::uint64_t>(units) : static_cast<std::uint64_t>(units);
    std::string digits = std::to_string(magnitude);
    const auto d = static_cast<std::size_t>(decimals);
    if (digits.size() < d + 1) digits = std::string(d + 1 - digits.size(), '0') + digits;
    const std::string integer = digits.substr(0, digits.size() - d), fraction = digits.substr(digits.size() - d);
    return std::string(units < 0 ? "-" : "") + integer + (d > 0 ? "." : "") + fraction;
  };
  std::vector<std::int64_t> all{0, 1, -1, 9, 10, 99, 100, 101, INT64_MAX, INT64_MIN, INT64_MIN + 1};
  std::mt19937_64 rng(5);
  for (int length = 1; length <= 19; ++length)
    for (int k = 0; k < 200; ++k) {
      // (19 digits led by 9 could pass INT64_MAX, 9.22e18: led by 1-8 there.)
      std::int64_t u = 1 + static_cast<std::int64_t>(rng() % (length == 19 ? 8 : 9));
      for (int d = 1; d < length; ++d) u = u * 10 + static_cast<std::int64_t>(rng() % 10);
      all.push_back(k % 2 ? -u : u);
    }
  for (const std::int64_t units : all)
    for (int decimals = 0; decimals <= 9; ++decimals) {
      char out[32];
      const std::size_t n = format_units(units, decimals, units < 0, out);
      ASSERT_EQ(std::string_view(out, n), expected(units, decimals)) << units << " with " << decimals << " decimals";
    }
}

TEST(Number, FixedUnitsAreTheDigitsToCharsWrites) {
  // The writer compares units instead of texts, and takes units / 10^d for what the text
  // means: both must hold whenever fixed_units answers, and it must answer for most.
  std::size_t answered = 0, asked = 0;  // the test is void if it never answers
  for_each_coordinate([&](double v, int decimals) {
    ++asked;
    std::int64_t units = 0;
    if (!fixed_units(v, decimals, units)) return;
    ++answered;
    std::string digits = to_chars_fixed(v, decimals);
    const bool negative = digits.starts_with('-');
    std::erase(digits, '-');
    std::erase(digits, '.');
    const long long written = std::stoll(digits);
    ASSERT_EQ(units, negative ? -written : written) << std::hexfloat << v << " with " << decimals << " decimals";
    const std::string text = to_chars_fixed(v, decimals);
    double read = 0.0;
    std::from_chars(text.data() + (negative ? 1 : 0), text.data() + text.size(), read);
    if (negative) read = -read;
    ASSERT_EQ(static_cast<double>(units) / std::pow(10.0, decimals), read) << text;
  });
  EXPECT_GT(answered, asked / 2);
  // Many of those sit on or next to halfway points or beyond 1e15; a program's coordinates
  // nearly never do, and the writer's speed rests on answering for them.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coordinate(-2000, 2000);
  int program_answered = 0;
  for (int k = 0; k < 10000; ++k) {
    std::int64_t u = 0;
    program_answered += fixed_units(coordinate(rng), 4, u) ? 1 : 0;
  }
  EXPECT_GT(program_answered, 9990);
  std::int64_t units = 0;
  EXPECT_FALSE(fixed_units(0.00005, 4, units)) << "next to halfway: to_chars decides";
  EXPECT_FALSE(fixed_units(1e300, 4, units));
  EXPECT_FALSE(fixed_units(std::nan(""), 4, units));
}

TEST(Number, ReadDecimalReadsWhatFromCharsReads) {
  auto expect_same = [](const std::string& text) {
    std::size_t at = 0;
    double ours = 0.0;
    ASSERT_TRUE(read_decimal(text, at, ours)) << text;
    EXPECT_EQ(at, text.size()) << text;
    // from_chars takes no '+'; its sign is read here.
    const bool negative = text[0] == '-';
    const std::size_t digits = text[0] == '-' || text[0] == '+' ? 1 : 0;
    double theirs = 0.0;
    std::from_chars(text.data() + digits, text.data() + text.size(), theirs);
    if (negative) theirs = -theirs;
    EXPECT_EQ(std::signbit(ours), std::signbit(theirs)) << text;
    EXPECT_EQ(ours, theirs) << text;
  };
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> digit(0, 9), count(0, 12), sign(0, 2);
  for (int k = 0; k < 200000; ++k) {
    std::string text = std::string(sign(rng) == 0 ? "-" : sign(rng) == 1 ? "+" : "");
    const int whole = count(rng), fraction = count(rng) + (k % 7 == 0 ? 8 : 0);  // past 15 digits too
    for (int i = 0; i < whole; ++i) text += static_cast<char>('0' + digit(rng));
    text += '.';
    for (int i = 0; i < fraction; ++i) text += static_cast<char>('0' + digit(rng));
    if (whole + fraction == 0) text += '5';
    expect_same(text);
  }
  for (const char* text : {".5", "-.25", "+3", "12.", "-0.0000", "0", "123456789012345.6", "0.1", "4.5500"})
    expect_same(text);
  std::size_t at = 0;
  double value = 7.0;
  EXPECT_FALSE(read_decimal("-.", at, value)) << "a sign and a point are no number";
  EXPECT_FALSE(read_decimal("X1", at = 0, value));
}

}  // namespace
}  // namespace ccomp::gcode
