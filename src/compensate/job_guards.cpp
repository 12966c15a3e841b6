#include "job_guards.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "number_style.hpp"

namespace ccomp::compensate {
namespace {

/// Widens [low, high] by the points of the arc where its in-plane axes are extreme.
void widen_by_arc_extremes(const gcode::Motion& m, gcode::Axes& low, gcode::Axes& high) {
  const gcode::ArcGeometry g = gcode::arc_geometry(m);
  const gcode::PlaneAxes pa = g.axes;
  const double c1 = m.arc.center_first, c2 = m.arc.center_second;
  constexpr double kTurn = 2.0 * std::numbers::pi;
  for (std::size_t axis : {pa.first, pa.second, pa.normal}) {
    low[axis] = std::min({low[axis], m.start[axis], m.end[axis]});
    high[axis] = std::max({high[axis], m.start[axis], m.end[axis]});
  }
  for (int k = 0; k < 4; ++k) {  // the four quadrant points, where the arc passes them
    const double angle = k * kTurn / 4.0;
    double delta = g.ccw ? angle - g.a_start : g.a_start - angle;
    while (delta < 0) delta += kTurn;
    if (delta > g.sweep) continue;
    const double p1 = c1 + g.r_start * std::cos(angle), p2 = c2 + g.r_start * std::sin(angle);
    low[pa.first] = std::min(low[pa.first], p1);
    high[pa.first] = std::max(high[pa.first], p1);
    low[pa.second] = std::min(low[pa.second], p2);
    high[pa.second] = std::max(high[pa.second], p2);
  }
}

}  // namespace

void motion_extent(const gcode::Motion& m, gcode::Axes& low, gcode::Axes& high) {
  low = high = m.end;
  if (m.kind == gcode::MotionKind::arc) widen_by_arc_extremes(m, low, high);
}

void check_limits(const gcode::Motion& m, const model::MachineModel& model, std::string_view file,
                  std::string_view text) {
  gcode::Axes low, high;
  motion_extent(m, low, high);
  for (const model::AxisSpec& a : model.axes) {
    const auto i = *gcode::axis_index(a.letter);
    const double tool = m.offsets ? m.offsets->tool[i] : 0.0;
    const double lo = low[i] + tool, hi = high[i] + tool;
    if (lo >= a.min - 1e-9 && hi <= a.max + 1e-9) continue;
    const double bad = lo < a.min - 1e-9 ? lo : hi;
    throw Error(ErrorKind::safety,
                fmt::format("axis {} would go to {:.4f}, outside its limits [{}, {}] of machine '{}'", a.letter, bad,
                            a.min, a.max, model.name),
                SourceLocation{std::string(file), m.line, 0}, std::string(text));
  }
}

double rotary_lever(const model::MachineModel& model) {
  double lever = 100.0;
  for (const model::AxisSpec& a : model.axes)
    if (a.type == model::AxisType::linear && std::isfinite(a.min) && std::isfinite(a.max))
      lever = std::max({lever, std::abs(a.min), std::abs(a.max)});
  return lever;
}

namespace {

/// The fewest decimals whose half place, times `mm_per_place_unit` (mm the unit place moves
/// the tool by), is at most a quarter of the tolerance.
int decimals_for(double tolerance, double mm_per_place_unit) {
  // (A tolerance of 1e-320 makes the ratio infinite: 99 says "too many" without overflow.)
  const double places = std::ceil(std::log10(2.0 * mm_per_place_unit / tolerance) - 1e-9);
  return places <= 99.0 ? static_cast<int>(places) : 99;
}

}  // namespace

void raise_digits_for_tolerance(JobOptions& options, const model::MachineModel& model) {
  int linear = 0, rotary = 0;
  for (const model::AxisSpec& a : model.axes) (a.type == model::AxisType::linear ? linear : rotary) += 1;
  const double tol = options.tolerance;
  const double across = std::sqrt(static_cast<double>(std::max(linear, 1)));
  // (Once raised, enough for inches too, whose place is 25.4 times coarser: a program may
  // switch units. Not raised for inches alone: their 5 decimals are warned of, as before.)
  if (options.decimals < 0 && linear > 0 && decimals_for(tol, across) > kDefaultDecimals)
    options.decimals = std::max(decimals_for(tol, across), decimals_for(tol, kMmPerInch * across));
  if (options.rotary_decimals < 0 && rotary > 0 &&
      decimals_for(tol, kRadPerDeg * rotary_lever(model)) > kDefaultRotaryDecimals)
    options.rotary_decimals = decimals_for(tol, kRadPerDeg * rotary_lever(model));
  for (const auto& [name, decimals] : {std::pair{"--decimals", options.decimals}, {"--rotary-decimals", options.rotary_decimals}})
    if (decimals > 9)
      throw Error(ErrorKind::usage,
                  fmt::format("a tolerance of {:.3g} um needs {} {} for the digits alone to stay within a quarter "
                              "of it: more than the 9 a coordinate may be written with (a larger --tolerance)",
                              tol * 1000.0, decimals, name == std::string_view("--decimals") ? "decimals" : "decimals in degrees"));
}

JobGuards::JobGuards(const model::MachineModel& model, const JobOptions& options, JobReport& report,
                     std::string_view file)
    : model_(model), options_(options), report_(report), file_(file), rotary_lever_(rotary_lever(model)) {
  for (const model::AxisSpec& a : model.axes) linear_axes_ += a.type == model::AxisType::linear ? 1 : 0;
}

void JobGuards::account(const MoveReport& move, gcode::Units units, std::uint32_t line, const std::string& text,
                        bool whole_move) {
  check_rounding(units, line, text);
  if (move.max_correction > model_.max_correction)
    throw Error(ErrorKind::safety,
                fmt::format("the correction is {:.4f} mm, beyond the model's bound of {} mm (max_correction): is "
                            "the model right for this machine?",
                            move.max_correction, model_.max_correction),
                SourceLocation{std::string(file_), line, 0}, text);
  if (const double bound = model_.max_correction * model::kRotaryBoundPerMm; move.max_rotary_correction > bound)
    throw Error(ErrorKind::safety,
                fmt::format("a rotary axis' correction is {:.4g} deg, beyond the model's bound of {:.4g} deg "
                            "(max_correction, {:g} mrad per mm): is the model right for this machine?",
                            move.max_rotary_correction / kRadPerDeg, bound / kRadPerDeg,
                            model::kRotaryBoundPerMm * 1e3),
                SourceLocation{std::string(file_), line, 0}, text);
  report_.max_error_before = std::max(report_.max_error_before, move.max_deviation_before);
  report_.max_error_after = std::max(report_.max_error_after, move.max_deviation_after);
  report_.max_correction = std::max(report_.max_correction, move.max_correction);
  report_.max_orientation_error = std::max(report_.max_orientation_error, move.max_orientation_error);
  report_.held_axes |= move.held_axes;
  warn_unhidden_reversals(move.unhidden_reversals, line);
  if (move.jogs_withheld)
    warn_once(warned_jogs_,
              "cutter radius compensation (G41/G42) is on: a move that turns back is an inside corner the "
              "control refuses, so ccomp writes no take-up moves there; what that leaves is in the summary's "
              "'after' (said once)",
              line);
  if (move.kept_whole && move.max_deviation_after > options_.tolerance) warn_kept_whole(move, line);
  if (move.start_error > 0.0 && !warned_start_error_)
    warn_once(warned_start_error_,
              fmt::format("this cut starts where a move in machine coordinates (G53, G28, G30) or a canned "
                          "cycle left the machine, uncompensated: the tool is {:.2f} um off the cut's start "
                          "there; ccomp moves it to the compensated start first. A rapid to the start "
                          "before the cut avoids cutting from there (said once)",
                          move.start_error * 1000.0),
              line);
  if (whole_move) ++report_.compensated_moves;  // a move in parts counts at its last
}

/// Per block, as the issue of each is its own: the first 20, then once how to see them all.
void JobGuards::warn_kept_whole(const MoveReport& move, std::uint32_t line) {
  constexpr int kShown = 20;
  if (!options_.warning || ++kept_whole_over_ > kShown + 1) return;
  if (kept_whole_over_ > kShown) {
    options_.warning("more blocks like the above: the summary's 'after' is the worst of them", line);
    return;
  }
  options_.warning(fmt::format("this move keeps {:.2f} um of error, more than the tolerance of {:.2f} um: the "
                               "control offsets it (G41/G42) as one piece (an entry move, an arc of several "
                               "turns), and the error field needs it split. --resolve-cutter-comp writes the "
                               "offset path itself, under G40, split as needed",
                               move.max_deviation_after * 1000.0, options_.tolerance * 1000.0),
                   line);
}

void JobGuards::warn_once(bool& said, const std::string& message, std::uint32_t line) {
  if (said || !options_.warning) return;
  said = true;
  options_.warning(message, line);
}

/// The written digits round each linear axis by up to half their last place, so the tool
/// by up to sqrt(axes) times that. Once per unit system: a --decimals that may take the
/// whole tolerance is refused (no written program could meet it), and digits that may
/// take a quarter of it are warned of, the program's own included.
void JobGuards::check_rounding(gcode::Units units, std::uint32_t line, const std::string& text) {
  check_rotary_rounding(line);
  const bool inch = units == gcode::Units::inch;
  bool& checked = rounding_checked_[inch ? 1 : 0];
  if (checked || linear_axes_ == 0) return;
  checked = true;
  const bool forced = options_.decimals >= 0;
  const int decimals = forced ? options_.decimals : inch ? kDefaultInchDecimals : kDefaultDecimals;
  const double place = std::pow(10.0, -decimals) * (inch ? kMmPerInch : 1.0);  // mm
  const double worst = 0.5 * place * std::sqrt(static_cast<double>(linear_axes_));
  const std::string digits =
      fmt::format("{} decimal{} in {}", decimals, decimals == 1 ? "" : "s", inch ? "inch" : "mm");
  if (forced && worst > options_.tolerance)
    throw Error(ErrorKind::usage,
                fmt::format("--decimals {}: coordinates written to {} may put the tool up to {:.3g} um from the "
                            "compensated point, more than the tolerance of {:.3g} um",
                            decimals, digits, worst * 1000.0, options_.tolerance * 1000.0),
                SourceLocation{std::string(file_), line, 0}, text);
  if (worst > 0.25 * options_.tolerance && options_.warning)
    options_.warning(fmt::format("coordinates written to {}{} may put the tool up to {:.3g} um from the compensated "
                                 "point, more than a quarter of the tolerance of {:.3g} um{}",
                                 forced ? "" : "at least ", digits, worst * 1000.0, options_.tolerance * 1000.0,
                                 forced ? "" : "; --decimals writes more"),
                     line);
}

/// A rotary axis' rounding moves the tool by its distance from the axis, which only the
/// model's limits bound: a --rotary-decimals too coarse at that distance is warned of.
void JobGuards::check_rotary_rounding(std::uint32_t line) {
  if (rotary_checked_ || options_.rotary_decimals < 0 || !options_.warning) return;
  rotary_checked_ = true;
  const double angle = 0.5 * std::pow(10.0, -options_.rotary_decimals) * kRadPerDeg;
  if (angle * rotary_lever_ > 0.25 * options_.tolerance)
    options_.warning(fmt::format("rotary coordinates written to {} decimals in degrees may turn the part by up to "
                                 "{:.3g} urad, {:.3g} um at {:g} mm from the axis (the farthest linear axis "
                                 "limit), more than a quarter of the tolerance of {:.3g} um",
                                 options_.rotary_decimals, angle * 1e6, angle * rotary_lever_ * 1000.0, rotary_lever_,
                                 options_.tolerance * 1000.0),
                     line);
}

/// Once per axis: a reversal the take-up cannot hide stays in the output.
void JobGuards::warn_unhidden_reversals(AxisSet axes, std::uint32_t line) {
  axes -= warned_reversals_;
  if (axes.empty()) return;  // (nearly every move: nothing new to say)
  warned_reversals_ |= axes;
  for (const Axis a : axes)
    if (options_.warning)
      options_.warning(fmt::format("axis {}'s reversal cannot be fully taken up, so part of each turn's error "
                                   "stays in the output: the reversal leads the command (a lag, backlash, is "
                                   "negative), or the axis has no positioning reversal (lost motion) of its own, "
                                   "or error motions switching with it act along it by more than its lost motion",
                                   letter(a)),
                       line);
}

void warn_coarse_tolerance(const JobReport& report, const JobOptions& options) {
  if (!options.warning || !(report.max_error_before > 0.0) || options.tolerance < report.max_error_before) return;
  // A tolerance a quarter of the error (and no coarser than the usual 1 um) leaves it a
  // quarter at most.
  const double suggested_um = std::min(1.0, 0.25 * report.max_error_before * 1000.0);
  options.warning(fmt::format("the tolerance of {:.3g} um is not below the machine's error on this program ({:.2f} um "
                              "before): the chords and digits it allows may leave the path as far off as the program "
                              "as written, or further; --tolerance {:.2g}um takes the error out",
                              options.tolerance * 1000.0, report.max_error_before * 1000.0, suggested_um),
                  0);
}

}  // namespace ccomp::compensate
