#include "trace_capture.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "ccomp/gcode/trace.hpp"

namespace ccomp::test {
namespace {

class CapturingPrinter : public gcode::TracePrinter {
 public:
  CapturingPrinter(std::FILE* f, std::vector<std::string>& warnings) : TracePrinter(f), warnings_(warnings) {}
  void warning(const std::string& message, std::uint32_t /*line*/) override { warnings_.push_back(message); }

 private:
  std::vector<std::string>& warnings_;
};

TraceResult run(gcode::LineSource& source, const gcode::InterpreterOptions& options) {
  TraceResult result;
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* f = open_memstream(&buffer, &size);
  {
    CapturingPrinter printer(f, result.warnings);
    gcode::Interpreter interpreter(options);
    try {
      interpreter.run(source, printer);
    } catch (const Error& e) {
      result.error = e;
    }
  }
  std::fclose(f);
  std::istringstream in(std::string(buffer, size));
  std::free(buffer);
  for (std::string line; std::getline(in, line);) result.lines.push_back(line);
  return result;
}

}  // namespace

TraceResult trace_file(const std::string& path, const gcode::InterpreterOptions& options) {
  gcode::LineSource source = gcode::LineSource::open(path);
  return run(source, options);
}

TraceResult trace_text(const std::string& program, const gcode::InterpreterOptions& options) {
  gcode::LineSource source = gcode::LineSource::from_string(program, "test.ngc");
  return run(source, options);
}

namespace {

class RecordingSink : public gcode::CanonSink {
 public:
  explicit RecordingSink(RunResult& r) : r_(r) {}
  void motion(const gcode::Motion& m) override {
    r_.motions.push_back({m, *m.offsets});
    r_.motions.back().motion.offsets = nullptr;
  }
  void call(const gcode::CanonCall& c) override {
    if (c.name == "MESSAGE") r_.messages.push_back(c.arguments.substr(1, c.arguments.size() - 2));
  }
  [[nodiscard]] bool wants_calls() const override { return true; }
  void warning(const std::string& message, std::uint32_t /*line*/) override { r_.warnings.push_back(message); }

 private:
  RunResult& r_;
};

}  // namespace

RunResult run_program(const std::string& program, const gcode::InterpreterOptions& options) {
  RunResult r;
  gcode::LineSource source = gcode::LineSource::from_string(program, "test.ngc");
  RecordingSink sink(r);
  gcode::Interpreter interpreter(options);
  try {
    interpreter.run(source, sink);
  } catch (const Error& e) {
    r.error = e;
  }
  return r;
}

double evaluate(const std::string& expression) {
  const RunResult r = run_program("G21 G0 X[" + expression + "]\nM2\n");
  if (r.error) throw *r.error;
  if (r.motions.size() != 1) throw std::runtime_error("no motion for " + expression);
  return r.motions[0].motion.end[0];
}

std::vector<std::string> calls_named(const std::vector<std::string>& lines, const std::string& name) {
  std::vector<std::string> out;
  const std::string key = name + "(";
  for (const std::string& l : lines) {
    const auto at = l.find(key);
    if (at == std::string::npos) continue;
    const auto close = l.rfind(')');
    out.push_back(l.substr(at + key.size(), close - at - key.size()));
  }
  return out;
}

std::vector<std::string> motion_calls(const std::vector<std::string>& lines) {
  static const std::regex call(R"((STRAIGHT_TRAVERSE|STRAIGHT_FEED|ARC_FEED|STRAIGHT_PROBE|MESSAGE)\((.*)\)$)");
  std::vector<std::string> out;
  for (const std::string& l : lines) {
    std::smatch m;
    if (std::regex_search(l, m, call)) out.push_back(m[1].str() + "(" + m[2].str() + ")");
  }
  return out;
}

std::vector<std::string> observable(const std::vector<std::string>& lines, bool awk) {
  static const std::regex call(R"(^\s*(\d+\s+)?N\S*\s+([A-Z_0-9.]+)\((.*)\)\s*$)");
  std::vector<std::string> out;
  for (std::string line : lines) {
    if (awk) {
      std::istringstream in(line);
      std::string field, joined;
      in >> field;  // dropped
      while (in >> field) joined += " " + field;
      line = joined;
    }
    std::smatch m;
    if (std::regex_match(line, m, call)) {
      const std::string name = m[2].str();
      if (name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED" || name == "ARC_FEED" || name == "STRAIGHT_PROBE" ||
          name == "MESSAGE")
        out.push_back(name + "(" + m[3].str() + ")");
      continue;
    }
    if (line.find_first_not_of(" \t") == std::string::npos || line == "executing") continue;
    std::istringstream in(line);
    std::string word, text;
    while (in >> word) text += (text.empty() ? "" : " ") + word;
    out.push_back("PRINT " + text);
  }
  return out;
}

std::optional<std::string> compare_calls(const std::vector<std::string>& actual,
                                         const std::vector<std::string>& expected, double tolerance) {
  auto split = [](const std::string& call, std::string& name, std::vector<double>& numbers) {
    const auto open = call.find('(');
    name = call.substr(0, open);
    std::string args = call.substr(open + 1, call.size() - open - 2);
    for (char& c : args)
      if (c == ',') c = ' ';
    std::istringstream in(args);
    numbers.clear();
    for (double v; in >> v;) numbers.push_back(v);
  };
  const std::size_t n = std::min(actual.size(), expected.size());
  for (std::size_t i = 0; i < n; ++i) {
    std::string an, en;
    std::vector<double> av, ev;
    split(actual[i], an, av);
    split(expected[i], en, ev);
    if (an.starts_with("MESSAGE") || an.starts_with("PRINT") || en.starts_with("MESSAGE") || en.starts_with("PRINT")) {
      // Text: the same words, numbers within the tolerance (messages print %f).
      std::istringstream a(actual[i]), e(expected[i]);
      std::string aw, ew;
      bool same = true;
      for (;;) {
        const bool ha = static_cast<bool>(a >> aw), he = static_cast<bool>(e >> ew);
        if (!ha || !he) {
          same = ha == he;
          break;
        }
        if (aw == ew) continue;
        // A zero's sign depends on rounding only (the suite's own scripts drop it too).
        for (std::string* w : {&aw, &ew})
          for (std::size_t at; (at = w->find("-0.000000")) != std::string::npos;) w->erase(at, 1);
        if (aw == ew) continue;
        char* ea = nullptr;
        char* ee = nullptr;
        const double va = std::strtod(aw.c_str(), &ea), ve = std::strtod(ew.c_str(), &ee);
        if (*ea || *ee || ea == aw.c_str() || std::abs(va - ve) > tolerance) {
          same = false;
          break;
        }
      }
      if (!same) return "line " + std::to_string(i + 1) + ": got " + actual[i] + ", expected " + expected[i];
      continue;
    }
    bool same = an == en && av.size() == ev.size();
    for (std::size_t k = 0; same && k < av.size(); ++k) same = std::abs(av[k] - ev[k]) <= tolerance + 1e-12;
    if (!same) return "motion " + std::to_string(i + 1) + ": got " + actual[i] + ", expected " + expected[i];
  }
  if (actual.size() != expected.size())
    return "got " + std::to_string(actual.size()) + " motions, expected " + std::to_string(expected.size()) +
           (actual.size() > n ? "; first extra: " + actual[n] : "; first missing: " + expected[n]);
  return std::nullopt;
}

// The file helpers fail the test that calls them when the file cannot be opened: a
// missing fixture or an unwritable folder must not pass as an empty text.
std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  if (!in) ADD_FAILURE() << "cannot read " << path;
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) ADD_FAILURE() << "cannot read " << path;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  if (!(out << text)) ADD_FAILURE() << "cannot write " << path;
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

CommandResult run_command(const std::string& command, const std::string& stdin_text) {
  static int counter = 0;
  const std::string dir = temp_dir("cmd" + std::to_string(++counter));
  write_file(dir + "/in", stdin_text);
  const std::string full = "(" + command + ") < " + shell_quote(dir + "/in") + " > " + shell_quote(dir + "/out") +
                           " 2> " + shell_quote(dir + "/err");
  const int status = std::system(full.c_str());
  EXPECT_NE(status, -1) << "the shell could not be started for: " << command;
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(dir + "/out");
  r.err = read_file(dir + "/err");
  return r;
}

std::string source_dir() {
  return CCOMP_SOURCE_DIR;
}
std::string corpus_dir() {
  return CCOMP_CORPUS_DIR;
}
std::string ccomp_binary() {
  return CCOMP_BINARY;
}

std::string ccomp() { return shell_quote(ccomp_binary()); }

std::string sample(const std::string& path) { return shell_quote(source_dir() + "/samples/" + path); }

std::string temp_dir(const std::string& name) {
  // Per process: ctest runs test cases as parallel processes that share the build tree.
  const auto dir = std::filesystem::path(CCOMP_TEST_TMP) / std::to_string(::getpid()) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace ccomp::test
