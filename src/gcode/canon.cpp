#include "ccomp/gcode/canon.hpp"

#include <cmath>

namespace ccomp::gcode {

Axes Offsets::rotated(const Axes& p, double degrees) const {
  if (degrees == 0.0) return p;
  const double a = degrees * 3.14159265358979323846 / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  Axes r = p;
  const double x = p[0] - g5x[0], y = p[1] - g5x[1];
  r[0] = g5x[0] + c * x - s * y;
  r[1] = g5x[1] + s * x + c * y;
  return r;
}

}  // namespace ccomp::gcode
