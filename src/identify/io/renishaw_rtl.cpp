// Renishaw's laser data file, the .rtl text that Laser10 and LaserXL write for a linear or
// an angular (rotary) positioning test.
//
// What the format is, as this reader takes it. The stored public corpora this project
// searches (code, pages, issues, docs: "rtl Renishaw laser file parser", "Target-Count
// Run-count", "Laser10 rtl", "Renishaw rtl") hold no reader of it and no file, so the layout
// below is the one the brief of issue 45 names (Target-Count, Run-count) filled in from what
// such a test records; it is written down here so that a real file that differs is easy to
// compare, and the reader refuses, at its line, anything it does not understand rather than
// guess:
//
//   - free text first (the software's name, "Renishaw" in it, a title, the machine, dates);
//   - "key: value" lines, several on one line allowed, keys in any case with '-' or blanks:
//       Axis: X                      the axis measured (a rotary one for an angular test)
//       Units: mm | inch | deg       the targets' unit
//       Error units: um | mm | arcsec | deg   the deviations' (errors') unit
//       Target-Count: N  Run-count: M
//   - "Targets:" then the N targets (mm, inch or deg), on that line or the next ones;
//   - per run "Run: k" with "Dir: Fwd" (the targets in their listed order), "Dir: Bwd" (the
//     list reversed) or no Dir (a run there and back: N readings in the listed order, then N
//     in the reverse; or N one way), then the errors (actual - target) in the order the run
//     visited the targets, on that line or the next ones.
//
// The run count is checked against the runs read; a reading's line is the line its number
// is on. Without "Error units" the deviations go through the plausibility rule of
// identify/axis_runs, as any file without a unit does.
#include <fmt/format.h>

#include <algorithm>

#include "ccomp/error.hpp"
#include "ccomp/identify/axis_runs.hpp"
#include "ccomp/identify/measurement_formats.hpp"
#include "line_reader.hpp"
#include "text_fields.hpp"

namespace ccomp::identify::io {
namespace {

bool detect(std::string_view head) {
  const std::string text = lower(head);
  return text.find("target-count") != std::string::npos ||
         (text.find("renishaw") != std::string::npos && text.find("targets") != std::string::npos);
}

/// A number of a block of values, with its line.
struct Value {
  double value = 0.0;
  std::uint32_t line = 0;
};

/// The key-value pairs of a line: "Target-Count: 6  Run-count: 4" -> {targetcount, 6},
/// {runcount, 4}. The first key may be several words ("Error units: um"), the keys after it
/// one word each.
std::vector<std::pair<std::string, std::string>> pairs_of(std::string_view line) {
  std::vector<std::string_view> parts;
  for (std::size_t start = 0;;) {
    const std::size_t colon = line.find(':', start);
    parts.push_back(line.substr(start, colon == std::string_view::npos ? std::string_view::npos : colon - start));
    if (colon == std::string_view::npos) break;
    start = colon + 1;
  }
  std::vector<std::pair<std::string, std::string>> pairs;
  std::string key = fold(parts.front());
  for (std::size_t i = 1; i < parts.size(); ++i) {
    std::vector<Field> words = split_blanks(parts[i]);
    std::string next_key;
    if (i + 1 < parts.size() && !words.empty()) {
      next_key = fold(words.back().text);
      words.pop_back();
    }
    std::string value;
    for (const Field& w : words) value += (value.empty() ? "" : " ") + w.text;
    pairs.emplace_back(key, value);
    key = next_key;
  }
  return pairs;
}

class RtlReader {
 public:
  RtlReader(std::istream& in, const std::string& name) : lines_(in, name), name_(name) {}

  AxisRuns read() {
    while (next_line()) {
      const std::string folded = fold(line_);
      if (folded.starts_with("targets")) {
        read_targets();
      } else if (folded.starts_with("run") && !folded.starts_with("runcount")) {
        read_run();
      } else {
        settings();
      }
    }
    if (targets_.empty()) fail_at(0, "no 'Targets:' block: not a laser file this reader understands");
    if (run_count_ > 0 && runs_read_ != run_count_)
      fail_at(lines_.number(), fmt::format("Run-count says {} runs, and the file has {}", run_count_, runs_read_));
    return std::move(runs_);
  }

 private:
  bool next_line() {
    if (pending_) {
      pending_ = false;
      return true;
    }
    return lines_.next(line_);
  }
  [[noreturn]] void fail_at(std::uint32_t line, const std::string& message) {
    throw Error(ErrorKind::data, message, SourceLocation{name_, line, 1}, line == lines_.number() ? line_.substr(0, 200) : std::string());
  }

  void settings() {
    for (const auto& [key, value] : pairs_of(line_)) {
      if (key == "axis") {
        const std::string v = fold(value);
        if (v.size() != 1 || std::string_view("xyzabc").find(v[0]) == std::string_view::npos)
          fail_at(lines_.number(), fmt::format("Axis: '{}' is not an axis letter (X Y Z A B C)", value));
        runs_.axis = static_cast<char>(std::toupper(static_cast<unsigned char>(v[0])));
      } else if (key == "units" || key == "targetunits" || key == "linearunits" || key == "angularunits") {
        runs_.target_unit = unit(value);
      } else if (key == "errorunits" || key == "deviationunits") {
        runs_.deviation_unit = unit(value);
        runs_.unit_line = lines_.number();
      } else if (key == "targetcount") {
        target_count_ = count(value, "Target-Count");
      } else if (key == "runcount") {
        run_count_ = count(value, "Run-count");
      }
    }
  }
  Unit unit(const std::string& text) {
    const std::optional<Unit> u = parse_unit(text);
    if (!u) fail_at(lines_.number(), fmt::format("'{}' is not a unit (mm, um, inch, deg, arcsec)", text));
    return *u;
  }
  int count(const std::string& text, std::string_view key) {
    const std::optional<double> v = parse_number(text, false);
    if (!v || *v < 1 || *v > 100000 || *v != std::floor(*v))
      fail_at(lines_.number(), fmt::format("{}: '{}' is not a count", key, text));
    return static_cast<int>(*v);
  }

  /// The numbers after the keyword's colon on this line and on the lines after it, up to a
  /// line that is not numbers (left for the caller).
  std::vector<Value> values() {
    std::vector<Value> out;
    auto take = [&](std::string_view text) {
      for (const Field& f : split_blanks(text)) {
        const std::optional<double> v = parse_number(f.text, false);
        if (!v || std::abs(*v) > 1e7) return false;
        out.push_back({*v, lines_.number()});
      }
      return true;
    };
    const std::size_t colon = line_.find(':');
    std::string_view rest = colon == std::string::npos ? std::string_view() : std::string_view(line_).substr(colon + 1);
    if (fold(line_).starts_with("run")) rest = {};  // "Run: 1 Dir: Fwd": its words are not values
    if (!take(rest)) fail_at(lines_.number(), "a value that is not a number");
    while (lines_.next(line_)) {
      if (line_.find_first_not_of(" \t\r") == std::string::npos) continue;
      const std::size_t size = out.size();
      if (!take(line_)) {
        if (out.size() != size) fail_at(lines_.number(), "a line of values with one that is not a number");
        pending_ = true;
        break;
      }
    }
    return out;
  }

  void read_targets() {
    const std::uint32_t line = lines_.number();
    for (const Value& v : values()) targets_.push_back(v.value);
    if (targets_.size() < 2) fail_at(line, "fewer than two targets");
    if (target_count_ > 0 && static_cast<int>(targets_.size()) != target_count_)
      fail_at(line, fmt::format("Target-Count says {} targets, and the block has {}", target_count_, targets_.size()));
  }

  void read_run() {
    if (targets_.empty()) fail_at(lines_.number(), "a run before the 'Targets:' block");
    const std::uint32_t line = lines_.number();
    int run = 0, direction = 0;
    for (const auto& [key, value] : pairs_of(line_)) {
      if (key == "run") {
        const std::optional<double> v = parse_number(value, false);
        if (!v || *v != std::floor(*v) || *v < 0 || *v > 1e6) fail_at(line, fmt::format("Run: '{}' is not a run number", value));
        run = static_cast<int>(*v);
      } else if (key == "dir" || key == "direction") {
        const std::optional<int> d = parse_direction(value);
        if (!d || *d == 0) fail_at(line, fmt::format("Dir: '{}' is Fwd or Bwd", value));
        direction = *d;
      }
    }
    ++runs_read_;
    const std::vector<Value> errors = values();
    const std::size_t n = targets_.size();
    if (errors.size() != n && !(direction == 0 && errors.size() == 2 * n))
      fail_at(line, fmt::format("run {} has {} errors for {} targets ({} expected{})", run, errors.size(), n, n,
                                direction == 0 ? fmt::format(", or {} there and back", 2 * n) : ""));
    const int listed = targets_.back() > targets_.front() ? 1 : -1;  // the listed order's direction
    for (std::size_t k = 0; k < errors.size(); ++k) {
      const bool back = direction < 0 || k >= n;
      AxisReading r;
      r.target = targets_[back ? n - 1 - (k % n) : k % n];
      r.deviation = errors[k].value;
      r.run = run;
      r.approach = direction == 0 ? 0 : listed * direction;  // 0: from the run's order
      r.line = errors[k].line;
      runs_.readings.push_back(r);
    }
  }

  LineReader lines_;
  std::string name_;
  std::string line_;
  bool pending_ = false;  // line_ is read and not yet handled
  AxisRuns runs_;
  std::vector<double> targets_;
  int target_count_ = 0, run_count_ = 0, runs_read_ = 0;
};

void read(std::istream& in, const std::string& name, const model::MachineModel& model, const ReadOptions& options,
          MeasurementSet& into) {
  const AxisRuns runs = RtlReader(in, name).read();
  append_axis_runs(runs, name, model, options, into);
}

}  // namespace

const MeasurementFormat& renishaw_rtl_format() {
  static const MeasurementFormat format{
      "renishaw-rtl", "Renishaw Laser10 / LaserXL .rtl text (Target-Count, Targets:, Run: blocks)", detect, read};
  return format;
}

}  // namespace ccomp::identify::io
