#include "ccomp/gcode/dialect.hpp"

namespace ccomp::gcode {

std::optional<Dialect> dialect_named(std::string_view name) {
  Dialect d;
  d.name = std::string(name);
  if (name == "linuxcnc") return d;
  if (name == "fanuc") {
    d.unused_words_are_errors = false;
    d.empty_word_values = true;
    d.cycles_own_modal_group = true;
    d.g53_alone_is_rapid = true;
    d.starts_in_g99 = false;
    d.cycles_need_spindle = false;
    return d;
  }
  if (name == "mazak") {
    d.unused_words_are_errors = false;
    d.empty_word_values = true;
    d.cycles_own_modal_group = true;
    d.g53_alone_is_rapid = true;
    d.repeated_modal_codes = true;
    // Mazak mill-turn codes: G122.1/G123.1 (milling mode on/off), G111 (cross machining),
    // G50 (spindle clamp); G53.5 moves in tool-tip machine coordinates.
    d.passthrough_g_codes = {1221, 1231, 1110, 500};
    d.passthrough_moving_g_codes = {535};
    return d;
  }
  if (name == "wincnc") {
    d.bracket_comments = true;
    d.empty_word_values = true;  // `F10 XY`: a feed rate for the axes named
    d.g53_alone_is_rapid = true;
    return d;
  }
  return std::nullopt;
}

std::vector<std::string> dialect_names() {
  return {"linuxcnc", "fanuc", "mazak", "wincnc"};
}

}  // namespace ccomp::gcode
