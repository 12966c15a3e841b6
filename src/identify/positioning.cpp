#include "ccomp/identify/positioning.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>

#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/util/interval.hpp"

namespace ccomp::identify {
namespace {


/// The deviations read at one target, by approach.
struct Approaches {
  std::vector<double> up, down;
};

double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

/// ISO 230-2's estimator of the standard uncertainty: n - 1 in the denominator, so one run
/// gives none (not 0, which would state a perfect repeatability nobody measured).
std::optional<double> spread_of(const std::vector<double>& v) {
  if (v.size() < 2) return std::nullopt;
  const double m = mean_of(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

/// A position as the reading's file gives it: program coordinates in its frame.
double file_position(const MeasurementSet& data, const Observation& o, std::size_t axis, bool rotary) {
  const double machine = file_axis_value(o, axis, rotary);
  if (o.file >= data.frames.size()) return machine;
  const ResolvedFrame& f = data.frames[o.file];
  const bool machine_z = f.frame.kind == FrameKind::machine && axis == 2;
  return machine - f.origin[axis] + (machine_z ? o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)] : 0.0);
}

/// The readings of the axis, by target (to 0.001 of the position's unit) and approach: a
/// linear axis' deviation along it; a rotary axis' turn, the reading over the lever its
/// point has from the axis' line (the inverse of what the one-axis reader does with a
/// calibrator's angle), for readings along the path the turn moves the point.
std::map<long long, Approaches> readings_by_target(const MeasurementSet& data, std::size_t axis, bool rotary,
                                                   const std::string& source, const model::ForwardModel* forward) {
  std::map<long long, Approaches> at;
  std::optional<model::ForwardData> scratch;
  if (rotary) scratch.emplace(*forward);
  const auto column = static_cast<Eigen::Index>(axis);
  for (const Observation& o : data.observations) {
    if (!source.empty() && data.sources[o.source] != source) continue;
    if (o.directions[axis] == 0) continue;
    double deviation = 0.0;
    if (!rotary) {
      const double along = o.direction[column];
      if (std::abs(std::abs(along) - 1.0) > 1e-6) continue;
      deviation = o.value * along;
    } else {
      model::forward(*forward, *scratch, o.q, MeasurementSet::conditions(o), true);
      const Eigen::Vector3d path = scratch->nominal_chain.oMp.R * scratch->J_q.col(column);
      const double lever = path.norm();
      if (lever < 1.0) continue;  // on the axis' line: no turn to read
      const double along = o.direction.dot(path / lever);
      if (std::abs(std::abs(along) - 1.0) > 1e-6) continue;
      deviation = o.value * along / lever;
    }
    const double target = file_position(data, o, axis, rotary);
    Approaches& a = at[std::llround(target * 1000.0)];
    (o.directions[axis] > 0 ? a.up : a.down).push_back(deviation);
  }
  return at;
}

PositioningTarget target_figures(double position, const Approaches& a) {
  PositioningTarget t;
  t.position = position;
  t.runs_up = static_cast<int>(a.up.size()), t.runs_down = static_cast<int>(a.down.size());
  if (!a.up.empty()) t.mean_up = mean_of(a.up), t.s_up = spread_of(a.up);
  if (!a.down.empty()) t.mean_down = mean_of(a.down), t.s_down = spread_of(a.down);
  if (t.s_up) t.repeatability_up = 4 * *t.s_up;
  if (t.s_down) t.repeatability_down = 4 * *t.s_down;
  if (t.mean_up && t.mean_down) {
    t.mean = 0.5 * (*t.mean_up + *t.mean_down);
    t.reversal = *t.mean_up - *t.mean_down;
    if (t.s_up && t.s_down)
      t.repeatability = std::max({2 * *t.s_up + 2 * *t.s_down + std::abs(*t.reversal), *t.repeatability_up,
                                  *t.repeatability_down});
  }
  return t;
}

/// One direction's figures over the targets approached that way: E (range of the means), A
/// (range of mean +- 2s) and R (largest 4s), the last two where every such target has two runs.
struct OneWay {
  std::optional<double> E, A, R;
  int runs = 0;  ///< fewest at a target
};

OneWay one_way(const std::vector<PositioningTarget>& targets, bool up) {
  OneWay w;
  util::Interval means, band;
  bool spread = true;
  double largest = 0.0;
  int fewest = 0;
  for (const PositioningTarget& t : targets) {
    const std::optional<double>& m = up ? t.mean_up : t.mean_down;
    if (!m) continue;
    const int runs = up ? t.runs_up : t.runs_down;
    fewest = fewest == 0 ? runs : std::min(fewest, runs);
    means.add(*m);
    const std::optional<double>& s = up ? t.s_up : t.s_down;
    if (!s) {
      spread = false;
      continue;
    }
    band.add(*m + 2 * *s), band.add(*m - 2 * *s);
    largest = std::max(largest, 4 * *s);
  }
  w.runs = fewest;
  if (means.empty()) return w;
  w.E = means.width();
  if (spread) w.A = band.width(), w.R = largest;
  return w;
}

/// The bidirectional figures over the targets approached both ways.
void bidirectional(PositioningReport& r) {
  util::Interval means, bidirectional_means, band;
  bool spread = true;
  double b_sum = 0.0, largest_r = 0.0;
  std::size_t both = 0;
  for (const PositioningTarget& t : r.targets) {
    if (!t.reversal) continue;
    ++both;
    means.add(*t.mean_up), means.add(*t.mean_down);
    bidirectional_means.add(*t.mean);
    b_sum += *t.reversal;
    if (!r.B || std::abs(*t.reversal) > *r.B) r.B = std::abs(*t.reversal), r.B_signed = *t.reversal, r.B_at = t.position;
    if (!t.repeatability) {
      spread = false;
      continue;
    }
    band.add(*t.mean_up + 2 * *t.s_up), band.add(*t.mean_up - 2 * *t.s_up);
    band.add(*t.mean_down + 2 * *t.s_down), band.add(*t.mean_down - 2 * *t.s_down);
    largest_r = std::max(largest_r, *t.repeatability);
  }
  r.one_way_targets = r.targets.size() - both;
  if (both == 0) return;
  r.E = means.width();
  r.M = bidirectional_means.width();
  r.B_mean = b_sum / static_cast<double>(both);
  if (spread) r.A = band.width(), r.R = largest_r;
}

/// Why each missing figure is missing, in the words of the runs it needs.
void say_what_is_not_stated(PositioningReport& r) {
  for (const auto& [up, E, A] : {std::tuple{true, r.E_up, r.A_up}, std::tuple{false, r.E_down, r.A_down}}) {
    const char* way = up ? "up" : "down";
    if (!E)
      r.not_stated.push_back(fmt::format("E, A and R {0}: no target is approached {0}", way));
    else if (!A)
      r.not_stated.push_back(fmt::format(
          "A and R {0}: a target approached {0} once has no spread (s needs 2 runs; the standard asks for 5)", way));
  }
  if (!r.M)
    r.not_stated.push_back("E, M, A, R and B bidirectional: no target is approached both ways");
  else if (!r.A)
    r.not_stated.push_back(
        "A and R bidirectional: a target approached once in a direction has no spread (s needs 2 runs each way)");
}

}  // namespace

PositioningReport analyse_positioning(const MeasurementSet& data, std::size_t axis, const std::string& source,
                                      const model::ForwardModel* forward) {
  if (axis > index(Axis::C)) throw Error(ErrorKind::usage, fmt::format("axis {}: not X Y Z A B or C", axis));
  const char letter = kAxisLetters[axis];
  PositioningReport report;
  report.axis = axis;
  // The machine's own word where it is given; the program's letter otherwise (the model
  // refuses a type its letter contradicts, so the two agree).
  const model::AxisSpec* spec = forward != nullptr ? forward->machine().axis(letter) : nullptr;
  report.rotary = spec != nullptr ? spec->rotary() : angular_at(axis);
  if (report.rotary && forward == nullptr)
    throw Error(ErrorKind::usage, fmt::format("rotary axis {}: the machine's kinematics are needed to read its turns", letter));
  const std::map<long long, Approaches> at = readings_by_target(data, axis, report.rotary, source, forward);
  if (at.empty())
    throw Error(ErrorKind::data, fmt::format("no readings {} {} with an approach direction (v{}){}",
                                             report.rotary ? "of the turn of" : "along", letter,
                                             static_cast<char>(std::tolower(letter)),
                                             source.empty() ? "" : " in source '" + source + "'"));
  for (const auto& [key, approaches] : at)
    report.targets.push_back(target_figures(static_cast<double>(key) / 1000.0, approaches));
  if (report.targets.size() < 2)
    throw Error(ErrorKind::data, fmt::format("readings {} {} at one target only ({:g}): ISO 230-2's figures are ranges "
                                             "over the targets, which needs two or more",
                                             report.rotary ? "of the turn of" : "along", letter,
                                             report.targets.front().position));
  const OneWay up = one_way(report.targets, true), down = one_way(report.targets, false);
  report.runs_up = up.runs, report.runs_down = down.runs;
  report.E_up = up.E, report.A_up = up.A, report.R_up = up.R;
  report.E_down = down.E, report.A_down = down.A, report.R_down = down.R;
  bidirectional(report);
  say_what_is_not_stated(report);
  split_mean_deviation(report);
  return report;
}

}  // namespace ccomp::identify
