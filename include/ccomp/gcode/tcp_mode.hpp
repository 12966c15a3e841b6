#pragma once
// Programs written for tool-centre-point control (TCP): the control runs the machine's
// kinematics, so the X Y Z words are the tool tip in the part and A B C the rotary axes'
// angles, not each axis' own position. Read as joint coordinates such a program would be
// corrected at points the machine never goes to, so the codes that switch a control into
// TCP are named here, and either followed (each motion says whether its words are the tip:
// Motion::tcp) or refused (exit 4, at the code): docs/compensation.md, "Tool-centre-point
// programs".
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ccomp/gcode/dialect.hpp"

namespace ccomp::gcode {

/// How an interpreter takes the codes that switch TCP on and off.
enum class TcpCodes : std::uint8_t {
  /// Read as any other M code (a trace, the zero model's rewrite: nothing is corrected, so
  /// nothing is misread); G43.4 and G43.5, which the interpreter has no group for, refused.
  pass,
  /// Refused at the code (exit 4): where the axis words must be the joints'.
  refuse,
  /// Followed: G43.4 (with G43's H), G43.5 (the tool's direction as I J K, where the caller
  /// gives InterpreterOptions::tcp_direction), M128 (Fanuc dialect), M428 (LinuxCNC dialect)
  /// and TRAORI (siemens dialect, off with TRAFOOF) switch TCP on; G43, G43.1, G43.2, G49,
  /// M129 and M429 off; each motion says which it is under. M430 (user kinematics) is refused.
  follow,
};

/// ModalState::tcp under Siemens' TRAORI (which is a command, not a code).
inline constexpr int kTraoriTcp = 1;

/// Whether M `code` switches TCP off again in the dialect (M129 of Fanuc-style dialects,
/// M429 of LinuxCNC's).
[[nodiscard]] bool tcp_off_m_code(const Dialect& dialect, int code);

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
