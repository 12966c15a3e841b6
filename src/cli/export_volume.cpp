// ccomp export --control isg: the model as one volumetric table over X, Y and Z (Beckhoff
// TwinCAT CNC's Volumetric Compensation), with what it leaves over the workspace and which
// terms it cannot hold.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "ccomp/controller/isg_volume.hpp"
#include "ccomp/controller/volume_table.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/conditions.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/version.hpp"
#include "export_parts.hpp"
#include "output_file.hpp"

namespace ccomp::cli {
namespace {

constexpr double kDefaultStep = 25.0;          // mm
constexpr std::size_t kMostNodes = 1'000'000;  // 60 MB of text: beyond it a coarser step serves better
constexpr std::size_t kResidualPoints = 2000;

/// The grid over each of X, Y, Z's travel, at multiples of the step (0 a node where the
/// travel holds it).
std::array<controller::Grid, 3> volume_grids(const model::MachineModel& m, double step) {
  std::array<controller::Grid, 3> grids;
  std::size_t nodes = 1;
  for (std::size_t a = 0; a < 3; ++a) {
    const char letter = "XYZ"[a];
    const model::AxisSpec* spec = m.axis(letter);
    if (spec == nullptr || spec->type != model::AxisType::linear)
      throw Error(ErrorKind::usage, fmt::format("--control isg: a volumetric table needs the linear axes X, Y and Z; "
                                                "the machine '{}' has no linear {}",
                                                m.name, letter));
    if (!std::isfinite(spec->min) || !std::isfinite(spec->max))
      throw Error(ErrorKind::usage, fmt::format("--control isg: the grid spans each axis' travel, and the model gives "
                                                "{} none (min and max under axes: {})",
                                                letter, letter));
    grids[a] = controller::grid_for(spec->min, spec->max, step, static_cast<std::size_t>(-1), step);
    nodes *= grids[a].points();
  }
  if (nodes > kMostNodes)
    throw Error(ErrorKind::usage, fmt::format("--step {:g}: {} nodes; a volumetric table of more than {} is refused: "
                                              "give a larger --step",
                                              step, nodes, kMostNodes));
  return grids;
}

/// A periodic term on X, Y or Z whose highest harmonic is shorter than four steps of the
/// grid: sampled, it would alias; the grid leaves it out (VolumeOptions::left_out).
bool periodic_too_short(const model::ErrorTermSpec& t, const std::array<controller::Grid, 3>& grids) {
  return t.primary.kind == model::VariableKind::axis && t.primary.index <= 2 &&
         t.shape.form == model::TermForm::periodic &&
         std::abs(t.parameters[0]) / std::max(1, t.shape.order) < 4 * grids[t.primary.index].step;
}

/// Other terms whose shape changes within a few of the grid's steps along their axis, which
/// linear interpolation between nodes cuts: a table's knots closer than two steps, a bump
/// narrower than two.
bool cut_by_grid(const model::ErrorTermSpec& t, const std::array<controller::Grid, 3>& grids) {
  if (t.primary.kind != model::VariableKind::axis || t.primary.index > 2) return false;
  const double step = grids[t.primary.index].step;
  if (t.shape.form == model::TermForm::table)
    for (std::size_t k = 1; k < t.shape.knots.size(); ++k)
      if (t.shape.knots[k] - t.shape.knots[k - 1] < 2 * step) return true;
  return t.shape.form == model::TermForm::bump && std::abs(t.parameters[2]) < 2 * step;
}

void add_once(std::vector<std::string>& names, const std::string& name) {
  if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
}

/// The reversal terms: the table holds the mean of both directions of travel.
std::vector<std::string> reversal_terms(const model::MachineModel& m) {
  std::vector<std::string> names;
  for (const model::ErrorTermSpec& t : m.terms)
    if (t.shape.form == model::TermForm::reversal && std::find(names.begin(), names.end(), t.name) == names.end())
      names.push_back(t.name);
  return names;
}

/// The configuration list beside the compensation file: its name with .lis.
std::string list_path(const std::string& output) {
  std::filesystem::path p(output);
  if (p.filename().string().find_first_of(" \t") != std::string::npos)
    throw Error(ErrorKind::usage, "-o " + output +
                                      ": the list names the CSV in a field without spaces: give a name "
                                      "without them");
  if (p.extension() == ".lis")
    throw Error(ErrorKind::usage, "-o " + output + ": that is the configuration list's name; give the CSV's (v.csv)");
  return p.replace_extension(".lis").string();
}

}  // namespace

int run_volume_export(const ExportArgs& args) {
  if (!args.axis.empty())
    throw Error(ErrorKind::usage,
                "--axis " + args.axis + ": the isg table is over X, Y and Z together; leave --axis out");
  if (!std::isnan(args.from) || !std::isnan(args.to))
    throw Error(ErrorKind::usage, "--from, --to: the isg table spans each axis' travel (the model's min and max)");
  if (args.output == "-")
    throw Error(ErrorKind::usage,
                "--control isg writes two files, the compensation CSV and its list: give -o FILE.csv");
  const std::string list = list_path(args.output);
  check_output(args.output, {{"the machine model", args.model}}, "-o");
  check_output(list, {{"the machine model", args.model}}, "the configuration list");
  const model::MachineModel m = model::load_machine_model(args.model);
  for (const std::string& at : args.at)
    if (!at.empty() && std::string_view("XYZxyz").find(at[0]) != std::string_view::npos)
      throw Error(ErrorKind::usage, "--at " + at + ": X, Y and Z span the volumetric table's grid");
  const model::ForwardModel forward(m);
  controller::VolumeOptions o;
  o.grids = volume_grids(m, args.step > 0 ? args.step : kDefaultStep);
  for (std::size_t a = 0; a < 3; ++a)
    o.reference[static_cast<Eigen::Index>(a)] = std::clamp(0.0, o.grids[a].from, o.grids[a].to);
  std::vector<std::string> left_out, cut;
  for (std::size_t t = 0; t < m.terms.size(); ++t) {
    if (periodic_too_short(m.terms[t], o.grids)) o.left_out.push_back(t), add_once(left_out, m.terms[t].name);
    if (cut_by_grid(m.terms[t], o.grids)) add_once(cut, m.terms[t].name);
  }
  o.line = table_line(m, args, '\0', true);
  o.conditions = model::conditions_for(m, model::parse_sensor_readings(args.sensors), args.time);
  const controller::VolumeTable table = controller::sample_volume_table(forward, o);
  const std::vector<std::string> header{
      fmt::format("ccomp {} volumetric export of '{}' (model SHA-256 {})", kVersion, m.name, m.sha256)};
  const controller::IsgVolumeFiles files =
      controller::write_isg_volume(table, std::filesystem::path(args.output).filename().string(), header);
  const controller::VolumeTable applied = controller::isg_as_applied(table);
  const std::vector<model::ChainQ> points = controller::volume_points(applied, o.line, kResidualPoints);
  model::ChainQ reference = o.line;
  reference.head<3>() = o.reference;
  const controller::Residual workspace = controller::corrected_residual(forward, controller::volume_corrector(applied),
                                                                        {0, 1, 2}, points, reference, o.conditions);
  const Uncarried u = uncarried_terms(m, true);
  const std::vector<std::string> reversals = reversal_terms(m);
  write_output(args.output, files.csv);
  write_output(list, files.list);
  if (args.json) {
    util::JsonWriter j;
    j.begin_object().field("command", "export").field("control", "isg");
    j.field("model", m.name).field("model_sha256", m.sha256).field("output", args.output).field("list", list);
    j.key("grid").begin_array();
    for (std::size_t a = 0; a < 3; ++a) {
      j.begin_object().field("axis", std::string(1, "XYZ"[a])).field("from", o.grids[a].from);
      j.field("to", o.grids[a].to).field("step", o.grids[a].step).field("points", o.grids[a].points()).end_object();
    }
    j.end_array();
    j.field("nodes", table.nodes()).field("tool_length_mm", args.tool_length);
    j.key("reference").begin_array().value(o.reference[0]).value(o.reference[1]).value(o.reference[2]).end_array();
    json_residual(j, "workspace", workspace);
    json_names(j, "thermal_terms", u.thermal);
    json_names(j, "rotary_terms", u.rotary);
    json_names(j, "reversal_terms", reversals);
    json_names(j, "left_out_terms", left_out);
    json_names(j, "cut_terms", cut);
    j.end_object();
    fmt::print("{}", j.text());
    return 0;
  }
  std::string at;
  for (const model::AxisSpec& a : m.axes)
    if (a.type == model::AxisType::rotary)
      at += fmt::format(" {}={:g}", a.letter,
                        o.line[static_cast<Eigen::Index>(std::string_view("XYZABCUVW").find(a.letter))] * 180.0 / M_PI);
  fmt::print(stderr, "{} and {}: volumetric table of '{}' for Beckhoff TwinCAT CNC (#VOLCOMP), {} nodes:\n",
             args.output, list, m.name, table.nodes());
  for (std::size_t a = 0; a < 3; ++a)
    fmt::print(stderr, "  {} from {:g} to {:g} mm every {:g} mm ({} points)\n", "XYZ"[a], o.grids[a].from,
               o.grids[a].to, o.grids[a].step, o.grids[a].points());
  fmt::print(stderr, "  for a {:g} mm tool{}{}; 0 at X {:g} Y {:g} Z {:g}, where a work offset takes the error\n",
             args.tool_length, at.empty() ? "" : ", rotary axes at", at, o.reference[0], o.reference[1],
             o.reference[2]);
  fmt::print(stderr, "  {}\n", header.front());
  fmt::print(stderr,
             "  over the workspace ({} points between the nodes, both directions of travel): max {:.2f} -> {:.2f} um, "
             "rms {:.2f} -> {:.2f} um\n",
             workspace.points, workspace.max_before_um, workspace.max_after_um, workspace.rms_before_um,
             workspace.rms_after_um);
  if (!left_out.empty())
    fmt::print(stderr, "  left out (periodic, shorter than four steps: the axis' own pitch table carries them): {}\n",
               joined(left_out));
  if (!cut.empty())
    fmt::print(stderr, "  cut by the grid (features shorter than two steps: a finer --step): {}\n", joined(cut));
  if (!reversals.empty())
    fmt::print(stderr, "  not carried (the table holds the mean of both directions of travel): {}\n",
               joined(reversals));
  if (!u.thermal.empty())
    fmt::print(stderr, "  held at this export's temperatures and time only: {}\n", joined(u.thermal));
  if (!u.rotary.empty()) fmt::print(stderr, "  held at these rotary positions only: {}\n", joined(u.rotary));
  fmt::print(stderr, "  set vol_comp[0].max_records to at least {} in the start-up list\n", table.nodes());
  return 0;
}

}  // namespace ccomp::cli
