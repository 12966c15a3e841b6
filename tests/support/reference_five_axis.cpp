#include "reference_five_axis.hpp"

#include <Eigen/Geometry>
#include <numbers>
#include <sstream>
#include <string>

namespace ccomp::test {

namespace {
constexpr double kRadPerDeg = std::numbers::pi / 180.0;

double value_of(const std::function<double(double)>& f, double v) {
  return f ? f(v) : 0.0;
}

/// Base coordinates -> coordinates of a body turned by -angle about the line through
/// `point` along `direction` (the tool turning by +angle about it, the body seen from it),
/// the body's coordinates counted from `origin` (its nominal centre).
Eigen::Vector3d into_turned_body(const Eigen::Vector3d& v, const Eigen::Vector3d& point,
                                 const Eigen::Vector3d& direction, double angle, const Eigen::Vector3d& origin) {
  return Eigen::AngleAxisd(angle, direction.normalized()) * (v - point) + point - origin;
}

/// A head's point `v` (from its nominal centre) turned with the head by `angle` about the line
/// through `point` (from the same centre) along `direction`, seen from the head's carrier.
Eigen::Vector3d turned_with_head(const Eigen::Vector3d& v, const Eigen::Vector3d& point,
                                 const Eigen::Vector3d& direction, double angle) {
  return Eigen::AngleAxisd(angle, direction.normalized()) * (v - point) + point;
}

/// The linear axes' positioning errors at a machine position, or nothing.
Eigen::Vector3d linear_errors(const std::function<double(double)>& ex, const std::function<double(double)>& ey,
                              const std::function<double(double)>& ez, const Eigen::Vector3d& machine) {
  return {value_of(ex, machine.x()), value_of(ey, machine.y()), value_of(ez, machine.z())};
}
}  // namespace

Eigen::Vector3d ReferenceTrunnion::work_offset() const {
  return a_centre + c_from_a + origin_from_c - spindle_nose;
}

PartPose ReferenceTrunnion::pose(const FiveAxisWords& w, double L, bool with_errors) const {
  const double e = with_errors ? 1.0 : 0.0;
  // The machine's positions: the program's words through the work offset, Z raised by the
  // tool length (G43); the tool tip below the nose by L, in the table base's frame.
  const Eigen::Vector3d machine = Eigen::Vector3d(w.x, w.y, w.z) + work_offset() + Eigen::Vector3d(0, 0, L);
  Eigen::Vector3d tip = spindle_nose + machine - Eigen::Vector3d(0, 0, L);
  tip += e * linear_errors(EXX, EYY, EZZ, machine);
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  // The trunnion: its real line, displaced against the tool's mean deviation and tilted.
  const Eigen::Vector3d a_point = a_centre - e * Eigen::Vector3d(0, EY0A, EZ0A);
  const Eigen::Vector3d a_line = Eigen::Vector3d(1, e * EC0A, -e * EB0A);
  const double a = w.a * kRadPerDeg + e * value_of(EAA, w.a);
  tip = into_turned_body(tip, a_point, a_line, a, a_centre);
  axis = Eigen::AngleAxisd(a, a_line.normalized()) * axis;
  // The C table on it, in the trunnion's frame from A's centre.
  const Eigen::Vector3d c_point = c_from_a - e * Eigen::Vector3d(EX0C, EY0C, 0);
  const Eigen::Vector3d c_line = Eigen::Vector3d(e * EB0C, -e * EA0C, 1);
  const double c = w.c * kRadPerDeg + e * value_of(ECC, w.c);
  tip = into_turned_body(tip, c_point, c_line, c, c_from_a);
  axis = Eigen::AngleAxisd(c, c_line.normalized()) * axis;
  return {tip - origin_from_c, axis.normalized()};
}

Eigen::Vector3d ReferenceHeads::work_offset() const {
  return program_origin - c_centre - b_from_c - nose_from_b;
}

PartPose ReferenceHeads::pose(const FiveAxisWords& w, double L, bool with_errors) const {
  const double e = with_errors ? 1.0 : 0.0;
  const Eigen::Vector3d machine = Eigen::Vector3d(w.x, w.y, w.z) + work_offset() + Eigen::Vector3d(0, 0, L);
  // The tool in the B fork, from B's centre; the fork turns the tool (positive: about +Y)
  // about its real line, which the tool's mean deviation over a turn displaces.
  Eigen::Vector3d tip = nose_from_b - Eigen::Vector3d(0, 0, L);
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d b_point = e * Eigen::Vector3d(EX0B, 0, EZ0B);
  const Eigen::Vector3d b_line(-e * EC0B, 1, e * EA0B);
  const double b = w.b * kRadPerDeg + e * value_of(EBB, w.b);
  tip = turned_with_head(tip, b_point, b_line, b) + b_from_c;
  axis = Eigen::AngleAxisd(b, b_line.normalized()) * axis;
  // The C head carries the fork, from C's centre.
  const Eigen::Vector3d c_point = e * Eigen::Vector3d(EX0C, EY0C, 0);
  const Eigen::Vector3d c_line(e * EB0C, -e * EA0C, 1);
  const double c = w.c * kRadPerDeg + e * value_of(ECC, w.c);
  tip = turned_with_head(tip, c_point, c_line, c);
  axis = Eigen::AngleAxisd(c, c_line.normalized()) * axis;
  // The head's carriages (Y, Z) and the table's X: the tool relative to the table base.
  tip += c_centre + machine + e * linear_errors(EXX, EYY, EZZ, machine);
  return {tip - program_origin, axis.normalized()};
}

std::string yaml_mm(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.precision(17);
  out << "[" << v.x() << " mm, " << v.y() << " mm, " << v.z() << " mm]";
  return out.str();
}

/// The trunnion in ccomp's terms: the table base moved by X and Y, the trunnion and its table
/// at their centres, the program origin a fixed link on the C table; the head's Z carries the
/// tool from where its tip meets the program origin at machine zero.
std::string ccomp_model(const ReferenceTrunnion& r) {
  return R"(
name: reference-trunnion
axes: {X: {}, Y: {}, Z: {}, A: {type: rotary}, C: {type: rotary}}
max_correction: 1 mm
chain:
  workpiece:
    - {link: Y, axis: Y, direction: [0, -1, 0]}
    - {link: X, axis: X, direction: [-1, 0, 0]}
    - {link: A, axis: A, direction: [-1, 0, 0], offset: )" +
         yaml_mm(r.a_centre) + R"(}
    - {link: C, axis: C, direction: [0, 0, -1], offset: )" +
         yaml_mm(r.c_from_a) + R"(}
    - {link: part, offset: )" +
         yaml_mm(r.origin_from_c) + R"(}
  tool:
    - {link: Z, axis: Z, direction: [0, 0, 1], offset: )" +
         yaml_mm(r.a_centre + r.c_from_a + r.origin_from_c) + R"(}
    - {link: tool, tool_length: [0, 0, -1]}
terms:
)";
}

/// The head-head machine in ccomp's terms: the table moved by X, the program origin where
/// the tool tip is at machine zero; the head's Y and Z, C at its centre, B's fork from it, the
/// tool from B's centre.
std::string ccomp_model(const ReferenceHeads& r) {
  return R"(
name: reference-heads
axes: {X: {}, Y: {}, Z: {}, B: {type: rotary}, C: {type: rotary}}
max_correction: 1 mm
chain:
  workpiece:
    - {link: X, axis: X, direction: [-1, 0, 0]}
    - {link: part, offset: )" +
         yaml_mm(r.c_centre + r.b_from_c + r.nose_from_b) + R"(}
  tool:
    - {link: Y, axis: Y, direction: [0, 1, 0]}
    - {link: Z, axis: Z, direction: [0, 0, 1], offset: )" +
         yaml_mm(r.c_centre) + R"(}
    - {link: C, axis: C, direction: [0, 0, 1]}
    - {link: B, axis: B, direction: [0, 1, 0], offset: )" +
         yaml_mm(r.b_from_c) + R"(}
    - {link: tool, tool_length: [0, 0, -1], offset: )" +
         yaml_mm(r.nose_from_b) + R"(}
terms:
)";
}

}  // namespace ccomp::test
