#pragma once
// The known name nearest a mistyped one, by edit distance: what a misspelt model key, command
// or option is answered with ("did you mean ...?").
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace ccomp::util {

/// Levenshtein distance: the fewest insertions, deletions and substitutions from a to b.
[[nodiscard]] std::size_t edit_distance(std::string_view a, std::string_view b);

/// The name in `names` nearest `text`, or empty when none is near: within a third of the
/// text's length (at least 2), so that "chek" finds "check" but "x" finds nothing.
[[nodiscard]] std::string nearest_name(std::string_view text, const std::vector<std::string_view>& names);

}  // namespace ccomp::util
