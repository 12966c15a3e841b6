#pragma once
// Test support: a reference horizontal machining centre written apart from ccomp's model
// code (no kinematics::, no model::, no simulate): its own lines, rotations and error
// functions, from the physical meaning docs/machine-model.md gives each term. Tests measure
// it as a metrology engineer would (laser lines, a grid, a sphere on the table probed as B
// turns) and hold ccomp's fit and compensation to it.
//
// The machine is the seed's: X and Z carry the table (its B centre 400 mm from the spindle
// nose along Z), B turns the table about the vertical, Y carries the spindle head, the tool
// hangs L below the head along -Z. Every error is the tool's relative to the workpiece.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <string>
#include <vector>

namespace ccomp::test {

/// What a reading of the reference depends on besides the axes: the approach of X, Y and Z
/// (+1 after travelling up, -1 down, 0 unknown) and the spindle's temperature (degC).
struct ReferenceState {
  std::array<double, 3> approach{};
  double b_approach = 0.0;  ///< the table's: +1 after turning B up, -1 down, 0 unknown
  double spindle_T = 20.0;
  double bed_T = 20.0;  ///< the bed, where X's scale is
};

struct ReferenceHmc {
  // Location errors (ISO 230-1): the tool relative to the workpiece travels along X's line
  // (1, EC0X, -EB0X) and Y's line (0, 1, EA0Y); the table turns about its line, which is
  // displaced so that over a turn the tool is off by (EX0B, 0, EZ0B) on average, and tilted
  // so that B's positive direction (the tool turning about +Y) is (-EC0B, 1, EA0B).
  double EC0X = 0, EB0X = 0, EA0Y = 0;  ///< rad
  double EX0B = 0, EZ0B = 0;            ///< mm
  double EA0B = 0, EC0B = 0;            ///< rad
  // Error motions, mm of the tool's deviation (rad for the Y head's pitch EAY) as functions
  // of the axis position (mm). Empty: none.
  std::function<double(double)> EXX, EYX, EZX, EYY, EZY, EZZ, EAY;
  /// The table's angular positioning error (rad) as a function of B (deg): the table turns
  /// by b + EBB(b) (a worm wheel, an encoder's eccentricity).
  std::function<double(double)> EBB;
  /// The X carriage's translation error motions that change with where the other
  /// carriages are too (a load, an overhang): the tool's deviation (mm) at x, y, z.
  std::function<Eigen::Vector3d(double, double, double)> table_load;
  /// X's scale grows with the bed's temperature: its positioning error gains this times
  /// x (T_bed - 20), per degC.
  double x_scale_expansion = 0.0;
  /// Reversal of X, Y, Z's positioning (mm), as ISO 230-2 gives it: the upward error less
  /// the downward one. The tool is off along the axis by half of it times the approach.
  std::array<double, 3> reversal{};
  /// What each axis' reversal adds where it is (mm, of the axis' position in mm): a screw
  /// worn more at one end plays more there. Empty: the same everywhere.
  std::array<std::function<double(double)>, 3> reversal_along{};
  /// The table's reversal (rad): turned up to an angle it stands at b + b_reversal / 2,
  /// turned down at b - b_reversal / 2 (the worm's backlash against the wheel).
  double b_reversal = 0.0;
  /// X's carriage rides on one flank of its guide or the other: the tool is off along Z by
  /// half of this (mm) times X's approach.
  double x_rides = 0.0;
  /// The spindle grows along Z with the temperature its sensor reads: mm per degC above 20.
  double spindle_growth = 0.0;
  double b_centre = 400.0;  ///< mm from the spindle nose to the B centre along Z
  /// Where this machine's programs have their zero, in its axis positions (the gauge line's,
  /// as its control's G54 holds it): neither machine zero nor the B centre (Z = -b_centre),
  /// so that no test can share a convention with ccomp's defaults.
  Eigen::Vector3d work_origin{-35.0, 20.0, -330.0};

  using State = ReferenceState;

  /// The axis positions (x, y and z of the gauge line, mm) that put a tool of length L on
  /// program point p (mm), and back.
  [[nodiscard]] Eigen::Vector3d axes_of_program(const Eigen::Vector3d& p, double L) const;
  [[nodiscard]] Eigen::Vector3d program_of_axes(const Eigen::Vector3d& axes, double L) const;
  /// work_origin as `--work-offset` takes it: "G54=X-35,Y20,Z-330".
  [[nodiscard]] std::string work_offset_text() const;

  /// The tool tip's deviation from where it should touch the part, in machine-axis
  /// directions (mm), for program (chain) values x y z (mm), b (deg) and tool length L (mm).
  [[nodiscard]] Eigen::Vector3d deviation(double x, double y, double z, double b_deg, double L,
                                          const State& state = ReferenceState{}) const;
  /// Where the tool tip really is on the table (table frame, mm), and where the perfect
  /// machine would put it.
  [[nodiscard]] Eigen::Vector3d actual_table_point(double x, double y, double z, double b_deg, double L,
                                                   const State& state = ReferenceState{}) const;
  [[nodiscard]] Eigen::Vector3d nominal_table_point(double x, double y, double z, double b_deg, double L) const;
  /// The chain values x, y, z that put the perfect machine's tool tip at the table point
  /// `s` (table frame, mm) at angle b with tool length L.
  [[nodiscard]] Eigen::Vector3d axes_for_table_point(const Eigen::Vector3d& s, double b_deg, double L) const;
};

/// A machine of the sample HMC's kind (samples/machines/hmc-xyzb-geometric.yaml): its
/// squareness, the B axis' line and its carriages' error motions, with values of its own.
[[nodiscard]] ReferenceHmc geometric_reference();

/// One reading of the reference: the deviation along `direction` at chain values.
struct ReferenceReading {
  double x = 0, y = 0, z = 0, b_deg = 0, L = 0;
  ReferenceHmc::State state;
  double time = 0;  ///< s since the start
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  double value = 0;  ///< mm, noise included
  std::string source;
};

struct ReferencePlans {
  double noise = 0.0002;  ///< mm, one sigma, on every reading
  unsigned seed = 1;
  bool nine_lines = true, grid = true, sphere = true;
  /// Three points read every 10 minutes for 4 hours while the spindle warms 20 -> 32 degC
  /// (time constant 40 minutes) and the bed by `bed_rise` (90 minutes).
  bool thermal = false;
  double bed_rise = 4.0;    ///< degC
  double sphere_step = 15;  ///< deg of B between the spheres' probings
  /// The spheres probed turning B up over the turn, then again turning it down.
  bool sphere_both_ways = false;
  /// The laser lines' targets displaced irregularly within +-line_step/4 (ISO 230-2's
  /// irregular spacing), the same on every pass; false: every line_step exactly.
  bool irregular_targets = false;
  double line_step = 20.0;  ///< mm between a laser line's readings (a lead screw's pitch needs a few per period)
  std::vector<double> grid_tool_lengths{0.0, 200.0};
};

/// Measures the reference: nine laser lines (three per axis at B0, out and back:
/// positioning on each, straightness across on lines 1 and 2), a 5x5x5 grid of full
/// deviations at each tool length, two spheres on the table probed every `sphere_step` of B, and
/// with `thermal` a warm-up run.
[[nodiscard]] std::vector<ReferenceReading> measure_reference(const ReferenceHmc& machine, const ReferencePlans& plans);

}  // namespace ccomp::test
