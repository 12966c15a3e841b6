#include "ccomp/gcode/canon.hpp"

#include <cmath>
#include <numbers>
#include <tuple>

#include "ccomp/constants.hpp"

namespace ccomp::gcode {

Axes Offsets::rotated(const Axes& p, double degrees) const {
  if (degrees == 0.0) return p;
  const double a = degrees * std::numbers::pi / 180.0;  // in this order: the digits of every output depend on it
  const double c = std::cos(a), s = std::sin(a);
  Axes r = p;
  const double x = p[0] - g5x[0], y = p[1] - g5x[1];
  r[0] = g5x[0] + c * x - s * y;
  r[1] = g5x[1] + s * x + c * y;
  return r;
}

ArcGeometry arc_geometry(const Motion& m) {
  ArcGeometry g;
  g.axes = plane_axes(m.arc.plane);
  const double c1 = m.arc.center_first, c2 = m.arc.center_second;
  const std::size_t f = g.axes.first, s = g.axes.second;
  g.r_start = std::hypot(m.start[f] - c1, m.start[s] - c2);
  g.r_end = std::hypot(m.end[f] - c1, m.end[s] - c2);
  g.a_start = std::atan2(m.start[s] - c2, m.start[f] - c1);
  const double a_end = std::atan2(m.end[s] - c2, m.end[f] - c1);
  constexpr double kTurn = 2.0 * std::numbers::pi;
  g.ccw = m.arc.turns > 0;
  g.sweep = g.ccw ? a_end - g.a_start : g.a_start - a_end;
  while (g.sweep <= 1e-12) g.sweep += kTurn;  // equal ends: a full circle
  g.sweep += (std::abs(m.arc.turns) - 1) * kTurn;
  return g;
}

std::pair<double, double> ArcGeometry::at(double f, double c1, double c2) const {
  const double angle = a_start + (ccw ? f : -f) * sweep;
  const double radius = r_start + f * (r_end - r_start);
  return {c1 + radius * std::cos(angle), c2 + radius * std::sin(angle)};
}

Axes arc_point(const Motion& arc, const ArcGeometry& g, double f) {
  if (f >= 1.0) return arc.end;  // the end exactly, as the interpreter has it
  Axes p;
  for (std::size_t i = 0; i < kAxisCount; ++i) p[i] = arc.start[i] + f * (arc.end[i] - arc.start[i]);
  std::tie(p[g.axes.first], p[g.axes.second]) = g.at(f, arc.arc.center_first, arc.arc.center_second);
  return p;
}

}  // namespace ccomp::gcode
