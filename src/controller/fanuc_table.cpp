// Fanuc's pitch-error compensation data and parameters.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "ccomp/error.hpp"
#include "ccomp/controller/control_tables.hpp"
#include "table_format.hpp"

namespace ccomp::controller {
namespace {

using format::written;
using format::axis_number;
using format::points_of;
using format::step_of;

// --- Fanuc: pitch-error compensation. Parameters 3620 (point of the reference position),
// 3621/3622 (most negative / positive point), 3623 (magnification), 3624 (interval, in
// detection units); data N10000+n, incremental: point n holds the change of the
// correction from point n-1 to n, in detection units times the magnification. The
// reference position is machine 0, approached travelling up; 1851 is the backlash
// compensation applied after a reversal.
struct FanucData {
  int reference = 0, first = 0, last = 0, magnification = 1, interval = 0, backlash = 0;
  long per_turn = 0;             ///< 3625: a rotary axis' travel of one turn, in detection units (0: linear)
  std::vector<long> increments;  ///< per point, from `first`
};

/// Fanuc numbers compensation points across all axes (0 to 1023); by default each axis
/// takes its own 128: X 0-127, Y 128-255, Z 256-383.
constexpr int kFanucPoints = 1024, kFanucPointsPerAxis = 128;

FanucData fanuc_data(const AxisTable& t, const WriteOptions& o) {
  FanucData f;
  const double step = step_of(t);
  const double units = step / o.fanuc_unit;
  if (std::abs(units - std::round(units)) > 1e-6)
    throw Error(ErrorKind::usage, fmt::format("the step {} mm is not a whole number of detection units of {} mm "
                                              "(parameter 3624): choose --step as a multiple of --fanuc-unit",
                                              step, o.fanuc_unit));
  f.interval = static_cast<int>(std::lround(units));
  const auto at_reference = static_cast<int>(std::lround((t.reference - t.positions.front()) / step));
  f.reference = o.fanuc_reference_point > 0 ? o.fanuc_reference_point
                                            : (axis_number(t, o) - 1) * kFanucPointsPerAxis + at_reference;
  // A rotary axis' table runs over one turn from its reference point (parameter 3625 the
  // travel of a turn), the reference point taking the last point's value.
  const bool turn = t.rotary && std::abs(t.positions.back() - t.positions.front() - 360.0) < 1e-9;
  if (turn) f.per_turn = static_cast<long>(std::lround(360.0 / o.fanuc_unit));
  if (t.rotary && (!turn || at_reference != 0))
    throw Error(ErrorKind::usage,
                "a Fanuc table of a rotary axis runs over one turn from its reference position: "
                "--from 0 --to 360");
  f.first = f.reference - at_reference;
  f.last = f.first + static_cast<int>(points_of(t)) - 1;
  if (f.first < 0 || f.last >= kFanucPoints)
    throw Error(ErrorKind::usage,
                fmt::format("--fanuc-reference-point {}: the table's points would run from {} to {}, outside Fanuc's "
                            "0 to {}",
                            f.reference, f.first, f.last, kFanucPoints - 1));
  // The corrections in whole units (the table is 0 at the reference point already), then
  // the increments between points, at the magnification that keeps them within 127.
  std::vector<long> absolute(points_of(t));
  for (std::size_t k = 0; k < absolute.size(); ++k) absolute[k] = std::lround(t.forward[k] / o.fanuc_unit);
  long largest = 0;
  for (std::size_t k = 1; k < absolute.size(); ++k)
    largest = std::max(largest, std::abs(absolute[k] - absolute[k - 1]));
  f.magnification = static_cast<int>(std::max(1L, (largest + 126) / 127));
  f.increments.assign(absolute.size(), 0);
  long previous = 0;
  for (std::size_t k = 0; k < absolute.size(); ++k) {
    // Rounded whole at the magnification, so rounding does not add up along the table.
    const long scaled = std::lround(static_cast<double>(absolute[k]) / f.magnification);
    if (k > 0) f.increments[k] = scaled - previous;
    previous = scaled;
  }
  if (turn) f.increments.front() = f.increments.back();
  double reversal = 0.0;
  for (std::size_t k = 0; k < points_of(t); ++k) reversal += t.forward[k] - t.reverse[k];
  f.backlash = static_cast<int>(std::lround(reversal / static_cast<double>(points_of(t)) / o.fanuc_unit));
  return f;
}

std::string write_fanuc(const AxisTable& t, const WriteOptions& o) {
  const FanucData f = fanuc_data(t, o);
  const int a = axis_number(t, o);
  std::string text = "%\n";
  text += fmt::format("N01851A{}P{}\n", a, f.backlash);
  text += fmt::format("N03620A{}P{}\nN03621A{}P{}\nN03622A{}P{}\nN03623A{}P{}\nN03624A{}P{}\n", a, f.reference, a,
                      f.first, a, f.last, a, f.magnification, a, f.interval);
  if (f.per_turn > 0) text += fmt::format("N03625A{}P{}\n", a, f.per_turn);
  for (std::size_t k = 0; k < f.increments.size(); ++k)
    text += fmt::format("N{}P{}\n", 10000 + f.first + static_cast<int>(k), f.increments[k]);
  return text + "%\n";
}

AxisTable fanuc_applies(const AxisTable& table, const WriteOptions& options) {
  AxisTable applied = table;
  const FanucData f = fanuc_data(table, options);
  double sum = 0.0;
  const double unit = options.fanuc_unit * f.magnification;
  // Rebuild the absolute corrections from the increments, relative to the reference.
  const std::size_t reference = static_cast<std::size_t>(f.reference - f.first);
  std::vector<double> absolute(f.increments.size(), 0.0);
  for (std::size_t k = reference + 1; k < absolute.size(); ++k)
    sum += static_cast<double>(f.increments[k]) * unit, absolute[k] = sum;
  sum = 0.0;
  for (std::size_t k = reference; k-- > 0;)
    sum -= static_cast<double>(f.increments[k + 1]) * unit, absolute[k] = sum;
  applied.forward = absolute;
  for (std::size_t k = 0; k < absolute.size(); ++k)
    applied.reverse[k] = absolute[k] - f.backlash * options.fanuc_unit;
  applied.cross.clear();
  return applied;
}

}  // namespace

extern const ControlTable kFanucTable{"fanuc", "Fanuc pitch-error compensation data and parameters",
                                      {128, 0.5, false},  // points between the extremes of one axis
                                      write_fanuc, fanuc_applies, nullptr};

}  // namespace ccomp::controller
