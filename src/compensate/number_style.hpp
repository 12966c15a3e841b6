#pragma once
// Rewriting, its smallest part: how a compensated coordinate is written. In the style of the
// word it replaces (as many decimals as the program wrote, ".5" stays ".5"), with enough
// digits for the tolerance, or exactly as many as the user asked for.
#include <optional>
#include <string>
#include <string_view>

#include "ccomp/gcode/block.hpp"

namespace ccomp::compensate {

/// At least 4 decimals in mm, 5 in inches, 5 in degrees (1e-5 deg is 0.07 um at 400 mm
/// from the axis): the digits then round the tool by a fraction of a 1 um tolerance.
inline constexpr int kDefaultDecimals = 4, kDefaultInchDecimals = 5, kDefaultRotaryDecimals = 5;

struct NumberStyle {
  int decimals = kDefaultDecimals;
  bool leading_zero = true;  ///< "0.5", not ".5"
};

/// The style of `original` (the word's value as written, empty for a word the block lacks)
/// for a linear axis in inches or mm, or a rotary one; `decimals` >= 0 overrides the count.
[[nodiscard]] NumberStyle style_of(std::string_view original, bool inch, bool rotary, int decimals);
/// The style of a number written with `written` digits after its point (0 without one),
/// the point first or not.
[[nodiscard]] inline NumberStyle style_written(int written, bool point_first, bool inch, bool rotary, int decimals) {
  NumberStyle style{rotary ? kDefaultRotaryDecimals : inch ? kDefaultInchDecimals : kDefaultDecimals, true};
  style.decimals = written > style.decimals ? written : style.decimals;
  style.leading_zero = !point_first;
  if (decimals >= 0) style.decimals = decimals;
  return style;
}

/// The same for a word's value (`word` null: a word the block lacks), from what the parser
/// read of it where it could (gcode::Word::decimals), else from its text in `block_text`.
/// Inline: every axis word of every line comes here.
[[nodiscard]] inline NumberStyle style_of(const gcode::Word* word, std::string_view block_text, bool inch, bool rotary,
                                          int decimals) {
  if (!word) return style_written(0, false, inch, rotary, decimals);
  if (word->decimals >= 0) return style_written(word->decimals, word->point_first, inch, rotary, decimals);
  return style_of(block_text.substr(word->value_span.begin, word->value_span.end - word->value_span.begin), inch,
                  rotary, decimals);
}

/// A coordinate as written: its text, and the number the text means (what the machine
/// will be told).
struct WrittenValue {
  std::string text;
  double value = 0.0;
};

[[nodiscard]] WrittenValue format_value(double v, const NumberStyle& style);
/// The same into `text` (its storage reused); returns the number the text means.
double format_value(double v, const NumberStyle& style, std::string& text);
[[nodiscard]] WrittenValue format_value(double v, std::string_view original, bool inch, bool rotary, int decimals);

/// The number v is written as in `style`, without making its text; nothing where only the
/// text can say (fixed_units cannot).
[[nodiscard]] std::optional<double> fixed_number(double v, const NumberStyle& style);
/// The number v is written as in `style` (its text made only where fixed_number cannot say).
[[nodiscard]] double written_number(double v, const NumberStyle& style);

/// Whether a and b are written alike in `style` ("-0.0000" is written "0.0000").
[[nodiscard]] bool written_alike(double a, double b, const NumberStyle& style);

}  // namespace ccomp::compensate
