#pragma once
// The smallest interval holding the values seen so far: what a range of readings, a chart's
// axis or an axis' travel is made of. Empty (lo > hi) before the first value, not a pair of
// sentinels a caller could mistake for values.
#include <algorithm>
#include <limits>

namespace ccomp::util {

struct Interval {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();

  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  void add(const Interval& other) {
    lo = std::min(lo, other.lo);
    hi = std::max(hi, other.hi);
  }
  [[nodiscard]] bool empty() const { return !(lo <= hi); }
  /// hi - lo; 0 when empty.
  [[nodiscard]] double width() const { return empty() ? 0.0 : hi - lo; }
};

}  // namespace ccomp::util
