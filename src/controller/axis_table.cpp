#include "ccomp/controller/axis_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string_view>

#include "ccomp/axis.hpp"
#include "ccomp/error.hpp"
#include "ccomp/kinematics/pose.hpp"
#include "correction_bound.hpp"
#include "tip_miss.hpp"

namespace ccomp::controller {
namespace {


/// Linear interpolation in `values` over the table's points, constant beyond its ends.
double interpolate(const std::vector<double>& positions, const std::vector<double>& values, double p) {
  if (p <= positions.front()) return values.front();
  if (p >= positions.back()) return values.back();
  const auto upper = std::upper_bound(positions.begin(), positions.end(), p);
  const std::size_t k = static_cast<std::size_t>(upper - positions.begin());
  const double w = (p - positions[k - 1]) / (positions[k] - positions[k - 1]);
  return values[k - 1] + w * (values[k] - values[k - 1]);
}

}  // namespace

double AxisTable::scale() const {
  return rotary ? M_PI / 180.0 : 1.0;
}

bool AxisTable::bidirectional() const {
  for (std::size_t k = 0; k < forward.size(); ++k)
    if (std::abs(forward[k] - reverse[k]) > 1e-9) return true;
  return false;
}

std::size_t Grid::points() const {
  return static_cast<std::size_t>(std::llround((to - from) / step)) + 1;
}

Grid grid_for(double lo, double hi, double step, std::size_t max_points, double granularity) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo))
    throw Error(ErrorKind::usage,
                fmt::format("the table's span [{}, {}] is not a finite range: give --from and --to", lo, hi));
  if (!(step > 0) || !std::isfinite(step)) throw Error(ErrorKind::usage, fmt::format("--step {}: not > 0", step));
  Grid g;
  for (g.step = step;; g.step = (std::floor(g.step / granularity + 1e-9) + 1) * granularity) {
    g.from = std::floor(lo / g.step + 1e-9) * g.step + 0.0;  // + 0.0: no -0
    g.to = std::ceil(hi / g.step - 1e-9) * g.step + 0.0;
    if (g.points() <= max_points) return g;
  }
}

AxisTable sample_axis_table(const model::ForwardModel& model, const TableOptions& options) {
  const model::MachineModel& machine = model.machine();
  AxisTable table;
  table.axis = options.axis;
  const model::AxisSpec* spec = machine.axis(options.axis);
  if (spec == nullptr)
    throw Error(ErrorKind::usage,
                fmt::format("--axis {}: the machine '{}' has no such axis", options.axis, machine.name));
  table.rotary = spec->type == model::AxisType::rotary;
  table.axis_index = kAxisLetters.find(options.axis);
  if (!(options.step > 0) || !std::isfinite(options.from) || !std::isfinite(options.to) || !(options.to > options.from))
    throw Error(ErrorKind::usage, fmt::format("--axis {}: no grid from {} to {} step {}", options.axis, options.from,
                                              options.to, options.step));
  const auto a = static_cast<Eigen::Index>(table.axis_index);
  const std::size_t n = static_cast<std::size_t>(std::llround((options.to - options.from) / options.step)) + 1;
  TipMiss miss(model, options.conditions);
  const double scale = table.scale();
  // The axis' own miss, in chain units, that the correction cancels: along its line, or
  // the turn about its axis.
  const double own_sense = table.rotary ? 1.0 : miss.sense(options.line, table.axis_index);
  const Eigen::Vector3d turn_axis =
      table.rotary ? miss.turn_axis(options.line, table.axis_index) : Eigen::Vector3d::Zero();
  for (const model::AxisSpec& other : machine.axes) {
    const std::size_t j = other.index();
    if (!table.rotary && other.type == model::AxisType::linear && j < 3 && j != table.axis_index)
      table.cross.push_back({other.letter, j, {}});
  }
  std::vector<double> sense(table.cross.size());
  for (std::size_t k = 0; k < table.cross.size(); ++k) sense[k] = miss.sense(options.line, table.cross[k].axis_index);
  for (std::size_t i = 0; i < n; ++i) {
    const double p = options.from + static_cast<double>(i) * options.step;
    table.positions.push_back(p);
    model::ChainQ target = options.line;
    target[a] = p * scale;
    Eigen::Vector3d miss_mean = Eigen::Vector3d::Zero();
    for (int direction : {+1, -1}) {
      // Newton with the nominal slope: the error's own slope is ~1e-4, so each step
      // gains four digits.
      double t = 0.0;
      Eigen::Vector3d m = Eigen::Vector3d::Zero();
      for (int iteration = 0; iteration < 8; ++iteration) {
        model::ChainQ commanded = target;
        commanded[a] += t;
        const AxisArray<double> travel = travelling({table.axis_index}, direction);
        m = miss(commanded, target, travel);
        const double step = table.rotary ? miss.turn(commanded, target, travel, turn_axis) : m[a] / own_sense;
        t -= step;
        if (std::abs(step) < 1e-12) break;
      }
      // Newton runs away where the error is far beyond any machine's: then what it would
      // have to correct is said, the model's error at the point.
      const AxisArray<double> travel = travelling({table.axis_index}, direction);
      const double said = std::isfinite(t) || table.rotary ? t : -miss(target, target, travel)[a] / own_sense;
      check_correction(machine, std::isfinite(said) ? said : t, table.rotary, fmt::format("the correction of {}", options.axis),
                       fmt::format("{} {:g} {} travelling {}", options.axis, p, table.rotary ? "deg" : "mm",
                                   direction > 0 ? "up" : "down"));
      (direction > 0 ? table.forward : table.reverse).push_back(t / scale);
      miss_mean += 0.5 * m;
    }
    for (std::size_t k = 0; k < table.cross.size(); ++k) {
      const double c = -miss_mean[static_cast<Eigen::Index>(table.cross[k].axis_index)] / sense[k];
      check_correction(machine, c, false, fmt::format("the correction of {}", table.cross[k].axis),
                       fmt::format("{} {:g} mm", options.axis, p));
      table.cross[k].correction.push_back(c);
    }
  }
  // Nothing at the reference position: there the work offset takes the machine's error.
  table.reference = options.reference;
  const double own = correction_at(table, options.reference, +1);
  for (std::size_t i = 0; i < n; ++i) table.forward[i] -= own, table.reverse[i] -= own;
  for (std::size_t k = 0; k < table.cross.size(); ++k) {
    const double c = cross_correction_at(table, k, options.reference);
    for (double& v : table.cross[k].correction) v -= c;
  }
  return table;
}

double correction_at(const AxisTable& table, double p, int direction) {
  return interpolate(table.positions, direction > 0 ? table.forward : table.reverse, p);
}

double cross_correction_at(const AxisTable& table, std::size_t k, double p) {
  return interpolate(table.positions, table.cross[k].correction, p);
}

Residual table_residual(const model::ForwardModel& model, const std::vector<AxisTable>& tables,
                        const std::vector<model::ChainQ>& points, const model::ChainQ& reference,
                        const model::Conditions& conditions, int component) {
  std::vector<std::size_t> moving;
  for (const AxisTable& t : tables) moving.push_back(t.axis_index);
  const Corrector corrector = [&tables](const model::ChainQ& q, int direction) {
    model::ChainQ c = model::ChainQ::Zero();
    for (const AxisTable& t : tables) {
      const double p = q[static_cast<Eigen::Index>(t.axis_index)] / t.scale();
      c[static_cast<Eigen::Index>(t.axis_index)] += correction_at(t, p, direction) * t.scale();
      for (std::size_t k = 0; k < t.cross.size(); ++k)
        c[static_cast<Eigen::Index>(t.cross[k].axis_index)] += cross_correction_at(t, k, p);
    }
    return c;
  };
  return corrected_residual(model, corrector, moving, points, reference, conditions, component);
}

Residual corrected_residual(const model::ForwardModel& model, const Corrector& corrector,
                            const std::vector<std::size_t>& moving_axes, const std::vector<model::ChainQ>& points,
                            const model::ChainQ& reference, const model::Conditions& conditions, int component) {
  Residual r;
  TipMiss miss(model, conditions);
  // The corrected axes travel together, up or down; the rest stand in the middle of their play.
  auto moving = [&moving_axes](int direction) { return travelling(moving_axes, direction); };
  // What is measured at each point: the tip's miss (um), one component of it, or the turn
  // about rotary axis `component` (arcsec), each less its value at the reference point.
  constexpr double kArcsec = 180.0 / M_PI * 3600.0;
  const bool turn = component >= 3;
  auto measure = [&](const model::ChainQ& commanded, const model::ChainQ& target, int direction) {
    if (turn) {
      const Eigen::Vector3d u = miss.turn_axis(target, static_cast<std::size_t>(component));
      return Eigen::Vector3d(miss.turn(commanded, target, moving(direction), u) * kArcsec, 0.0, 0.0);
    }
    return Eigen::Vector3d(miss(commanded, target, moving(direction)) * 1e3);
  };
  auto size = [component, turn](const Eigen::Vector3d& v) {
    return component < 0 ? v.norm() : std::abs(v[turn ? 0 : component]);
  };
  const Eigen::Vector3d offset = measure(reference, reference, +1);
  r.reference_um = size(offset);
  double sum_before = 0.0, sum_after = 0.0;
  for (const model::ChainQ& q : points) {
    for (int direction : {+1, -1}) {
      const model::ChainQ commanded = q + corrector(q, direction);
      const double before = size(measure(q, q, direction) - offset);
      const double after = size(measure(commanded, q, direction) - offset);
      r.max_before_um = std::max(r.max_before_um, before);
      r.max_after_um = std::max(r.max_after_um, after);
      sum_before += before * before, sum_after += after * after;
      ++r.points;
    }
  }
  if (r.points > 0) {
    r.rms_before_um = std::sqrt(sum_before / static_cast<double>(r.points));
    r.rms_after_um = std::sqrt(sum_after / static_cast<double>(r.points));
  }
  return r;
}

model::ChainQ reference_point(const AxisTable& table, const TableOptions& options) {
  model::ChainQ q = options.line;
  q[static_cast<Eigen::Index>(table.axis_index)] = options.reference * table.scale();
  return q;
}

std::vector<model::ChainQ> line_points(const AxisTable& table, const TableOptions& options) {
  std::vector<model::ChainQ> points;
  const double spacing = options.step / 8;
  for (double p = table.positions.front(); p <= table.positions.back() + 1e-9; p += spacing) {
    model::ChainQ q = options.line;
    q[static_cast<Eigen::Index>(table.axis_index)] = p * table.scale();
    points.push_back(q);
  }
  return points;
}

std::vector<model::ChainQ> workspace_points(const model::MachineModel& machine, const model::ChainQ& line,
                                            std::size_t per_axis, bool rotaries) {
  std::vector<model::ChainQ> points{line};
  for (const model::AxisSpec& spec : machine.axes) {
    const auto j = static_cast<Eigen::Index>(spec.index());
    const bool rotary = spec.type == model::AxisType::rotary;
    if (rotary && !rotaries) continue;
    double lo = spec.min, hi = spec.max;
    if (rotary) {
      if (!std::isfinite(lo) || !std::isfinite(hi) || hi - lo > 360.0)
        lo = 0.0, hi = 360.0 - 360.0 / static_cast<double>(per_axis);
      lo *= M_PI / 180.0, hi *= M_PI / 180.0;
    }
    if (!std::isfinite(lo) || !std::isfinite(hi)) continue;  // no travel known: keep the line's
    std::vector<model::ChainQ> grown;
    for (const model::ChainQ& q : points)
      for (std::size_t k = 0; k < per_axis; ++k) {
        model::ChainQ p = q;
        p[j] = lo + (hi - lo) * static_cast<double>(k) / static_cast<double>(per_axis - 1);
        grown.push_back(p);
      }
    points = std::move(grown);
  }
  return points;
}

}  // namespace ccomp::controller
