// Decimal numbers read and written exactly: what std::from_chars and std::to_chars give,
// on random coordinates, halfway points, long digit strings and the forms G-code allows.
#include "ccomp/gcode/number.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <random>
#include <string>
#include <string_view>

namespace ccomp::gcode {
namespace {

TEST(Number, FormatFixedWritesWhatToCharsWrites) {
  // Random coordinates of every size the programs carry, values on and next to the
  // halfway points of each precision (exact binary ties like 0.125, and the decimal ones
  // like 0.00005 that binary can only come near), and signed zeros.
  auto expect_same = [](double v, int decimals) {
    char ours[40], theirs[400];
    const std::size_t n = format_fixed(v, decimals, ours);
    const auto end = std::to_chars(theirs, theirs + sizeof theirs, v, std::chars_format::fixed, decimals).ptr;
    ASSERT_EQ(std::string_view(ours, n), std::string_view(theirs, static_cast<std::size_t>(end - theirs)))
        << std::hexfloat << v << " with " << decimals << " decimals";
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> exponent(-8, 12);
  for (int k = 0; k < 200000; ++k) {
    const double v = unit(rng) * std::pow(10.0, exponent(rng));
    for (int decimals : {0, 3, 4, 5, 6, 9}) expect_same(v, decimals);
  }
  for (int decimals = 0; decimals <= 9; ++decimals) {
    for (long long m = -3000; m <= 3000; ++m) {
      const double halfway = (static_cast<double>(m) + 0.5) / std::pow(10.0, decimals);
      for (double v : {halfway, std::nextafter(halfway, 1e300), std::nextafter(halfway, -1e300),
                       static_cast<double>(m) / 8.0, static_cast<double>(m) / 1024.0})
        expect_same(v, decimals);
    }
  }
  for (double v : {0.0, -0.0, -1e-12, 1e-12, 1e14 + 0.5, -9.99995e8, 123456789.0125})
    for (int decimals = 0; decimals <= 12; ++decimals) expect_same(v, decimals);
  char out[40];
  EXPECT_EQ(format_fixed(1e300, 4, out), 0U) << "does not fit: the caller formats it otherwise";
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
