#include "ccomp/identify/plan.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/identify/check.hpp"
#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/fit_information.hpp"
#include "ccomp/identify/physical_scale.hpp"
#include "table_point.hpp"

namespace ccomp::identify {
namespace {


/// The programs' poses, every k-th so that at most `most` are kept.
std::vector<ProgramPose> spread(const std::vector<ProgramPose>& poses, std::size_t most) {
  if (poses.size() <= most) return poses;
  std::vector<ProgramPose> out;
  const double step = static_cast<double>(poses.size()) / static_cast<double>(most);
  for (std::size_t k = 0; k < most; ++k) out.push_back(poses[static_cast<std::size_t>(static_cast<double>(k) * step)]);
  return out;
}

/// One group of candidate readings, before it is weighed.
struct Candidate {
  std::string source, kind, where;
  std::vector<Observation> readings;
  Eigen::MatrixXd rows;  ///< its design matrix (scaled: each row / noise, each column by its physical scale)
  bool taken = false;
};

/// The rotary angles the programs run at (rad, per rotary axis of the model), rounded to a
/// degree, the most frequent first (at most 12).
std::vector<std::vector<double>> rotary_settings(const model::MachineModel& m, const std::vector<ProgramPose>& poses) {
  std::vector<std::size_t> rotary;
  for (const model::AxisSpec& a : m.axes)
    if (a.type == model::AxisType::rotary) rotary.push_back(a.index());
  std::map<std::vector<long>, std::size_t> seen;
  for (const ProgramPose& p : poses) {
    std::vector<long> key;
    for (const std::size_t i : rotary) key.push_back(std::lround(p.q[static_cast<Eigen::Index>(i)] / kRadPerDeg));
    ++seen[key];
  }
  std::vector<std::pair<std::size_t, std::vector<long>>> by_count;
  for (const auto& [key, n] : seen) by_count.emplace_back(n, key);
  std::sort(by_count.begin(), by_count.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::vector<double>> out;
  for (std::size_t k = 0; k < by_count.size() && k < 12; ++k) {
    std::vector<double> angles;
    for (const long deg : by_count[k].second) angles.push_back(static_cast<double>(deg) * kRadPerDeg);
    out.push_back(angles);
  }
  return out;
}

/// "B180" (or "A30-C90"; empty without rotary axes).
std::string setting_name(const model::MachineModel& m, const std::vector<double>& angles) {
  std::string s;
  std::size_t k = 0;
  for (const model::AxisSpec& a : m.axes)
    if (a.type == model::AxisType::rotary)
      s += fmt::format("{}{}{:g}", s.empty() ? "" : "-", a.letter, std::round(angles[k++] / kRadPerDeg));
  return s;
}

struct ProgramBox {
  model::ChainQ low, high, middle;
  std::vector<std::size_t> linear;  ///< chain indices of the model's linear axes
  double tool_length = 0.0;
  ProgramPose conditions;  ///< the first pose's conditions, for the readings' temperatures and time
};

ProgramBox box_of(const model::MachineModel& m, const std::vector<ProgramPose>& poses) {
  ProgramBox b;
  b.low = b.high = poses.front().q;
  for (const ProgramPose& p : poses) b.low = b.low.cwiseMin(p.q), b.high = b.high.cwiseMax(p.q);
  b.middle = (b.low + b.high) / 2;
  for (const model::AxisSpec& a : m.axes)
    if (a.type == model::AxisType::linear) b.linear.push_back(a.index());
  std::vector<double> L;
  for (const ProgramPose& p : poses) L.push_back(p.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]);
  std::nth_element(L.begin(), L.begin() + static_cast<std::ptrdiff_t>(L.size() / 2), L.end());
  b.tool_length = L[L.size() / 2];
  b.conditions = poses.front();
  return b;
}

Observation reading_at(const ProgramBox& box, model::ChainQ q, const Eigen::Vector3d& direction) {
  Observation o;
  o.q = q;
  o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)] = box.tool_length;
  o.time = box.conditions.conditions.time;
  o.temperatures = box.conditions.conditions.temperatures;
  o.direction = direction;
  return o;
}

/// `q` with the model's rotary axes at `angles` (rad, in the model's order of axes).
model::ChainQ at_setting(const model::MachineModel& m, model::ChainQ q, const std::vector<double>& angles) {
  std::size_t k = 0;
  for (const model::AxisSpec& a : m.axes)
    if (a.type == model::AxisType::rotary) q[static_cast<Eigen::Index>(a.index())] = angles[k++];
  return q;
}

/// At one rotary setting: a grid of 3 points a linear axis over the programs' box (full
/// deviations: three readings a point), and a laser line along each linear axis through the
/// box's middle, 11 targets out and back.
void candidates_at(const model::MachineModel& m, const ProgramBox& box, const std::vector<double>& angles,
                   std::vector<Candidate>& out) {
  const model::ChainQ base = at_setting(m, box.middle, angles);
  const std::string at = setting_name(m, angles);
  const std::string suffix = at.empty() ? "" : "-" + at;
  const std::string where = at.empty() ? "" : " at " + at;
  // The grid.
  Candidate grid{"plan-grid" + suffix, "grid", where, {}, {}, false};
  std::vector<model::ChainQ> points{base};
  for (const std::size_t i : box.linear) {
    std::vector<model::ChainQ> more;
    const auto e = static_cast<Eigen::Index>(i);
    const bool spread_out = box.high[e] - box.low[e] > 1.0;
    for (const model::ChainQ& p : points)
      for (int s = 0; s < (spread_out ? 3 : 1); ++s) {
        model::ChainQ q = p;
        if (spread_out) q[e] = box.low[e] + (box.high[e] - box.low[e]) * s / 2.0;
        more.push_back(q);
      }
    points = std::move(more);
  }
  for (const model::ChainQ& q : points)
    for (int c = 0; c < 3; ++c) grid.readings.push_back(reading_at(box, q, Eigen::Vector3d::Unit(c)));
  out.push_back(std::move(grid));
  // The lines.
  for (const std::size_t i : box.linear) {
    const auto e = static_cast<Eigen::Index>(i);
    if (i > 2 || box.high[e] - box.low[e] <= 1.0) continue;  // X Y Z: a laser reads along the machine's axes
    Candidate line{fmt::format("plan-{}-line{}", kAxisLetters[i], suffix), "laser line", where, {}, {}, false};
    for (const int way : {+1, -1})
      for (int t = 0; t <= 10; ++t) {
        model::ChainQ q = base;
        q[e] = box.low[e] + (box.high[e] - box.low[e]) * (way > 0 ? t : 10 - t) / 10.0;
        Observation o = reading_at(box, q, Eigen::Vector3d::Unit(static_cast<int>(i)));
        o.directions[i] = static_cast<std::int8_t>(way);
        line.readings.push_back(o);
      }
    out.push_back(std::move(line));
  }
}

/// `q` moved so that the nominal tip is on `point` (table frame), where it has X, Y and Z
/// and they stay within the axes' limits.
std::optional<model::ChainQ> reaching(const model::ForwardModel& model, model::ForwardData& fd,
                                      const ProgramBox& box, model::ChainQ q, const Eigen::Vector3d& point) {
  for (std::size_t i = 0; i < 3; ++i)
    if (std::find(box.linear.begin(), box.linear.end(), i) == box.linear.end()) return std::nullopt;
  reach_table_point(model, fd, q, point, box.conditions.conditions);
  model::forward(model, fd, q, box.conditions.conditions, false, model::Evaluate::nominal);
  if (!q.allFinite() || (fd.nominal - point).norm() > 1e-6 || !within_limits(model.machine(), q)) return std::nullopt;
  return q;
}

/// The rotary angles a sphere is probed at: over the range the programs turn each rotary
/// axis through, evenly, about every 15 degrees (at least 3 angles where the axis turns a
/// degree or more, at most 13), a full turn without its end again; with two axes every
/// combination, each axis' count lowered until there are at most 25 (rad, per rotary axis
/// of the model).
std::vector<std::vector<double>> sweep_angles(const model::MachineModel& m, const ProgramBox& box) {
  struct Range {
    double low, high;
    bool full_turn;
    int count;
  };
  std::vector<Range> ranges;
  for (const model::AxisSpec& a : m.axes) {
    if (a.type != model::AxisType::rotary) continue;
    const auto e = static_cast<Eigen::Index>(a.index());
    const double low = box.low[e], high = box.high[e], range_deg = (high - low) / kRadPerDeg;
    const bool full_turn = range_deg >= 360.0 - 1e-6;
    const int count = range_deg < 1.0 ? 1 : std::clamp(static_cast<int>(std::ceil(range_deg / 15.0)) + 1, 3, 13);
    ranges.push_back({low, full_turn ? low + 2 * std::numbers::pi : high, full_turn, count});
  }
  auto combinations = [&] {
    std::size_t n = 1;
    for (const Range& r : ranges) n *= static_cast<std::size_t>(r.count);
    return n;
  };
  while (combinations() > 25) {
    Range& most = *std::max_element(ranges.begin(), ranges.end(),
                                    [](const Range& a, const Range& b) { return a.count < b.count; });
    --most.count;
  }
  std::vector<std::vector<double>> out{{}};
  for (const Range& r : ranges) {
    std::vector<std::vector<double>> more;
    const int intervals = r.full_turn ? r.count : r.count - 1;
    for (const std::vector<double>& prefix : out)
      for (int k = 0; k < r.count; ++k) {
        more.push_back(prefix);
        more.back().push_back(r.count == 1 ? r.low : r.low + (r.high - r.low) * k / intervals);
      }
    out = std::move(more);
  }
  return out;
}

/// Spheres fixed on the table where the programs cut (their box's middle and two opposite
/// corners, at the programs' most frequent rotary setting), each probed (its centre's full
/// deviation: three readings) at every angle of the sweep the rotary axes can reach it at:
/// what a rotary axis' location and wobble show (ISO 10791-6's probed sphere).
void sphere_candidates(const model::ForwardModel& model, const ProgramBox& box, const std::vector<double>& usual,
                       std::vector<Candidate>& out) {
  const model::MachineModel& m = model.machine();
  if (usual.empty()) return;
  const std::vector<std::vector<double>> sweep = sweep_angles(m, box);
  if (sweep.size() < 3) return;
  model::ForwardData fd(model);
  // The probe the readings are taken with (reading_at's tool length) is the one the tip is
  // placed with.
  model::ChainQ middle = box.middle;
  middle[static_cast<Eigen::Index>(model::kToolLengthIndex)] = box.tool_length;
  model::ChainQ low = middle, high = middle;
  for (const std::size_t i : box.linear) {
    const auto e = static_cast<Eigen::Index>(i);
    low[e] = box.low[e] + 0.25 * (box.high[e] - box.low[e]);
    high[e] = box.high[e] - 0.25 * (box.high[e] - box.low[e]);
  }
  for (const model::ChainQ& place : {middle, low, high}) {
    const model::ChainQ at = at_setting(m, place, usual);
    model::forward(model, fd, at, box.conditions.conditions, false, model::Evaluate::nominal);
    const Eigen::Vector3d centre = fd.nominal;
    // Named by where it sits: a later plan's sphere at the same place is the same sphere.
    Candidate sphere{fmt::format("plan-sphere-X{:.0f}-Y{:.0f}-Z{:.0f}", centre.x(), centre.y(), centre.z()),
                     "probed sphere", " (fixed on the table)", {}, {}, false};
    std::size_t reached = 0;
    for (const std::vector<double>& angles : sweep) {
      const std::optional<model::ChainQ> q = reaching(model, fd, box, at_setting(m, at, angles), centre);
      if (!q) continue;
      ++reached;
      for (int c = 0; c < 3; ++c) {
        Observation o = reading_at(box, *q, Eigen::Vector3d::Unit(c));
        for (const model::AxisSpec& a : m.axes)  // the rotary axes turned one way through the sweep
          if (a.type == model::AxisType::rotary) o.directions[a.index()] = 1;
        sphere.readings.push_back(o);
      }
    }
    if (reached >= 3) out.push_back(std::move(sphere));
  }
}

/// Where the data were thin at a candidate's rotary setting: "the data had only sphere (24
/// readings) at B 180" (empty where they were not).
std::string thin_note(const model::MachineModel& m, const std::vector<model::AxisCoverage>& coverage,
                      const std::vector<double>& angles) {
  std::string note;
  std::size_t k = 0;
  for (const model::AxisSpec& a : m.axes) {
    if (a.type != model::AxisType::rotary) continue;
    const double deg = angles[k++] / kRadPerDeg;
    for (const model::AxisCoverage& c : coverage) {
      if (c.axis != a.letter || c.bins.empty()) continue;
      std::size_t fullest = 0;
      for (const model::CoverageBin& b : c.bins) fullest = std::max(fullest, b.total());
      const double turn = deg - 360.0 * std::floor(deg / 360.0);
      for (const model::CoverageBin& b : c.bins) {
        const double v = (c.bins.front().from == 0.0 && c.bins.back().to == 360.0) ? turn : deg;
        if (v < b.from || v >= b.to || !model::is_thin(b, fullest))
          continue;
        std::string what;
        for (const auto& [source, n] : b.readings) what += fmt::format("{}{} ({} readings)", what.empty() ? "" : ", ", source, n);
        note += fmt::format("; the data had {} at {} {:g}-{:g}", what.empty() ? "nothing" : "only " + what, a.letter,
                            b.from, b.to);
      }
    }
  }
  return note;
}

}  // namespace

MeasurementPlan plan_measurements(const model::ForwardModel& model, const MeasurementSet& data,
                                  const std::vector<ProgramPose>& all_poses, const PlanOptions& options) {
  if (all_poses.empty())
    throw Error(ErrorKind::data, "the programs have no cutting move: nothing to plan the measurements for");
  const model::MachineModel& m = model.machine();
  const std::vector<std::size_t> free = free_parameters(model);
  if (free.empty())
    throw Error(ErrorKind::data, fmt::format("model '{}' has no free terms (fit: true): nothing a measurement could "
                                             "narrow",
                                             m.name));
  const auto n = static_cast<Eigen::Index>(free.size());
  const Eigen::VectorXd p = model_parameters(model);
  const Eigen::VectorXd physical_all = physical_scales(model, data);
  Eigen::VectorXd physical(n);
  for (Eigen::Index j = 0; j < n; ++j) physical[j] = physical_all[static_cast<Eigen::Index>(free[static_cast<std::size_t>(j)])];
  // The data so far: their information, with one physical scale as what is known without them.
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  design_matrix(model, p, data, free, r, &J);
  double noise = options.noise;
  if (!(noise > 0)) noise = noise_floor(data, r).value;
  if (!(noise > 0)) noise = 0.0002;
  Eigen::MatrixXd information = physical.asDiagonal() * normal_matrix(J) * physical.asDiagonal() / (noise * noise);
  information += Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd C = information.ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  // The programs' error variance: trace(H C), H summed over their poses.
  const std::vector<ProgramPose> poses = spread(all_poses, options.max_poses);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  {
    model::ForwardData fd(model);
    Eigen::MatrixXd G(3, n);
    for (const ProgramPose& pose : poses) {
      model::forward(model, fd, pose.q, pose.conditions, true);
      for (Eigen::Index j = 0; j < n; ++j)
        G.col(j) = fd.J_parameters.col(static_cast<Eigen::Index>(free[static_cast<std::size_t>(j)])) * physical[j];
      H += G.transpose() * G;
    }
  }
  const auto count = static_cast<double>(poses.size());
  auto uncertainty = [&](const Eigen::MatrixXd& cov) { return std::sqrt(std::max(0.0, (H * cov).trace()) / count); };
  // The candidates, each with its scaled design matrix.
  const ProgramBox box = box_of(m, poses);
  std::vector<Candidate> candidates;
  const std::vector<std::vector<double>> settings = rotary_settings(m, poses);
  for (const std::vector<double>& angles : settings) candidates_at(m, box, angles, candidates);
  if (!settings.empty()) sphere_candidates(model, box, settings.front(), candidates);
  std::map<std::string, std::string> notes;  // by the candidate's place
  const std::vector<model::AxisCoverage> coverage = coverage_of(m, data);
  for (const std::vector<double>& angles : settings) {
    const std::string name = setting_name(m, angles);
    notes[name.empty() ? "" : " at " + name] = thin_note(m, coverage, angles);
  }
  for (Candidate& c : candidates) {
    MeasurementSet set;
    set.sources = {c.source};
    set.observations = c.readings;
    Eigen::VectorXd rc;
    Eigen::MatrixXd Jc;
    design_matrix(model, p, set, free, rc, &Jc);
    c.rows = Jc * physical.asDiagonal() / noise;
  }
  MeasurementPlan plan;
  plan.candidates = candidates.size();
  plan.before = uncertainty(C);
  std::size_t left = options.budget;
  for (;;) {
    double best_score = 0.0, best_gain = 0.0;
    Candidate* best = nullptr;
    for (Candidate& c : candidates) {
      if (c.taken || c.readings.size() > left) continue;
      const Eigen::MatrixXd K = c.rows * C;  // readings x parameters
      const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(K.rows(), K.rows()) + K * c.rows.transpose();
      const double gain = M.ldlt().solve(K * H * K.transpose()).trace();
      const double score = gain / static_cast<double>(c.readings.size());
      if (score > best_score) best_score = score, best_gain = gain, best = &c;
    }
    // A group that takes less than a hundredth of what is left is not worth its readings.
    const double now = (H * C).trace();
    if (!best || best_gain < 0.01 * now) break;
    const Eigen::MatrixXd K = best->rows * C;
    const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(K.rows(), K.rows()) + K * best->rows.transpose();
    const Eigen::MatrixXd next = C - K.transpose() * M.ldlt().solve(K);
    // What it pins down most: the parameters whose share of the programs' variance fell most.
    const Eigen::VectorXd fell = (H * C).diagonal() - (H * next).diagonal();
    std::vector<std::pair<double, Eigen::Index>> order;
    for (Eigen::Index j = 0; j < n; ++j) order.emplace_back(-fell[j], j);
    std::sort(order.begin(), order.end());
    std::string pins;
    for (std::size_t k = 0; k < order.size() && k < 3 && -order[k].first > 0.05 * (now - (H * next).trace()); ++k) {
      const std::size_t index = free[static_cast<std::size_t>(order[k].second)];
      std::size_t t = 0;
      while (t + 1 < m.terms.size() && model.parameter_offset(t + 1) <= index) ++t;
      pins += (pins.empty() ? "" : ", ") + parameter_label(m.terms[t], index - model.parameter_offset(t));
    }
    PlannedGroup g;
    g.source = best->source;
    g.kind = best->kind;
    g.before = uncertainty(C);
    g.after = uncertainty(next);
    g.why = fmt::format("{} {}{} over the programs' reach: their uncertainty {:.3f} -> {:.3f} um (rms over their "
                        "points, {} readings){}{}",
                        g.kind, best->source, best->where, g.before * 1e3, g.after * 1e3, best->readings.size(),
                        pins.empty() ? "" : "; pins down " + pins, notes[best->where]);
    const auto source = static_cast<std::uint32_t>(plan.sources.size());
    plan.sources.push_back(best->source);
    for (Observation o : best->readings) {
      o.source = source;
      g.readings.push_back(o);
    }
    left -= best->readings.size();
    plan.readings += best->readings.size();
    best->taken = true;
    C = next;
    plan.groups.push_back(std::move(g));
  }
  plan.after = uncertainty(C);
  return plan;
}

std::string plan_csv(const MeasurementPlan& plan, const model::MachineModel& model, const ResolvedFrame& frame) {
  std::string out = frame_line(frame) + "\nx,y,z";
  std::vector<std::size_t> rotary;
  for (const model::AxisSpec& a : model.axes)
    if (a.type == model::AxisType::rotary) {
      rotary.push_back(a.index());
      out += fmt::format(",{}", static_cast<char>(std::tolower(a.letter)));
    }
  out += ",L,vx,vy,vz";
  for (const std::size_t i : rotary) out += fmt::format(",v{}", static_cast<char>(std::tolower(kAxisLetters[i])));
  out += ",nx,ny,nz,source\n";
  const bool machine = frame.frame.kind == FrameKind::machine;
  for (const PlannedGroup& g : plan.groups) {
    out += fmt::format("# {}\n", g.why);
    for (const Observation& o : g.readings) {
      const double tool = o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
      out += fmt::format("{:.6f},{:.6f},{:.6f}", o.q[0] - frame.origin[0], o.q[1] - frame.origin[1],
                         o.q[2] - frame.origin[2] - (machine ? 0.0 : tool));
      for (const std::size_t i : rotary)
        out += fmt::format(",{:.6f}", o.q[static_cast<Eigen::Index>(i)] / kRadPerDeg - frame.origin[i]);
      out += fmt::format(",{:.3f}", tool);
      for (std::size_t i = 0; i < 3; ++i) out += fmt::format(",{}", static_cast<int>(o.directions[i]));
      for (const std::size_t i : rotary) out += fmt::format(",{}", static_cast<int>(o.directions[i]));
      out += fmt::format(",{:.9g},{:.9g},{:.9g},{}\n", o.direction.x(), o.direction.y(), o.direction.z(), g.source);
    }
  }
  return out;
}

void read_plan(const std::string& path, const model::MachineModel& model, const ReadOptions& options,
               MeasurementSet& into) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::io, fmt::format("cannot read '{}'", path));
  // The contract's reader, given a `d` of 0 on every row: the rows keep their lines, so an
  // error names the plan's own row and column.
  std::string text, line;
  bool header = false;
  char separator = ',';
  while (std::getline(in, line)) {
    const bool cr = !line.empty() && line.back() == '\r';
    if (cr) line.pop_back();
    const std::size_t start = line.find_first_not_of(" \t");
    const bool content = start != std::string::npos && line[start] != '#';
    if (content && !header) {
      header = true;
      separator = line.find('\t') != std::string::npos ? '\t' : line.find(';') != std::string::npos ? ';' : ',';
      line += std::string(1, separator) + "d";
    } else if (content) {
      line += std::string(1, separator) + "0";
    }
    text += line + (cr ? "\r\n" : "\n");
  }
  parse_measurements(text, path, model, options, into);
}

void measure_on(const model::ForwardModel& truth, MeasurementSet& set, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise > 0 ? noise : 1.0);
  model::ForwardData data(truth);
  for (Observation& o : set.observations) o.value = predict(truth, data, o) + (noise > 0 ? gauss(rng) : 0.0);
}

}  // namespace ccomp::identify
