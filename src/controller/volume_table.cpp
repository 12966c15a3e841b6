#include "ccomp/controller/volume_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "ccomp/error.hpp"
#include "correction_bound.hpp"
#include "tip_miss.hpp"

namespace ccomp::controller {
namespace {

/// The node at or below p along one axis and p's fraction of the way to the next, held
/// at the ends.
struct CellCoordinate {
  std::size_t lower = 0;
  double fraction = 0.0;
};
CellCoordinate cell_coordinate(const std::vector<double>& positions, double p) {
  if (positions.size() == 1 || !(p > positions.front())) return {0, 0.0};  // NaN too
  if (p >= positions.back()) return {positions.size() - 2, 1.0};
  const auto upper = std::upper_bound(positions.begin(), positions.end(), p);
  const auto k = static_cast<std::size_t>(upper - positions.begin()) - 1;
  return {k, (p - positions[k]) / (positions[k + 1] - positions[k])};
}

/// The nodes along one axis, rounded to the nanometre (so 0.3 is 0.3, not 0.30000000000000004).
std::vector<double> node_positions(const Grid& g) {
  std::vector<double> p(g.points());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = std::round((g.from + static_cast<double>(i) * g.step) * 1e9) / 1e9;
  return p;
}

/// The sampling model: each left-out harmonic's parameters at 0 (a periodic term's
/// parameters: its period, then a_k, b_k for k = 1, 2, ...).
void leave_out(const model::ForwardModel& model, const std::vector<VolumeOptions::LeftOut>& left_out, TipMiss& miss) {
  for (const VolumeOptions::LeftOut& l : left_out) {
    const model::ErrorTermSpec& term = model.machine().terms.at(l.term);
    if (term.shape.form != model::TermForm::periodic || l.first_harmonic < 1)
      throw Error(
          ErrorKind::usage,
          fmt::format("term {}: only a periodic term's harmonics can be left out of a volumetric table", term.name));
    const auto first = static_cast<std::size_t>(2 * l.first_harmonic - 1);
    const auto count = static_cast<std::size_t>(term.parameters.size());
    if (first < count) miss.zero_parameters(model.parameter_offset(l.term) + first, count - first);
  }
}

/// How far the tip moves along X, Y, Z as each is commanded 1 mm further (+1 or -1 on a
/// machine whose axes move along themselves): Newton's slope.
Eigen::Vector3d senses(const model::MachineModel& machine, const model::ChainQ& line, TipMiss& miss) {
  Eigen::Vector3d sense;
  for (std::size_t a = 0; a < 3; ++a) {
    sense[static_cast<Eigen::Index>(a)] = miss.sense(line, a);
    if (!(std::abs(sense[static_cast<Eigen::Index>(a)]) > 0.5))
      throw Error(ErrorKind::model, fmt::format("the machine '{}' moves the tool {:g} mm along {} for 1 mm of {}: a "
                                                "volumetric table corrects X, Y, Z along themselves",
                                                machine.name, sense[static_cast<Eigen::Index>(a)], "XYZ"[a], "XYZ"[a]));
  }
  return sense;
}

/// Refuses a node's correction beyond the model's max_correction or not finite, as the
/// main job refuses it.
void check_node(const model::MachineModel& machine, const Eigen::Vector3d& t, const model::ChainQ& target) {
  for (Eigen::Index a = 0; a < 3; ++a)
    check_correction(machine, t[a], false, fmt::format("the correction of {}", "XYZ"[a]),
                     fmt::format("X {:g} Y {:g} Z {:g}", target[0], target[1], target[2]));
}

/// The correction at `target`, Newton from `t` (the last node's: neighbours correct alike)
/// with the nominal slope (the error's own is ~1e-4: four digits a step). One beyond the
/// model's bound is refused as such, converged or not.
Eigen::Vector3d solve_node(const model::MachineModel& machine, TipMiss& miss, const model::ChainQ& target,
                           const Eigen::Vector3d& sense, Eigen::Vector3d t) {
  for (int iteration = 0; iteration < 12; ++iteration) {
    model::ChainQ commanded = target;
    commanded.head<3>() += t;
    const Eigen::Vector3d m =
        0.5 * (miss(commanded, target, travelling({0, 1, 2}, +1)) + miss(commanded, target, travelling({0, 1, 2}, -1)));
    const Eigen::Vector3d step = m.cwiseQuotient(sense);
    t -= step;
    if (step.cwiseAbs().maxCoeff() < 1e-12 && t.allFinite()) {
      check_node(machine, t, target);
      return t;
    }
  }
  // Newton runs away where the error is far beyond any machine's: then what it would have to
  // correct is said, the model's error at the node.
  const Eigen::Vector3d said = -0.5 * (miss(target, target, travelling({0, 1, 2}, +1)) +
                                       miss(target, target, travelling({0, 1, 2}, -1)))
                                          .cwiseQuotient(sense);
  check_node(machine, said.allFinite() && !t.allFinite() ? said : t, target);
  throw Error(ErrorKind::model, fmt::format("the correction at X {:g} Y {:g} Z {:g} does not converge: the model's "
                                            "error there changes as fast as the axes move",
                                            target[0], target[1], target[2]));
}

/// The radical inverse of n in `base`: the n-th Halton coordinate, in [0, 1).
double radical_inverse(std::size_t n, std::size_t base) {
  double inverse = 0.0, digit = 1.0 / static_cast<double>(base);
  for (; n > 0; n /= base, digit /= static_cast<double>(base)) inverse += static_cast<double>(n % base) * digit;
  return inverse;
}

}  // namespace

Eigen::Vector3d VolumeTable::correction_at(const Eigen::Vector3d& p) const {
  std::array<CellCoordinate, 3> c;
  for (std::size_t a = 0; a < 3; ++a) c[a] = cell_coordinate(positions[a], p[static_cast<Eigen::Index>(a)]);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t corner = 0; corner < 8; ++corner) {
    std::array<std::size_t, 3> node{};
    double weight = 1.0;
    for (std::size_t a = 0; a < 3; ++a) {
      const bool upper = (corner >> a & 1U) != 0;
      node[a] = std::min(c[a].lower + (upper ? 1 : 0), positions[a].size() - 1);
      weight *= upper ? c[a].fraction : 1.0 - c[a].fraction;
    }
    if (weight != 0.0) sum += weight * correction[index(node[0], node[1], node[2])];
  }
  return sum;
}

VolumeTable sample_volume_table(const model::ForwardModel& model, const VolumeOptions& options) {
  const model::MachineModel& machine = model.machine();
  for (const char letter : {'X', 'Y', 'Z'}) {
    const model::AxisSpec* spec = machine.axis(letter);
    if (spec == nullptr || spec->type != model::AxisType::linear)
      throw Error(ErrorKind::usage, fmt::format("a volumetric table needs the linear axes X, Y and Z; the machine "
                                                "'{}' has no linear {}",
                                                machine.name, letter));
  }
  VolumeTable table;
  table.reference = options.reference;
  for (std::size_t a = 0; a < 3; ++a) {
    table.positions[a] = node_positions(options.grids[a]);
    const std::vector<double>& p = table.positions[a];
    const double r = options.reference[static_cast<Eigen::Index>(a)];
    if (std::none_of(p.begin(), p.end(), [r](double v) { return std::abs(v - r) < 1e-9; }))
      throw Error(ErrorKind::usage,
                  fmt::format("the volumetric table's reference {} = {:g} mm is not one of its nodes", "XYZ"[a], r));
  }
  TipMiss miss(model, options.conditions);
  leave_out(model, options.left_out, miss);
  const Eigen::Vector3d sense = senses(machine, options.line, miss);
  table.correction.resize(table.nodes());
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < table.positions[2].size(); ++k)
    for (std::size_t j = 0; j < table.positions[1].size(); ++j)
      for (std::size_t i = 0; i < table.positions[0].size(); ++i) {
        model::ChainQ target = options.line;
        target.head<3>() << table.positions[0][i], table.positions[1][j], table.positions[2][k];
        t = solve_node(machine, miss, target, sense, t);
        table.correction[table.index(i, j, k)] = t;
      }
  const Eigen::Vector3d at_reference = table.correction_at(options.reference);
  for (Eigen::Vector3d& c : table.correction) c -= at_reference;
  return table;
}

std::vector<model::ChainQ> volume_points(const VolumeTable& table, const model::ChainQ& line, std::size_t count) {
  std::vector<model::ChainQ> points;
  points.reserve(count);
  for (std::size_t n = 1; n <= count; ++n) {
    model::ChainQ q = line;
    const std::array<std::size_t, 3> bases{2, 3, 5};
    for (std::size_t a = 0; a < 3; ++a) {
      const std::vector<double>& p = table.positions[a];
      q[static_cast<Eigen::Index>(a)] = p.front() + radical_inverse(n, bases[a]) * (p.back() - p.front());
    }
    points.push_back(q);
  }
  return points;
}

Corrector volume_corrector(const VolumeTable& table) {
  return [&table](const model::ChainQ& q, int) {
    model::ChainQ c = model::ChainQ::Zero();
    c.head<3>() = table.correction_at(q.head<3>());
    return c;
  };
}

}  // namespace ccomp::controller
