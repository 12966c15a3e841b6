#pragma once
// The machine model: which axes the machine has, their limits, the G-code dialect of its
// control, its kinematic chains and error terms. Plain data; reading and writing its file
// is ccomp/model/model_file.hpp.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/model/error_term.hpp"
#include "ccomp/model/units.hpp"
#include "ccomp/model/work_offsets.hpp"

namespace ccomp::model {

enum class AxisType : std::uint8_t { linear, rotary };

/// Whether the compensation may turn a rotary axis the program does not turn
/// (docs/machine-model.md, "Axes the compensation holds").
enum class AxisHold : std::uint8_t {
  /// Held at the program's value until the program first turns it, then corrected as `free`:
  /// an axis a program never commands (a 3-axis job on a machine with a table) stays still.
  automatic,
  /// Never turned by the compensation: it stands where the program puts it, and the other
  /// axes take what they can (an indexing table on its detents, a table clamped while cutting).
  clamped,
  /// Corrected on every move, as a servo axis that holds any angle it is given.
  free,
};
/// "auto", "clamped" (or "indexing", the same), "free"; nullopt for another word.
[[nodiscard]] std::optional<AxisHold> axis_hold_named(std::string_view name);
[[nodiscard]] std::string_view axis_hold_name(AxisHold hold);

struct AxisSpec {
  char letter = 'X';
  AxisType type = AxisType::linear;
  AxisHold hold = AxisHold::free;  ///< a rotary axis': see AxisHold
  double min = -std::numeric_limits<double>::infinity();  ///< mm or deg
  double max = std::numeric_limits<double>::infinity();

  /// The axis its letter names (validate() has checked the letter).
  [[nodiscard]] Axis axis() const { return axis_named(letter).value(); }
  /// Its place in X Y Z A B C U V W, where arrays of all nine axes (a ChainQ) hold it.
  [[nodiscard]] std::size_t index() const { return ccomp::index(axis()); }
  [[nodiscard]] bool rotary() const { return type == AxisType::rotary; }
};

/// Why an axis' type cannot be, where the words programs give for its letter say otherwise
/// (A B C are angles, the others lengths); nothing where the two agree.
[[nodiscard]] std::optional<std::string> type_contradiction(const AxisSpec& a);

/// What a term depends on.
enum class VariableKind : std::uint8_t { none, axis, tool_length, time, temperature, direction };

struct Variable {
  VariableKind kind = VariableKind::none;
  std::size_t index = 0;  ///< axis index (X Y Z A B C U V W) or sensor index
  std::string text;       ///< as written: "x", "T_spindle", "vx", "L", "t"
};

/// One link of a chain: an axis moving along or about `direction`, or a fixed link.
struct LinkSpec {
  std::string name;          ///< "X", "B", "S", "tool"...
  std::optional<char> axis;  ///< the program axis that moves it
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< placement before it moves (mm)
  bool tool = false;                                 ///< the tool tip: the tool length L along `direction`
};

/// Where a term acts on its link (ISO 230-1). An error motion (EXX, EBB, a thermal drift
/// EX0X of T_bed) acts after the axis' motion and moves what the axis carries. A location
/// error (a constant E<c>0<axis>: squareness EC0X, the B axis' position EX0B and tilt EA0B)
/// places the axis' line: a linear axis travels along its turned line, a rotary axis turns
/// about its displaced and tilted line (kinematics/chain.hpp).
enum class ErrorPlacement : std::uint8_t { motion, location };

/// Whether the model files' reference frame (docs/error-model.md: Ref 1, its sect. 2.3) fixes the turn of linear
/// axis `axis`'s line about `rotation` (3 4 5: about x y z): Z's line is the frame's primary
/// axis (its turns about x and y are zero by definition), Y's lies in the frame's Z-Y plane
/// (its turn about z is). The squareness between the lines is carried by X's and Y's.
[[nodiscard]] constexpr bool frame_fixes_line_turn(char axis, int rotation) {
  return (axis == 'Z' && (rotation == 3 || rotation == 4)) || (axis == 'Y' && rotation == 5);
}

/// An error term: one component of one link's error motion or location, a form of a variable.
struct ErrorTermSpec {
  std::string name;  ///< ISO 230-1 ("EXX", "EC0X", "EBB") as the file names it, or its alias from docs/error-model.md Ref 1
  std::string iso;   ///< the ISO 230-1 name
  std::string link;  ///< the link whose error it is
  int component = 0;  ///< 0 1 2: translation x y z (mm); 3 4 5: rotation about x y z (rad)
  ErrorPlacement placement = ErrorPlacement::motion;
  TermShape shape;
  Variable primary, secondary;
  Eigen::VectorXd parameters;  ///< in mm, rad, s, degC, with the ISO name's sign
  /// Internal units per file unit, to write values back; negative where the file's name is
  /// a Ref 1 symbol of the opposite sign (S_xy = -EC0X).
  std::vector<double> parameter_unit;
  /// Where it was fitted (the file's `span`): its value is held at the ends beyond. None:
  /// the form as it is everywhere.
  std::optional<TermSpan> span;
  double variable_unit = 1.0;  ///< internal units per file unit of the primary variable (its span's)
  bool free = false;           ///< a fit may change it
  bool free_period = false;  ///< periodic: a fit may change the period too (fit_period: true)
  std::string note;
};

/// rad per mm: a rotary axis' correction and limit margin as max_correction bounds them
/// (10 mrad for each mm, a tool about 100 mm from the axis).
inline constexpr double kRotaryBoundPerMm = 1e-2;

struct MachineModel {
  std::string name;
  std::string description;
  std::vector<AxisSpec> axes;
  std::vector<LinkSpec> workpiece_chain;  ///< base W -> workpiece point p
  std::vector<LinkSpec> tool_chain;       ///< base W -> tool tip
  std::vector<std::string> sensors;       ///< temperature sensors, for T_<name> variables
  std::vector<ErrorTermSpec> terms;
  double max_correction = 0.5;  ///< mm: larger corrections are refused (a rotary axis': kRotaryBoundPerMm of it)
  /// The work offsets programs on this machine run with, as its control stores them
  /// (`work_offsets:`): where program zero lies in machine coordinates.
  WorkOffsets work_offsets;
  std::string dialect = "linuxcnc";
  std::string path;    ///< where it was read from
  std::string sha256;  ///< of the file's bytes: names the model in compensated programs

  [[nodiscard]] const AxisSpec* axis(char letter) const {
    for (const AxisSpec& a : axes)
      if (a.letter == letter) return &a;
    return nullptr;
  }
};

/// Checks a model: known axis letters, no duplicates, limits ordered and not NaN, a dialect
/// ccomp knows. Throws ccomp::Error (model) with the offending entry.
void validate(const MachineModel& model);

}  // namespace ccomp::model
