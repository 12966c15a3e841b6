#pragma once
// Which controller's G-code a program is written for. The dialect changes a few lexical
// rules and what the interpreter tolerates; the default is LinuxCNC's RS-274/NGC.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ccomp::gcode {

struct Dialect {
  std::string name = "linuxcnc";
  /// WinCNC reads `[ ... ]` as a comment and has no expressions.
  bool bracket_comments = false;
  /// Haas and Fanuc controls accept a letter with no value (`G82 ... P F15.`): ignored.
  bool empty_word_values = false;
  /// Mazak posts repeat a G code of one modal group (`G98 G98`): accepted when identical.
  bool repeated_modal_codes = false;
  /// G codes (times 10, e.g. 1221 for G122.1) the controller knows and ccomp passes
  /// through without modelling them. A block carrying one keeps its axis words verbatim.
  std::vector<int> passthrough_g_codes;
  /// M codes outside the standard set (M100-M199 are always user codes) are accepted and
  /// passed through unless this is set.
  bool strict_m_codes = false;
};

/// The presets: linuxcnc, fanuc (Haas), mazak, wincnc. Unknown names give nullopt.
[[nodiscard]] std::optional<Dialect> dialect_named(std::string_view name);
[[nodiscard]] std::vector<std::string> dialect_names();

}  // namespace ccomp::gcode
