// ccomp positioning: ISO 230-2's figures of one axis, as the standard's report lists them
// (each figure up, down and bidirectional; the per-target table), in text and JSON.
#include <fmt/format.h>

#include <cctype>
#include <numbers>
#include <optional>
#include <string>

#include "ccomp/error.hpp"
#include "ccomp/identify/positioning.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/util/json.hpp"
#include "commands.hpp"
#include "identify_json.hpp"

namespace ccomp::cli {
namespace {


/// How the report writes deviations: um on a linear axis, arcsec (or urad) on a rotary one,
/// as ISO 230-2 gives a rotary axis' figures in angle.
struct DeviationUnit {
  std::string name;
  double per_internal = 1e3;  ///< units per mm, or per rad
  std::string position;      ///< mm or deg
};

DeviationUnit unit_for(const identify::PositioningReport& r, const std::string& angle) {
  if (!r.rotary) return {"um", 1e3, "mm"};
  if (angle == "urad") return {"urad", 1e6, "deg"};
  return {"arcsec", identify::kArcsecPerRad, "deg"};
}

std::string cell(const std::optional<double>& v, double scale, int width, const char* missing = "-") {
  return v ? fmt::format("{:>{}.3f}", *v * scale, width) : fmt::format("{:>{}}", missing, width);
}

void print_figures(const identify::PositioningReport& r, const DeviationUnit& u, char letter) {
  const double k = u.per_internal;
  fmt::print("ISO 230-2, axis {} ({}): {} targets from {:g} to {:g} {}; runs {} up, {} down{}; deviations in {}\n",
             letter, r.rotary ? "rotary" : "linear", r.targets.size(), r.targets.front().position,
             r.targets.back().position, u.position, r.runs_up, r.runs_down,
             (r.runs_up > 0 && r.runs_up < 5) || (r.runs_down > 0 && r.runs_down < 5) ? " (the standard asks for 5)" : "",
             u.name);
  constexpr const char* kNot = "not stated";
  fmt::print("  {:<28} {:>11} {:>11} {:>14}\n", "", "up", "down", "bidirectional");
  fmt::print("  {:<28} {} {} {}\n", "accuracy                A", cell(r.A_up, k, 11, kNot), cell(r.A_down, k, 11, kNot),
             cell(r.A, k, 14, kNot));
  fmt::print("  {:<28} {} {} {}\n", "systematic deviation    E", cell(r.E_up, k, 11, kNot),
             cell(r.E_down, k, 11, kNot), cell(r.E, k, 14, kNot));
  fmt::print("  {:<28} {} {} {}\n", "repeatability           R", cell(r.R_up, k, 11, kNot),
             cell(r.R_down, k, 11, kNot), cell(r.R, k, 14, kNot));
  fmt::print("  {:<28} {:>23} {}\n", "mean bidirectional dev. M", "", cell(r.M, k, 14, kNot));
  fmt::print("  {:<28} {:>23} {}", "reversal value          B", "", cell(r.B, k, 14, kNot));
  if (r.B_signed) fmt::print("  (B_i {:+.3f} at {:g} {})", *r.B_signed * k, *r.B_at, u.position);
  fmt::print("\n  {:<28} {:>23} {}\n", "mean reversal value B mean", "",
             r.B_mean ? fmt::format("{:>+14.3f}", *r.B_mean * k) : fmt::format("{:>14}", kNot));
  for (const std::string& why : r.not_stated) fmt::print("  not stated: {}\n", why);
  if (r.one_way_targets > 0 && r.M)
    fmt::print("  {} target(s) approached one way only are outside the bidirectional figures\n", r.one_way_targets);
}

void print_targets(const identify::PositioningReport& r, const DeviationUnit& u) {
  const double k = u.per_internal;
  fmt::print("per target ({}; s the estimator of the standard uncertainty, R up/down = 4s, R_i = max(2s up + 2s down "
             "+ |B_i|, R up, R down); -: not stated):\n",
             u.name);
  fmt::print("  {:>10} {:>7} {:>9} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8}\n", "position", "runs", "mean up",
             "mean dn", "mean", "B_i", "s up", "s dn", "R up", "R dn", "R_i");
  for (const identify::PositioningTarget& t : r.targets)
    fmt::print("  {:>10g} {:>7} {} {} {} {} {} {} {} {} {}\n", t.position, fmt::format("{}/{}", t.runs_up, t.runs_down),
               cell(t.mean_up, k, 9), cell(t.mean_down, k, 9), cell(t.mean, k, 9), cell(t.reversal, k, 9),
               cell(t.s_up, k, 8), cell(t.s_down, k, 8), cell(t.repeatability_up, k, 8),
               cell(t.repeatability_down, k, 8), cell(t.repeatability, k, 8));
}

void print_split(const identify::PositioningReport& r, const DeviationUnit& u) {
  const double k = u.per_internal;
  fmt::print("parts of the {} deviation (docs/error-model.md [Ref 3]): cumulative cubic [{:.4g}, {:.4g}, {:.4g}, {:.4g}] "
             "{}/{}^k",
             r.M ? "mean bidirectional" : "mean", r.cumulative[0] * k, r.cumulative[1] * k, r.cumulative[2] * k,
             r.cumulative[3] * k, u.name, u.position);
  if (r.period > 0) fmt::print("; periodic {:.4g} {}, {:.3f} {}", r.period, u.position, r.periodic_amplitude * k, u.name);
  if (r.B_mean) fmt::print("; reversal {:+.3f} {}", *r.B_mean * k, u.name);
  fmt::print("; {:.3f} {} left\n", r.rms_left * k, u.name);
  if (!r.split_caveat.empty()) fmt::print("  caveat: {}\n", r.split_caveat);
}

std::size_t axis_index(const std::string& axis) {
  const std::size_t i = std::string_view("xyzabc").find(static_cast<char>(std::tolower(axis.at(0))));
  if (axis.size() != 1 || i == std::string_view::npos)
    throw Error(ErrorKind::usage, fmt::format("--axis {}: not x, y, z, a, b or c", axis));
  return i;
}

/// What the files and the options state of the test: ISO 230-2's report gives the
/// instrument, the temperatures and the uncertainty of measurement beside the figures.
identify::StatedConditions stated_of(const identify::MeasurementSet& data, const IdentifyArgs& args) {
  std::vector<identify::StatedField> fields = data.stated;
  if (!args.instrument.empty()) fields.push_back({"Instrument", args.instrument, "--instrument"});
  if (!args.uncertainty.empty()) fields.push_back({"Uncertainty", args.uncertainty, "--uncertainty"});
  for (const std::string& t : args.temperatures) fields.push_back(identify::temperature_option(t));
  return identify::sort_stated(fields);
}

constexpr std::string_view kNotStated = "not stated";

void print_stated(const identify::StatedConditions& s) {
  fmt::print("the test as stated (the report gives these beside the figures):\n");
  fmt::print("  instrument     {}\n", s.instrument ? s.instrument->value : std::string(kNotStated) + " (--instrument)");
  if (s.temperatures.empty()) fmt::print("  temperatures   {} (--temperature air=20.3, repeatable)\n", kNotStated);
  for (const auto& t : s.temperatures) fmt::print("  temperature    {}: {:.2f} degC\n", t.name, t.degc);
  fmt::print("  uncertainty    {}\n",
             s.uncertainty ? s.uncertainty->value
                           : std::string(kNotStated) + " (--uncertainty \"U = 1.2 um, k = 2, ISO 230-9\")");
  for (const identify::StatedField& f : s.others) fmt::print("  {}: {}\n", f.key, f.value);
}

void write_stated(util::JsonWriter& j, const identify::StatedConditions& s) {
  j.key("stated").begin_object();
  const auto text = [&](std::string_view name, const std::optional<identify::StatedField>& f) {
    if (f)
      j.field(name, f->value);
    else
      j.key(name).null();
  };
  text("instrument", s.instrument);
  text("uncertainty", s.uncertainty);
  j.key("temperatures").begin_array();
  for (const auto& t : s.temperatures) j.begin_object().field("name", t.name).field("degC", t.degc).field("source", t.source).end_object();
  j.end_array().key("others").begin_array();
  for (const identify::StatedField& f : s.others)
    j.begin_object().field("key", f.key).field("value", f.value).field("source", f.source).end_object();
  j.end_array().end_object();
}

}  // namespace

std::string positioning_json(const std::string& axis, const identify::PositioningReport& r,
                             const std::string& angle, const identify::StatedConditions& stated) {
  const DeviationUnit u = unit_for(r, angle);
  const double k = u.per_internal;
  util::JsonWriter j;
  const auto figure = [&](std::string_view name, const std::optional<double>& v) {
    if (v)
      j.field(name, *v * k);
    else
      j.key(name).null();
  };
  j.begin_object().field("command", "positioning").field("axis", axis).field("rotary", r.rotary);
  j.field("position_unit", u.position).field("deviation_unit", u.name);
  j.field("runs_up", r.runs_up).field("runs_down", r.runs_down).field("one_way_targets", r.one_way_targets);
  figure("A_up", r.A_up), figure("A_down", r.A_down), figure("A", r.A);
  figure("E_up", r.E_up), figure("E_down", r.E_down), figure("E", r.E);
  figure("R_up", r.R_up), figure("R_down", r.R_down), figure("R", r.R);
  figure("M", r.M), figure("B", r.B), figure("B_signed", r.B_signed), figure("B_mean", r.B_mean);
  if (r.B_at)
    j.field("B_at", *r.B_at);
  else
    j.key("B_at").null();
  j.key("not_stated").begin_array();
  for (const std::string& why : r.not_stated) j.value(why);
  j.end_array().key("cumulative").begin_array();
  for (double c : r.cumulative) j.value(c * k);
  j.end_array().field("period", r.period).field("periodic_amplitude", r.periodic_amplitude * k);
  j.field("rms_left", r.rms_left * k);
  if (r.split_caveat.empty())
    j.key("split_caveat").null();
  else
    j.field("split_caveat", r.split_caveat);
  j.key("targets").begin_array();
  for (const identify::PositioningTarget& t : r.targets) {
    j.begin_object().field("position", t.position).field("runs_up", t.runs_up).field("runs_down", t.runs_down);
    figure("mean_up", t.mean_up), figure("mean_down", t.mean_down), figure("mean", t.mean);
    figure("reversal", t.reversal), figure("s_up", t.s_up), figure("s_down", t.s_down);
    figure("R_up", t.repeatability_up), figure("R_down", t.repeatability_down), figure("R", t.repeatability);
    j.end_object();
  }
  j.end_array();
  write_stated(j, stated);
  return j.end_object().text();
}

CLI::App* add_positioning(CLI::App& app, IdentifyArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "positioning", "ISO 230-2 positioning figures of a linear or rotary axis, up, down and bidirectional");
  cmd->add_option("measurements", args.measurements,
                  "measurement files (the CSV contract, or an instrument's: docs/identification.md)")
      ->required();
  cmd->add_option("-m,--model", args.model, "machine model (YAML)")->required();
  cmd->add_option("--tool-length", args.tool_length, "mm: tool or optic length of rows without an L column (100)");
  add_frame_options(*cmd, args);
  cmd->add_option("--axis", args.axis, "x, y, z, or a rotary axis a, b, c")
      ->required()
      ->check(CLI::IsMember({"x", "y", "z", "a", "b", "c", "X", "Y", "Z", "A", "B", "C"}));
  cmd->add_option("--source", args.source, "only the rows of this source (a laser line)");
  cmd->add_option("--angle-unit", args.angle_unit, "a rotary axis' deviations in arcsec (default) or urad")
      ->check(CLI::IsMember({"arcsec", "urad"}));
  cmd->add_flag("--json", args.json, "the figures as JSON on stdout");
  cmd->add_option("--instrument", args.instrument, "the instrument, for the report (over what the files state)");
  cmd->add_option("--temperature", args.temperatures,
                  "NAME=DEGC: a temperature during the test, for the report (air, material, machine; repeatable)");
  cmd->add_option("--uncertainty", args.uncertainty,
                  "the uncertainty of measurement, for the report (\"U = 1.2 um, k = 2, ISO 230-9\")");
  add_reading_options(*cmd, args, false);  // its --axis names a one-axis file's axis too
  return cmd;
}

int run_positioning(const IdentifyArgs& args) {
  const model::MachineModel m = model::load_machine_model(args.model);
  identify::MeasurementSet data;
  identify::ReadOptions o = reading_options(args);
  o.frame = frame_of(args);
  for (const std::string& path : args.measurements) identify::read_measurements(path, m, o, data);
  for (const std::string& notice : data.notices) fmt::print(stderr, "notice: {}\n", notice);
  const std::size_t axis = axis_index(args.axis);
  const char letter = kAxisLetters[axis];
  if (!m.axis(letter))
    throw Error(ErrorKind::usage, fmt::format("--axis {}: machine '{}' has no axis {}", args.axis, m.name, letter));
  const model::ForwardModel forward(m);
  const identify::StatedConditions stated = stated_of(data, args);
  const identify::PositioningReport r = identify::analyse_positioning(data, axis, args.source, &forward);
  if (args.json) {
    fmt::print("{}", positioning_json(std::string(1, static_cast<char>(std::tolower(letter))), r, args.angle_unit,
                                      stated));
    return 0;
  }
  const DeviationUnit u = unit_for(r, args.angle_unit);
  print_figures(r, u, letter);
  print_targets(r, u);
  print_split(r, u);
  print_stated(stated);
  return 0;
}

}  // namespace ccomp::cli
