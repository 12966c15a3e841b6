// ccomp import: an instrument's file (a Renishaw .rtl, a one-axis table, a rotary
// calibrator's runs) converted to the measurement contract, and the options every command
// reading measurements shares for placing a one-axis file (docs/identification.md).
#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <fstream>

#include "ccomp/axis.hpp"
#include "ccomp/error.hpp"
#include "ccomp/identify/measurement_formats.hpp"
#include "ccomp/model/model_file.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "output_file.hpp"
#include "ccomp/util/json.hpp"

namespace ccomp::cli {
namespace {

char axis_letter(const std::string& text, std::string_view option) {
  if (text.size() != 1 || kAxisLetters.find(static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])))) ==
                              std::string_view::npos)
    throw Error(ErrorKind::usage, fmt::format("{} {}: an axis is one letter, X Y Z A B C U V W", option, text));
  return static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
}

/// "y=-360,z=-400" (also given as several --at) into axis positions.
std::vector<identify::AxisPosition> positions(const std::vector<std::string>& at) {
  std::vector<identify::AxisPosition> out;
  for (const std::string& option : at) {
    std::size_t start = 0;
    while (start <= option.size()) {
      const std::size_t comma = std::min(option.find(',', start), option.size());
      const std::string item = option.substr(start, comma - start);
      start = comma + 1;
      const std::size_t eq = item.find('=');
      if (eq == std::string::npos)
        throw Error(ErrorKind::usage, fmt::format("--at {}: not AXIS=VALUE (mm, deg), as in --at y=-360,z=-400", item));
      const char letter = axis_letter(item.substr(0, eq), "--at");
      const bool rotary = letter == 'A' || letter == 'B' || letter == 'C';
      const double value = quantity_in(std::string_view(item).substr(eq + 1),
                                       rotary ? model::rules::angle() : model::rules::position(), "--at", option);
      for (const identify::AxisPosition& p : out)
        if (p.axis == letter) throw Error(ErrorKind::usage, fmt::format("--at names axis {} twice", letter));
      out.push_back({letter, value});
    }
  }
  return out;
}

/// The model a conversion without -m places readings on: the three linear axes, nothing else.
model::MachineModel linear_axes_only() {
  model::MachineModel m;
  m.name = "X Y Z (no model given)";
  for (const char letter : {'X', 'Y', 'Z'}) m.axes.push_back({letter, model::AxisType::linear});
  return m;
}

std::string import_json(const std::string& input, std::string_view format, const identify::MeasurementSet& set,
                        const std::string& output) {
  util::JsonWriter j;
  j.begin_object().field("command", "import").field("input", input).field("format", format);
  j.field("output", output).field("observations", set.observations.size());
  j.key("sources").begin_array();
  for (const std::string& s : set.sources) j.value(s);
  j.end_array();
  return j.end_object().text();
}

}  // namespace

void add_reading_options(CLI::App& cmd, IdentifyArgs& args, bool with_axis) {
  if (with_axis)
    cmd.add_option("--axis", args.axis, "the axis a one-axis file measures, where it does not say (X, Y, Z, B...)");
  cmd.add_option("--at", args.at,
                 "where the other axes stood for a one-axis file: AXIS=VALUE,... (mm, deg; 0 unless given; a rotary "
                 "axis' readings 100 mm off its line)");
  cmd.add_option("--unit", args.unit,
                 "the deviations' unit of a one-axis file that states none (mm, um, nm, inch, deg, arcsec, urad)");
}

identify::ReadOptions reading_options(const IdentifyArgs& args) {
  identify::ReadOptions o;
  o.tool_length = args.tool_length;
  if (!args.axis.empty()) o.axis = axis_letter(args.axis, "--axis");
  o.at = positions(args.at);
  o.unit = args.unit;
  return o;
}

CLI::App* add_import(CLI::App& app, IdentifyArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "import", "converts an instrument's file (Renishaw .rtl, a one-axis table, a rotary calibrator's runs) to the "
                "measurement CSV");
  cmd->add_option("file", args.measurements, "the instrument's file")->required()->expected(1);
  cmd->add_option("-o,--output", args.output, "the measurement CSV to write (- for stdout)")->required();
  cmd->add_option("-m,--model", args.model,
                  "machine model (YAML): its axes, rotary axes' lines and max_correction (without one: X Y Z)");
  cmd->add_option("--tool-length", args.tool_length, "mm: tool or optic length of the readings (100)");
  cmd->add_option("--source", args.source, "the label of the rows (the file's name without folder and extension)");
  add_reading_options(*cmd, args, true);
  add_frame_options(*cmd, args);
  cmd->add_flag("--json", args.json, "what was converted as JSON on stdout (needs -o FILE; docs/json.md)");
  return cmd;
}

int run_import(const IdentifyArgs& args) {
  const std::string& input = args.measurements.front();
  if (args.json && args.output == "-") throw Error(ErrorKind::usage, "--json writes on stdout: give -o FILE");
  std::vector<RunInput> inputs{{"the measurement file", input}};
  if (!args.model.empty()) inputs.push_back({"the machine model", args.model});
  if (args.output != "-") check_output(args.output, inputs, "-o");
  const model::MachineModel m = args.model.empty() ? linear_axes_only() : model::load_machine_model(args.model);
  identify::ReadOptions o = reading_options(args);
  o.frame = frame_of(args);
  o.source = args.source;
  std::string head(identify::io::kDetectBytes, '\0');
  {
    std::ifstream f(input, std::ios::binary);
    if (!f) throw Error(ErrorKind::io, fmt::format("cannot read measurement file '{}'", input));
    f.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(f.gcount()));
  }
  const std::string_view format = identify::io::detect_format(head, input).name;
  identify::MeasurementSet set;
  identify::read_measurements(input, m, o, set);
  for (const std::string& notice : set.notices) fmt::print(stderr, "notice: {}\n", notice);
  // Written in the frame it was read in (the file's, the options', or the model's work offset).
  write_output(args.output, identify::to_csv(set, m, set.frames.front()));
  if (args.json) {
    fmt::print("{}", import_json(input, format, set, args.output));
  } else if (args.output != "-") {
    fmt::print(stderr, "{}: {} file, {} observations as source '{}' -> {}\n", input, format, set.observations.size(),
               fmt::join(set.sources, "', '"), args.output);
  }
  return 0;
}

}  // namespace ccomp::cli
