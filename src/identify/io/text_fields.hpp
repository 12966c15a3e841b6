#pragma once
// Small pieces the instrument readers share: fields of a delimited line with their columns,
// numbers with a decimal point or comma, names compared without case or unit.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ccomp::identify::io {

struct Field {
  std::string text;         ///< trimmed, quotes removed
  std::uint32_t column = 1;  ///< 1-based, where it starts in the line
};

/// The fields of `line` split at `delimiter` (double quotes protect one), trimmed; a CR at the end dropped.
[[nodiscard]] std::vector<Field> split_fields(std::string_view line, char delimiter);
/// Fields split at runs of blanks (spaces, tabs).
[[nodiscard]] std::vector<Field> split_blanks(std::string_view line);

/// A finite number written with a decimal point, or (decimal_comma) a comma; a leading '+' allowed.
[[nodiscard]] std::optional<double> parse_number(std::string_view text, bool decimal_comma);

/// Lower case (ASCII).
[[nodiscard]] std::string lower(std::string_view text);
/// Lower case, blanks and '-' '_' removed: "Target-Count" and "target count" compare equal.
[[nodiscard]] std::string fold(std::string_view text);

/// `text` without a unit in brackets or parentheses at its end, and that unit ("" if none).
[[nodiscard]] std::pair<std::string_view, std::string_view> name_and_unit(std::string_view text);

/// "+", "+1", "1", "up", "fwd", "forward", "positive" -> +1; "-", "-1", "down", "bwd", "back",
/// "backward", "reverse", "negative" -> -1; "" -> 0; anything else nullopt.
[[nodiscard]] std::optional<int> parse_direction(std::string_view text);

}  // namespace ccomp::identify::io
