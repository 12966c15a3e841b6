#include "ccomp/gcode/tcp_mode.hpp"

#include <fmt/format.h>

#include <string>

namespace ccomp::gcode {

std::optional<std::string_view> tcp_g_code(int code) {
  if (code == 434) return "tool centre point control, type 1 (the tool tip in the part, the rotary axes given)";
  if (code == 435) return "tool centre point control, type 2 (the tool tip in the part, the tool's direction given)";
  return std::nullopt;
}

std::optional<std::string_view> tcp_m_code(const Dialect& dialect, int code) {
  if (dialect.name == "linuxcnc") {
    // configs/sim/axis/vismach/5axis/table-rotary-tilting: REMAP = M428 ngc=428remap
    // selects kinstype 1, the xyzac/xyzbc-trt TCP kinematics; M430 the user kinematics.
    if (code == 428) return "LinuxCNC's switchable kinematics: the table-rotary-tilting TCP kinematics (kinstype 1)";
    if (code == 430) return "LinuxCNC's switchable kinematics: the user kinematics (kinstype 2)";
    return std::nullopt;
  }
  if (dialect.name == "fanuc" && code == 128)
    return "Heidenhain's TCPM (the tool tip kept in the part as the rotary axes turn)";
  return std::nullopt;
}

bool tcp_off_m_code(const Dialect& dialect, int code) {
  return (dialect.name == "linuxcnc" && code == 429) || (dialect.name == "fanuc" && code == 129);
}

std::string tcp_refusal(std::string_view code, std::string_view mode) {
  // M430's coordinates are whatever the user's kinematics make them: nothing can follow them.
  const std::string_view why = code == "M430"
                                   ? "whose coordinates ccomp cannot know"
                                   : "which this command does not follow (the main job, verify and predict follow "
                                     "G43.4, M128 and M428)";
  return fmt::format(
      "{} switches to {}: the program's X Y Z would be the tool tip in the part, not the axes' positions, {} "
      "(docs/compensation.md, \"Tool-centre-point programs\")",
      code, mode, why);
}

}  // namespace ccomp::gcode
