#pragma once
// Where program zero lies in machine coordinates. The machine model describes the machine
// in its machine coordinates (where each rotary line lies with every axis at zero, as a
// control's kinematic parameters store it); a program's points and a measurement file's
// rows are in program coordinates. The work offsets (G54 ... G59.3, as the control stores
// them) turn the one into the other: machine position = program point + origin (+ the tool
// length along the tool), so they set the lever of every rotary error.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/error.hpp"

namespace ccomp::model {

/// The coordinate systems a control keeps, numbered as #5220 numbers them: 1 = G54 ...
/// 6 = G59, 7 = G59.1, 8 = G59.2, 9 = G59.3.
inline constexpr std::size_t kCoordinateSystems = 9;

/// A coordinate system's origin in machine coordinates, per axis X Y Z A B C U V W: mm for
/// the linear axes, degrees for the rotary ones.
using WorkOrigin = AxisArray<double>;

/// The origins known of each coordinate system (index 0 is G54); an unknown one is absent.
struct WorkOffsets {
  std::array<std::optional<WorkOrigin>, kCoordinateSystems> systems;

  [[nodiscard]] const std::optional<WorkOrigin>& of(std::size_t number) const { return systems.at(number - 1); }
  void set(std::size_t number, const WorkOrigin& origin) { systems.at(number - 1) = origin; }
  [[nodiscard]] bool any() const;
  /// `other`'s known systems replace these.
  void override_with(const WorkOffsets& other);
  friend bool operator==(const WorkOffsets&, const WorkOffsets&) = default;
};

/// "G54" -> 1 ... "G59" -> 6, "G59.1" -> 7 ... "G59.3" -> 9, in any case; nullopt otherwise.
[[nodiscard]] std::optional<std::size_t> coordinate_system_number(std::string_view name);
/// 1 -> "G54" ... 9 -> "G59.3".
[[nodiscard]] std::string coordinate_system_name(std::size_t number);

/// One system as ccomp writes it (in headers, measurement files, reports): "G54 X0 Y0
/// Z-400", X Y Z always and the other axes where not zero, with up to 6 decimals.
[[nodiscard]] std::string describe_work_offset(std::size_t number, const WorkOrigin& origin);
/// Every known system, described and joined by ", "; "none" when none is known.
[[nodiscard]] std::string describe_work_offsets(const WorkOffsets& offsets);

/// Refuses (ccomp::Error of `kind`, naming `what`) an origin that moves an axis not among
/// `axes` (the machine's letters): an offset of an axis the machine lacks is a mistake.
void check_on_machine(const WorkOrigin& origin, std::size_t system, const std::vector<char>& axes, ErrorKind kind,
                      const std::string& what);

struct WorkOffsetEntry {
  std::size_t system = 1;
  WorkOrigin origin{};
};
/// Parses one system as a user writes it: "G54=X-250,Y0,Z-300" or "G54 X-250 Y0 Z-300"
/// (commas, blanks or both between the words; an axis not written is 0). A value may carry
/// its unit ("Z-300mm", "X-10in", "B0.5deg", "B30arcmin"): mm and degrees without one.
/// Throws ccomp::Error (usage) naming `what` and the word at fault.
[[nodiscard]] WorkOffsetEntry parse_work_offset(std::string_view text, const std::string& what);

}  // namespace ccomp::model
