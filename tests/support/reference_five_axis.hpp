#pragma once
// Test support: two reference five-axis machines, a trunnion table (XYZAC: the table moves
// X and Y, an A trunnion about X sits on it, a C table on the trunnion, the head moves Z) and
// a head-head one (XYZBC: the table moves X, the head Y and Z, a C head about Z carries a B
// fork about Y), written apart from ccomp's model code (no kinematics::, no model::): their
// own rotations about their own lines, their own geometry and program origin, from the
// physical meaning docs/machine-model.md gives each term. Tests hold ccomp's five-axis
// compensation to them.
//
// Their geometry is a machine's, not a chain's: the points below are in the frame of the
// table base at machine zero, the program origin is set by a work offset
// (G54, machine coordinates) on a point of the part away from both rotary lines, and the
// linear axes' errors are functions of the machine position, not of the program's.
#include <Eigen/Core>
#include <functional>
#include <string>

namespace ccomp::test {

/// A program's words for one pose: x y z in mm (program coordinates, the tool length
/// applied by G43 along Z), a b c in degrees.
struct FiveAxisWords {
  double x = 0, y = 0, z = 0, a = 0, b = 0, c = 0;
};

/// Where the tool is in the part: the tip (mm) and the tool's axis (unit, from the tip toward
/// the spindle), both in the part's (program) frame.
struct PartPose {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
};

/// What both references share: the linear axes' positioning errors, and the tool's pose in
/// the part for a program's words.
class ReferenceFiveAxis {
 public:
  virtual ~ReferenceFiveAxis() = default;
  /// Positioning of the linear axes (mm of the tool along the axis, as functions of the
  /// machine position in mm). Empty: none.
  std::function<double(double)> EXX, EYY, EZZ;

  /// G54: the machine position (mm) that puts the tool tip on the program origin with the
  /// rotary axes at 0.
  [[nodiscard]] virtual Eigen::Vector3d work_offset() const = 0;
  /// Where the tool is in the part for the words, with a tool of length L (mm).
  [[nodiscard]] PartPose actual(const FiveAxisWords& w, double L) const { return pose(w, L, true); }
  /// The same on a perfect machine.
  [[nodiscard]] PartPose nominal(const FiveAxisWords& w, double L) const { return pose(w, L, false); }

 protected:
  ReferenceFiveAxis() = default;
  ReferenceFiveAxis(const ReferenceFiveAxis&) = default;
  ReferenceFiveAxis& operator=(const ReferenceFiveAxis&) = default;
  [[nodiscard]] virtual PartPose pose(const FiveAxisWords& w, double L, bool with_errors) const = 0;
};

struct ReferenceTrunnion : ReferenceFiveAxis {
  // Geometry, mm, in the table base's frame with every axis at machine zero.
  Eigen::Vector3d spindle_nose{-35, 22, 480};  ///< the gauge point
  Eigen::Vector3d a_centre{10, -15, 160};      ///< a point of A's line (along +X)
  Eigen::Vector3d c_from_a{4, 8, -30};         ///< C's centre from A's (C along +Z at A 0)
  Eigen::Vector3d origin_from_c{-20, 35, 45};  ///< the program origin from C's centre
  // Location errors (ISO 230-7 names, the tool's error relative to the work): A's line is
  // displaced so that the tool is off by (0, EY0A, EZ0A) on average over a turn, and runs
  // along (1, EC0A, -EB0A); C's line (in the trunnion, at A 0 in machine directions) likewise
  // by (EX0C, EY0C, 0), along (EB0C, -EA0C, 1).
  double EY0A = 0, EZ0A = 0, EX0C = 0, EY0C = 0;  ///< mm
  double EB0A = 0, EC0A = 0, EA0C = 0, EB0C = 0;  ///< rad
  /// Angular positioning (rad, of the angle in degrees): the tool turns by a + EAA(a) about
  /// A's line, by c + ECC(c) about C's. Empty: none.
  std::function<double(double)> EAA, ECC;

  [[nodiscard]] Eigen::Vector3d work_offset() const override;

 protected:
  [[nodiscard]] PartPose pose(const FiveAxisWords& w, double L, bool with_errors) const override;
};

struct ReferenceHeads : ReferenceFiveAxis {
  // Geometry, mm: C's centre in the table base's frame with every axis at machine zero (C
  // along +Z), B's centre from C's (B along +Y at C 0), the spindle nose from B's centre
  // (the pivot), the program origin on the table.
  Eigen::Vector3d c_centre{5, -12, 420};
  Eigen::Vector3d b_from_c{3, -2, -95};
  Eigen::Vector3d nose_from_b{0, 0, -150};
  Eigen::Vector3d program_origin{-40, 25, 60};
  // Location errors: the tool is off by (EX0C, EY0C, 0) on average over a turn of C, whose
  // line runs along (EB0C, -EA0C, 1); by (EX0B, 0, EZ0B) over a turn of B (in the C head, at
  // C 0 in machine directions), whose line runs along (-EC0B, 1, EA0B).
  double EX0C = 0, EY0C = 0, EX0B = 0, EZ0B = 0;  ///< mm
  double EA0C = 0, EB0C = 0, EA0B = 0, EC0B = 0;  ///< rad
  /// Angular positioning (rad, of the angle in degrees): the tool turns by b + EBB(b), c +
  /// ECC(c). Empty: none.
  std::function<double(double)> EBB, ECC;

  [[nodiscard]] Eigen::Vector3d work_offset() const override;

 protected:
  [[nodiscard]] PartPose pose(const FiveAxisWords& w, double L, bool with_errors) const override;
};

/// A point as a model file writes it: "[x mm, y mm, z mm]", to the last digit.
[[nodiscard]] std::string yaml_mm(const Eigen::Vector3d& v);

/// The references in ccomp's terms, without error terms (a `terms:` key last, to append
/// them to). The trunnion: the table base moved by X and Y, the trunnion and its table at
/// their centres, the program origin a fixed link on the C table; the head's Z carries the
/// tool from where its tip meets the program origin at machine zero. The head-head machine:
/// the table moved by X, the program origin where the tool tip is at machine zero; the
/// head's Y and Z, C at its centre, B's fork from it, the tool from B's centre.
[[nodiscard]] std::string ccomp_model(const ReferenceTrunnion& r);
[[nodiscard]] std::string ccomp_model(const ReferenceHeads& r);

}  // namespace ccomp::test
