#include "ccomp/gcode/dialect.hpp"

namespace ccomp::gcode {

std::optional<Dialect> dialect_named(std::string_view name) {
  Dialect d;
  d.name = std::string(name);
  if (name == "linuxcnc") return d;
  if (name == "fanuc") {
    d.empty_word_values = true;
    return d;
  }
  if (name == "mazak") {
    d.empty_word_values = true;
    d.repeated_modal_codes = true;
    // Mazak mill-turn codes: G53.5 (tool-tip machine coordinates), G122.1/G123.1 (milling
    // mode on/off), G111 (cross machining), G50 (spindle clamp).
    d.passthrough_g_codes = {535, 1221, 1231, 1110, 500};
    return d;
  }
  if (name == "wincnc") {
    d.bracket_comments = true;
    return d;
  }
  return std::nullopt;
}

std::vector<std::string> dialect_names() { return {"linuxcnc", "fanuc", "mazak", "wincnc"}; }

}  // namespace ccomp::gcode
