#include "ccomp/identify/simulate.hpp"

#include <fmt/format.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <random>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "table_point.hpp"

namespace ccomp::identify {
namespace {

/// The span of an axis to measure over: its limits, or +-200 mm (+-180 deg) when unlimited.
std::pair<double, double> span(const model::MachineModel& m, char letter) {
  const model::AxisSpec* a = m.axis(letter);
  if (!a) return {0.0, 0.0};
  const double fallback = a->type == model::AxisType::rotary ? 180.0 : 200.0;
  return {std::isfinite(a->min) ? a->min : -fallback, std::isfinite(a->max) ? a->max : fallback};
}

struct Recorder {
  const model::ForwardModel& truth;
  model::ForwardData data;
  MeasurementSet& set;
  std::mt19937 rng;
  std::normal_distribution<double> noise;

  std::uint32_t source(const std::string& label) {
    const auto it = std::find(set.sources.begin(), set.sources.end(), label);
    if (it != set.sources.end()) return static_cast<std::uint32_t>(it - set.sources.begin());
    set.sources.push_back(label);
    return static_cast<std::uint32_t>(set.sources.size() - 1);
  }
  /// Records the reading along each direction at the controlled point (x, y, z, b deg) in
  /// machine coordinates.
  void record(const std::string& label, double x, double y, double z, double b_deg, double tool, double time,
              const std::vector<double>& temperatures, const AxisArray<double>& directions,
              std::initializer_list<Eigen::Vector3d> along) {
    model::ChainQ q;
    q << x, y, z + tool, 0, b_deg * kRadPerDeg, 0, 0, 0, 0, tool;
    record(label, q, time, temperatures, directions, along);
  }
  /// The same at the axis positions `q` (the tool length in it).
  void record(const std::string& label, const model::ChainQ& q, double time, const std::vector<double>& temperatures,
              const AxisArray<double>& directions, std::initializer_list<Eigen::Vector3d> along) {
    Observation o;
    o.q = q;
    o.time = time;
    o.temperatures = temperatures;
    for (std::size_t i = 0; i < directions.size(); ++i) o.directions[i] = static_cast<std::int8_t>(directions[i]);
    o.source = source(label);
    o.row = static_cast<std::uint32_t>(set.observations.size() + 2);
    for (const Eigen::Vector3d& n : along) {
      o.direction = n;
      o.value = predict(truth, data, o) + noise(rng);
      set.observations.push_back(o);
    }
  }
};

/// Readings of a part measured on a CMM against its own faces, not against the machine:
/// the CMM aligns the part on the faces cut at B0 (`datum` sources), so what it reports is
/// each reading less what the best rigid displacement of the part explains on those faces.
void against_datum_faces(const model::ForwardModel& truth, MeasurementSet& set, std::size_t first,
                         const std::vector<std::uint32_t>& datum) {
  model::ForwardData d(truth);
  const std::size_t n = set.observations.size() - first;
  Eigen::MatrixXd A(static_cast<Eigen::Index>(n), 6);  // the part moved by t + w x s (table frame)
  for (std::size_t i = 0; i < n; ++i) {
    const Observation& o = set.observations[first + i];
    model::forward(truth, d, o.q, MeasurementSet::conditions(o), false, model::Evaluate::nominal);
    const Eigen::Vector3d along = d.nominal_chain.oMp.R.transpose() * o.direction;  // in the table frame
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
      A(static_cast<Eigen::Index>(i), k) = -along.dot(e);  // the tool relative to the moved part
      A(static_cast<Eigen::Index>(i), 3 + k) = -along.dot(e.cross(d.nominal));
    }
  }
  Eigen::MatrixXd A_datum = Eigen::MatrixXd::Zero(A.rows(), 6);
  Eigen::VectorXd b_datum = Eigen::VectorXd::Zero(A.rows());
  for (std::size_t i = 0; i < n; ++i) {
    const Observation& o = set.observations[first + i];
    if (std::find(datum.begin(), datum.end(), o.source) == datum.end()) continue;
    A_datum.row(static_cast<Eigen::Index>(i)) = A.row(static_cast<Eigen::Index>(i));
    b_datum[static_cast<Eigen::Index>(i)] = o.value;
  }
  const Eigen::VectorXd displacement = A_datum.completeOrthogonalDecomposition().solve(b_datum);
  const Eigen::VectorXd explained = A * displacement;
  for (std::size_t i = 0; i < n; ++i) set.observations[first + i].value -= explained[static_cast<Eigen::Index>(i)];
}

/// A reading that is not a number (a term of 1e308, a polynomial far beyond where it means
/// anything) or beyond the model's max_correction is refused as the main job refuses such an
/// error (exit 7): no NaN row, and no row `fit` would refuse as a file in the wrong unit.
void refuse_beyond_bound(const model::MachineModel& m, const MeasurementSet& set) {
  for (const Observation& o : set.observations) {
    if (std::abs(o.value) <= m.max_correction) continue;
    std::string at;
    for (const model::AxisSpec& a : m.axes) {
      const auto j = static_cast<Eigen::Index>(a.index());
      at += fmt::format(" {} {:g}", a.letter, a.type == model::AxisType::rotary ? o.q[j] / kRadPerDeg : o.q[j]);
    }
    const std::string size = std::isfinite(o.value)
                                 ? fmt::format("{:.6g} mm, beyond its bound of {} mm (max_correction)", o.value,
                                               m.max_correction)
                                 : fmt::format("not a number ({})", o.value);
    throw Error(ErrorKind::safety,
                fmt::format("the model's error at{} ({}, row {}) is {}: nothing is written; is the model right for "
                            "this machine?",
                            at, set.sources[o.source], o.row, size));
  }
}

/// The rotary axes the model has, as indices of the chain's variables (3 A, 4 B, 5 C).
std::vector<Eigen::Index> rotary_indices(const model::MachineModel& m) {
  std::vector<Eigen::Index> out;
  for (const model::AxisSpec& a : m.axes)
    if (a.type == model::AxisType::rotary)
      out.push_back(static_cast<Eigen::Index>(a.index()));
  std::sort(out.begin(), out.end());
  return out;
}

/// A B table alone (the HMC): the sphere plan it has always had, kept so its files do not change.
bool turns_only_b(const model::MachineModel& m) {
  const std::vector<Eigen::Index> r = rotary_indices(m);
  return r.size() == 1 && r[0] == 4;
}

/// The angles (deg, machine) a rotary axis is probed at: a turn in `step` where it is
/// unlimited or turns a full circle, else its range (at most 240 deg of it, centred on the
/// middle of its limits) in about 30 deg steps, ends included.
std::vector<double> probe_angles(const model::MachineModel& m, char letter, double step) {
  const auto [lo, hi] = span(m, letter);
  std::vector<double> out;
  if (hi - lo >= 360.0 - 1e-9) {
    const int count = std::max(4, static_cast<int>(std::lround(360.0 / step)));
    for (int k = 0; k < count; ++k) out.push_back(-180.0 + 360.0 * k / count);
    return out;
  }
  const double middle = 0.5 * (lo + hi), half = std::min(120.0, 0.5 * (hi - lo));
  const int count = std::max(3, static_cast<int>(std::lround(2.0 * half / 30.0)) + 1);
  for (int k = 0; k < count; ++k) out.push_back(middle - half + 2.0 * half * k / (count - 1));
  return out;
}

}  // namespace

std::vector<double> iso230_targets(double from, double to, double step) {
  const int count = std::max(2, static_cast<int>(std::floor((to - from) / step)) + 1);
  const double p = (to - from) / (count - 1);
  std::vector<double> targets(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    // The golden ratio's multiples modulo 1: offsets that never repeat a pattern, spread
    // evenly over +-p/4 (a random draw would differ from build to build of the library).
    const double u = std::fmod(0.5 + 0.6180339887498949 * i, 1.0);
    const double r = i == 0 || i == count - 1 ? 0.0 : 0.25 * p * (2.0 * u - 1.0);
    targets[static_cast<std::size_t>(i)] = from + i * p + r;
  }
  return targets;
}

std::vector<model::ChainQ> sphere_poses(const model::ForwardModel& truth, const SimulateOptions& options) {
  const model::MachineModel& m = truth.machine();
  const model::WorkOrigin& o = options.origin;
  const std::vector<Eigen::Index> rotary = rotary_indices(m);
  if (rotary.empty()) return {};
  // Every combination of the rotary axes' probing angles (a tilt axis' range by a turn of
  // the other), as ISO 10791-6's K tests and the control cycles that fit a kinematics do.
  std::vector<std::vector<double>> angles;
  for (const Eigen::Index j : rotary) angles.push_back(probe_angles(m, kAxisLetters[j], options.rotary_step));
  std::vector<model::ChainQ> out;
  model::ForwardData d(truth);
  const double L = options.tool_length;
  // Two spheres on the part at different radii, bearings and heights from program zero: one
  // alone cannot tell a line's offset from its tilt.
  for (const Eigen::Vector3d& sphere : {Eigen::Vector3d(80, 40, 20), Eigen::Vector3d(-50, -60, 90)}) {
    model::ChainQ rest = model::ChainQ::Zero();
    rest << sphere.x() + o[0], sphere.y() + o[1], sphere.z() + o[2] + L, o[3] * kRadPerDeg, o[4] * kRadPerDeg,
        o[5] * kRadPerDeg, 0, 0, 0, L;
    model::forward(truth, d, rest, model::Conditions{}, false, model::Evaluate::nominal);
    const Eigen::Vector3d on_table = d.nominal;  // where the sphere sits on the table
    std::vector<std::size_t> at(rotary.size(), 0);
    for (bool more = true; more;) {
      model::ChainQ q = rest;
      for (std::size_t r = 0; r < rotary.size(); ++r) q[rotary[r]] = angles[r][at[r]] * kRadPerDeg;
      reach_table_point(truth, d, q, on_table);
      if (within_limits(m, q)) out.push_back(q);
      more = false;  // the next combination, the last axis fastest
      for (std::size_t r = rotary.size(); r-- > 0;) {
        if (++at[r] < angles[r].size()) {
          more = true;
          break;
        }
        at[r] = 0;
      }
    }
  }
  return out;
}

Plan plan_from_name(const std::string& name) {
  if (name == "nine_lines" || name == "lines") return Plan::nine_lines;
  if (name == "grid") return Plan::grid;
  if (name == "sphere") return Plan::sphere;
  if (name == "thermal") return Plan::thermal;
  if (name == "test_piece") return Plan::test_piece;
  throw Error(ErrorKind::usage,
              fmt::format("unknown measurement plan '{}' (nine_lines, grid, sphere, thermal, test_piece)", name));
}

MeasurementSet simulate(const model::ForwardModel& truth, const SimulateOptions& options) {
  const model::MachineModel& m = truth.machine();
  MeasurementSet set;
  set.files.push_back("simulated");
  set.sensors = m.sensors;
  Recorder rec{truth, model::ForwardData(truth), set, std::mt19937(options.seed),
               std::normal_distribution<double>(0.0, options.noise)};
  const std::vector<double> cold(m.sensors.size(), 20.0);
  const bool has_b = m.axis('B') != nullptr;    // the test piece's B table
  const model::WorkOrigin& o = options.origin;  // program zero, for the plans on the part
  const Eigen::Vector3d e[3] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
  const char letters[3] = {'X', 'Y', 'Z'};
  std::pair<double, double> s[3];
  for (int i = 0; i < 3; ++i) s[i] = span(m, letters[i]);
  auto mid = [&](int i) { return 0.5 * (s[i].first + s[i].second); };
  auto inset = [&](int i, double f) { return s[i].first + f * (s[i].second - s[i].first); };
  for (Plan plan : options.plans) {
    switch (plan) {
      case Plan::nine_lines: {
        // Per axis: line 1 with two straightnesses, line 2 with one, line 3 positioning
        // only; lines 1 and 3 spread across the workspace (the advice of docs/error-model.md Ref 4).
        for (int a = 0; a < 3; ++a) {
          const int u = (a + 1) % 3, w = (a + 2) % 3;
          const double edge = options.line_inset;
          const double offsets[3][2] = {
              {inset(u, edge), inset(w, edge)}, {mid(u), mid(w)}, {inset(u, 1 - edge), inset(w, 1 - edge)}};
          for (int line = 0; line < 3; ++line) {
            const std::string label = fmt::format("{}-line{}", static_cast<char>(std::tolower(letters[a])), line + 1);
            for (int pass = 0; pass < 2 * std::max(1, options.runs); ++pass) {  // out and back, each run
              AxisArray<double> dirs{};
              dirs[static_cast<std::size_t>(a)] = pass % 2 == 0 ? 1.0 : -1.0;
              const std::vector<double> targets = iso230_targets(s[a].first, s[a].second, options.step);
              const auto count = targets.size();
              for (std::size_t k = 0; k < count; ++k) {
                double p[3];
                p[a] = targets[pass % 2 == 0 ? k : count - 1 - k];
                p[u] = offsets[line][0];
                p[w] = offsets[line][1];
                if (line == 0)
                  rec.record(label, p[0], p[1], p[2], 0, options.tool_length, 0, cold, dirs, {e[a], e[u], e[w]});
                else if (line == 1)
                  rec.record(label, p[0], p[1], p[2], 0, options.tool_length, 0, cold, dirs, {e[a], e[u]});
                else
                  rec.record(label, p[0], p[1], p[2], 0, options.tool_length, 0, cold, dirs, {e[a]});
              }
            }
          }
        }
        break;
      }
      case Plan::grid: {
        for (double tool : {0.0, options.tool_length, 2.0 * options.tool_length})
          for (int i = 0; i < 5; ++i)
            for (int j = 0; j < 5; ++j)
              for (int k = 0; k < 5; ++k)
                rec.record(fmt::format("grid-L{:g}", tool), inset(0, 0.1 + 0.2 * i), inset(1, 0.1 + 0.2 * j),
                           inset(2, 0.1 + 0.2 * k), 0, tool, 0, cold, {}, {e[0], e[1], e[2]});
        break;
      }
      case Plan::sphere: {
        if (!turns_only_b(m)) {
          for (const model::ChainQ& q : sphere_poses(truth, options))
            rec.record("sphere", q, 0, cold, {}, {e[0], e[1], e[2]});
          break;
        }
        // Two spheres on the table, at different radii and bearings (one point alone cannot
        // tell the table's X error motion from its Z one), probed at two heights as B turns.
        const int count = std::max(4, static_cast<int>(std::lround(360.0 / options.rotary_step)));
        for (int k = 0; k < count; ++k)
          for (const auto& [px, pz] : {std::pair{150.0, 0.0}, std::pair{-60.0, 100.0}})
            for (double y : {mid(1) - 50, mid(1) + 50})
              rec.record("sphere", px + o[0], y + o[1], pz + o[2], -180.0 + 360.0 * k / count + o[4],
                         options.tool_length, 0, cold, {}, {e[0], e[1], e[2]});
        break;
      }
      case Plan::test_piece: {
        if (!has_b) break;
        // The test piece of docs/error-model.md Ref 2: a cube on the table centre; at B = 0, 90, 180, 270 deg the face
        // toward the spindle (+Z) and a side face (+X) are cut, then probed on a CMM at 3 x 3 points along their
        // normals (the error-sensitive directions of the cut), against the part's own faces cut at B0.
        const std::size_t first = set.observations.size();
        for (double b : {0.0, 90.0, 180.0, 270.0})
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
              const double u = -40.0 + 40.0 * i, v = -40.0 + 40.0 * j;
              rec.record(fmt::format("face-b{:g}-top", b), u + o[0], v + o[1], 60.0 + o[2], b + o[4],
                         options.tool_length, 0, cold, {}, {e[2]});
              rec.record(fmt::format("face-b{:g}-side", b), 60.0 + o[0], v + o[1], u + o[2], b + o[4],
                         options.tool_length, 0, cold, {}, {e[0]});
            }
        against_datum_faces(truth, set, first, {rec.source("face-b0-top"), rec.source("face-b0-side")});
        break;
      }
      case Plan::thermal: {
        // Three fixed points read every 10 minutes while the sensors warm toward their
        // end values, each at its own pace (first order, time constants 40, 70, 100...
        // minutes): sensors that warm alike could not be told apart.
        const int samples = static_cast<int>(options.hours * 6) + 1;
        for (int k = 0; k < samples; ++k) {
          const double t = 600.0 * k;
          std::vector<double> T = cold;
          for (std::size_t i = 0; i < T.size(); ++i) {
            const double end = i < options.warm_temperatures.size() ? options.warm_temperatures[i]
                                                                    : 20.0 + 4.0 + 2.0 * static_cast<double>(i);
            T[i] = 20.0 + (end - 20.0) * (1.0 - std::exp(-t / (2400.0 + 1800.0 * static_cast<double>(i))));
          }
          for (int point = 0; point < 3; ++point)
            rec.record("thermal", inset(0, 0.2 + 0.3 * point), mid(1), inset(2, 0.2 + 0.3 * point), 0,
                       options.tool_length, t, T, {}, {e[0], e[1], e[2]});
        }
        break;
      }
    }
  }
  refuse_beyond_bound(m, set);
  return set;
}

}  // namespace ccomp::identify
