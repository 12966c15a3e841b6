#include "candidates.hpp"

#include "candidate_families.hpp"

#include "aliasing.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>

#include "ccomp/constants.hpp"
#include "ccomp/model/error_term.hpp"
#include "ccomp/util/interval.hpp"

namespace ccomp::identify::detail {

/// A candidate's columns at a scanned value (a period, a time constant): its probe's
/// column times each basis function, on the probe's rows (`out` has a row per probe row),
/// or on every reading (`out` has n rows, zero off the probe's rows).
void candidate_columns(const Candidate& c, const Probe& p, const MeasurementSet& data, double value, bool every_row,
                       Eigen::Ref<Eigen::MatrixXd> out) {
  for (std::size_t i = 0; i < p.rows.size(); ++i) {
    const Eigen::Index row = p.rows[i];
    const Observation& o = data.observations[static_cast<std::size_t>(row)];
    for (int k = 0; k < c.basis_count; ++k)
      out(every_row ? row : static_cast<Eigen::Index>(i), k) = p.g[row] * c.basis(o, k, value);
  }
}

std::string axis_name(std::size_t i) {
  return std::string(1, static_cast<char>(std::tolower(kAxisLetters[i])));
}

/// An axis' position in a reading, in the file's units (mm, deg): a linear axis' slide
/// position (Z without the tool length), a rotary axis' angle.
double axis_value(const Observation& o, const AxisInfo& a) {
  return file_axis_value(o, a.index, a.rotary);
}

std::vector<AxisInfo> axes_of(const model::MachineModel& mm, const MeasurementSet& data) {
  std::vector<AxisInfo> axes;
  for (const auto* chain : {&mm.workpiece_chain, &mm.tool_chain})
    for (const model::LinkSpec& l : *chain) {
      if (!l.axis) continue;
      AxisInfo a;
      a.index = kAxisLetters.find(*l.axis);
      a.link = l.name;
      a.rotary = mm.axis(*l.axis) && mm.axis(*l.axis)->type == model::AxisType::rotary;
      Eigen::Index along = 0;
      l.direction.cwiseAbs().maxCoeff(&along);
      a.own = static_cast<int>(along) + (a.rotary ? 3 : 0);
      const auto qi = static_cast<Eigen::Index>(a.index);
      util::Interval reach;
      for (const Observation& o : data.observations) reach.add(axis_value(o, a));
      a.from = reach.lo, a.to = reach.hi;
      // The median spacing between consecutive readings that differ along this axis only.
      std::vector<double> steps, positions;  // and the positions such moves visit
      for (std::size_t i = 1; i < data.observations.size(); ++i) {
        const model::ChainQ d = data.observations[i].q - data.observations[i - 1].q;
        const double travel = std::abs(d[qi]);
        if (travel > 1e-9 && d.norm() - travel < 1e-9 * (1.0 + travel)) {
          steps.push_back(a.rotary ? travel / kRadPerDeg : travel);
          positions.push_back(axis_value(data.observations[i - 1], a));
          positions.push_back(axis_value(data.observations[i], a));
        }
      }
      if (steps.empty()) {
        // No reading moves along this axis alone (a sphere probed as B turns moves X and Z
        // with it): the spacing of the distinct positions the data visit.
        std::vector<double> visited;
        for (const Observation& o : data.observations) visited.push_back(axis_value(o, a));
        std::sort(visited.begin(), visited.end());
        for (std::size_t i = 1; i < visited.size(); ++i)
          if (visited[i] - visited[i - 1] > 1e-9 * (1.0 + std::abs(visited[i]))) {
            steps.push_back(visited[i] - visited[i - 1]);
            positions.push_back(visited[i]);
          }
      }
      if (!steps.empty()) {
        std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
        a.step = steps[steps.size() / 2];
        a.on_lattice = on_lattice(positions, a.step);
      }
      axes.push_back(a);
    }
  return axes;
}

/// A term's ISO name: "EXX", a location error "EC0X".
std::string term_name(int component, const std::string& link, bool location) {
  return fmt::format("E{}{}{}", kComponents[static_cast<std::size_t>(component)], location ? "0" : "", link);
}

LibraryContext::LibraryContext(const model::MachineModel& model, const MeasurementSet& measured,
                               std::vector<Probe>& into)
    : mm(model), data(measured), probes(into) {
  for (const model::LinkSpec& l : mm.tool_chain)
    if (!l.tool) spindle = l.name;
  auto varies = [&](auto get) {
    util::Interval range;
    for (const Observation& o : data.observations) range.add(get(o));
    return range.hi > range.lo + 1e-12;
  };
  tool_length_varies =
      varies([](const Observation& o) { return o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]; });
  time_varies = varies([](const Observation& o) { return o.time; });
}

std::size_t LibraryContext::probe(const std::string& link, int component, model::ErrorPlacement placement) {
  for (std::size_t i = 0; i < probes.size(); ++i)
    if (probes[i].link == link && probes[i].component == component && probes[i].placement == placement) return i;
  probes.push_back(Probe{link, component, placement, {}, {}, {}});
  return probes.size() - 1;
}

bool LibraryContext::sensor_varies(std::size_t sensor) const {
  util::Interval range;
  for (const Observation& o : data.observations) {
    if (sensor >= o.temperatures.size() || std::isnan(o.temperatures[sensor])) return false;
    range.add(o.temperatures[sensor]);
  }
  return range.hi > range.lo + 1e-12;
}

namespace {

/// The families, in the order their candidates are listed (and their probes registered).
constexpr AxisFamily kLinearAxisFamilies[] = {screw_pitch,  reversal,        higher_order, local_defect,
                                              squareness, scale_expansion, cross_axis};
constexpr AxisFamily kRotaryAxisFamilies[] = {table_harmonics, worm_wheel, reversal, rotary_location};
constexpr MachineFamily kMachineFamilies[] = {spindle_tilt, spindle_heat};

}  // namespace

std::vector<Candidate> candidate_library(const model::MachineModel& mm, const MeasurementSet& data,
                                         const std::vector<AxisInfo>& axes, std::vector<Probe>& probes) {
  LibraryContext ctx(mm, data, probes);
  std::vector<Candidate> candidates;
  for (const AxisInfo& a : axes) {
    if (!(a.to - a.from > 0)) continue;  // the data do not move it
    for (const AxisFamily family : a.rotary ? std::span<const AxisFamily>(kRotaryAxisFamilies)
                                            : std::span<const AxisFamily>(kLinearAxisFamilies))
      family(ctx, a, axes, candidates);
  }
  for (const MachineFamily family : kMachineFamilies) family(ctx, candidates);
  return candidates;
}

}  // namespace ccomp::identify::detail
