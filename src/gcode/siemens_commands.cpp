#include "siemens_commands.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>

namespace ccomp::gcode {
namespace {

using enum CommandKind;

constexpr std::array kCommands{
    CommandDescriptor{"TRAORI", tcp_on},
    CommandDescriptor{"TRAFOOF", tcp_off},
    CommandDescriptor{"ORIAXES", orientation_axes},
    CommandDescriptor{"ORIVECT", orientation_vector},
    CommandDescriptor{"ORIPLANE", orientation_vector},
    CommandDescriptor{"ORIPATH", orientation_other},
    CommandDescriptor{"ORIPATHS", orientation_other},
    CommandDescriptor{"ORICONCW", orientation_other},
    CommandDescriptor{"ORICONCCW", orientation_other},
    CommandDescriptor{"ORICONIO", orientation_other},
    CommandDescriptor{"ORICONTO", orientation_other},
    CommandDescriptor{"ORICURVE", orientation_other},
    // How the orientation is programmed as angles or vectors (refused at their addresses),
    // the messages, and how the control smooths and paces the path.
    CommandDescriptor{"ORIWKS", orientation_workpiece},
    CommandDescriptor{"ORIMKS", orientation_machine},
    CommandDescriptor{"ORIEULER", setting},
    CommandDescriptor{"ORIRPY", setting},
    CommandDescriptor{"MSG", setting},
    CommandDescriptor{"CYCLE832", setting},
    CommandDescriptor{"SOFT", setting},
    CommandDescriptor{"BRISK", setting},
    CommandDescriptor{"DRIVE", setting},
    CommandDescriptor{"FFWON", setting},
    CommandDescriptor{"FFWOF", setting},
    CommandDescriptor{"CFTCP", setting},
    CommandDescriptor{"CFC", setting},
    CommandDescriptor{"CFIN", setting},
    CommandDescriptor{"COMPOF", setting},
    CommandDescriptor{"COMPON", setting},
    CommandDescriptor{"COMPCURV", setting},
    CommandDescriptor{"COMPCAD", setting},
    CommandDescriptor{"COMPSURF", setting},
    CommandDescriptor{"UPATH", setting},
    CommandDescriptor{"SPATH", setting},
    CommandDescriptor{"STOPRE", setting},
    CommandDescriptor{"WORKPIECE", setting},
    CommandDescriptor{"SPOS", setting},
};

bool starts_with_any(std::string_view name, std::initializer_list<std::string_view> prefixes) {
  return std::any_of(prefixes.begin(), prefixes.end(), [&](std::string_view p) { return name.starts_with(p); });
}

}  // namespace

const CommandDescriptor* siemens_command(std::string_view name) {
  const auto* it = std::find_if(kCommands.begin(), kCommands.end(),
                                [&](const CommandDescriptor& c) { return c.name == name; });
  return it == kCommands.end() ? nullptr : &*it;
}

std::string siemens_refusal(std::string_view name) {
  std::string_view why = "a command the siemens dialect does not read (docs/dialects.md lists those it does)";
  if (name == "CYCLE800")
    why = "swivels the working plane: it turns the rotary axes and rotates the coordinates, which ccomp does not follow";
  else if (name.starts_with("CYCLE") || name.starts_with("POCKET") || name.starts_with("SLOT") || name == "MCALL" ||
           name == "HOLES1" || name == "HOLES2")
    why = "a machining cycle: it moves the axes in ways ccomp does not model";
  else if (starts_with_any(name, {"TRAANG", "TRACYL", "TRANSMIT", "TRACON"}))
    why = "a kinematic transformation other than TRAORI, which ccomp does not follow";
  else if (starts_with_any(name, {"TRANS", "ATRANS", "ROT", "AROT", "SCALE", "ASCALE", "MIRROR", "AMIRROR"}))
    why = "a programmable frame: it shifts, turns or scales the coordinates, which ccomp does not follow";
  else if (starts_with_any(name, {"CR", "AR", "CT", "CIP", "TURN", "SPLINE", "BSPLINE", "POLY", "ASPLINE", "CSPLINE"}))
    why = "an interpolation ccomp does not read (arcs are read by I J K)";
  else if (name == "ORIRESET" || name == "SUPA")
    why = "moves axes to positions ccomp does not know";
  else if (starts_with_any(name, {"IF", "GOTO", "DEF", "LOOP", "WHILE", "FOR", "REPEAT", "CASE", "ELSE", "END"}))
    why = "control flow and variables, which the siemens dialect does not read";
  return fmt::format("{}: {}", name, why);
}

std::string extended_address_refusal(char letter, unsigned extension) {
  const bool orientation = (letter == 'A' || letter == 'B' || letter == 'C') && extension >= 2 && extension <= 7;
  if (!orientation) return fmt::format("{}{}=: an extended address the siemens dialect does not read", letter, extension);
  const std::string_view what = extension == 2   ? "the tool's direction as Euler or RPY angles"
                                : extension == 3 ? "the tool's direction as a vector"
                                                 : "a surface normal or a cone of the tool's direction";
  return fmt::format(
      "{}{}=: {}; ccomp follows TRAORI programs that give the rotary axes' positions (A B C), not the direction",
      letter, extension, what);
}

}  // namespace ccomp::gcode
