// ccomp export --control isg: the model as one volumetric table over X, Y and Z (Beckhoff
// TwinCAT CNC's Volumetric Compensation), with what it leaves over the workspace and which
// terms it cannot hold.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "ccomp/axis.hpp"
#include "ccomp/controller/isg_volume.hpp"
#include "ccomp/controller/table_checks.hpp"
#include "ccomp/controller/volume_table.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/conditions.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/version.hpp"
#include "export_parts.hpp"
#include "output_file.hpp"

namespace ccomp::cli {
namespace {

constexpr double kDefaultStep = 25.0;  // mm
constexpr double kMostNodes = 1e6;     // 60 MB of text: beyond it a coarser step serves better
constexpr std::size_t kResidualPoints = 2000;

/// The grid over each of X, Y, Z's travel, at multiples of the step (0 a node where the
/// travel holds it): its ends lie beyond the travel by less than a step.
std::array<controller::Grid, 3> volume_grids(const model::MachineModel& m, double step) {
  std::array<controller::Grid, 3> grids;
  double nodes = 1;  // in floating point: a tiny step must not wrap the count
  for (std::size_t a = 0; a < 3; ++a) {
    const char letter = "XYZ"[a];
    const model::AxisSpec* spec = m.axis(letter);
    if (spec != nullptr && (!std::isfinite(spec->min) || !std::isfinite(spec->max)))
      throw Error(ErrorKind::usage, fmt::format("--control isg: the grid spans each axis' travel, and the model gives "
                                                "{} none (min and max under axes: {})",
                                                letter, letter));
    // (a machine without linear X, Y or Z is refused by the sampling, with the reason)
    grids[a] = spec == nullptr ? controller::Grid{0, 0, step}
                               : controller::grid_for(spec->min, spec->max, step, static_cast<std::size_t>(-1), step);
    nodes *= (grids[a].to - grids[a].from) / step + 1;
  }
  if (nodes > kMostNodes)
    throw Error(ErrorKind::usage, fmt::format("--step {:g}: {:.3g} nodes; a volumetric table of more than {:g} is "
                                              "refused: give a larger --step",
                                              step, nodes, kMostNodes));
  return grids;
}

void add_once(std::vector<std::string>& names, const std::string& name) {
  if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
}

/// A periodic term on X, Y or Z with harmonics shorter than four steps of the grid: the
/// first of them (sampled, they would alias), or none.
std::optional<controller::VolumeOptions::LeftOut> short_harmonics(const model::MachineModel& m, std::size_t term,
                                                                  const std::array<controller::Grid, 3>& grids) {
  const model::ErrorTermSpec& t = m.terms[term];
  if (t.primary.kind != model::VariableKind::axis || t.primary.index > 2 || t.shape.form != model::TermForm::periodic)
    return std::nullopt;
  // The same bound as every export's (controller/table_checks.hpp); here the harmonics are
  // left out of the table rather than sampled into it.
  const std::optional<int> first =
      controller::first_short_harmonic(t.parameters[0], t.shape.order, grids[t.primary.index].step);
  if (!first) return std::nullopt;
  return controller::VolumeOptions::LeftOut{term, *first};
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

/// What the grid holds only in part, by term name.
struct Partial {
  std::vector<std::string> left_out, cut, reversals;
};

/// The configuration list beside the compensation file: its name with .lis.
std::string list_path(const std::string& output) {
  std::filesystem::path p(output);
  if (p.filename().string().find_first_of(" \t") != std::string::npos)
    throw Error(ErrorKind::usage,
                "-o " + output + ": the list names the CSV in a field without spaces: give a name without them");
  std::string extension = p.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".lis")
    throw Error(ErrorKind::usage, "-o " + output + ": that is the configuration list's name; give the CSV's (v.csv)");
  return p.replace_extension(".lis").string();
}

void check_arguments(const ExportArgs& args) {
  if (!args.axis.empty())
    throw Error(ErrorKind::usage,
                "--axis " + args.axis + ": the isg table is over X, Y and Z together; leave --axis out");
  if (!std::isnan(args.from) || !std::isnan(args.to))
    throw Error(ErrorKind::usage, "--from, --to: the isg table spans each axis' travel (the model's min and max)");
  if (args.output == "-")
    throw Error(ErrorKind::usage,
                "--control isg writes two files, the compensation CSV and its list: give -o FILE.csv");
  for (const std::string& at : args.at)
    if (!at.empty() && std::string_view("XYZxyz").find(at[0]) != std::string_view::npos)
      throw Error(ErrorKind::usage, "--at " + at + ": X, Y and Z span the volumetric table's grid");
}

controller::VolumeOptions volume_options(const model::MachineModel& m, const ExportArgs& args, Partial& partial) {
  controller::VolumeOptions o;
  o.grids = volume_grids(m, args.step > 0 ? args.step : kDefaultStep);
  for (std::size_t a = 0; a < 3; ++a)
    o.reference[static_cast<Eigen::Index>(a)] = std::clamp(0.0, o.grids[a].from, o.grids[a].to);
  for (std::size_t t = 0; t < m.terms.size(); ++t) {
    if (const auto l = short_harmonics(m, t, o.grids)) {
      o.left_out.push_back(*l);
      add_once(partial.left_out, m.terms[t].name);
    }
    if (cut_by_grid(m.terms[t], o.grids)) add_once(partial.cut, m.terms[t].name);
    // Any form in an approach is linear in it: at the node, its value at 0 is the mean of both.
    if (m.terms[t].primary.kind == model::VariableKind::direction) add_once(partial.reversals, m.terms[t].name);
  }
  o.line = table_line(m, args, '\0', true);
  o.conditions = model::conditions_for(m, model::parse_sensor_readings(args.sensors), args.time);
  return o;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Both files through temporaries, committed together once both are written; a list that
/// exists with other content (edited for the machine's axis numbers or path) is kept.
/// Whether the list was written.
bool write_files(const std::string& csv_path, const std::string& list_path, const controller::IsgVolumeFiles& files) {
  const bool keep_list = std::filesystem::exists(list_path) && read_text(list_path) != files.list;
  OutputFile csv(csv_path);
  std::fwrite(files.csv.data(), 1, files.csv.size(), csv.file());
  std::optional<OutputFile> list;
  if (!keep_list) {
    list.emplace(list_path);
    std::fwrite(files.list.data(), 1, files.list.size(), list->file());
  }
  csv.commit();
  if (list) list->commit();
  return !keep_list;
}

struct Summary {
  const model::MachineModel& m;
  const ExportArgs& args;
  const controller::VolumeOptions& o;
  const controller::VolumeTable& table;
  const controller::Residual& workspace;
  const Partial& partial;
  const Uncarried& uncarried;
  std::string list, header;
  bool list_written = true;
};

void print_json(const Summary& s) {
  util::JsonWriter j;
  j.begin_object().field("command", "export").field("control", "isg");
  j.field("model", s.m.name).field("model_sha256", s.m.sha256).field("output", s.args.output).field("list", s.list);
  j.key("grid").begin_array();
  for (std::size_t a = 0; a < 3; ++a) {
    const controller::Grid& g = s.o.grids[a];
    j.begin_object().field("axis", std::string(1, "XYZ"[a])).field("from", g.from).field("to", g.to);
    j.field("step", g.step).field("points", g.points()).end_object();
  }
  j.end_array();
  j.field("nodes", s.table.nodes()).field("tool_length_mm", s.args.tool_length);
  j.key("reference").begin_array().value(s.o.reference[0]).value(s.o.reference[1]).value(s.o.reference[2]).end_array();
  json_residual(j, "workspace", s.workspace);
  json_names(j, "thermal_terms", s.uncarried.thermal);
  json_names(j, "rotary_terms", s.uncarried.rotary);
  json_names(j, "reversal_terms", s.partial.reversals);
  json_names(j, "left_out_terms", s.partial.left_out);
  json_names(j, "cut_terms", s.partial.cut);
  json_names(j, "warnings", controller::worse_than_none(s.workspace, "over the workspace"));
  j.end_object();
  fmt::print("{}", j.text());
}

void print_text(const Summary& s) {
  std::string at;
  for (const model::AxisSpec& a : s.m.axes)
    if (a.type == model::AxisType::rotary)
      at += fmt::format(" {}={:g}", a.letter,
                        s.o.line[static_cast<Eigen::Index>(a.index())] * 180.0 / M_PI);
  fmt::print(stderr, "{} and {}: volumetric table of '{}' for Beckhoff TwinCAT CNC (#VOLCOMP), {} nodes:\n",
             s.args.output, s.list, s.m.name, s.table.nodes());
  for (std::size_t a = 0; a < 3; ++a)
    fmt::print(stderr, "  {} from {:g} to {:g} mm every {:g} mm ({} points)\n", "XYZ"[a], s.o.grids[a].from,
               s.o.grids[a].to, s.o.grids[a].step, s.o.grids[a].points());
  fmt::print(stderr, "  for a {:g} mm tool{}{}; 0 at X {:g} Y {:g} Z {:g}, where a work offset takes the error\n",
             s.args.tool_length, at.empty() ? "" : ", rotary axes at", at, s.o.reference[0], s.o.reference[1],
             s.o.reference[2]);
  fmt::print(stderr, "  {}\n", s.header);
  if (!s.list_written)
    fmt::print(stderr,
               "  kept {}, which differs from what this export writes (edited for the machine?): check that "
               "it names {}\n",
               s.list, std::filesystem::path(s.args.output).filename().string());
  const controller::Residual& w = s.workspace;
  fmt::print(stderr,
             "  over the workspace ({} points between the nodes, both directions of travel): max {:.2f} -> {:.2f} um, "
             "rms {:.2f} -> {:.2f} um\n",
             w.points, w.max_before_um, w.max_after_um, w.rms_before_um, w.rms_after_um);
  auto names = [](const char* what, const std::vector<std::string>& list) {
    if (!list.empty()) fmt::print(stderr, "  {}: {}\n", what, joined(list));
  };
  names(
      "left out (periodic harmonics shorter than four steps, which would alias: a finer --step, or the axis' "
      "own pitch compensation)",
      s.partial.left_out);
  names("cut by the grid (features shorter than two steps: a finer --step)", s.partial.cut);
  names("not carried (reversals: the table holds one value a node, the mean of both directions)", s.partial.reversals);
  names("held at this export's temperatures and time only", s.uncarried.thermal);
  names("held at these rotary positions only", s.uncarried.rotary);
  fmt::print(stderr, "  set vol_comp[0].max_records to at least {} in the start-up list\n", s.table.nodes());
  for (const std::string& warning : controller::worse_than_none(s.workspace, "over the workspace"))
    fmt::print(stderr, "warning: {}\n", warning);
}

}  // namespace

int run_volume_export(const ExportArgs& args) {
  check_arguments(args);
  const std::string list = list_path(args.output);
  check_output(args.output, {{"the machine model", args.model}}, "-o");
  check_output(list, {{"the machine model", args.model}}, "the configuration list");
  const model::MachineModel m = model::load_machine_model(args.model);
  const model::ForwardModel forward(m);
  Partial partial;
  const controller::VolumeOptions o = volume_options(m, args, partial);
  {
    model::ChainQ low = o.line, high = o.line;
    for (std::size_t a = 0; a < 3; ++a)
      low[static_cast<Eigen::Index>(a)] = o.grids[a].from, high[static_cast<Eigen::Index>(a)] = o.grids[a].to;
    warn_beyond_spans(m, low, high, o.conditions);
  }
  const controller::VolumeTable table = controller::sample_volume_table(forward, o);
  const std::string header =
      fmt::format("ccomp {} volumetric export of '{}' (model SHA-256 {})", kVersion, m.name, m.sha256);
  const controller::IsgVolumeFiles files =
      controller::write_isg_volume(table, std::filesystem::path(args.output).filename().string(), {header});
  // What the control applies: the written digits, measured against the whole model.
  const controller::VolumeTable applied = controller::isg_as_applied(table);
  model::ChainQ reference = o.line;
  reference.head<3>() = o.reference;
  const controller::Residual workspace = controller::corrected_residual(
      forward, controller::volume_corrector(applied), {0, 1, 2},
      controller::volume_points(applied, o.line, kResidualPoints), reference, o.conditions);
  const Uncarried uncarried = uncarried_terms(m, true);
  Summary summary{m, args, o, table, workspace, partial, uncarried, list, header};
  summary.list_written = write_files(args.output, list, files);
  if (args.json)
    print_json(summary);
  else
    print_text(summary);
  return 0;
}

}  // namespace ccomp::cli
