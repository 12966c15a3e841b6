#include "ccomp/gcode/dialect.hpp"

#include <fmt/format.h>

#include "g_codes.hpp"

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
  if (name == "siemens") {
    d.parenthesis_comments = false;
    d.named_commands = true;
    d.d_selects_cutting_edge = true;
    d.dwell_in_f_or_s = true;
    d.unused_words_are_errors = false;  // H words go to the PLC
    d.starts_in_g99 = false;
    // Path control (G60, G64, G641-G645), exact stop (G9, G601-G603): how the control blends
    // blocks, not where they go.
    d.passthrough_g_codes = {90, 600, 6010, 6020, 6030, 6410, 6420, 6430, 6440, 6450};
    d.g_code_aliases = {{710, 210}, {7100, 210}, {7000, 200}, {1530, 530}};
    d.unsupported_g_codes = {
        {700, "G70 gives lengths in inches and feed rates in millimetres, which ccomp does not model (G700: both "
              "in inches)"},
        {5000, "G500 switches the settable work offsets off; ccomp's work offsets are G54 to G59.3 (--work-offset)"},
        {580, "G58 is a Siemens axial programmable offset (a frame), not a work offset: not followed"},
        {590, "G59 is a Siemens axial programmable offset (a frame), not a work offset: not followed"},
        {920, "G92 limits the spindle speed in Siemens syntax; ccomp does not read it"},
        {250, "G25 sets a lower working-area or spindle limit in Siemens syntax; ccomp does not read it"},
        {260, "G26 sets an upper working-area or spindle limit in Siemens syntax; ccomp does not read it"},
        {740, "G74 approaches the reference point: ccomp does not know where it moves"},
        {750, "G75 approaches a fixed point: ccomp does not know where it moves"},
    };
    for (int system = 505; system <= 599; ++system)
      d.unsupported_g_codes.emplace_back(
          system * 10, fmt::format("G{}: a settable work offset beyond G57; ccomp's are G54 to G59.3 (--work-offset)",
                                   system));
    // RS-274 codes a Sinumerik does not have in its own syntax, or gives another meaning:
    // read as LinuxCNC's they would be wrong (its ISO mode, G291, is the fanuc dialect).
    for (int code : {100, 280, 300, 430, 431, 432, 434, 435, 490, 730, 810, 820, 830, 840, 850, 860, 870, 880, 890})
      d.unsupported_g_codes.emplace_back(
          code, fmt::format("{} is not Siemens syntax (tool lengths come with D, cycles are CYCLE81 and on); a "
                            "program for a Sinumerik's ISO mode (G291) is read with --dialect fanuc",
                            g_name(code)));
    return d;
  }
  return std::nullopt;
}

std::vector<std::string> dialect_names() {
  return {"linuxcnc", "fanuc", "mazak", "wincnc", "siemens"};
}

}  // namespace ccomp::gcode
