#pragma once
// What the interpreter tells the rest of ccomp: the canonical machining calls of LinuxCNC
// (STRAIGHT_TRAVERSE, STRAIGHT_FEED, ARC_FEED, offsets...), with every position as the
// controlled point in machine coordinates (work offsets applied, tool length not).
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "ccomp/gcode/axes.hpp"
#include "ccomp/gcode/block.hpp"
#include "ccomp/gcode/source.hpp"

namespace ccomp::gcode {

enum class Plane : std::uint8_t { xy, zx, yz };  ///< G17, G18, G19
enum class Units : std::uint8_t { mm, inch };    ///< G21, G20
enum class FeedMode : std::uint8_t { units_per_minute, inverse_time, units_per_rev };

/// The two in-plane axes and the normal axis of a plane, as ARC_FEED orders them.
struct PlaneAxes {
  std::size_t first, second, normal;
};
[[nodiscard]] constexpr PlaneAxes plane_axes(Plane p) {
  switch (p) {
    case Plane::xy:
      return {0, 1, 2};
    case Plane::zx:
      return {2, 0, 1};
    case Plane::yz:
      return {1, 2, 0};
  }
  return {0, 1, 2};
}

/// The offsets in force: origin = G5x + G92/G52 (mm, deg); tool = tool length offset;
/// rotation = G10 L2 R, degrees about Z of the G5x system. The interpreter keeps points in
/// an unrotated frame (program + origin, as rs274ngc does); to_machine() applies the
/// rotation about the G5x origin.
struct Offsets {
  int coordinate_system = 1;  ///< 1 = G54 ... 9 = G59.3
  Axes g5x{};
  Axes g92{};
  Axes tool{};
  double rotation = 0.0;
  [[nodiscard]] double origin(std::size_t axis) const { return g5x[axis] + g92[axis]; }
  [[nodiscard]] Axes to_machine(const Axes& p) const { return rotation == 0.0 ? p : rotated(p, rotation); }
  [[nodiscard]] Axes from_machine(const Axes& m) const { return rotation == 0.0 ? m : rotated(m, -rotation); }
  /// Program coordinates (current system, mm and deg) of a machine-frame point.
  [[nodiscard]] Axes program_of(const Axes& machine) const {
    Axes p = from_machine(machine);
    for (std::size_t i = 0; i < kAxisCount; ++i) p[i] -= origin(i);
    return p;
  }

 private:
  [[nodiscard]] Axes rotated(const Axes& p, double degrees) const;
};

enum class MotionKind : std::uint8_t { traverse, feed, arc, probe };

/// Where a motion came from, for compensation and reports.
enum class MotionSource : std::uint8_t { program, canned_cycle, reference_return, machine_coordinates };

struct Arc {
  Plane plane = Plane::xy;
  double center_first = 0.0;   ///< centre, machine frame, first plane axis (mm)
  double center_second = 0.0;  ///< centre, second plane axis (mm)
  int turns = 1;               ///< signed: + counter-clockwise (G3), - clockwise (G2)
};

/// How a TCP program gives the tool's direction, where it does instead of the rotary axes'
/// angles.
enum class DirectionWords : std::uint8_t {
  none,            ///< the angles (A B C)
  ijk,             ///< G43.5's I J K
  siemens_vector,  ///< Siemens' A3= B3= C3= under TRAORI
};

struct Motion {
  MotionKind kind = MotionKind::traverse;
  MotionSource source = MotionSource::program;
  Axes start{};  ///< controlled point before the move (machine frame, no tool length)
  Axes end{};    ///< after the move
  Arc arc;       ///< when kind == arc
  FeedMode feed_mode = FeedMode::units_per_minute;
  double feed = 0.0;             ///< mm/min, or 1/min in inverse time, or mm/rev
  Units units = Units::mm;       ///< the program's units at the time (for printing)
  bool incremental = false;      ///< G91 in force: the block's axis words are distances
  bool absolute_centre = false;  ///< G90.1 in force: an arc's I J K are a point, not distances
  /// G41/G42 in force: the controller offsets the path by the tool's radius.
  bool radius_compensation = false;
  /// Tool centre point control in force (InterpreterOptions::tcp, TcpCodes::follow): `start`
  /// and `end` are the tool tip in the part and the rotary axes' angles, which the control's
  /// kinematics turn into the axes' positions, and it moves them in a straight line.
  bool tcp = false;
  /// Under TCP, the control turns the tool's direction along the great circle from the
  /// start's to the end's, the rotary axes wherever its kinematics put it on the way (G43.5,
  /// Siemens' ORIWKS with ORIVECT); else it moves the rotary axes linearly.
  bool tcp_great_circle = false;
  /// Under TCP, how the program gives the tool's direction where it does not give the rotary
  /// axes' angles: `start` and `end` hold the angles the control's kinematics take for it
  /// (InterpreterOptions::tcp_direction), and a rewriter writes the direction back so.
  DirectionWords direction_words = DirectionWords::none;
  /// With the programmed path reported (CutterPath::programmed): the move the tool centre
  /// makes under G41/G42 (and on the move after G40, from where the offset left it), as the
  /// control offsets it before the next move settles its corner; machine frame. Without an
  /// offset, `offset` is false and the tool centre is the controlled point.
  bool offset = false;
  Axes tool_start{}, tool_end{};
  const Offsets* offsets = nullptr;  ///< in force during the move
  std::uint32_t line = 0;            ///< source line of the block that commanded it
};

/// An arc's geometry in its plane (machine frame): radius at the start and at the end (they
/// differ within LinuxCNC's tolerance), start angle, and the angle swept in the arc's
/// direction, with its whole extra turns.
struct ArcGeometry {
  PlaneAxes axes;
  double r_start = 0, r_end = 0;
  double a_start = 0;
  double sweep = 0;  ///< > 0
  bool ccw = true;
  /// The in-plane point at fraction f of the sweep (radius interpolated).
  [[nodiscard]] std::pair<double, double> at(double f, double c1, double c2) const;
};
[[nodiscard]] ArcGeometry arc_geometry(const Motion& arc);
/// The controlled point at fraction f of an arc's sweep (`g` its geometry): in the plane on
/// the arc (radius interpolated), the other axes linear from start to end.
[[nodiscard]] Axes arc_point(const Motion& arc, const ArcGeometry& g, double f);

/// A non-motion canonical call, already formatted as LinuxCNC's rs274 prints it. An empty
/// name is plain output of (PRINT,...).
struct CanonCall {
  std::string_view name;
  std::string arguments;
  std::uint32_t line = 0;
};

/// Receives what the interpreter does. Sinks that only want motions leave the rest.
class CanonSink {
 public:
  virtual ~CanonSink() = default;
  /// Every block the interpreter executes, before its motions, in execution order.
  virtual void block(const Block& /*block*/, const SourceLine& /*line*/) {}
  virtual void motion(const Motion& /*motion*/) {}
  /// Only called when wants_calls() is true, since formatting costs time.
  virtual void call(const CanonCall& /*call*/) {}
  [[nodiscard]] virtual bool wants_calls() const { return false; }
  /// A block about to be executed (not an O-word statement, not a line a loop or a
  /// subroutine definition skips), from `file`, with the value of each of its words in
  /// `block.words` order: expressions and parameters evaluated, NaN for a lone letter.
  /// Only called when wants_values() is true.
  virtual void values(const Block& /*block*/, const SourceLine& /*line*/, std::string_view /*file*/,
                      std::span<const double> /*values*/) {}
  [[nodiscard]] virtual bool wants_values() const { return false; }
  /// A warning: something ccomp accepted but the user should know.
  virtual void warning(const std::string& /*message*/, std::uint32_t /*line*/) {}
};

}  // namespace ccomp::gcode
