#pragma once
// Programs written for tool-centre-point control (TCP): the control runs the machine's
// kinematics, so the X Y Z words are the tool tip in the part and A B C the tool's
// orientation, not each axis' own position. ccomp compensates joint-coordinate programs
// (posted for the machine without TCP); a TCP program read as one would be corrected at
// points the machine never goes to. The codes that switch a control into TCP are therefore
// named here, and refused (exit 4, at the code) wherever a program is compensated or
// measured: docs/compensation.md, "Tool-centre-point programs".
#include <optional>
#include <string>
#include <string_view>

#include "ccomp/gcode/dialect.hpp"

namespace ccomp::gcode {

/// What a G code (times ten) switches on, when it is a TCP mode: G43.4 and G43.5 (Fanuc's
/// tool centre point control, types 1 and 2; LinuxCNC has neither). nullopt otherwise.
[[nodiscard]] std::optional<std::string_view> tcp_g_code(int code);

/// What an M code switches on in the dialect, when it is a kinematics switch whose
/// coordinates are not the joints': LinuxCNC's switchable kinematics as its trt
/// configurations remap them (M428 the TCP kinematics, M430 user kinematics; M429, back to
/// identity, is not refused), Heidenhain's M128 (TCPM) in the Fanuc-style dialects.
[[nodiscard]] std::optional<std::string_view> tcp_m_code(const Dialect& dialect, int code);

/// The refusal's text for a mode named by the functions above.
[[nodiscard]] std::string tcp_refusal(std::string_view code, std::string_view mode);

}  // namespace ccomp::gcode
