// ccomp export: a machine model as the compensation tables a control reads (those of
// controller/control_tables.hpp's registry, and ISG's volumetric table), with what the
// tables leave that only ccomp's rewriting corrects.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/controller/control_tables.hpp"
#include "ccomp/controller/table_checks.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/conditions.hpp"
#include "ccomp/model/model_file.hpp"
#include "ccomp/model/term_span.hpp"
#include "ccomp/util/json.hpp"
#include "ccomp/version.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "export_parts.hpp"
#include "output_file.hpp"

namespace ccomp::cli {

model::ChainQ table_line(const model::MachineModel& m, const ExportArgs& args, char axis, bool own_table) {
  model::ChainQ q = model::ChainQ::Zero();
  for (const model::AxisSpec& a : m.axes) {
    const auto j = static_cast<Eigen::Index>(a.index());
    if (a.type == model::AxisType::linear && !(a.min <= 0 && a.max >= 0) && std::isfinite(a.min) &&
        std::isfinite(a.max))
      q[j] = 0.5 * (a.min + a.max);
  }
  for (const std::string& at : args.at) {
    const auto eq = at.find('=');
    double v = 0;
    if (eq != 1) throw Error(ErrorKind::usage, "--at takes AXIS=VALUE (Y=0, B=90), not '" + at + "'");
    const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(at[0])));
    const model::AxisSpec* spec = m.axis(letter);
    if (spec == nullptr)
      throw Error(ErrorKind::usage, fmt::format("--at {}: the machine '{}' has no {} axis", at, m.name, letter));
    if (letter == axis) {
      if (!own_table) continue;
      throw Error(ErrorKind::usage, fmt::format("--at {}: {} is the table's own axis, which runs over its travel "
                                                "(--from, --to)",
                                                at, letter));
    }
    v = quantity_in(std::string_view(at).substr(2),
                    spec->type == model::AxisType::rotary ? model::rules::angle() : model::rules::position(), "--at", at);
    if (v < spec->min || v > spec->max)
      throw Error(ErrorKind::usage,
                  fmt::format("--at {}: {} travels from {:g} to {:g}", at, letter, spec->min, spec->max));
    q[static_cast<Eigen::Index>(kAxisLetters.find(letter))] =
        spec->type == model::AxisType::rotary ? v * M_PI / 180.0 : v;
  }
  q[static_cast<Eigen::Index>(model::kToolLengthIndex)] = args.tool_length;
  return q;
}

namespace {

controller::TableOptions table_options(const model::MachineModel& m, const ExportArgs& args, char axis,
                                       const controller::ControlTable& control, bool own_table = true) {
  const model::AxisSpec* spec = m.axis(axis);
  if (spec == nullptr)
    throw Error(ErrorKind::usage, fmt::format("--axis {}: the machine '{}' has no such axis", axis, m.name));
  // A rotary axis without limits, or turning more than once, gets a table over one turn.
  const bool turn = spec->type == model::AxisType::rotary &&
                    (!std::isfinite(spec->min) || !std::isfinite(spec->max) || spec->max - spec->min > 360.0);
  double lo = !std::isnan(args.from) ? args.from : turn ? 0.0 : spec->min;
  double hi = !std::isnan(args.to) ? args.to : turn ? 360.0 : spec->max;
  const controller::ControlLimits& limits = control.limits;
  if (limits.from_zero && lo < 0 && hi > 0 && std::isnan(args.from) && std::isnan(args.to)) {
    // A table that runs from machine home (0) one way cannot hold a travel on both sides
    // of 0: the user says which side; another axis, for the workspace figure, gets its
    // longer side (the control holds the end values beyond).
    if (own_table)
      throw Error(ErrorKind::usage,
                  fmt::format("--control {}: its table runs from machine home (0) to one end of the travel, and {} "
                              "travels from {:g} to {:g} in the model: give --from 0 or --to 0",
                              control.name, axis, lo, hi));
    (hi >= -lo ? lo : hi) = 0.0;
  }
  // Finest step the control's points allow over the travel, unless told.
  const double wanted = args.step > 0 ? args.step : limits.granularity;
  const controller::Grid grid = controller::grid_for(lo, hi, wanted, limits.max_points, limits.granularity);
  if (args.step > 0 && std::abs(grid.step - args.step) > 1e-9)
    throw Error(ErrorKind::usage,
                fmt::format("--step {}: {} needs more than the {} points {} holds; {} fits", args.step, axis,
                            limits.max_points, control.name, grid.step));
  controller::TableOptions o;
  o.axis = axis;
  o.from = grid.from, o.to = grid.to, o.step = grid.step;
  o.reference = std::clamp(0.0, o.from, o.to);
  o.line = table_line(m, args, axis, own_table);
  o.conditions = model::conditions_for(m, model::parse_sensor_readings(args.sensors), args.time);
  return o;
}

controller::WriteOptions write_options(const ExportArgs& args, const model::MachineModel& m,
                                       const controller::TableOptions& o) {
  controller::WriteOptions w;
  w.linuxcnc_file_type = args.comp_file_type;
  w.axis_number = args.axis_number;
  w.fanuc_unit = args.fanuc_unit;
  w.fanuc_reference_point = args.fanuc_reference_point;
  w.header.push_back(
      fmt::format("ccomp {} export of axis {} of '{}' (model SHA-256 {})", kVersion, o.axis, m.name, m.sha256));
  return w;
}

const model::LinkSpec* link_of(const model::MachineModel& m, const std::string& name) {
  for (const std::vector<model::LinkSpec>* chain : {&m.workpiece_chain, &m.tool_chain})
    for (const model::LinkSpec& l : *chain)
      if (l.name == name) return &l;
  return nullptr;
}

/// What makes the table worse than it looks: periodic errors its step cannot hold, and a
/// table that leaves more than none, along its line (its own axis, the whole error) or over
/// the workspace with every axis' table.
std::vector<std::string> table_warnings(const model::MachineModel& m, const controller::AxisTable& table, double step,
                                        const controller::Residual& own, const controller::Residual& along,
                                        const controller::Residual& workspace) {
  std::vector<std::string> out;
  const char* unit = table.rotary ? "deg" : "mm";
  for (const controller::ShortPeriod& s : controller::short_periods(m, table.axis_index, step))
    out.push_back(controller::describe(m, s, unit));
  const auto add = [&](std::vector<std::string> more) { out.insert(out.end(), more.begin(), more.end()); };
  add(controller::worse_than_none(own, fmt::format("along the line, for {}'s own error{}", table.axis,
                                                   table.rotary ? " (its turn)" : ""),
                                  table.rotary ? "arcsec" : "um"));
  add(controller::worse_than_none(along, "along the line, for the whole error"));
  add(controller::worse_than_none(workspace, "over the workspace, with every axis' table made so"));
  return out;
}

}  // namespace

Uncarried uncarried_terms(const model::MachineModel& m, bool cross) {
  Uncarried u;
  std::vector<std::string> seen;
  for (const model::ErrorTermSpec& t : m.terms) {
    if (std::find(seen.begin(), seen.end(), t.name) != seen.end()) continue;
    const model::LinkSpec* l = link_of(m, t.link);
    const model::AxisSpec* spec = l != nullptr && l->axis ? m.axis(*l->axis) : nullptr;
    const bool thermal =
        t.primary.kind == model::VariableKind::temperature || t.primary.kind == model::VariableKind::time ||
        t.secondary.kind == model::VariableKind::temperature || t.secondary.kind == model::VariableKind::time;
    const bool linear = spec != nullptr && spec->type == model::AxisType::linear;
    const auto own = linear ? static_cast<int>(spec->index()) : -1;
    const bool location = t.placement == model::ErrorPlacement::location;
    std::vector<std::string>* list = nullptr;
    if (thermal)
      list = &u.thermal;
    else if (spec != nullptr && !linear)
      list = &u.rotary;
    else if (linear && !cross && ((t.component < 3 && t.component != own) || (location && t.component >= 3)))
      list = &u.straightness;  // straightness and squareness: other axes' corrections
    else if (linear && !location && t.component >= 3)
      list = &u.off_line;
    if (list == nullptr) continue;
    list->push_back(t.name);
    seen.push_back(t.name);
  }
  return u;
}

void warn_beyond_spans(const model::MachineModel& m, const model::ChainQ& low, const model::ChainQ& high,
                       const model::Conditions& conditions) {
  model::SpanWatch spans(m);
  for (const std::string& message : spans.beyond(low, high, conditions)) fmt::print(stderr, "warning: {}\n", message);
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : " ") + n;
  return out;
}

void json_names(util::JsonWriter& j, std::string_view key, const std::vector<std::string>& names) {
  j.key(key).begin_array();
  for (const std::string& n : names) j.value(n);
  j.end_array();
}

void json_residual(util::JsonWriter& j, std::string_view key, const controller::Residual& r) {
  j.key(key).begin_object();
  j.field("points", r.points).field("max_before_um", r.max_before_um).field("rms_before_um", r.rms_before_um);
  j.field("max_after_um", r.max_after_um).field("rms_after_um", r.rms_after_um);
  j.field("reference_um", r.reference_um).end_object();
}

CLI::App* add_export(CLI::App& app, ExportArgs& args) {
  std::vector<std::string> names;
  std::string listed;
  for (const controller::ControlTable* t : controller::control_tables()) {
    names.emplace_back(t->name);
    listed += (listed.empty() ? "" : ", ") + std::string(t->name);
  }
  names.emplace_back("isg");
  CLI::App* cmd = app.add_subcommand(
      "export", "a fitted model as a control's compensation tables (LinuxCNC, Fanuc, Siemens 840D sl, Heidenhain, "
                "Centroid, Beckhoff TwinCAT CNC)");
  cmd->add_option("-m,--model", args.model, "machine model (YAML)")->required();
  cmd->add_option("--control", args.control,
                  listed + " (a table along --axis), isg (Beckhoff TwinCAT CNC: a volumetric table over X Y Z)")
      ->required()
      ->check(CLI::IsMember(names));
  cmd->add_option("--axis", args.axis, "the axis the table is for (X, Y, Z, B ...; not for isg)");
  cmd->add_option("-o,--output", args.output, "the table file (- for stdout, the default)");
  cmd->add_option("--step", args.step,
                  "mm between the table's points (default: the finest the control holds; isg: 25 mm on each axis)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--from", args.from, "mm: the table's first point (default: the axis' travel)");
  cmd->add_option("--to", args.to, "mm: the table's last point (default: the axis' travel)");
  cmd->add_option("--at", args.at,
                  "AXIS=VALUE: where the other axes stand on the table's line (mm, deg; default 0 or mid-travel)")
      ->take_all();
  cmd->add_option("--tool-length", args.tool_length, "mm: the tool the table is for (100)")
      ->transform(quantity(model::rules::tool_length(), "--tool-length"));
  cmd->add_option("--sensor", args.sensors, "a temperature reading for the model's thermal terms: NAME=DEGC");
  cmd->add_option("--time", args.time, "s since the machine's warm-up started");
  cmd->add_option("--comp-file-type", args.comp_file_type, "LinuxCNC COMP_FILE_TYPE: 0 (actual positions) or 1 (trims)")
      ->check(CLI::IsMember({0, 1}));
  cmd->add_option("--axis-number", args.axis_number, "Fanuc's axis number (A), Siemens' AXn (default: X 1, Y 2, Z 3)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--fanuc-unit", args.fanuc_unit, "mm per detection unit (0.001)")->check(CLI::PositiveNumber);
  cmd->add_option("--fanuc-reference-point", args.fanuc_reference_point,
                  "parameter 3620, the point of the reference position (default: the first point is 0)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--json", args.json, "the summary as JSON on stdout (the table then needs -o FILE)");
  return cmd;
}

int run_export(const ExportArgs& args) {
  if (args.json && args.output == "-")
    throw Error(ErrorKind::usage, "--json writes the summary on stdout: give the table -o FILE");
  if (args.control == "isg") return run_volume_export(args);
  if (args.axis.empty())
    throw Error(ErrorKind::usage,
                "--axis: a " + args.control + " table is for one axis: give --axis X (or Y, Z, B ...)");
  if (args.axis.size() != 1) throw Error(ErrorKind::usage, "--axis takes one axis letter, not '" + args.axis + "'");
  if (args.output != "-") check_output(args.output, {{"the machine model", args.model}}, "-o");
  const char axis = static_cast<char>(std::toupper(args.axis[0]));
  const controller::ControlTable& control = *controller::control_named(args.control);
  const model::MachineModel m = model::load_machine_model(args.model);
  const model::ForwardModel forward(m);
  const controller::TableOptions o = table_options(m, args, axis, control);
  const controller::WriteOptions w = write_options(args, m, o);
  {
    model::ChainQ low = o.line, high = o.line;
    const auto a = static_cast<Eigen::Index>(kAxisLetters.find(axis));
    const double scale = m.axis(axis)->type == model::AxisType::rotary ? M_PI / 180.0 : 1.0;
    low[a] = o.from * scale, high[a] = o.to * scale;
    warn_beyond_spans(m, low, high, o.conditions);
  }
  const controller::AxisTable table = controller::sample_axis_table(forward, o);
  const std::string text = controller::write_table(control, table, w);
  const controller::AxisTable applied = controller::as_control_applies(control, table, w);
  // Along the table's own line: its own axis (what the table is for), and the whole error.
  const std::vector<model::ChainQ> line = controller::line_points(table, o);
  const model::ChainQ reference = controller::reference_point(table, o);
  const controller::Residual own =
      controller::table_residual(forward, {applied}, line, reference, o.conditions, static_cast<int>(table.axis_index));
  const controller::Residual along = controller::table_residual(forward, {applied}, line, reference, o.conditions);
  // Over the workspace, with every linear axis' table made the same way.
  std::vector<controller::AxisTable> all;
  ExportArgs others = args;  // the other axes over their travel, at the finest step
  others.from = others.to = std::nan(""), others.step = 0;
  if (table.rotary) all.push_back(applied);
  for (const model::AxisSpec& a : m.axes) {
    if (a.type != model::AxisType::linear || !std::isfinite(a.min) || !std::isfinite(a.max)) continue;
    if (a.letter == axis) {
      all.push_back(applied);
      continue;
    }
    const controller::TableOptions other = table_options(m, others, a.letter, control, false);
    all.push_back(controller::as_control_applies(control, controller::sample_axis_table(forward, other), w));
  }
  const controller::Residual workspace =
      controller::table_residual(forward, all, controller::workspace_points(m, o.line, 5), reference, o.conditions);
  const controller::Residual linear_workspace = controller::table_residual(
      forward, all, controller::workspace_points(m, o.line, 5, false), reference, o.conditions);
  const Uncarried u = uncarried_terms(m, control.limits.cross);
  const std::vector<std::string> warnings = table_warnings(m, table, o.step, own, along, workspace);
  write_output(args.output, text);
  if (args.json) {
    util::JsonWriter j;
    j.begin_object().field("command", "export").field("control", args.control).field("axis", std::string(1, axis));
    j.field("model", m.name).field("model_sha256", m.sha256).field("output", args.output);
    // Positions in the axis' unit (mm, or deg for a rotary axis); its own error in um, or
    // arcsec for the turn of a rotary axis.
    j.field("unit", table.rotary ? "deg" : "mm").field("own_axis_unit", table.rotary ? "arcsec" : "um");
    j.field("points", table.positions.size()).field("from", o.from).field("to", o.to).field("step", o.step);
    j.field("bidirectional", table.bidirectional()).field("tool_length_mm", args.tool_length);
    j.field("reference", o.reference);
    json_residual(j, "line_own_axis", own);
    json_residual(j, "line", along);
    json_residual(j, "workspace", workspace);
    json_residual(j, "workspace_linear_axes", linear_workspace);
    json_names(j, "thermal_terms", u.thermal);
    json_names(j, "rotary_terms", u.rotary);
    json_names(j, "cross_terms", u.straightness);
    json_names(j, "angular_terms", u.off_line);
    json_names(j, "warnings", warnings);
    j.end_object();
    fmt::print("{}", j.text());
    return 0;
  }
  const char* unit = table.rotary ? "deg" : "mm";
  const char* own_unit = table.rotary ? "arcsec" : "um";
  std::string on_line;
  for (const model::AxisSpec& a : m.axes)
    if (a.letter != axis) {
      const double v = o.line[static_cast<Eigen::Index>(a.index())];
      on_line += fmt::format(" {}={:g}", a.letter, a.type == model::AxisType::rotary ? v * 180.0 / M_PI : v);
    }
  fmt::print(stderr,
             "{}: {} table of {} for '{}': {} points from {:g} to {:g} {} every {:g} {}{}, on the line{} with a {:g} "
             "mm tool\n",
             args.output == "-" ? "stdout" : args.output, args.control, axis, m.name, table.positions.size(), o.from,
             o.to, unit, o.step, unit, table.bidirectional() ? ", by direction of travel" : "", on_line,
             args.tool_length);
  fmt::print(stderr, "  {}\n", w.header.front());
  fmt::print(stderr,
             "  errors relative to the reference point ({} at {:g}, where every table is 0; the tool is {:.3f} um "
             "off there, which a work offset probed there takes)\n",
             axis, o.reference, along.reference_um);
  fmt::print(stderr,
             "  along the line, {}'s own error{}: max {:.3f} {} -> {:.3f} {} as the control applies the table\n", axis,
             table.rotary ? " (its turn)" : "", own.max_before_um, own_unit, own.max_after_um, own_unit);
  fmt::print(stderr, "  along the line, the whole error: max {:.3f} um -> {:.3f} um\n", along.max_before_um,
             along.max_after_um);
  fmt::print(stderr,
             "  with every linear axis' table made so, over the workspace (both directions of travel; without -> "
             "with tables):\n    the linear axes alone ({} points, rotary axes as on the line): max {:.2f} -> {:.2f} "
             "um, rms {:.2f} -> {:.2f} um\n    every axis ({} points): max {:.2f} -> {:.2f} um, rms {:.2f} -> {:.2f} "
             "um\n  the tables hold their own lines; the rest only ccomp's rewriting corrects:\n",
             linear_workspace.points, linear_workspace.max_before_um, linear_workspace.max_after_um,
             linear_workspace.rms_before_um, linear_workspace.rms_after_um, workspace.points, workspace.max_before_um,
             workspace.max_after_um, workspace.rms_before_um, workspace.rms_after_um);
  if (!u.thermal.empty())
    fmt::print(stderr, "    not carried (they change with temperature or time): {}\n", joined(u.thermal));
  if (!u.rotary.empty()) fmt::print(stderr, "    not carried (rotary axes): {}\n", joined(u.rotary));
  if (!u.straightness.empty())
    fmt::print(stderr, "    not carried ({} has no cross tables: straightness, squareness): {}\n", args.control,
               joined(u.straightness));
  if (!u.off_line.empty())
    fmt::print(stderr, "    carried on this line only (angular errors act through offsets that change elsewhere): {}\n",
               joined(u.off_line));
  for (const std::string& warning : warnings) fmt::print(stderr, "warning: {}\n", warning);
  return 0;
}

}  // namespace ccomp::cli
