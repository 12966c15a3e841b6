#include <charconv>
#include <cmath>

#include "ccomp/compensate/machine_coordinates.hpp"
#include "ccomp/error.hpp"
#include "ccomp/gcode/dialect.hpp"
#include "ccomp/gcode/tool_table.hpp"
#include "command_line.hpp"
#include "commands.hpp"

namespace ccomp::cli {

void add_program_options(CLI::App& cmd, ProgramArgs& args) {
  cmd.add_option("--tool-table", args.tool_table, "LinuxCNC tool table (T1 P1 Z0.5 D0.25 ...)");
  cmd.add_option("--machine-units", args.machine_units,
                 "units of the tool table and stored offsets: mm, or inch as LinuxCNC's rs274 alone")
      ->check(CLI::IsMember({"mm", "inch"}));
  cmd.add_option("--param", args.params,
                 "a value only the controller has: NAME=VALUE (e.g. '_hal[x.y]=2.5' or 5063=1.2)");
  cmd.add_option("--work-offset", args.work_offsets,
                 "where a coordinate system's zero lies in machine coordinates, as the control stores it: "
                 "G54=X-250,Y0,Z-300 (mm and deg; repeat for G55 ... G59.3; over the model's work_offsets)");
  cmd.add_option("--dialect", args.dialect, "G-code dialect: linuxcnc, fanuc, mazak, wincnc, siemens")
      ->check(CLI::IsMember(gcode::dialect_names()));
  cmd.add_option("--sub-path", args.sub_path, "folder with subroutine files (name.ngc)");
  cmd.add_flag("--block-delete", args.block_delete, "skip lines that start with '/'");
  cmd.add_option("--max-blocks", args.max_blocks,
                 "blocks a program may execute (loops counted each run) before it is taken for an endless loop")
      ->check(CLI::PositiveNumber);
}

CLI::Validator tolerance_in_mm() {
  return quantity(model::rules::tolerance(), "--tolerance");
}

CLI::Validator angle_in_urad() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec == std::errc() && ptr == text.data() + text.size() && std::isfinite(v) && v > 0.0) return {};
        return "'" + text + "' is not an angle in urad (0 < tolerance; 10 arcsec is 48.5)";
      },
      "URAD > 0");
}

CLI::Validator seconds_since_warm_up() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec == std::errc() && ptr == text.data() + text.size() && std::isfinite(v) && v >= 0.0) return {};
        return "'" + text + "' is not a time in s since the warm-up started (0 or more)";
      },
      "S >= 0");
}

model::WorkOffsets work_offsets_of(const std::vector<std::string>& specs) {
  model::WorkOffsets offsets;
  for (const std::string& spec : specs) {
    model::WorkOffsetEntry e;
    try {
      e = model::parse_work_offset(spec, "--work-offset " + spec);
    } catch (const Error& refused) {  // shown at its place on the command line
      if (refused.kind() != ErrorKind::usage) throw;
      throw usage_error_at("--work-offset", spec, refused.message());
    }
    if (offsets.of(e.system))
      throw Error(ErrorKind::usage,
                  "--work-offset gives " + model::coordinate_system_name(e.system) + " twice: give each system once");
    offsets.set(e.system, e.origin);
  }
  return offsets;
}

gcode::InterpreterOptions interpreter_options(const ProgramArgs& args, const std::string& model_dialect,
                                              const model::WorkOffsets& base) {
  gcode::InterpreterOptions o;
  model::WorkOffsets offsets = base;
  offsets.override_with(work_offsets_of(args.work_offsets));
  compensate::set_work_offsets(offsets, o);
  const std::string name = !args.dialect.empty() ? args.dialect : model_dialect.empty() ? "linuxcnc" : model_dialect;
  auto dialect = gcode::dialect_named(name);
  if (!dialect) throw Error(ErrorKind::usage, "unknown dialect '" + name + "'");
  o.dialect = *dialect;
  if (!args.tool_table.empty()) {
    o.tools = gcode::read_tool_table_file(args.tool_table);
  }
  o.machine_units = args.machine_units == "inch" ? gcode::Units::inch : gcode::Units::mm;
  for (const std::string& p : args.params) {
    const auto eq = p.rfind('=');
    double v = 0.0;
    if (eq == std::string::npos || eq == 0) throw Error(ErrorKind::usage, "--param takes NAME=VALUE, not '" + p + "'");
    const std::string value = p.substr(eq + 1);
    const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
    if (ec != std::errc() || ptr != value.data() + value.size() || !std::isfinite(v))
      throw Error(ErrorKind::usage, "--param " + p + ": '" + value + "' is not a number");
    o.parameters.emplace_back(p.substr(0, eq), v);
  }
  o.subroutine_path = args.sub_path;
  o.block_delete = args.block_delete;
  if (args.max_blocks > 0) o.max_blocks = args.max_blocks;
  return o;
}

}  // namespace ccomp::cli
