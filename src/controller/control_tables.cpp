#include "ccomp/controller/control_tables.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "ccomp/error.hpp"
#include "correction_bound.hpp"

namespace ccomp::controller {
namespace {

constexpr std::array<std::string_view, 4> kNames{"linuxcnc", "fanuc", "siemens", "heidenhain"};

/// `v` rounded to `decimals` as the file writes it, a zero without its sign: a correction
/// of -0.000001 mm written "-0.00000" reads as a sign error to whoever checks the file.
double written(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  const double r = std::round(v * scale) / scale;
  return r == 0.0 ? 0.0 : r;
}

std::size_t points_of(const AxisTable& t) {
  return t.positions.size();
}
double step_of(const AxisTable& t) {
  return t.positions.size() > 1 ? t.positions[1] - t.positions[0] : 1.0;
}

int axis_number(const AxisTable& t, const WriteOptions& o) {
  return o.axis_number > 0 ? o.axis_number : static_cast<int>(t.axis_index) + 1;
}

void check_fits(Control control, const AxisTable& t) {
  const ControlLimits limits = control_limits(control);
  if (points_of(t) > limits.max_points)
    throw Error(ErrorKind::usage, fmt::format("--control {}: {} points on {}, more than its table holds ({}): a larger "
                                              "--step",
                                              control_name(control), points_of(t), t.axis, limits.max_points));
}

// --- LinuxCNC: [JOINT_n]COMP_FILE, read by usrmotLoadComp(): "nominal a b" triplets, one a
// line, ascending; reading stops at the first line that is not three numbers, so the file
// carries no comment. Type 0: a, b are where the joint really is travelling up and down
// (LinuxCNC adds nominal - a); type 1: a, b are the trims it adds.
/// No value that is not a number reaches a table (a NaN prints as -nan, and Fanuc's
/// rounding makes it P0).
void check_finite(Control control, const AxisTable& t) {
  const std::string_view name = control_name(control);
  for (std::size_t k = 0; k < t.positions.size(); ++k) {
    const std::string where = fmt::format("{} {:g}", t.axis, t.positions[k]);
    check_written(t.positions[k], name, where);
    check_written(t.forward[k], name, where);
    check_written(t.reverse[k], name, where);
    for (const AxisTable::Cross& c : t.cross) check_written(c.correction[k], name, where);
  }
}

std::string write_linuxcnc(const AxisTable& t, const WriteOptions& o) {
  std::string text;
  for (std::size_t k = 0; k < points_of(t); ++k) {
    const double p = t.positions[k];
    if (o.linuxcnc_file_type == 0)
      text += fmt::format("{:.6f} {:.6f} {:.6f}\n", written(p, 6), written(p - t.forward[k], 6),
                          written(p - t.reverse[k], 6));
    else
      text += fmt::format("{:.6f} {:.6f} {:.6f}\n", written(p, 6), written(t.forward[k], 6), written(t.reverse[k], 6));
  }
  return text;
}

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

// --- Siemens 840D sl (K3, interpolatory compensation): the leadscrew table
// $AA_ENC_COMP holds the measuring system's error (a positive value moves the axis the
// negative way); sag/cross tables $AN_CEC hold the correction added to the output axis,
// one with $AN_CEC_DIRECTION -1 carrying what differs travelling down.
std::string siemens_cec(int index, const std::string& input, const std::string& output, const AxisTable& t,
                        const std::vector<double>& values, int direction) {
  std::string text;
  for (std::size_t k = 0; k < values.size(); ++k) text += fmt::format("$AN_CEC[{},{}]={:.6f}\n", index, k, written(values[k], 6));
  text += fmt::format(
      "$AN_CEC_INPUT_AXIS[{0}]={1}\n$AN_CEC_OUTPUT_AXIS[{0}]={2}\n$AN_CEC_STEP[{0}]={3:.4f}\n$AN_CEC_MIN[{0}]={4:."
      "4f}\n$AN_CEC_MAX[{0}]={5:.4f}\n$AN_CEC_DIRECTION[{0}]={6}\n$AN_CEC_MULT_BY_TABLE[{0}]=0\n$AN_CEC_IS_MODULO[{0}]="
      "{7}\n",
      index, input, output, step_of(t), t.positions.front(), t.positions.back(), direction, t.rotary ? 1 : 0);
  return text;
}

std::string write_siemens(const AxisTable& t, const WriteOptions& o) {
  const std::string ax = fmt::format("AX{}", axis_number(t, o));
  std::string text;
  for (const std::string& line : o.header) text += "; " + line + "\n";
  text += fmt::format(
      "; machine data: MD32700 $MA_ENC_COMP_ENABLE[0,{0}]=1, MD38000 $MA_MM_ENC_COMP_MAX_POINTS[0,{0}]>={1}", ax,
      points_of(t));
  text += ", MD32710 $MA_CEC_ENABLE[AXn]=1 on each output axis, MD18342 $MN_MM_CEC_MAX_POINTS[table]>=" +
          std::to_string(points_of(t)) + "\n; the other axes are AX1 AX2 AX3 for X Y Z\nCHANDATA(1)\n";
  // The leadscrew table: the error travelling up (0 at the reference point); a table that
  // acts travelling down only adds what differs then (position-dependent backlash).
  for (std::size_t k = 0; k < points_of(t); ++k)
    text += fmt::format("$AA_ENC_COMP[0,{},{}]={:.6f}\n", k, ax, written(-t.forward[k], 6));
  text += fmt::format(
      "$AA_ENC_COMP_STEP[0,{0}]={1:.4f}\n$AA_ENC_COMP_MIN[0,{0}]={2:.4f}\n$AA_ENC_COMP_MAX[0,{0}]={3:.4f}\n$AA_ENC_"
      "COMP_"
      "IS_MODULO[0,{0}]={4}\n",
      ax, step_of(t), t.positions.front(), t.positions.back(), t.rotary ? 1 : 0);
  int index = o.siemens_first_cec_table;
  if (t.bidirectional()) {
    std::vector<double> down(points_of(t));
    for (std::size_t k = 0; k < down.size(); ++k) down[k] = t.reverse[k] - t.forward[k];
    text += siemens_cec(index++, ax, ax, t, down, -1);
  }
  for (const AxisTable::Cross& c : t.cross)
    text += siemens_cec(index++, ax, fmt::format("AX{}", c.axis_index + 1), t, c.correction, 0);
  return text + "M17\n";
}

// --- Heidenhain TNC: a compensation-value table (*.COM) for the axis' dependences: AXISPOS
// the axis' positions from the machine datum, a column per axis compensated (the axis
// itself: its pitch, the others: their straightness), BACKLASH the axis' own values for
// travel the negative way. Entered in the *.CMA assignment table's column of this axis.
std::string write_heidenhain(const AxisTable& t, const WriteOptions&) {
  std::string text = fmt::format("BEGIN {}.COM MM\n{:<6}{:<14}{:<14}", t.axis, "NR", "AXISPOS", std::string(1, t.axis));
  for (const AxisTable::Cross& c : t.cross) text += fmt::format("{:<14}", std::string(1, c.axis));
  text += "BACKLASH\n";
  for (std::size_t k = 0; k < points_of(t); ++k) {
    text += fmt::format("{:<6}{:<+14.4f}{:<+14.5f}", k, written(t.positions[k], 4), written(t.forward[k], 5));
    for (const AxisTable::Cross& c : t.cross) text += fmt::format("{:<+14.5f}", written(c.correction[k], 5));
    text += fmt::format("{:+.5f}\n", written(t.reverse[k], 5));
  }
  return text + "[END]\n";
}

/// `values` rounded to `digits` decimals, as the file holds them.
std::vector<double> rounded(const std::vector<double>& values, int digits) {
  const double scale = std::pow(10.0, digits);
  std::vector<double> out(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) out[k] = std::round(values[k] * scale) / scale;
  return out;
}

}  // namespace

std::optional<Control> control_named(std::string_view name) {
  for (std::size_t k = 0; k < kNames.size(); ++k)
    if (kNames[k] == name) return static_cast<Control>(k);
  return std::nullopt;
}

std::string_view control_name(Control control) {
  return kNames[static_cast<std::size_t>(control)];
}

ControlLimits control_limits(Control control) {
  switch (control) {
    case Control::linuxcnc:
      return {256, 0.5, false};  // EMCMOT_COMP_SIZE; joint comp only
    case Control::fanuc:
      return {128, 0.5, false};  // points between the extremes of one axis
    case Control::siemens:
      return {1000, 0.5, true};  // MD38000 / MD18342 are the machine's; 1000 is common
    case Control::heidenhain:
      return {256, 0.5, true};  // entries of one *.COM
  }
  return {};
}

std::string write_table(Control control, const AxisTable& table, const WriteOptions& options) {
  check_fits(control, table);
  check_finite(control, table);
  switch (control) {
    case Control::linuxcnc:
      return write_linuxcnc(table, options);
    case Control::fanuc:
      return write_fanuc(table, options);
    case Control::siemens:
      return write_siemens(table, options);
    case Control::heidenhain:
      return write_heidenhain(table, options);
  }
  return {};
}

AxisTable as_control_applies(Control control, const AxisTable& table, const WriteOptions& options) {
  AxisTable applied = table;
  switch (control) {
    case Control::linuxcnc:
      applied.forward = rounded(table.forward, 6), applied.reverse = rounded(table.reverse, 6);
      applied.cross.clear();
      break;
    case Control::fanuc: {
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
      break;
    }
    case Control::siemens: {
      applied.forward = rounded(table.forward, 6);
      for (std::size_t k = 0; k < table.forward.size(); ++k)
        applied.reverse[k] = applied.forward[k] + std::round((table.reverse[k] - table.forward[k]) * 1e6) / 1e6;
      for (AxisTable::Cross& c : applied.cross) c.correction = rounded(c.correction, 6);
      break;
    }
    case Control::heidenhain:
      applied.forward = rounded(table.forward, 5), applied.reverse = rounded(table.reverse, 5);
      for (AxisTable::Cross& c : applied.cross) c.correction = rounded(c.correction, 5);
      break;
  }
  return applied;
}

}  // namespace ccomp::controller
