// A one-axis table as a spreadsheet or an instrument's software exports it: a header naming
// the target and the deviation (and optionally the run and the direction of approach), then a
// row per reading. Fields separated by commas, semicolons or tabs (the header's tells which);
// with semicolons or tabs a decimal comma is read as a point. Units come from the header
// ("Deviation [um]", "target (mm)") or a line before it ("unit: um", "axis: B"); lines
// starting with '#' are comments, but for a '# frame:' line as the contract has it. Without a direction column, the approach is worked out from
// the order of each run (identify/axis_runs). docs/identification.md describes the format.
#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "ccomp/error.hpp"
#include "ccomp/identify/axis_runs.hpp"
#include "ccomp/identify/measurement_formats.hpp"
#include "line_reader.hpp"
#include "text_fields.hpp"

namespace ccomp::identify::io {
namespace {

enum class Column : std::uint8_t { target, deviation, run, direction, other };

Column column_of(std::string_view header_name) {
  const std::string f = fold(name_and_unit(header_name).first);
  for (const char* n : {"target", "targetposition", "position", "nominal", "nominalposition", "setpoint", "pos"})
    if (f == n) return Column::target;
  for (const char* n : {"deviation", "error", "dev", "err", "positionaldeviation", "positionerror", "positionalerror"})
    if (f == n) return Column::deviation;
  for (const char* n : {"run", "runno", "runnumber", "cycle", "pass", "series"})
    if (f == n) return Column::run;
  for (const char* n : {"direction", "dir", "approach", "approachdirection"})
    if (f == n) return Column::direction;
  return Column::other;
}

/// The delimiter of a header line: a tab or a semicolon where it has one, else a comma.
char delimiter_of(std::string_view line) {
  if (line.find('\t') != std::string_view::npos) return '\t';
  if (line.find(';') != std::string_view::npos) return ';';
  return ',';
}

/// Whether `line` is a header of this format: a target and a deviation column, and not the
/// contract's x, y, z (whose extra columns may have any name).
bool is_header(std::string_view line) {
  bool target = false, deviation = false;
  int contract = 0;
  for (const Field& f : split_fields(line, delimiter_of(line))) {
    const Column c = column_of(f.text);
    target = target || c == Column::target;
    deviation = deviation || c == Column::deviation;
    contract += f.text == "x" || f.text == "y" || f.text == "z";
  }
  return target && deviation && contract < 3;
}

/// A line before the header saying "key: value" (or "key;value"): the axis or a unit.
struct Setting {
  std::string key, value, written;  ///< key folded, its value, the key as written
};
std::optional<Setting> setting_of(std::string_view line) {
  const std::size_t at = line.find_first_of(":;=\t");
  if (at == std::string_view::npos) return std::nullopt;
  std::vector<Field> value = split_fields(line.substr(at + 1), '\0');
  const std::vector<Field> key = split_blanks(line.substr(0, at));
  std::string written;
  for (const Field& w : key) written += (written.empty() ? "" : " ") + w.text;
  return Setting{fold(line.substr(0, at)), value.front().text, written};
}

bool detect(std::string_view head) {
  std::size_t start = 0;
  while (start < head.size()) {
    const std::size_t end = std::min(head.find('\n', start), head.size());
    const std::string_view line = head.substr(start, end - start);
    start = end + 1;
    if (line.find_first_not_of(" \t\r") == std::string_view::npos || line.front() == '#') continue;
    if (is_header(line)) return true;
    if (!setting_of(line)) return false;  // neither a setting nor the header: another format
  }
  return false;
}

void read(std::istream& in, const std::string& name, const model::MachineModel& model, const ReadOptions& options,
          MeasurementSet& into) {
  LineReader lines(in, name);
  std::string line;
  auto fail = [&](std::uint32_t column, const std::string& message) {
    throw Error(ErrorKind::data, message, SourceLocation{name, lines.number(), column}, line.substr(0, 200));
  };
  AxisRuns runs;
  auto set_unit = [&](std::optional<Unit>& unit, std::string_view text, std::uint32_t column) {
    if (text.empty()) return;
    unit = parse_unit(text);
    if (!unit) fail(column, fmt::format("'{}' is not a unit (mm, um, nm, inch, deg, arcsec, urad)", text));
    runs.unit_line = lines.number();
  };
  // The settings, up to the header.
  std::vector<Field> header;
  char delimiter = ',';
  while (lines.next(line)) {
    if (is_frame_line(line)) {
      if (runs.frame) fail(1, "a second '# frame:' line: a file has one frame");
      runs.frame = parse_frame_line(line, name, lines.number());
    }
    if (line.find_first_not_of(" \t\r") == std::string::npos || line.front() == '#') continue;
    if (is_header(line)) {
      delimiter = delimiter_of(line);
      header = split_fields(line, delimiter);
      break;
    }
    const std::optional<Setting> s = setting_of(line);
    if (!s) fail(1, "neither a setting ('axis: X', 'unit: um') nor the header (target, deviation, ...)");
    if (s->key == "axis") {
      const std::string letter = fold(s->value);
      if (letter.size() != 1 || std::string_view("xyzabcuvw").find(letter[0]) == std::string_view::npos)
        fail(1, fmt::format("axis '{}': an axis is one letter, X Y Z A B C U V W", s->value));
      runs.axis = static_cast<char>(std::toupper(static_cast<unsigned char>(letter[0])));
    } else if (s->key == "unit" || s->key == "units" || s->key == "deviationunit" || s->key == "errorunit") {
      set_unit(runs.deviation_unit, s->value, 1);
    } else if (s->key == "targetunit" || s->key == "positionunit") {
      set_unit(runs.target_unit, s->value, 1);
    } else if (!s->value.empty()) {  // title, machine, date, temperatures: the report's, not the data's
      runs.stated.push_back({s->written, s->value, name});
    }
  }
  if (header.empty()) throw Error(ErrorKind::data, "no header (target, deviation, ...) in the file", SourceLocation{name, 0, 0});
  const std::uint32_t header_line = lines.number();
  std::array<int, 4> at{-1, -1, -1, -1};  // the column of each Column, by its value
  for (std::size_t i = 0; i < header.size(); ++i) {
    const Column c = column_of(header[i].text);
    if (c == Column::other) {
      into.notices.push_back(fmt::format("{}: column '{}' is not read", name, header[i].text));
      continue;
    }
    int& slot = at[static_cast<std::size_t>(c)];
    if (slot >= 0) fail(header[i].column, fmt::format("two '{}' columns", header[i].text));
    slot = static_cast<int>(i);
    const std::string_view unit = name_and_unit(header[i].text).second;
    if (c == Column::target) set_unit(runs.target_unit, unit, header[i].column);
    if (c == Column::deviation) set_unit(runs.deviation_unit, unit, header[i].column);
  }
  const bool decimal_comma = delimiter != ',';
  std::vector<Field> fields;
  while (lines.next(line)) {
    if (is_frame_line(line)) fail(1, "a '# frame:' line after the header row: put it before the header");
    if (line.find_first_not_of(" \t\r") == std::string::npos || line.front() == '#') continue;
    fields = split_fields(line, delimiter);
    if (fields.size() != header.size())
      fail(1, fmt::format("this row has {} fields, the header (line {}) {}", fields.size(), header_line, header.size()));
    auto number = [&](Column c, bool required) -> std::optional<double> {
      const int i = at[static_cast<std::size_t>(c)];
      if (i < 0) return std::nullopt;
      const Field& f = fields[static_cast<std::size_t>(i)];
      if (f.text.empty() && !required) return std::nullopt;
      const std::optional<double> v = parse_number(f.text, decimal_comma);
      if (!v || std::abs(*v) > 1e7)
        fail(f.column, fmt::format("column '{}': '{}' is not a number of a reading", header[static_cast<std::size_t>(i)].text, f.text));
      return v;
    };
    AxisReading r;
    r.line = lines.number();
    r.target = *number(Column::target, true);
    r.deviation = *number(Column::deviation, true);
    if (const std::optional<double> run = number(Column::run, false)) {
      if (*run != std::floor(*run) || std::abs(*run) > 1e6) fail(fields[static_cast<std::size_t>(at[2])].column, "a run is a whole number");
      r.run = static_cast<int>(*run);
    }
    if (const int i = at[static_cast<std::size_t>(Column::direction)]; i >= 0) {
      const Field& f = fields[static_cast<std::size_t>(i)];
      const std::optional<int> d = parse_direction(f.text);
      if (!d) fail(f.column, fmt::format("direction '{}': +1 / -1, up / down, fwd / bwd, or empty (unknown)", f.text));
      r.approach = *d;
    }
    runs.readings.push_back(r);
  }
  append_axis_runs(runs, name, model, options, into);
}

}  // namespace

const MeasurementFormat& axis_table_format() {
  static const MeasurementFormat format{
      "axis-table",
      "one axis' readings: a header with target and deviation columns (run, direction optional), comma, semicolon "
      "or tab separated, units in the header or a 'unit:' line",
      detect, read};
  return format;
}

}  // namespace ccomp::identify::io
