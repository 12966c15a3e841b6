#pragma once
// The named commands of the siemens dialect (Sinumerik 840D) that ccomp reads, one
// descriptor each: what the interpreter does with them. A command not listed is refused at
// its name (exit 4) with the reason siemens_refusal() gives.
#include <cstdint>
#include <string>
#include <string_view>

namespace ccomp::gcode {

enum class CommandKind : std::uint8_t {
  tcp_on,             ///< TRAORI: the five-axis transformation (tool-centre-point control)
  tcp_off,            ///< TRAFOOF
  orientation_vector,     ///< ORIVECT, ORIPLANE (G group 51): the direction along a great circle
  orientation_axes,       ///< ORIAXES (G group 51): the rotary axes linearly
  orientation_other,      ///< the rest of G group 51: cones, curves, the path's tangent
  orientation_workpiece,  ///< ORIWKS (G group 25): the direction's turn in the workpiece
  orientation_machine,    ///< ORIMKS (G group 25): the rotary axes' in the machine
  setting,            ///< moves nothing and changes no coordinates: passed through
};

struct CommandDescriptor {
  std::string_view name;
  CommandKind kind;
};

/// The descriptor of a command ccomp reads (its name upper case), or nullptr.
[[nodiscard]] const CommandDescriptor* siemens_command(std::string_view name);

/// Why ccomp does not read the command `name`: what it does that ccomp does not follow.
[[nodiscard]] std::string siemens_refusal(std::string_view name);

/// Why an extended address (`A3=`: letter and digits) is not read.
[[nodiscard]] std::string extended_address_refusal(char letter, unsigned extension);

}  // namespace ccomp::gcode
