#pragma once
// What the control tables' writers share (src/controller/*_table.cpp): a value as a file
// writes it, the table's points and step, the axis number a format names.
#include <cmath>
#include <cstddef>
#include <vector>

#include "ccomp/controller/axis_table.hpp"
#include "ccomp/controller/control_tables.hpp"

namespace ccomp::controller::format {

/// `v` rounded to `decimals` as the file writes it, a zero without its sign: a correction
/// of -0.000001 mm written "-0.00000" reads as a sign error to whoever checks the file.
inline double written(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  const double r = std::round(v * scale) / scale;
  return r == 0.0 ? 0.0 : r;
}

/// `values` rounded to `digits` decimals, as the file holds them.
inline std::vector<double> rounded(const std::vector<double>& values, int digits) {
  const double scale = std::pow(10.0, digits);
  std::vector<double> out(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) out[k] = std::round(values[k] * scale) / scale;
  return out;
}

inline std::size_t points_of(const AxisTable& t) {
  return t.positions.size();
}
inline double step_of(const AxisTable& t) {
  return t.positions.size() > 1 ? t.positions[1] - t.positions[0] : 1.0;
}

inline int axis_number(const AxisTable& t, const WriteOptions& o) {
  return o.axis_number > 0 ? o.axis_number : static_cast<int>(t.axis_index) + 1;
}

}  // namespace ccomp::controller::format
