#include "ccomp/identify/axis_runs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/identify/measurement_formats.hpp"
#include "ccomp/model/forward.hpp"
#include "io/text_fields.hpp"

namespace ccomp::identify {
namespace {

constexpr double kRadPerArcsec = kRadPerDeg / 3600.0;

// The plausibility of deviations read in the contract's units (mm, deg) where the file states
// none. A machine axis' positioning error grows along its travel at most as a screw of the
// worst accuracy class does (ISO 3408-3 class 10: 210 um over 300 mm, 0.7 mm/m; a scale
// glued on without compensation a few tenths more): 1 mm per metre of the travel measured. On
// top, what does not grow with the travel: the reversal of a worn drive and the scatter of
// repeated approaches, some 20 um at most on a machine that is still used. A rotary axis'
// indexing error is within some 60 arcsec on a worm-driven table (a worn one 120): 180 arcsec,
// 0.05 deg. um written where mm is due puts 1000 times the numbers in the file: a 0.1 um
// stage's errors then read as 90 um over 25 mm (3.6 mm/m), and a 20 um one's as 20 mm.
constexpr double kLargestSlope = 1e-3;       // mm per mm of travel
constexpr double kLargestReversal = 0.020;   // mm: reversal and repeatability
constexpr double kLargestIndexing = 0.05;    // deg

bool is_length(Unit u) { return u == Unit::mm || u == Unit::um || u == Unit::nm || u == Unit::inch; }

/// mm (lengths) or rad (angles) per unit.
double scale_of(Unit u) {
  switch (u) {
    case Unit::mm: return 1.0;
    case Unit::um: return 1e-3;
    case Unit::nm: return 1e-6;
    case Unit::inch: return 25.4;
    case Unit::deg: return kRadPerDeg;
    case Unit::arcsec: return kRadPerArcsec;
    case Unit::urad: return 1e-6;
  }
  return 1.0;
}

double median_abs(const std::vector<AxisReading>& readings) {
  std::vector<double> sizes;
  sizes.reserve(readings.size());
  for (const AxisReading& r : readings) sizes.push_back(std::abs(r.deviation));
  std::nth_element(sizes.begin(), sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2), sizes.end());
  return sizes[sizes.size() / 2];
}

/// The deviations' unit: the file's, else the option's, else none (nullopt).
std::optional<Unit> deviation_unit(const AxisRuns& runs, const std::string& name, const ReadOptions& options) {
  if (options.unit.empty()) return runs.deviation_unit;
  const std::optional<Unit> given = parse_unit(options.unit);
  if (!given) throw Error(ErrorKind::usage, fmt::format("--unit {}: not a unit (mm, um, nm, inch, deg, arcsec, urad)", options.unit));
  if (runs.deviation_unit && *runs.deviation_unit != *given)
    throw Error(ErrorKind::usage, fmt::format("{}: the file states its deviations in {}, and --unit says {}", name,
                                              unit_name(*runs.deviation_unit), unit_name(*given)));
  return given;
}

/// Refuses deviations that cannot be the contract's unit, which a file without one is read in.
void check_plausible(const AxisRuns& runs, const std::string& name, bool rotary, double target_scale) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, t_lo = lo, t_hi = -lo;
  const AxisReading* largest = &runs.readings.front();
  for (const AxisReading& r : runs.readings) {
    lo = std::min(lo, r.deviation), hi = std::max(hi, r.deviation);
    t_lo = std::min(t_lo, r.target), t_hi = std::max(t_hi, r.target);
    if (std::abs(r.deviation) > std::abs(largest->deviation)) largest = &r;
  }
  const double span = hi - lo;
  if (rotary) {
    if (span <= kLargestIndexing) return;
    throw Error(ErrorKind::data,
                fmt::format("no unit stated, and read as degrees the deviations span {:.4g} deg ({:.4g} arcsec), "
                            "beyond any rotary axis' indexing error (at most {} deg): written in arcsec? State the "
                            "unit: a line 'unit: arcsec', the header 'deviation [arcsec]', or --unit arcsec",
                            span, span * 3600.0, kLargestIndexing),
                SourceLocation{name, largest->line, 1});
  }
  const double travel = (t_hi - t_lo) * target_scale;
  const double limit = kLargestSlope * travel + kLargestReversal;
  if (span <= limit) return;
  throw Error(ErrorKind::data,
              fmt::format("no unit stated, and read as mm the deviations span {:.4g} um over {:.4g} mm of travel: "
                          "beyond any machine axis (at most 1 mm/m of the travel and 20 um of reversal and "
                          "repeatability, {:.4g} um here): written in um? State the unit: a line 'unit: um', the "
                          "header 'deviation [um]', or --unit um",
                          span * 1e3, travel, limit * 1e3),
              SourceLocation{name, largest->line, 1});
}

/// The program point the readings are taken at, the measured axis aside: the --at values,
/// and for a rotary axis without any, a point 100 mm from its line.
model::ChainQ base_point(const model::MachineModel& model, const ReadOptions& options, std::size_t measured,
                         bool rotary) {
  model::ChainQ q = model::ChainQ::Zero();
  for (const AxisPosition& p : options.at) {
    const std::size_t i = kAxisLetters.find(p.axis);
    if (i == std::string_view::npos || !model.axis(p.axis))
      throw Error(ErrorKind::usage, fmt::format("--at {}={:g}: machine '{}' has no axis {}", p.axis, p.value,
                                                model.name, p.axis));
    if (i == measured)
      throw Error(ErrorKind::usage, fmt::format("--at {}: that is the axis the file measures", p.axis));
    const bool at_rotary = model.axis(p.axis)->type == model::AxisType::rotary;
    q[static_cast<Eigen::Index>(i)] = at_rotary ? p.value * kRadPerDeg : p.value;
  }
  if (rotary && options.at.empty()) q[measured == 3 ? 1 : 0] = 100.0;  // A turns about X: off it along Y
  return q;
}

/// What the model needs that a one-axis file cannot give.
void check_conditions(const model::MachineModel& model, const std::string& name) {
  for (const model::ErrorTermSpec& t : model.terms)
    for (const model::Variable* v : {&t.primary, &t.secondary}) {
      if (v->kind == model::VariableKind::time)
        throw Error(ErrorKind::data, fmt::format("{}: term {} depends on the time, which a one-axis file does not "
                                                 "give: convert it with 'ccomp import' and add a 't' column",
                                                 name, t.name));
      if (v->kind == model::VariableKind::temperature)
        throw Error(ErrorKind::data,
                    fmt::format("{}: term {} depends on sensor '{}', which a one-axis file does not give: convert "
                                "it with 'ccomp import' and add a 'T_{}' column",
                                name, t.name, model.sensors[v->index], model.sensors[v->index]));
    }
}

/// What a one-axis file became, for the user to see: the axis, the runs, the units, the
/// approaches worked out and the point the readings are placed at.
std::string conversion_summary(const AxisRuns& runs, const std::vector<AxisReading>& readings, const std::string& name,
                               char axis, const model::ChainQ& base, const model::MachineModel& model,
                               std::optional<Unit> stated, bool rotary) {
  std::vector<int> run_numbers;
  std::size_t worked_out = 0, unknown = 0;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    if (std::find(run_numbers.begin(), run_numbers.end(), readings[i].run) == run_numbers.end())
      run_numbers.push_back(readings[i].run);
    worked_out += runs.readings[i].approach == 0 && readings[i].approach != 0;
    unknown += readings[i].approach == 0;
  }
  std::string at;
  for (const model::AxisSpec& a : model.axes) {
    const std::size_t i = a.index();
    if (a.letter == axis) continue;
    const double v = base[static_cast<Eigen::Index>(i)];
    at += fmt::format(" {}={:g}", static_cast<char>(std::tolower(a.letter)),
                      a.type == model::AxisType::rotary ? v / kRadPerDeg : v);
  }
  return fmt::format("{}: axis {}, {} readings in {} run(s); deviations in {}{}; {} approaches worked out from the run "
                     "order{}; placed at{}",
                     name, axis, readings.size(), run_numbers.size(),
                     unit_name(stated.value_or(rotary ? Unit::deg : Unit::mm)), stated ? "" : " (assumed)", worked_out,
                     unknown ? fmt::format(", {} unknown", unknown) : "", at);
}

}  // namespace

std::optional<Unit> parse_unit(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '[' || text.front() == '(')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == ']' || text.back() == ')')) text.remove_suffix(1);
  static const std::map<std::string, Unit, std::less<>> names{
      {"mm", Unit::mm},         {"millimetre", Unit::mm}, {"millimeter", Unit::mm}, {"um", Unit::um},
      {"\xC2\xB5m", Unit::um},  {"\xCE\xBCm", Unit::um},  {"micron", Unit::um},     {"microns", Unit::um},
      {"micrometre", Unit::um}, {"micrometer", Unit::um}, {"nm", Unit::nm},         {"in", Unit::inch},
      {"inch", Unit::inch},     {"inches", Unit::inch},   {"deg", Unit::deg},       {"degree", Unit::deg},
      {"degrees", Unit::deg},   {"\xC2\xB0", Unit::deg},  {"arcsec", Unit::arcsec}, {"arc-sec", Unit::arcsec},
      {"arcseconds", Unit::arcsec}, {"sec", Unit::arcsec}, {"\"", Unit::arcsec},   {"urad", Unit::urad},
      {"\xC2\xB5rad", Unit::urad}, {"\xCE\xBCrad", Unit::urad}, {"microradian", Unit::urad}};
  const auto it = names.find(io::lower(text));
  if (it == names.end()) return std::nullopt;
  return it->second;
}

std::string_view unit_name(Unit unit) {
  switch (unit) {
    case Unit::mm: return "mm";
    case Unit::um: return "um";
    case Unit::nm: return "nm";
    case Unit::inch: return "inch";
    case Unit::deg: return "deg";
    case Unit::arcsec: return "arcsec";
    case Unit::urad: return "urad";
  }
  return "?";
}

void approach_from_run_order(std::vector<AxisReading>& readings) {
  const std::size_t n = readings.size();
  auto same_run = [&](std::size_t a, std::size_t b) { return readings[a].run == readings[b].run; };
  std::vector<double> steps;
  for (std::size_t i = 1; i < n; ++i)
    if (same_run(i - 1, i) && readings[i].target != readings[i - 1].target)
      steps.push_back(std::abs(readings[i].target - readings[i - 1].target));
  if (steps.empty()) return;
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
  const double step = steps[steps.size() / 2];
  // The sign of the move from reading a to b when it is a step of a pass (0 otherwise: another
  // run, the same target, or a return over other targets, ISO 230-2's targets being spaced
  // irregularly by a fraction of the step).
  auto pass = [&](std::size_t a, std::size_t b) {
    const double move = readings[b].target - readings[a].target;
    if (!same_run(a, b) || move == 0.0 || std::abs(move) > 1.5 * step) return 0;
    return move > 0.0 ? 1 : -1;
  };
  for (std::size_t i = 0; i < n; ++i) {
    AxisReading& r = readings[i];
    if (r.approach != 0) continue;
    if (i > 0) r.approach = pass(i - 1, i);
    if (r.approach == 0 && i + 1 < n) r.approach = pass(i, i + 1);
    if (r.approach == 0 && i > 0 && same_run(i - 1, i) && readings[i - 1].target == r.target)
      r.approach = readings[i - 1].approach;  // read again where the run ended
  }
}

void append_axis_runs(const AxisRuns& runs, const std::string& name, const model::MachineModel& model,
                      const ReadOptions& options, MeasurementSet& into) {
  if (options.axis && runs.axis && options.axis != runs.axis)
    throw Error(ErrorKind::usage,
                fmt::format("{}: the file measures axis {}, and --axis says {}", name, runs.axis, options.axis));
  const char axis = options.axis ? options.axis : runs.axis;
  if (!axis)
    throw Error(ErrorKind::usage,
                fmt::format("{}: the file does not say which axis it measures: give --axis (X, Y, Z or a rotary axis)",
                            name));
  const std::uint32_t first_line = runs.readings.empty() ? 0 : runs.readings.front().line;
  if (runs.readings.empty())
    throw Error(ErrorKind::data, "no readings: there is nothing to compare the model with", SourceLocation{name, 0, 0});
  const model::AxisSpec* spec = model.axis(axis);
  const std::size_t index = kAxisLetters.find(axis);
  if (!spec || index == std::string_view::npos)
    throw Error(ErrorKind::data, fmt::format("the file measures axis {}, which machine '{}' does not have", axis, model.name),
                SourceLocation{name, first_line, 1});
  if (index >= 6)
    throw Error(ErrorKind::data, fmt::format("axis {}: a parallel axis' runs are not read from one-axis files", axis),
                SourceLocation{name, first_line, 1});
  check_conditions(model, name);
  const bool rotary = spec->type == model::AxisType::rotary;
  const auto unit_error = [&](std::string_view what, Unit u) {
    return Error(ErrorKind::data,
                 fmt::format("{} in {} on {} axis {}", what, unit_name(u), rotary ? "rotary" : "linear", axis),
                 SourceLocation{name, runs.unit_line, 1});
  };
  // Targets in mm (inch converted) or deg; deviations to mm or rad.
  const Unit target_unit = runs.target_unit.value_or(rotary ? Unit::deg : Unit::mm);
  if (rotary ? target_unit != Unit::deg : !(target_unit == Unit::mm || target_unit == Unit::inch))
    throw unit_error("targets", target_unit);
  const double target_scale = rotary ? 1.0 : scale_of(target_unit);
  const std::optional<Unit> stated = deviation_unit(runs, name, options);
  if (stated && is_length(*stated) == rotary) throw unit_error("deviations", *stated);
  if (!stated) {
    check_plausible(runs, name, rotary, target_scale);
    into.notices.push_back(fmt::format("{}: no unit stated: deviations read as {} (plausible as such; state the "
                                       "unit to be sure)",
                                       name, rotary ? "deg" : "mm"));
  }
  const double deviation_scale = scale_of(stated.value_or(rotary ? Unit::deg : Unit::mm));
  if (!rotary && median_abs(runs.readings) * deviation_scale > model.max_correction)
    throw Error(ErrorKind::data,
                fmt::format("the deviations' median size is {:.6g} mm, beyond the model's max_correction of {:.6g} mm: "
                            "is the unit the file states right?",
                            median_abs(runs.readings) * deviation_scale, model.max_correction),
                SourceLocation{name, first_line, 1});

  std::vector<AxisReading> readings = runs.readings;
  approach_from_run_order(readings);
  const model::ChainQ base = base_point(model, options, index, rotary);
  std::optional<model::ForwardModel> forward;  // a rotary axis' readings are placed through the kinematics
  std::optional<model::ForwardData> data;
  if (rotary) forward.emplace(model), data.emplace(*forward);

  // The --at point and the targets are program coordinates, placed in the machine as the
  // contract's rows are: in the file's own '# frame:', else the options', else the model's.
  const ResolvedFrame frame = resolve_frame(runs.frame, options.frame, model, name);
  const std::size_t first_observation = into.observations.size();
  const auto file_index = static_cast<std::uint32_t>(into.files.size());
  into.files.push_back(name);
  into.stated.insert(into.stated.end(), runs.stated.begin(), runs.stated.end());
  if (into.sensors.empty()) into.sensors = model.sensors;
  // The file's name without folder and extension: a laser line saved as x-line1.rtl is source x-line1.
  const std::string label = options.source.empty() ? std::filesystem::path(name).stem().string() : options.source;
  auto source = std::find(into.sources.begin(), into.sources.end(), label);
  if (source == into.sources.end()) source = into.sources.insert(into.sources.end(), label);
  Observation o;
  o.file = file_index;
  o.source = static_cast<std::uint32_t>(source - into.sources.begin());
  o.temperatures.assign(into.sensors.size(), std::nan(""));
  const double tool = options.tool_length;
  for (const AxisReading& r : readings) {
    o.q = base;
    o.q[static_cast<Eigen::Index>(index)] = r.target * (rotary ? kRadPerDeg : target_scale);
    o.q[2] += tool;  // program coordinates carry the tool length, as in the contract
    o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)] = tool;
    o.directions = {};
    o.directions[index] = static_cast<std::int8_t>(r.approach);
    o.row = r.line;
    if (!rotary) {
      o.direction = Eigen::Vector3d::Unit(static_cast<Eigen::Index>(index));
      o.value = r.deviation * deviation_scale;
    } else {
      // The table turned by e beyond its target moves the point, relative to the tool, as the
      // axis turning by e would: along d(point)/d(angle), by e times its length (mm/rad).
      model::ChainQ machine = o.q;
      io::to_machine(machine, frame);
      model::forward(*forward, *data, machine, MeasurementSet::conditions(o), true);
      const Eigen::Vector3d along = data->nominal_chain.oMp.R * data->J_q.col(static_cast<Eigen::Index>(index));
      if (along.norm() < 1.0)
        throw Error(ErrorKind::usage,
                    fmt::format("{}: the point the readings are placed at is {:.3g} mm from axis {}'s line: give a "
                                "point off it with --at (a rotary reading is taken as the table's turn at a radius)",
                                name, along.norm(), axis));
      o.direction = along.normalized();
      o.value = r.deviation * deviation_scale * along.norm();
    }
    into.observations.push_back(o);
  }
  into.notices.push_back(conversion_summary(runs, readings, name, axis, base, model, stated, rotary));
  io::place_in_machine(into, first_observation, frame, model, name);
}

}  // namespace ccomp::identify
