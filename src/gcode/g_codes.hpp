#pragma once
// Private to the interpreter: what G codes are (times ten, as the interpreter keeps them).
#include <string>

namespace ccomp::gcode {

/// Modal group of a G code; -1 when unknown. Group numbers follow RS-274/NGC.
[[nodiscard]] int g_group(int code);
/// Modal group of an M code; -1 when unknown.
[[nodiscard]] int m_group(int code);
/// A canned cycle (G73, G81-G89).
[[nodiscard]] bool is_cycle(int code);
/// "G81", "G92.1".
[[nodiscard]] std::string g_name(int code);
/// A number as rs274 prints canonical arguments.
[[nodiscard]] std::string fixed4(double v);

}  // namespace ccomp::gcode
