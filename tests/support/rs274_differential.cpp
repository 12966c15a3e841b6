#include "rs274_differential.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

#include "ccomp/constants.hpp"
#include "ccomp/gcode/tool_table.hpp"
#include "rs274_oracle.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

class ProgramGenerator {
 public:
  explicit ProgramGenerator(unsigned seed) : rng_(seed) {}

  std::string program(int blocks) {
    out_.str("");
    out_ << "(generated, seed-driven)\nG21 G17 G90 G94 G40 G49 G80 G54 G91.1\nM3 S1000\nF500\nG0 X0 Y0 Z10\n";
    out_ << "o<wiggle> sub\nG1 X[#1] Y[#2] Z[#3]\nG1 X[#1 + 1] Y[#2 - 1]\no<wiggle> endsub\n";
    for (int i = 0; i < blocks; ++i) block(i);
    out_ << "G80 G90 G17 G94 G21\nM2\n";
    return out_.str();
  }

 private:
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
  /// A length in the current units, printed as a program would.
  std::string len(double mm) { return fmt(inch_ ? mm / kMmPerInch : mm); }
  static std::string fmt(double v) {
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(4);
    s << v;
    return s.str();
  }
  void absolute_move(const char* g, double x, double y, double z) {
    out_ << "G90 " << g << " X" << len(x) << " Y" << len(y) << " Z" << len(z);
    if (g93_ && g[1] == '1') out_ << " F" << fmt(uniform(1, 50));
    out_ << "\n";
    x_ = x, y_ = y, z_ = z;
  }

  void arc() {
    // From a known point: an arc of random radius and sweep in the current plane.
    const double p1 = uniform(-40, 40), p2 = uniform(-40, 40), pn = uniform(-20, 20);
    // plane axes: 17 -> (X,Y,Z), 18 -> (Z,X,Y), 19 -> (Y,Z,X)
    double x = p1, y = p2, z = pn;
    if (plane_ == 18) x = p2, y = pn, z = p1;
    if (plane_ == 19) x = pn, y = p1, z = p2;
    absolute_move("G1", x, y, z);
    const double r = uniform(2, 30), a0 = uniform(0, 2 * std::numbers::pi);
    const double sweep = uniform(0.2, 1.8 * std::numbers::pi) * (pick(2) ? 1 : -1);
    const bool ccw = sweep > 0;
    const double c1 = p1 - r * std::cos(a0), c2 = p2 - r * std::sin(a0);
    const double e1 = c1 + r * std::cos(a0 + sweep), e2 = c2 + r * std::sin(a0 + sweep);
    const double en = pn + (pick(3) == 0 ? uniform(-5, 5) : 0.0);
    const char* l1 = plane_ == 17 ? "X" : plane_ == 18 ? "Z" : "Y";
    const char* l2 = plane_ == 17 ? "Y" : plane_ == 18 ? "X" : "Z";
    const char* ln = plane_ == 17 ? "Z" : plane_ == 18 ? "Y" : "X";
    const char* i1 = plane_ == 17 ? "I" : plane_ == 18 ? "K" : "J";
    const char* i2 = plane_ == 17 ? "J" : plane_ == 18 ? "I" : "K";
    out_ << (ccw ? "G3 " : "G2 ") << l1 << len(e1) << " " << l2 << len(e2) << " " << ln << len(en);
    const bool use_r = pick(2) == 0 && std::abs(std::abs(sweep) - std::numbers::pi) > 0.2;
    if (use_r) {
      const bool long_way = std::abs(sweep) > std::numbers::pi;
      out_ << " R" << len(long_way ? -r : r);
    } else {
      out_ << " " << i1 << len(c1 - p1) << " " << i2 << len(c2 - p2);
      if (pick(5) == 0) out_ << " P" << (1 + pick(3));
    }
    if (g93_) out_ << " F" << fmt(uniform(1, 20));
    out_ << "\n";
  }

  void cycle() {
    // XY plane drilling with the cycles rs274 and ccomp both read; G84 and G86 need M3.
    static const char* kCycles[] = {"G81", "G82 P0.5", "G83 Q2.5", "G73 Q1.5", "G85", "G89 P0.2", "G84", "G86 P0.1"};
    const char* cycle = kCycles[pick(8)];
    out_ << "G17 " << (pick(2) ? "G98 " : "G99 ");
    plane_ = 17;
    if (pick(3) == 0) {  // incremental with repeats
      out_ << "G91 " << cycle << " X" << len(uniform(-10, 10)) << " Y" << len(uniform(-10, 10)) << " Z"
           << len(-uniform(2, 15)) << " R" << len(uniform(-5, 5)) << " L" << (1 + pick(3)) << "\nG80 G90\n";
      return;
    }
    const double r = uniform(-5, 8);
    out_ << cycle << " X" << len(uniform(-50, 50)) << " Y" << len(uniform(-50, 50)) << " Z" << len(r - uniform(1, 20))
         << " R" << len(r) << "\n";
    for (int k = pick(3); k > 0; --k) out_ << "X" << len(uniform(-50, 50)) << "\n";
    out_ << "G80\n";
  }

  /// The plane's two axis words for (first, second) in the current plane, G17 or G18.
  std::string plane_words(double first, double second) {
    return plane_ == 18 ? "Z" + len(first) + " X" + len(second) : "X" + len(first) + " Y" + len(second);
  }

  /// A profile under cutter radius compensation (G41/G42, G41.1/G42.1) in G17 or G18: an
  /// entry move, lines and arcs turning either way (so inside and outside corners, tangent
  /// and not), moves along the normal axis and queued calls between them, G40 and the exit
  /// move. Some cannot be cut without gouging: rs274 must refuse those, and ccomp with it.
  void contour() {
    plane_ = pick(4) == 0 ? 18 : 17;
    const char* normal = plane_ == 18 ? "Y" : "Z";
    double p1 = uniform(-40, 40), p2 = uniform(-40, 40);
    out_ << "G" << plane_ << " G90 G0 " << plane_words(p1, p2) << " " << normal << len(uniform(-5, 5)) << "\n";
    static const char* kOn[] = {"G41 D1", "G42 D1", "G41 D2", "G42 D2", "G41", "G42"};
    if (pick(4) == 0)
      out_ << (pick(2) ? "G41.1" : "G42.1") << " D" << len(uniform(-4, 8)) << "\n";
    else
      out_ << kOn[pick(6)] << "\n";
    double heading = uniform(0, 2 * std::numbers::pi);
    auto line_to = [&](double length) {
      p1 += length * std::cos(heading), p2 += length * std::sin(heading);
      out_ << "G1 " << plane_words(p1, p2);
      if (pick(5) == 0) out_ << " " << normal << len(uniform(-5, 5));  // a ramp
      out_ << "\n";
    };
    if (pick(4) == 0) {  // an entry arc, a half circle at most
      const bool ccw = pick(2) == 0;
      const double r = uniform(12, 25), sweep = uniform(0.5, 2.8);
      const double to_centre = heading + (ccw ? 1 : -1) * std::numbers::pi / 2;
      const double c1 = p1 + r * std::cos(to_centre), c2 = p2 + r * std::sin(to_centre);
      const double end_angle = to_centre + std::numbers::pi + (ccw ? sweep : -sweep);
      const double e1 = c1 + r * std::cos(end_angle), e2 = c2 + r * std::sin(end_angle);
      out_ << (ccw ? "G3 " : "G2 ") << plane_words(e1, e2)
           << (plane_ == 18 ? " K" + len(c1 - p1) + " I" + len(c2 - p2) : " I" + len(c1 - p1) + " J" + len(c2 - p2))
           << "\n";
      p1 = e1, p2 = e2;
      heading = end_angle + (ccw ? 1 : -1) * std::numbers::pi / 2;
    } else {
      line_to(uniform(12, 30));
    }
    for (int k = 2 + pick(6); k > 0; --k) {
      const int kind = pick(8);
      if (kind <= 2) {
        heading += uniform(-2.5, 2.5);
        line_to(uniform(12, 40));
      } else if (kind <= 5) {
        const bool ccw = pick(2) == 0;
        const double r = uniform(9, 40);
        // Tangent to the way the tool goes, or turned off it to make a corner.
        const double corner = pick(2) ? 0.0 : uniform(-1.2, 1.2);
        const double to_centre = heading + corner + (ccw ? 1 : -1) * std::numbers::pi / 2;
        const double c1 = p1 + r * std::cos(to_centre), c2 = p2 + r * std::sin(to_centre);
        const double sweep = uniform(0.3, 2.6);
        const double end_angle = to_centre + std::numbers::pi + (ccw ? sweep : -sweep);
        const double e1 = c1 + r * std::cos(end_angle), e2 = c2 + r * std::sin(end_angle);
        out_ << (ccw ? "G3 " : "G2 ") << plane_words(e1, e2);
        if (std::abs(sweep - std::numbers::pi) > 0.2 && pick(2))
          out_ << " R" << len(sweep > std::numbers::pi ? -r : r);
        else if (plane_ == 18)
          out_ << " K" << len(c1 - p1) << " I" << len(c2 - p2);
        else
          out_ << " I" << len(c1 - p1) << " J" << len(c2 - p2);
        out_ << "\n";
        p1 = e1, p2 = e2;
        heading = end_angle + (ccw ? 1 : -1) * std::numbers::pi / 2;
      } else if (kind == 6) {
        out_ << "G1 " << normal << len(uniform(-5, 5)) << "\n";
      } else {
        static const char* kBetween[] = {"M8", "M9", "F400", "G4 P0.1", "S800", "(a comment)", "M1"};
        out_ << kBetween[pick(7)] << "\n";
      }
    }
    out_ << "G40\n";
    if (pick(25) == 0) {  // rs274 refuses an arc as the move after G40
      out_ << "G2 " << plane_words(p1 + 10, p2) << " R8\n";
      return;
    }
    heading += uniform(-1.5, 1.5);
    line_to(uniform(10, 20));
  }

  void block(int i) {
    switch (pick(18)) {
      case 16:
      case 17:
        contour();
        break;
      case 0:
      case 1:
      case 2:
        absolute_move(pick(2) ? "G0" : "G1", uniform(-60, 60), uniform(-60, 60), uniform(-20, 20));
        break;
      case 3:
        out_ << "G91 G1 X" << len(uniform(-5, 5)) << " Y" << len(uniform(-5, 5)) << "\nG90\n";
        break;
      case 4:
      case 5:
      case 6:
        arc();
        break;
      case 7:
        plane_ = 17 + pick(3);
        out_ << "G" << plane_ << "\n";
        break;
      case 8:
        // (rs274 does not convert an active tool length offset when the units change; ccomp
        // keeps lengths in mm. So units change here only with no tool offset in force.)
        if (tool_offset_) break;
        inch_ = !inch_;
        out_ << (inch_ ? "G20" : "G21") << "\n";
        break;
      case 9: {
        const int p = 1 + pick(3);
        out_ << "G10 L2 P" << p << " X" << len(uniform(-20, 20)) << " Y" << len(uniform(-20, 20)) << " Z"
             << len(uniform(-5, 5)) << "\nG" << 53 + p << "\n";
        break;
      }
      case 10: {
        static const char* kG92[] = {"G92.1", "G92.2", "G92.3"};
        if (pick(2))
          out_ << "G92 X" << len(uniform(-10, 10)) << " Y" << len(uniform(-10, 10)) << "\n";
        else if (pick(2))
          out_ << "G52 X" << len(uniform(-10, 10)) << " Z" << len(uniform(-3, 3)) << "\n";
        else
          out_ << kG92[pick(3)] << "\n";
        break;
      }
      case 11:
        cycle();
        break;
      case 12:
        // G49 and a retract before M6, as posts write it: rs274 alone resets its position at M6
        // to the last point it was commanded to, which ignores offset changes since (a stub of
        // its own, not what a machine does). M6 stops the spindle.
        if (pick(2))
          out_ << "G49\nG90 G0 Z" << len(uniform(10, 20)) << "\nT" << (1 + pick(2)) << " M6\nG43\nM3\n",
              tool_offset_ = true;
        else if (pick(2))
          out_ << "G43.1 Z" << len(uniform(-5, 5)) << "\n", tool_offset_ = true;
        else
          out_ << "G49\n", tool_offset_ = false;
        break;
      case 13: {
        const std::string l = std::to_string(100 + i);
        out_ << "#" << 100 << "=0\no" << l << " while [#100 LT " << 1 + pick(3) << "]\nG1 X[#100 * "
             << len(uniform(1, 9)) << " + SIN[30]] Y[-#100 ** 2]\n#100=[#100 + 1]\no" << l << " endwhile\n";
        break;
      }
      case 14:
        out_ << "o<wiggle> call [" << len(uniform(-20, 20)) << "] [" << len(uniform(-20, 20)) << "] ["
             << len(uniform(-5, 5)) << "]\n";
        break;
      case 15:
        if (pick(2)) {  // inverse time: an F on every feed block
          out_ << "G93\nG1 X" << len(uniform(-30, 30)) << " F" << fmt(uniform(1, 50)) << "\n";
          g93_ = true;
          arc();
          g93_ = false;
          out_ << "G94 F500\n";
        } else if (pick(2) && !tool_offset_) {
          // (rs274 subtracts a tool offset from G53 in the units it was set in, even after a
          // G20/G21 switch: a bug of its own, so G53 is generated without a tool offset.)
          out_ << "G53 G0 Z" << len(uniform(-10, 0)) << "\n";
        } else {
          out_ << (pick(2) ? "G0" : "G1") << "\n";  // no axis words: rs274 moves nowhere, but moves
        }
        break;
    }
  }

  std::mt19937 rng_;
  std::ostringstream out_;
  bool inch_ = false;
  bool g93_ = false;
  bool tool_offset_ = false;
  int plane_ = 17;
  double x_ = 0, y_ = 0, z_ = 10;
};

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

}  // namespace

/// The motions without zero-length straight moves: rs274 emits some where its positions,
/// converted between inches and mm, are 1e-12 short of an R plane, and one after G84's
/// feed out. Geometry is what counts.
std::vector<std::string> geometry(const std::vector<std::string>& lines) {
  std::vector<std::string> out;
  std::string last_end;
  for (const std::string& call : motion_calls(lines)) {
    const auto open = call.find('(');
    const std::string name = call.substr(0, open);
    std::string end = call.substr(open);
    if (name == "ARC_FEED") {
      last_end.clear();
      out.push_back(call);
      continue;
    }
    if (end == last_end && (name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED")) continue;
    last_end = end;
    out.push_back(call);
  }
  return out;
}

std::optional<std::string> rs274_divergence(const std::string& path, const std::string& tool_table, bool* refused) {
  const TraceResult theirs = rs274_trace(path, tool_table);
  if (refused) *refused = theirs.error.has_value();
  gcode::InterpreterOptions o;
  o.machine_units = gcode::Units::inch;
  o.tools = gcode::read_tool_table_file(tool_table);
  const TraceResult ours = trace_file(path, o);
  if (theirs.error && ours.error) {  // both refuse it: the same motions up to there
    if (auto diff = compare_calls(geometry(ours.lines), geometry(theirs.lines)))
      return "both refuse it, after different motions: " + *diff;
    return std::nullopt;
  }
  if (theirs.error) return "rs274 refuses it, ccomp does not: " + std::string(theirs.error->what());
  if (ours.error) return "ccomp refuses it, rs274 does not: " + format_error(*ours.error);
  return compare_calls(geometry(ours.lines), geometry(theirs.lines));
}

std::string generated_program(unsigned seed, int blocks) {
  return ProgramGenerator(seed).program(blocks);
}

std::string smallest_divergent(const std::string& program, const std::string& tool_table, const std::string& scratch) {
  std::vector<std::string> lines = split_lines(program);
  // A cut keeps the kind of divergence it started from: one that only drops the program's
  // end (which rs274 refuses and ccomp warns about) shows nothing new.
  // A refusal keeps its reason too: rs274's message (the line after its "executing").
  auto kind_of = [](const std::optional<std::string>& d) -> std::string {
    if (!d) return "";
    if (d->starts_with("ccomp refuses")) return "ccomp refuses";
    if (!d->starts_with("rs274 refuses")) return "motions";
    const auto at = d->find("executing\n");
    if (at == std::string::npos) return "rs274 refuses";
    const auto from = at + 10;
    return "rs274 refuses: " + d->substr(from, d->find('\n', from) - from);
  };
  write_file(scratch, program);
  const std::string kind = kind_of(rs274_divergence(scratch, tool_table));
  auto diverges = [&](const std::vector<std::string>& candidate) {
    write_file(scratch, joined(candidate));
    return kind_of(rs274_divergence(scratch, tool_table)) == kind;
  };
  for (std::size_t piece = lines.size() / 2; piece >= 1; piece /= 2) {
    for (std::size_t at = 0; at + piece <= lines.size();) {
      std::vector<std::string> candidate = lines;
      candidate.erase(candidate.begin() + static_cast<std::ptrdiff_t>(at),
                      candidate.begin() + static_cast<std::ptrdiff_t>(at + piece));
      if (diverges(candidate))
        lines = std::move(candidate);  // the same place now holds the next piece
      else
        at += piece;
    }
  }
  write_file(scratch, joined(lines));
  return joined(lines);
}

}  // namespace ccomp::test
