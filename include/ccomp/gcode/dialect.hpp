#pragma once
// Which controller's G-code a program is written for. The dialect changes a few lexical
// rules and what the interpreter tolerates; the default is LinuxCNC's RS-274/NGC.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
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
  /// A word no code of its block uses (`G96 S392 R1`): an error in LinuxCNC, a warning for
  /// controls whose manuals give such words meanings ccomp does not model.
  bool unused_words_are_errors = true;
  /// Fanuc-family controls keep canned cycles in a modal group of their own: after G80 the
  /// G0/G1/G2/G3 mode in force before the cycle applies again. (LinuxCNC: G80 is group 1.)
  bool cycles_own_modal_group = false;
  /// `G53 Z0` with no motion mode moves at rapid (Fanuc, WinCNC); LinuxCNC needs G0 or G1.
  bool g53_alone_is_rapid = false;
  /// The retract mode at program start: rs274 starts in G99 (back to R), Fanuc in G98.
  bool starts_in_g99 = true;
  /// LinuxCNC refuses G84/G86/G88 with the spindle stopped; rigid-tapping controls (Haas,
  /// Fanuc) drive the spindle from the cycle.
  bool cycles_need_spindle = true;
  /// G codes (times 10, e.g. 1221 for G122.1) the controller knows and ccomp passes
  /// through without modelling them: modes that move nothing themselves.
  std::vector<int> passthrough_g_codes;
  /// Pass-through G codes that move the axes they name in a way ccomp does not model: the
  /// block keeps its words verbatim and those axes are unknown until the program sets them.
  std::vector<int> passthrough_moving_g_codes;
  /// M codes outside the standard set (M100-M199 are always user codes) are accepted and
  /// passed through unless this is set.
  bool strict_m_codes = false;

  // Siemens Sinumerik (the `siemens` preset: docs/dialects.md).
  /// `(` opens a comment. Not in Siemens syntax, where only `;` does and parentheses hold a
  /// command's arguments.
  bool parenthesis_comments = true;
  /// A name of two letters or more is a command (`TRAORI`, `ORIAXES`, `CYCLE832(...)`), and an
  /// address may take its value after `=` (`X=10`, `A3=0`): gcode::Command, Word::extension.
  bool named_commands = false;
  /// D selects a cutting edge of the tool in the spindle: D1 and up put its length offset in
  /// force at once (and its radius under G41/G42), D0 none; a tool change takes edge 1. In
  /// RS-274 D only names the radius' tool for G41/G42, and G43 puts the length in force.
  bool d_selects_cutting_edge = false;
  /// G4 takes its time in F (seconds) or S (spindle turns) and leaves the feed rate alone.
  bool dwell_in_f_or_s = false;
  /// G codes (times ten) read as another: Siemens' G71/G710 as G21, G700 as G20.
  std::vector<std::pair<int, int>> g_code_aliases;
  /// G codes refused at their word (exit 4) with the reason: what the dialect's G code does
  /// that ccomp does not follow.
  std::vector<std::pair<int, std::string>> unsupported_g_codes;
};

/// The presets: linuxcnc, fanuc (Haas), mazak, wincnc, siemens (Sinumerik 840D). Unknown names give nullopt.
[[nodiscard]] std::optional<Dialect> dialect_named(std::string_view name);
[[nodiscard]] std::vector<std::string> dialect_names();

}  // namespace ccomp::gcode
