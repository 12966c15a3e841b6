// Renishaw's laser data file, the .rtl text that Laser10 and LaserXL write for a linear or
// an angular (rotary) positioning test.
//
// What the format is, as this reader takes it, and from where. The public corpora this
// project searches hold no Renishaw file and one public reader of its text: a PyQt
// laser-plot tool found by the code index's exact-string search ("Renishaw Laser"; the index
// names no repository) reads a Renishaw text file (it offers *.rta and *.rtl) as: "Renishaw"
// somewhere in it; header lines "Machine: ...", "Serial No: ...", "Date: ..."; "Targets :"
// followed by the targets separated by blanks up to "Flags"; "Run Target Data:" followed by a
// line per reading whose last field is the error, up to "EQUIPMENT::"; the first half of the
// readings one way over the targets and the second half back, in reverse order. Issue 45's
// brief names "Target-Count" and "Run-count" as keys of the header. Read here (no code
// copied), with what a test records filled in where neither says:
//
//   - free text, "key: value" lines (several on a line, the keys after the first one word
//     each), keys in any case, with '-' or blanks, a blank before the colon allowed:
//       Axis: X                      the axis measured (a rotary one for an angular test)
//       Units: mm | inch | deg       the targets' unit
//       Error units: um | mm | arcsec | deg   the deviations' (errors') unit
//       Target-Count: N  Run-count: M   checked against the targets and runs read
//     any other key (Machine, Serial No, Date, temperatures) is the report's, kept as stated
//     (identify/stated_conditions.hpp);
//   - "Targets :" then the N targets (mm, inch or deg), on that line or the next ones, up to
//     a word that is not a number ("Flags");
//   - the readings, either as "Run Target Data:" above (passes there and back, run after run,
//     each line's last number the error), or per run "Run: k" with "Dir: Fwd" (the targets
//     in their listed order), "Dir: Bwd" (the list reversed) or no Dir (N readings in the
//     listed order, or 2N there and back), then its errors (actual - target) in the order
//     the run visited the targets.
//
// Where neither the file nor the order says, the approach comes from the run order
// (identify/axis_runs). Without "Error units" (the public reader assumes its own scale) the
// deviations go through the plausibility rule of identify/axis_runs, as any file without a
// unit does: state it with --unit. Anything else is refused at its line rather than guessed:
// a real file that differs should be compared with this and the reader corrected here.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>

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

/// A "key: value" pair of a line, its key folded ("targetcount") and as written.
struct KeyValue {
  std::string key, written, value;
};

/// The key-value pairs of a line: "Target-Count: 6  Run-count: 4" -> {targetcount, 6},
/// {runcount, 4}. The first key may be several words ("Error units: um"); a later one is
/// the words after the previous value's last number ("Material temperature: 20.4  Air
/// temperature: 20.9"), or its last word where the value has no number.
std::vector<KeyValue> pairs_of(std::string_view line) {
  std::vector<std::string_view> parts;
  for (std::size_t start = 0;;) {
    const std::size_t colon = line.find(':', start);
    parts.push_back(line.substr(start, colon == std::string_view::npos ? std::string_view::npos : colon - start));
    if (colon == std::string_view::npos) break;
    start = colon + 1;
  }
  auto joined = [](const std::vector<Field>& words, std::size_t from, std::size_t to) {
    std::string text;
    for (std::size_t k = from; k < to; ++k) text += (text.empty() ? "" : " ") + words[k].text;
    return text;
  };
  std::vector<KeyValue> pairs;
  const std::vector<Field> first = split_blanks(parts.front());
  std::string written = joined(first, 0, first.size());
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const std::vector<Field> words = split_blanks(parts[i]);
    std::size_t value_end = words.size();
    if (i + 1 < parts.size() && !words.empty()) {
      value_end = words.size() - 1;
      for (std::size_t k = words.size() - 1; k-- > 0;)
        if (parse_number(words[k].text, false)) {
          value_end = k + 1;
          break;
        }
    }
    pairs.push_back({fold(written), written, joined(words, 0, value_end)});
    written = joined(words, value_end, words.size());
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
      } else if (folded.starts_with("runtargetdata")) {
        read_run_target_data();
      } else if (const auto pairs = pairs_of(line_); !pairs.empty() && pairs.front().key == "run") {
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
    for (const auto& [key, written, value] : pairs_of(line_)) {
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
      } else if (!key.empty() && !value.empty()) {
        runs_.stated.push_back({written, value, name_});  // the report's: title, machine, temperatures, ...
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
  /// line, or a word within one ("Targets : 0  10  20  Flags : ..."), that is not a number:
  /// what starts there is left for the caller as the next line.
  std::vector<Value> values() {
    std::vector<Value> out;
    // Takes the numbers of line_ from `from`; where a word that is not one starts, or npos.
    auto take = [&](std::size_t from) {
      for (const Field& f : split_blanks(std::string_view(line_).substr(from))) {
        const std::optional<double> v = parse_number(f.text, false);
        if (!v || std::abs(*v) > 1e7) return from + f.column - 1;
        out.push_back({*v, lines_.number()});
      }
      return std::string::npos;
    };
    // What follows a word that is not a number: the next key ("Flags :"), else a bad value.
    auto stop = [&](std::size_t at) {
      if (!std::isalpha(static_cast<unsigned char>(line_[at])) || line_.find(':', at) == std::string::npos ||
          out.empty())
        fail_at(lines_.number(), fmt::format("'{}' is not a number", split_blanks(line_.substr(at)).front().text));
      line_.erase(0, at);
      pending_ = true;
    };
    const std::size_t colon = line_.find(':');
    // "Run: 1 Dir: Fwd": its words are no values
    if (colon != std::string::npos && !fold(line_).starts_with("run"))
      if (const std::size_t at = take(colon + 1); at != std::string::npos) {
        stop(at);
        return out;
      }
    while (lines_.next(line_)) {
      if (line_.find_first_not_of(" \t\r") == std::string::npos) continue;
      const std::size_t size = out.size();
      if (const std::size_t at = take(0); at != std::string::npos) {
        if (out.size() == size) {
          pending_ = true;  // a line of words: the next keyword
        } else {
          stop(at);
        }
        break;
      }
    }
    return out;
  }

  /// "Run Target Data:" and a line per reading, its error the last number of the line, in
  /// the order measured: passes of the targets there and back, run after run (as the public
  /// reader named in the header takes the file).
  void read_run_target_data() {
    if (targets_.empty()) fail_at(lines_.number(), "'Run Target Data' before the 'Targets :' block");
    const std::uint32_t first = lines_.number();
    std::vector<Value> errors;
    while (lines_.next(line_)) {
      if (line_.find_first_not_of(" \t\r") == std::string::npos) continue;
      const std::vector<Field> words = split_blanks(line_);
      if (!parse_number(words.front().text, false)) {
        pending_ = true;  // "EQUIPMENT::" and what follows
        break;
      }
      for (const Field& w : words)
        if (const std::optional<double> v = parse_number(w.text, false); !v || std::abs(*v) > 1e7)
          fail_at(lines_.number(), fmt::format("'{}' is not a number", w.text));
      errors.push_back({*parse_number(words.back().text, false), lines_.number()});
    }
    const std::size_t n = targets_.size();
    if (errors.empty() || errors.size() % n != 0)
      fail_at(first, fmt::format("{} readings for {} targets: not whole passes over the targets", errors.size(), n));
    for (std::size_t k = 0; k < errors.size(); ++k) {
      const std::size_t pass = k / n;
      AxisReading r;
      r.target = targets_[pass % 2 == 1 ? n - 1 - k % n : k % n];
      r.deviation = errors[k].value;
      r.run = static_cast<int>(pass / 2) + 1;
      r.line = errors[k].line;
      runs_.readings.push_back(r);  // the approach from the run's order
    }
    runs_read_ += static_cast<int>((errors.size() / n + 1) / 2);
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
    for (const auto& [key, written, value] : pairs_of(line_)) {
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
