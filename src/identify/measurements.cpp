#include "ccomp/identify/measurements.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/identify/measurement_formats.hpp"
#include "ccomp/util/ascii.hpp"
#include "io/line_reader.hpp"

namespace ccomp::identify {
namespace {

/// A "# key: value" comment before the header ("# instrument: Renishaw XL-80", "# air
/// temperature: 20.3"): what the file states beside its readings (the report's).
std::optional<StatedField> stated_comment(std::string_view line, const std::string& name) {
  if (line.empty() || line.front() != '#') return std::nullopt;
  const std::size_t colon = line.find(':');
  if (colon == std::string_view::npos) return std::nullopt;
  auto trimmed = [](std::string_view t) {
    const std::size_t a = t.find_first_not_of(" \t\r#"), b = t.find_last_not_of(" \t\r");
    return a == std::string_view::npos ? std::string() : std::string(t.substr(a, b - a + 1));
  };
  std::string key = trimmed(line.substr(0, colon)), value = trimmed(line.substr(colon + 1));
  if (key.empty() || value.empty() || key.size() > 60) return std::nullopt;
  return StatedField{std::move(key), std::move(value), name};
}

/// The largest magnitude a reading's number may have (mm, deg, s, degC).
constexpr double kLargestReading = 1e7;
/// Times may be clock readings (s since 1970: 1.7e9 today).
constexpr double kLatestTime = 1e11;

constexpr std::string_view kAxes = "xyzabcuvw";

/// Splits one CSV line at `delimiter` into its fields (blanks around them trimmed; double
/// quotes allow a delimiter in a source label) and the 1-based column where each starts.
void split(std::string_view line, char delimiter, std::vector<std::string>& fields,
           std::vector<std::uint32_t>& columns) {
  fields.assign(1, std::string());
  columns.assign(1, 1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"') {
      if (quoted && i + 1 < line.size() && line[i + 1] == '"')
        fields.back() += '"', ++i;
      else
        quoted = !quoted;
    } else if (c == delimiter && !quoted) {
      fields.emplace_back();
      columns.push_back(static_cast<std::uint32_t>(i + 2));
    } else if (c != '\r') {
      if (fields.back().empty() && (c == ' ' || c == '\t'))
        ++columns.back();  // leading blanks
      else
        fields.back() += c;
    }
  }
  for (std::string& f : fields) f.erase(f.find_last_not_of(" \t") + 1);
}

/// The approach-direction column of each axis.
constexpr std::array<std::string_view, 9> kDirectionNames{"vx", "vy", "vz", "va", "vb", "vc", "vu", "vv", "vw"};

/// Where each column a row is read from sits in it (-1: absent).
struct RowColumns {
  std::array<int, 9> axis{}, direction{};
  int L = -1, t = -1, source = -1, d = -1, nx = -1, ny = -1, nz = -1, dx = -1, dy = -1, dz = -1;
};

struct Columns {
  std::map<std::string, std::size_t> index;
  [[nodiscard]] int at(const std::string& name) const {
    const auto it = index.find(name);
    return it == index.end() ? -1 : static_cast<int>(it->second);
  }
};

}  // namespace

namespace {

/// Deviations are in mm: a file whose typical reading is beyond what the model may correct
/// (max_correction) was written in another unit (um where mm is due). The median, so that
/// a few spikes (a laser beam cut) do not trip it; `fail` gets the first row beyond.
template <class Fail>
void check_magnitude(const MeasurementSet& set, std::size_t first, const model::MachineModel& model, Fail fail) {
  std::vector<double> sizes;
  for (std::size_t i = first; i < set.observations.size(); ++i) sizes.push_back(std::abs(set.observations[i].value));
  if (sizes.empty()) return;
  std::nth_element(sizes.begin(), sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2), sizes.end());
  const double median = sizes[sizes.size() / 2];
  if (!(median > model.max_correction)) return;
  for (std::size_t i = first; i < set.observations.size(); ++i)
    if (std::abs(set.observations[i].value) > model.max_correction)
      fail(set.observations[i].row,
           fmt::format("the readings' median size is {:.6g} mm, beyond the model's max_correction of {:.6g} mm: "
                       "deviations are in mm (written in um?)",
                       median, model.max_correction));
}

/// The same row twice, to the last digit: ISO 230-2's repeated approaches read at the
/// instrument's resolution do that, and so does a file pasted together twice. Kept, and said
/// (the first few), so that a doubled file does not count double unnoticed. A hash two
/// different rows share would only cost a wrong notice.
void note_repeated_rows(std::vector<std::pair<std::uint64_t, std::uint32_t>>& rows, const std::string& name,
                        std::vector<std::string>& notices) {
  std::sort(rows.begin(), rows.end());  // by text, then line
  std::vector<std::pair<std::uint32_t, std::uint32_t>> repeats;  // a row's line, and the first with its text
  for (std::size_t i = 1, first = 0; i < rows.size(); ++i) {
    if (rows[i].first != rows[first].first) first = i;
    else repeats.emplace_back(rows[i].second, rows[first].second);
  }
  rows = {};
  std::sort(repeats.begin(), repeats.end());
  for (std::size_t k = 0; k < repeats.size() && k < 3; ++k)
    notices.push_back(fmt::format("{}:{}: the row repeats row {} to the last digit (a repeated approach, or a "
                                  "file pasted in twice?)",
                                  name, repeats[k].first, repeats[k].second));
  if (repeats.size() > 3)
    notices.push_back(fmt::format("{}: {} rows repeat an earlier row to the last digit", name, repeats.size()));
}

}  // namespace

void io::to_machine(model::ChainQ& q, const ResolvedFrame& frame) {
  if (frame.frame.kind == FrameKind::machine) {
    q[2] -= q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
    return;
  }
  for (std::size_t i = 0; i < 9; ++i)
    q[static_cast<Eigen::Index>(i)] += angular_at(i) ? frame.origin[i] * kRadPerDeg : frame.origin[i];
}

/// The rows read as program coordinates (work offset zero) become machine positions: the
/// frame's origin added, or for a machine frame the tool length taken back off Z (the axis
/// positions themselves). An origin nobody gave is said where a rotary axis turns.
void io::place_in_machine(MeasurementSet& set, std::size_t first, const ResolvedFrame& frame,
                          const model::MachineModel& model, const std::string& name) {
  set.frames.push_back(frame);
  for (std::size_t k = first; k < set.observations.size(); ++k) to_machine(set.observations[k].q, frame);
  if (!frame.unknown) return;
  for (const model::AxisSpec& a : model.axes) {
    if (a.type != model::AxisType::rotary) continue;
    const auto i = static_cast<Eigen::Index>(a.index());
    for (std::size_t k = first + 1; k < set.observations.size(); ++k)
      if (set.observations[k].q[i] != set.observations[first].q[i]) {
        set.notices.push_back(fmt::format(
            "{}: its rows are program coordinates of {}, whose origin nobody gave (no '# frame:' line with it, "
            "no --work-offset, no work_offsets in the model): taken at machine zero, and every rotary error's "
            "lever with it (docs/identification.md, 'Frames')",
            name, model::coordinate_system_name(frame.frame.system)));
        return;
      }
  }
}

void io::read_contract(std::istream& stream, const std::string& name, const model::MachineModel& model,
                       const ReadOptions& options, MeasurementSet& into) {
  const auto file_index = static_cast<std::uint32_t>(into.files.size());
  into.files.push_back(name);
  io::LineReader in(stream, name);  // a line's length capped while it is read
  std::string line;
  std::uint32_t number = 0;
  auto fail = [&](std::uint32_t row, std::uint32_t column, const std::string& message) {
    throw Error(ErrorKind::data, message, SourceLocation{name, row, column}, line.substr(0, 200));
  };
  // Line ends of CR alone read as one line: said as such, not as what that line seems.
  auto check_line_end = [&] {
    if (const auto cr = line.find('\r'); cr != std::string::npos && cr + 1 < line.size()) {
      line.resize(cr);  // shown up to it: a terminal would write the rest over it
      fail(number, static_cast<std::uint32_t>(cr + 1),
           "a carriage return inside the line: line ends of CR alone (classic Mac files) are not read; "
           "convert them to LF or CRLF");
    }
  };
  // The header: the first line that is not blank or a # comment (one of which may state
  // the file's frame).
  std::vector<std::string> header;
  std::vector<std::uint32_t> column_of_field;  // 1-based text column of each header field
  char delimiter = ',';
  std::optional<MeasurementFrame> file_frame;
  while (in.next(line)) {
    number = in.number();
    check_line_end();
    if (is_frame_line(line)) {
      if (file_frame) fail(number, 1, "a second '# frame:' line: a file has one frame");
      file_frame = parse_frame_line(line, name, number);
    } else if (std::optional<StatedField> stated = stated_comment(line, name)) {
      into.stated.push_back(std::move(*stated));
    }
    if (line.find_first_not_of(" \t\r") == std::string::npos || line.front() == '#') continue;
    // A spreadsheet set to a decimal comma writes semicolons (or tabs) between fields.
    delimiter = line.find('\t') != std::string::npos ? '\t' : line.find(';') != std::string::npos ? ';' : ',';
    split(line, delimiter, header, column_of_field);
    break;
  }
  if (header.empty()) fail(0, 0, "the file is empty: a measurement file starts with a header row (x,y,z,...)");
  const std::uint32_t header_line = number;
  Columns cols;
  if (into.sensors.empty()) into.sensors = model.sensors;
  std::vector<int> sensor_column(into.sensors.size(), -1);
  for (std::size_t i = 0; i < header.size(); ++i) {
    const std::string& h = header[i];
    if (h.empty()) fail(header_line, column_of_field[i], fmt::format("column {} has no name", i + 1));
    if (cols.index.count(h)) fail(header_line, column_of_field[i], fmt::format("column '{}' appears twice", h));
    cols.index[h] = i;
    bool known = h == "nx" || h == "ny" || h == "nz" || h == "d" || h == "dx" || h == "dy" || h == "dz" || h == "L" ||
                 h == "t" || h == "source";
    if (h.size() == 1 && kAxes.find(h[0]) != std::string_view::npos) known = true;
    if (h.size() == 2 && h[0] == 'v' && kAxes.find(h[1]) != std::string_view::npos) known = true;
    if (h.starts_with("T_") && h.size() > 2) {
      // A sensor the model lacks is read too: a thermal effect may be what is missing.
      auto it = std::find(into.sensors.begin(), into.sensors.end(), h.substr(2));
      if (it == into.sensors.end()) {
        into.sensors.push_back(h.substr(2));
        sensor_column.push_back(-1);
        for (Observation& o : into.observations) o.temperatures.push_back(std::nan(""));  // earlier files lack it
        it = into.sensors.end() - 1;
      }
      sensor_column[static_cast<std::size_t>(it - into.sensors.begin())] = static_cast<int>(i);
      known = true;
    }
    if (!known) into.notices.push_back(fmt::format("{}: column '{}' is not part of the contract; ignored", name, h));
  }
  for (const char* required : {"x", "y", "z"})
    if (cols.at(required) < 0)
      fail(header_line, 1, fmt::format("the header has no '{}' column (x, y, z are required)", required));
  const bool scalar = cols.at("d") >= 0, full = cols.at("dx") >= 0;
  if (scalar && (cols.at("nx") < 0 || cols.at("ny") < 0 || cols.at("nz") < 0))
    fail(header_line, 1, "a 'd' column needs its direction in nx, ny, nz");
  if (full && (cols.at("dy") < 0 || cols.at("dz") < 0)) fail(header_line, 1, "a 'dx' column needs dy and dz too");
  if (!scalar && !full)
    fail(header_line, 1, "the header has neither nx,ny,nz,d nor dx,dy,dz: there is nothing measured");
  // What the model needs that the file must give.
  for (const model::ErrorTermSpec& t : model.terms)
    for (const model::Variable* v : {&t.primary, &t.secondary}) {
      if (v->kind == model::VariableKind::time && cols.at("t") < 0)
        fail(header_line, 1, fmt::format("term {} depends on the time, and the file has no 't' column", t.name));
      if (v->kind == model::VariableKind::temperature && sensor_column[v->index] < 0)
        fail(header_line, 1,
             fmt::format("term {} depends on sensor '{}', and the file has no 'T_{}' column", t.name,
                         model.sensors[v->index], model.sensors[v->index]));
    }
  for (std::size_t i = 0; i < header.size(); ++i) {
    const std::string& h = header[i];
    if (h.size() == 1 && kAxes.find(h[0]) != std::string_view::npos &&
        !model.axis(static_cast<char>(std::toupper(h[0]))))
      fail(header_line, column_of_field[i],
           fmt::format("column '{}' is an axis machine '{}' does not have", h, model.name));
  }

  // The columns a row is read from, found once (-1: the file has none).
  RowColumns at;
  for (std::size_t i = 0; i < 9; ++i)
    at.axis[i] = cols.at(std::string(1, kAxes[i])), at.direction[i] = cols.at(std::string(kDirectionNames[i]));
  at.L = cols.at("L"), at.t = cols.at("t"), at.source = cols.at("source");
  at.d = cols.at("d"), at.nx = cols.at("nx"), at.ny = cols.at("ny"), at.nz = cols.at("nz");
  at.dx = cols.at("dx"), at.dy = cols.at("dy"), at.dz = cols.at("dz");
  std::vector<std::string> sensor_names;
  for (const std::string& sensor : into.sensors) sensor_names.push_back("T_" + sensor);
  std::map<std::string, std::uint32_t> source_index;
  for (std::size_t s = 0; s < into.sources.size(); ++s) source_index[into.sources[s]] = static_cast<std::uint32_t>(s);
  std::vector<std::string> fields;  // reused row after row
  std::vector<std::uint32_t> at_column;
  // Each row's text hashed, with its line: 16 bytes a row while the file is read (a map of
  // the texts took a hundred and more), sorted once at the end to find the rows read twice.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> row_hashes;
  const std::size_t first_observation = into.observations.size();
  while (in.next(line)) {
    number = in.number();
    check_line_end();
    // A frame said among the rows would be read as a comment and the rows placed in another
    // frame: refused where it stands.
    if (is_frame_line(line)) fail(number, 1, "a '# frame:' line after the header row: put it before the header");
    if (line.find_first_not_of(" \t\r") == std::string::npos || line.front() == '#') continue;
    std::string_view key = line;
    while (!key.empty() && (key.back() == '\r' || key.back() == ' ' || key.back() == '\t')) key.remove_suffix(1);
    row_hashes.emplace_back(std::hash<std::string_view>{}(key), number);
    split(line, delimiter, fields, at_column);
    if (fields.size() != header.size())
      fail(number, 1, fmt::format("this row has {} fields, the header {}", fields.size(), header.size()));
    // A number from column c (its name for messages); `fallback` when the file has no such
    // column or leaves it empty.
    auto value = [&](int c, std::string_view column, double fallback) {
      if (c < 0) return fallback;
      std::string& f = fields[static_cast<std::size_t>(c)];
      if (f.empty()) return fallback;
      if (delimiter != ',') std::replace(f.begin(), f.end(), ',', '.');  // a decimal comma
      double v = 0.0;
      const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
      if (ec != std::errc() || end != f.data() + f.size())
        fail(number, at_column[static_cast<std::size_t>(c)],
             fmt::format("column '{}': '{}' is not a number", column, f));
      if (!std::isfinite(v))
        fail(number, at_column[static_cast<std::size_t>(c)],
             fmt::format("column '{}' is {}: every value must be finite", column, f));
      // Beyond any machine (10 km, 10 million degrees or seconds, degC):
      // a corrupt value, which would otherwise swamp the fit's arithmetic.
      const double largest = c == at.t ? kLatestTime : kLargestReading;
      if (std::abs(v) > largest)
        fail(number, at_column[static_cast<std::size_t>(c)],
             fmt::format("column '{}' is {}: beyond any machine's range (at most {:g})", column, f, largest));
      return v;
    };
    auto required = [&](int c, std::string_view column) {
      if (fields[static_cast<std::size_t>(c)].empty())
        fail(number, at_column[static_cast<std::size_t>(c)], fmt::format("column '{}' is empty", column));
      return value(c, column, 0.0);
    };
    Observation o;
    o.row = number;
    o.file = file_index;
    const double tool = value(at.L, "L", options.tool_length);
    for (std::size_t i = 0; i < 9; ++i) {
      const std::string_view axis = kAxes.substr(i, 1);
      const bool rotary = angular_at(i);
      const double v = i < 3 ? required(at.axis[i], axis) : value(at.axis[i], axis, 0.0);
      o.q[static_cast<Eigen::Index>(i)] = rotary ? v * kRadPerDeg : v;
      const double sign = value(at.direction[i], kDirectionNames[i], 0.0);
      if (sign != 0.0 && sign != 1.0 && sign != -1.0)
        fail(number, at_column[static_cast<std::size_t>(at.direction[i])],
             fmt::format("column 'v{}' is {}: an approach direction is +1, -1 or 0 (unknown)", axis, sign));
      o.directions[i] = static_cast<std::int8_t>(sign);
    }
    // Program coordinates carry the tool length: the Z axis sits L above the tool tip.
    o.q[2] += tool;
    o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)] = tool;
    o.time = value(at.t, "t", 0.0);
    o.temperatures.assign(into.sensors.size(), std::nan(""));  // a sensor this file does not read
    for (std::size_t s = 0; s < model.sensors.size(); ++s) o.temperatures[s] = 20.0;  // the model's: unused then
    for (std::size_t s = 0; s < sensor_column.size(); ++s) {
      if (sensor_column[s] < 0) continue;
      const bool models = s < model.sensors.size();  // the model's own must be read on every row
      if (models || !fields[static_cast<std::size_t>(sensor_column[s])].empty())
        o.temperatures[s] = required(sensor_column[s], sensor_names[s]);
    }
    std::string label = name;
    if (at.source >= 0 && !fields[static_cast<std::size_t>(at.source)].empty())
      label = fields[static_cast<std::size_t>(at.source)];
    const auto [it, added] = source_index.try_emplace(label, static_cast<std::uint32_t>(into.sources.size()));
    if (added) into.sources.push_back(label);
    o.source = it->second;
    if (scalar && !fields[static_cast<std::size_t>(at.d)].empty()) {
      const Eigen::Vector3d n(required(at.nx, "nx"), required(at.ny, "ny"), required(at.nz, "nz"));
      if (std::abs(n.norm() - 1.0) > 1e-3)
        fail(number, at_column[static_cast<std::size_t>(at.nx)],
             fmt::format("the direction ({}, {}, {}) is not a unit vector (length {:.6f})", n.x(), n.y(), n.z(),
                         n.norm()));
      o.direction = n.normalized();
      o.value = required(at.d, "d");
      into.observations.push_back(o);
    }
    if (full && !fields[static_cast<std::size_t>(at.dx)].empty()) {
      const double d[3] = {required(at.dx, "dx"), required(at.dy, "dy"), required(at.dz, "dz")};
      for (int k = 0; k < 3; ++k) {
        Observation along = o;
        along.direction = Eigen::Vector3d::Unit(k);
        along.value = d[k];
        into.observations.push_back(along);
      }
    }
  }
  line.clear();
  io::place_in_machine(into, first_observation, resolve_frame(file_frame, options.frame, model, name), model, name);
  note_repeated_rows(row_hashes, name, into.notices);
  if (into.observations.size() == first_observation)
    fail(header_line, 1, "no readings after the header: there is nothing to compare the model with");
  check_magnitude(into, first_observation, model, [&](std::uint32_t row, const std::string& message) {
    const int c = cols.at(scalar ? "d" : "dx");
    fail(row, c >= 0 ? column_of_field[static_cast<std::size_t>(c)] : 1, message);
  });
}

void parse_measurements(const std::string& text, const std::string& name, const model::MachineModel& model,
                        const ReadOptions& options, MeasurementSet& into) {
  std::istringstream in(text);
  io::detect_format(std::string_view(text).substr(0, io::kDetectBytes), name).read(in, name, model, options, into);
}

void read_measurements(const std::string& path, const model::MachineModel& model, const ReadOptions& options,
                       MeasurementSet& into) {
  // Read as a stream, a line at a time: the file is never held whole.
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(ErrorKind::io, fmt::format("cannot read measurement file '{}'", path));
  std::string head(io::kDetectBytes, '\0');
  f.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(f.gcount()));
  f.clear();
  f.seekg(0);
  if (!f) throw Error(ErrorKind::io, fmt::format("cannot read measurement file '{}' (not a file one can read twice)", path));
  io::detect_format(head, path).read(f, path, model, options, into);
}

double file_axis_value(const Observation& o, std::size_t axis, bool rotary) {
  const double q = o.q[static_cast<Eigen::Index>(axis)];
  if (rotary) return q / kRadPerDeg;
  return axis == 2 ? q - o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)] : q;
}

void summarize(MeasurementSet& set, const model::MachineModel& model) {
  set.ranges.clear();
  if (set.observations.empty()) return;
  auto add = [&](const std::string& name, const std::string& unit, auto get) {
    VariableRange r{name, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), unit};
    for (const Observation& o : set.observations)
      if (const double v = get(o); !std::isnan(v)) r.min = std::min(r.min, v), r.max = std::max(r.max, v);
    if (r.min <= r.max) set.ranges.push_back(r);
  };
  for (const model::AxisSpec& a : model.axes) {
    const std::size_t i = a.index();
    const bool rotary = a.type == model::AxisType::rotary;
    // As the files write it: in each file's own frame.
    add(std::string(1, static_cast<char>(std::tolower(a.letter))), rotary ? "deg" : "mm", [&](const Observation& o) {
      if (o.file >= set.frames.size()) return file_axis_value(o, i, rotary);
      const ResolvedFrame& f = set.frames[o.file];
      const bool machine_z = f.frame.kind == FrameKind::machine && i == 2;  // the axis itself, tool not taken off
      return file_axis_value(o, i, rotary) - f.origin[i] +
             (machine_z ? o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)] : 0.0);
    });
  }
  add("L", "mm", [](const Observation& o) { return o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)]; });
  add("t", "s", [](const Observation& o) { return o.time; });
  const std::vector<std::string>& sensors = set.sensors.empty() ? model.sensors : set.sensors;
  for (std::size_t s = 0; s < sensors.size(); ++s)
    add("T_" + sensors[s], "degC",
        [&](const Observation& o) { return s < o.temperatures.size() ? o.temperatures[s] : std::nan(""); });
}

double predict(const model::ForwardModel& model, model::ForwardData& data, const Observation& o) {
  model::forward(model, data, o.q, MeasurementSet::conditions(o));
  return o.direction.dot(model::deviation(data));
}

std::string to_csv(const MeasurementSet& set, const model::MachineModel& model, const ResolvedFrame& frame) {
  std::string out = frame_line(frame) + "\n";
  // What the files state beside their readings, as the comments the reader takes back.
  for (const StatedField& f : set.stated)
    if (util::lower_ascii(f.key) != "frame" && f.key.size() <= 60) out += fmt::format("# {}: {}\n", f.key, f.value);
  out += "x,y,z";
  std::vector<std::size_t> rotary;
  for (const model::AxisSpec& a : model.axes)
    if (a.type == model::AxisType::rotary) {
      rotary.push_back(a.index());
      out += fmt::format(",{}", static_cast<char>(std::tolower(a.letter)));
    }
  out += ",L,t";
  for (const std::string& s : set.sensors.empty() ? model.sensors : set.sensors) out += ",T_" + s;
  out += ",vx,vy,vz";
  for (std::size_t i : rotary) out += fmt::format(",v{}", kAxes[i]);
  out += ",nx,ny,nz,d,source\n";
  for (const Observation& o : set.observations) {
    const double tool = o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
    const bool machine = frame.frame.kind == FrameKind::machine;
    out += fmt::format("{:.6f},{:.6f},{:.6f}", o.q[0] - frame.origin[0], o.q[1] - frame.origin[1],
                       o.q[2] - frame.origin[2] - (machine ? 0.0 : tool));
    for (std::size_t i : rotary)
      out += fmt::format(",{:.6f}", o.q[static_cast<Eigen::Index>(i)] / kRadPerDeg - frame.origin[i]);
    out += fmt::format(",{:.3f},{:.3f}", tool, o.time);
    for (double T : o.temperatures) out += std::isnan(T) ? std::string(",") : fmt::format(",{:.4f}", T);
    for (std::size_t i = 0; i < 3; ++i) out += fmt::format(",{}", static_cast<int>(o.directions[i]));
    for (std::size_t i : rotary) out += fmt::format(",{}", static_cast<int>(o.directions[i]));
    out += fmt::format(",{:.9g},{:.9g},{:.9g},{:.9e},{}\n", o.direction.x(), o.direction.y(), o.direction.z(), o.value,
                       set.sources[o.source]);
  }
  return out;
}

}  // namespace ccomp::identify
