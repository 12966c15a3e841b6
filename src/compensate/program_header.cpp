#include "ccomp/compensate/program_header.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <string>
#include <system_error>

#include "ccomp/error.hpp"
#include "ccomp/version.hpp"
#include "ccomp/util/ascii.hpp"

namespace ccomp::compensate {
namespace {

constexpr std::string_view kWorkOffsets = "work offsets ", kSensors = "sensors ", kTime = "time ";

/// "G54 X0 Y0 Z-400, G55 X100 Y0 Z0" (or "none") as header_line() writes it.
std::optional<model::WorkOffsets> read_work_offsets(std::string_view text) {
  model::WorkOffsets offsets;
  if (text == "none") return offsets;
  while (!text.empty()) {
    const auto comma = text.find(',');
    const std::string_view one = text.substr(0, comma);
    try {
      const model::WorkOffsetEntry e = model::parse_work_offset(one, "the header");
      offsets.set(e.system, e.origin);
    } catch (const Error&) {
      return std::nullopt;
    }
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  return offsets;
}

/// "bed=20, column=21.5" as header_line() writes it (nullopt: not that).
std::optional<std::vector<model::SensorReading>> read_sensors(std::string_view text) {
  std::vector<model::SensorReading> readings;
  while (!text.empty()) {
    const auto comma = text.find(", ");
    try {
      readings.push_back(model::parse_sensor_reading(std::string(text.substr(0, comma))));
    } catch (const Error&) {
      return std::nullopt;
    }
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 2);
  }
  return readings;
}

/// "3600 s" as header_line() writes it.
std::optional<double> read_time(std::string_view text) {
  double s = 0.0;
  const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), s);
  if (ec != std::errc() || std::string_view(p, text.data() + text.size()) != " s") return std::nullopt;
  return s;
}

/// A sensor's name the header can carry and give back: none of the characters that end a
/// comment, a reading or the list.
bool fits_header(const std::string& name) {
  return name.find_first_of("()=;,\n\r") == std::string::npos;
}

/// "; sensors bed=20, column=21.5" in the model's sensor order (nothing when none was given,
/// or a name the header could not give back: a check then needs --sensor, as before).
std::string sensors_part(const model::MachineModel& model, const std::vector<model::SensorReading>& readings) {
  if (readings.empty()) return "";
  std::vector<const model::SensorReading*> ordered;
  for (const std::string& sensor : model.sensors)
    for (const model::SensorReading& r : readings)
      if (r.first == sensor) ordered.push_back(&r);
  for (const model::SensorReading& r : readings)  // a name the model lacks (the job refuses it) last
    if (std::find(model.sensors.begin(), model.sensors.end(), r.first) == model.sensors.end()) ordered.push_back(&r);
  std::string out = fmt::format("; {}", kSensors);
  for (std::size_t i = 0; i < ordered.size(); ++i) {
    if (!fits_header(ordered[i]->first)) return "";
    out += fmt::format("{}{}={}", i ? ", " : "", ordered[i]->first, ordered[i]->second);
  }
  return out;
}

/// The model's name inside a comment: no parenthesis or line end may close it early.
std::string sanitize(std::string_view s) {
  std::string out;
  for (char c : s) out.push_back(c == '(' || c == ')' || c == '\n' || c == '\r' ? '_' : c);
  return out;
}

}  // namespace

std::string header_line(const model::MachineModel& model, double tolerance, const RunConditions& conditions,
                        bool parenthesis_comments) {
  // Shortest round-trip numbers ({}): a check reads back the very readings and time.
  const std::string text = fmt::format(
      "ccomp {} compensated for machine '{}' model sha256:{} at {:g} um; {}{}{}{}", kVersion, sanitize(model.name),
      model.sha256, tolerance * 1000.0, kWorkOffsets, model::describe_work_offsets(conditions.work_offsets),
      sensors_part(model, conditions.sensors), conditions.time ? fmt::format("; {}{} s", kTime, *conditions.time) : std::string());
  return parenthesis_comments ? "(" + text + ")" : "; " + text;
}

std::optional<HeaderFacts> read_header(std::string_view line) {
  if (!is_header_line(line)) return std::nullopt;
  HeaderFacts facts;
  constexpr std::string_view kSha = "model sha256:", kAt = " at ";
  // (The hash and the tolerance read in any case: an upper-cased header is still ours.)
  const std::string lower = util::lower_ascii(line);
  const std::string_view original = line;
  line = lower;
  if (const auto sha = line.rfind(kSha); sha != std::string_view::npos) {
    const auto begin = sha + kSha.size();
    const auto end = line.find_first_not_of("0123456789abcdef", begin);
    facts.model_sha256 = std::string(line.substr(begin, end == std::string_view::npos ? end : end - begin));
    if (end != std::string_view::npos && line.substr(end).starts_with(kAt)) {
      double um = 0.0;
      const std::string_view number = line.substr(end + kAt.size());
      if (const auto [p, ec] = std::from_chars(number.data(), number.data() + number.size(), um);
          ec == std::errc() && (std::string_view(p, number.data() + number.size()).starts_with(" um)") ||
                                std::string_view(p, number.data() + number.size()).starts_with(" um;")))
        facts.tolerance = um / 1000.0;
    }
  }
  // What the run assumed: "; "-separated parts after the tolerance, up to the closing ')';
  // found in the lower-cased line, their values read from the line as written (sensor names
  // keep their case).
  const auto sha = line.rfind(kSha);
  const auto tail = line.find(" um; ", sha == std::string_view::npos ? 0 : sha);
  auto close = line.rfind(')');
  if (close == std::string_view::npos || close < tail) close = line.size();  // the `; ccomp ...` form
  if (tail == std::string_view::npos) return facts;
  std::size_t at = tail + 5;
  while (at < close) {
    const auto semicolon = std::min(line.find("; ", at), close);
    const std::string_view part = line.substr(at, semicolon - at), as_written = original.substr(at, semicolon - at);
    if (part.starts_with(kWorkOffsets)) facts.work_offsets = read_work_offsets(as_written.substr(kWorkOffsets.size()));
    if (part.starts_with(kSensors)) facts.sensors = read_sensors(as_written.substr(kSensors.size()));
    if (part.starts_with(kTime)) facts.time = read_time(as_written.substr(kTime.size()));
    at = semicolon + 2;
  }
  return facts;
}

/// A line that is one comment, `( ... )` or `; ...`: its text lower-cased with every blank
/// taken out (a Fanuc control or a DNC transfer stores comments upper-cased, an editor may
/// respace them); empty for any other line.
std::string comment_letters(std::string_view line) {
  if (line.starts_with("\xEF\xBB\xBF")) line.remove_prefix(3);  // a byte-order mark before it
  const auto first = line.find_first_not_of(" \t");
  if (first == std::string_view::npos || (line[first] != '(' && line[first] != ';')) return {};
  std::string letters;
  for (const char c : line.substr(first + 1))
    if (c != ' ' && c != '\t' && c != '\r') letters.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  return letters;
}

bool is_header_line(std::string_view line) {
  const std::string letters = comment_letters(line);
  return letters.starts_with("ccomp") && letters.find("compensatedformachine") != std::string::npos;
}

}  // namespace ccomp::compensate
