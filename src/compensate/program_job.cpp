#include "ccomp/compensate/program_job.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>
#include <system_error>
#include <tuple>

#include "ccomp/compensate/compensator.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/gcode/flatten.hpp"
#include "ccomp/gcode/writer.hpp"
#include "ccomp/model/chain_values.hpp"
#include "ccomp/util/parallel.hpp"
#include "ccomp/version.hpp"

namespace ccomp::compensate {

using model::chain_of;
using model::controlled_of_chain;
namespace {

constexpr std::string_view kHeaderPrefix = "(ccomp ";

/// How a compensated coordinate is written, in the style of the word it replaces: at least
/// as many decimals as the program wrote, and enough for the tolerance: 4 in mm, 5 in
/// inches, 5 in degrees (1e-5 deg is 0.07 um at 400 mm from the axis). Exactly `decimals`
/// when the user set them (>= 0).
struct NumberStyle {
  int decimals = 4;
  bool leading_zero = true;  ///< "0.5", not ".5"
};

constexpr int kDefaultDecimals = 4, kDefaultInchDecimals = 5, kDefaultRotaryDecimals = 5;

NumberStyle style_of(std::string_view original, bool inch, bool rotary, int decimals) {
  NumberStyle style{rotary ? kDefaultRotaryDecimals : inch ? kDefaultInchDecimals : kDefaultDecimals, true};
  if (const auto dot = original.find('.'); dot != std::string_view::npos) {
    int written = 0;
    for (std::size_t i = dot + 1; i < original.size() && std::isdigit(static_cast<unsigned char>(original[i])); ++i)
      ++written;
    style.decimals = std::max(style.decimals, written);
    const auto first_digit = original.find_first_of("0123456789.");
    style.leading_zero = !(first_digit != std::string_view::npos && original[first_digit] == '.');
  }
  if (decimals >= 0) style.decimals = decimals;
  return style;
}

/// The number a value as written means (".5", "-.25", "12.0000").
double number_of(std::string_view text) {
  double value = 0.0;
  std::size_t end = 0;
  if (gcode::read_decimal(text, end, value) && end == text.size()) return value;
  std::from_chars(text.data(), text.data() + text.size(), value);
  return value;
}

/// A coordinate as written: its text, and the number the text means (what the machine
/// will be told).
struct WrittenValue {
  std::string text;
  double value = 0.0;
};

WrittenValue format_value(double v, const NumberStyle& style) {
  // Rounds the exact binary value as fmt does, without parsing a format string: this runs
  // for every number the job writes.
  std::array<char, 40> buffer{};
  const std::size_t length = gcode::format_fixed(v, style.decimals, buffer.data());
  WrittenValue written{length > 0 ? std::string(buffer.data(), length) : fmt::format("{:.{}f}", v, style.decimals),
                       0.0};
  std::string& text = written.text;
  if (text.starts_with('-') && text.find_first_not_of("0.", 1) == std::string::npos) text.erase(0, 1);  // no "-0.0000"
  if (!style.leading_zero) {
    if (text.starts_with("0."))
      text.erase(0, 1);
    else if (text.starts_with("-0."))
      text.erase(1, 1);
  }
  // The text's digits are units / 10^decimals: the division read_decimal does reading it.
  std::int64_t units = 0;
  static constexpr double kPower[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  written.value = gcode::fixed_units(v, style.decimals, units) ? static_cast<double>(units) / kPower[style.decimals]
                                                               : number_of(text);
  return written;
}

WrittenValue format_value(double v, std::string_view original, bool inch, bool rotary, int decimals) {
  return format_value(v, style_of(original, inch, rotary, decimals));
}

/// Whether a and b are written alike in `style`, without writing them when their rounded
/// digits tell.
bool written_alike(double a, double b, const NumberStyle& style) {
  std::int64_t units_a = 0, units_b = 0;
  if (gcode::fixed_units(a, style.decimals, units_a) && gcode::fixed_units(b, style.decimals, units_b))
    return units_a == units_b;  // "-0.0000" is written "0.0000"
  return format_value(a, style).text == format_value(b, style).text;
}

/// Which of a move's chords a task compensates: all of them (count 0), or [begin, end) of
/// `count`.
struct ChordRange {
  std::size_t begin = 0, end = 0, count = 0;
  [[nodiscard]] bool whole() const { return count == 0; }
  [[nodiscard]] bool first() const { return begin == 0; }
  [[nodiscard]] bool last() const { return whole() || end == count; }
};

/// A move on its way from the interpreter, through the compensation, to the writer: what
/// its block said, and what the compensation made of it.
struct MoveTask {
  gcode::Motion motion;  ///< its offsets point to `offsets`
  gcode::Offsets offsets;
  bool first = false;  ///< the program's first motion: the play is followed from its start
  std::string text, terminator;
  gcode::Block block;  ///< the words, and the text (in `text`), for the writer
  std::uint64_t offset = 0;
  /// An arc of more chords than a task may hold is compensated in parts, each a task of
  /// its own, in order: this one's chords are [chords.begin, chords.end) of chords.count.
  ChordRange chords;
  // what the compensation made of it
  std::vector<CompensatedPoint> points;
  MoveReport report;
  NominalPose end_pose;            ///< the nominal tool pose at its end (the reading thread's)
  std::vector<ErrorProbe> probes;  ///< where the uncompensated machine's error is taken
  std::exception_ptr error;
};

/// A batch of moves: the interpreter's thread fills one while the other is compensated.
/// Each on cache lines of its own, as the two threads write them at once.
struct alignas(64) MoveBatch {
  std::vector<MoveTask> tasks;
  std::size_t filled = 0;
};

/// How many chords an arc takes to stay within `tolerance` of it (sagitta r (1 - cos(step / 2))).
std::size_t arc_chord_count(const gcode::ArcGeometry& g, double tolerance) {
  const double r = std::max(g.r_start, g.r_end);
  const double step = r > tolerance ? 2.0 * std::acos(1.0 - tolerance / r) : 2.0 * std::numbers::pi;
  return static_cast<std::size_t>(std::max(1.0, std::ceil(g.sweep / step)));
}

/// Points along an arc (controlled points, machine frame) whose chords stay within
/// `tolerance` of it: the ends of the chords in `range` (all: start and end included).
void arc_chords(const gcode::Motion& m, double tolerance, const ChordRange& range, std::vector<gcode::Axes>& out) {
  const gcode::ArcGeometry g = gcode::arc_geometry(m);
  const std::size_t n = range.whole() ? arc_chord_count(g, tolerance) : range.count;
  const std::size_t begin = range.whole() ? 0 : range.begin, end = range.whole() ? n : range.end;
  out.resize(end - begin + 1);
  for (std::size_t k = begin; k <= end; ++k)
    out[k - begin] = gcode::arc_point(m, g, static_cast<double>(k) / static_cast<double>(n));
}

/// The compensation of the moves, as the worker thread runs it. An object of its own (on
/// cache lines of its own): the interpreter's thread goes on writing its own state meanwhile.
class alignas(64) MoveSolver {
 public:
  MoveSolver(const model::ForwardModel& model, const CompensationOptions& options)
      : compensator(model, options), model_(model), data_(model), tolerance_(options.tolerance) {}

  /// Compensates the batch's moves in order, up to the first that fails (its error kept).
  void solve_batch(MoveBatch& batch) {
    bool failed = false;
    for (std::size_t k = 0; k < batch.filled; ++k) {
      MoveTask& t = batch.tasks[k];
      t.points.clear();
      t.probes.clear();
      t.report = MoveReport{};
      t.error = nullptr;
      if (failed) continue;  // never written: the writing stops at the failure
      try {
        compensator.defer_error_before(&t.probes);
        if (t.first) compensator.moved(chain_of(t.motion.start, t.offsets));
        compensator.expect(chain_of(t.motion.end, t.offsets), t.end_pose);
        solve(t.motion, t.offsets, t.report, t.points, t.chords);
      } catch (...) {
        t.error = std::current_exception();
        failed = true;
      }
    }
    compensator.defer_error_before(nullptr);
  }

  /// The compensated points of a motion into `points`: a rapid's end (its path is the
  /// control's), a feed move split as its error field needs, an arc as chords within half
  /// the tolerance, each compensated within the other half.
  void solve(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move,
             std::vector<CompensatedPoint>& points, const ChordRange& range = {}) {
    const model::ChainQ start = chain_of(m.start, offsets), end = chain_of(m.end, offsets);
    compensator.offset_by_control(m.radius_compensation);
    // The move that starts the control's offset must stay one line longer than the tool's
    // radius (LinuxCNC refuses a shorter one): its end is compensated, as a rapid's.
    const bool entry = m.radius_compensation && !offset_before_;
    offset_before_ = m.radius_compensation;
    if (m.kind == gcode::MotionKind::traverse || (entry && m.kind == gcode::MotionKind::feed)) {
      compensator.error_before_at(end, move);
      compensator.rapid(end, points, move);
    } else if (m.kind == gcode::MotionKind::arc && m.radius_compensation) {
      // The control offsets an arc as one piece; its chords would be pieces shorter than the
      // radius at inside corners, which it refuses. So it stays an arc, its end compensated
      // (its centre words count from its start, as written), and what the arc does between
      // is measured.
      model::ChainQ from = compensator.commanded();
      if (from.hasNaN()) from = start;
      const gcode::ArcGeometry g = gcode::arc_geometry(m);
      const int n = 2 * std::max(8, static_cast<int>(std::ceil(g.sweep / (std::numbers::pi / 8))));
      for (int k = 1; k < n; ++k)
        compensator.error_before_at(chain_of(gcode::arc_point(m, g, static_cast<double>(k) / n), offsets), move);
      compensator.error_before_at(end, move);
      compensator.rapid(end, points, move);
      move.max_deviation_after =
          std::max(move.max_deviation_after, kept_arc_deviation(m, g, offsets, from, points.back().q, n));
    } else if (m.kind == gcode::MotionKind::arc) {
      arc_chords(m, tolerance_ / 2.0, range, chords_);
      points.clear();
      const auto n = static_cast<double>(range.whole() ? chords_.size() - 1 : range.count);
      for (std::size_t k = 1; k < chords_.size(); ++k) {
        compensator.straight(chain_of(chords_[k - 1], offsets), chain_of(chords_[k], offsets), pieces_, move,
                             tolerance_ / 2.0);
        for (CompensatedPoint& piece : pieces_) {
          piece.s = (static_cast<double>(range.begin + k - 1) + piece.s) / n;
          points.push_back(piece);
        }
      }
      // What is left is measured from the chords; the arc bulges from them by their sagitta.
      const gcode::ArcGeometry g = gcode::arc_geometry(m);
      move.max_deviation_after += std::max(g.r_start, g.r_end) * (1.0 - std::cos(g.sweep / n / 2.0));
    } else {
      compensator.straight(start, end, points, move);
    }
  }

  Compensator compensator;

 private:
  /// The largest distance, at n + 1 points, between the nominal arc `m` and the arc the
  /// control cuts from the compensated `from` to `to` (chain values), its centre moved with
  /// its start.
  double kept_arc_deviation(const gcode::Motion& m, const gcode::ArcGeometry& g, const gcode::Offsets& offsets,
                            const model::ChainQ& from, const model::ChainQ& to, int n) {
    gcode::Motion cut = m;
    cut.start = controlled_of_chain(from, offsets);
    cut.end = controlled_of_chain(to, offsets);
    cut.arc.center_first += cut.start[g.axes.first] - m.start[g.axes.first];
    cut.arc.center_second += cut.start[g.axes.second] - m.start[g.axes.second];
    const gcode::ArcGeometry cut_g = gcode::arc_geometry(cut);
    double worst = 0.0;
    for (int k = 0; k <= n; ++k) {
      const double f = static_cast<double>(k) / n;
      model::forward(model_, data_, chain_of(gcode::arc_point(m, g, f), offsets), compensator.conditions(), false,
                     model::Evaluate::nominal);
      const Eigen::Vector3d meant = data_.nominal;
      model::forward(model_, data_, chain_of(gcode::arc_point(cut, cut_g, f), offsets), compensator.conditions(), false,
                     model::Evaluate::actual);
      worst = std::max(worst, (data_.actual - meant).norm());
    }
    return worst;
  }

  const model::ForwardModel& model_;
  model::ForwardData data_;  ///< scratch for kept_arc_deviation()
  double tolerance_;
  bool offset_before_ = false;  ///< the last move was under the control's radius offset
  std::vector<gcode::Axes> chords_;
  std::vector<CompensatedPoint> pieces_;
};

class JobSink : public gcode::CanonSink {
 public:
  JobSink(gcode::ProgramWriter& writer, const model::MachineModel& model, const JobOptions& options,
          const gcode::LineSource& input, JobReport& report)
      : writer_(writer), model_(model), options_(options), input_(input), report_(report) {
    for (const model::AxisSpec& a : model.axes) {
      machine_axes_ |= 1U << (a.letter - 'A');
      linear_axes_ += a.type == model::AxisType::linear ? 1 : 0;
      if (a.type == model::AxisType::linear && std::isfinite(a.min) && std::isfinite(a.max))
        rotary_lever_ = std::max({rotary_lever_, std::abs(a.min), std::abs(a.max)});
      has_limits_ = has_limits_ || std::isfinite(a.min) || std::isfinite(a.max);
    }
    if (!model.terms.empty()) {
      forward_ = std::make_unique<model::ForwardModel>(model);
      CompensationOptions c;
      c.tolerance = options.tolerance;
      c.conditions.time = options.time;
      c.conditions.temperatures.assign(model.sensors.size(), std::nan(""));
      for (const auto& [name, value] : options.sensors) {
        const auto it = std::find(model.sensors.begin(), model.sensors.end(), name);
        if (it == model.sensors.end())
          throw Error(ErrorKind::usage,
                      fmt::format("--sensor {}: machine '{}' has no sensor of that name", name, model.name));
        c.conditions.temperatures[static_cast<std::size_t>(it - model.sensors.begin())] = value;
      }
      for (const model::ErrorTermSpec& t : model.terms)
        for (const model::Variable* v : {&t.primary, &t.secondary})
          if (v->kind == model::VariableKind::temperature && std::isnan(c.conditions.temperatures[v->index]))
            throw Error(ErrorKind::safety,
                        fmt::format("term {} depends on sensor '{}', and no reading was given: --sensor {}=VALUE",
                                    t.name, model.sensors[v->index], model.sensors[v->index]));
      solver_ = std::make_unique<MoveSolver>(*forward_, c);
      compensator_ = &solver_->compensator;
      error_before_ = std::make_unique<Compensator>(*forward_, c);
      nominal_ = std::make_unique<model::ForwardData>(*forward_);
      if (options.threads > 1) worker_ = std::make_unique<util::BackgroundThread>();
    }
  }

  void block(const gcode::Block& block, const gcode::SourceLine& line) override {
    finish_cycle();
    for (const gcode::Word& w : block.words)  // the cycle a modal repeat line drills
      if (w.letter == 'G' && w.value.is_literal() && is_cycle_code(w.value.literal)) cycle_code_ = w.value.literal;
    ++report_.blocks;
    block_ = &block;
    line_ = line;
    // A line of another file (a subroutine file on the path) is not in the program written
    // here; a line before the furthest one read runs again (a loop, a subroutine).
    elsewhere_ = line.file.data() != input_.name().data() && line.file != input_.name();
    repeated_ = !elsewhere_ && line.offset < furthest_;
    if (!elsewhere_) furthest_ = std::max(furthest_, line.offset);
    for (const gcode::Word& w : block.words) {
      if (w.letter < 'A' || w.letter > 'Z' || ((machine_axes_ >> (w.letter - 'A')) & 1U) ||
          !gcode::axis_index(w.letter))
        continue;
      throw Error(ErrorKind::safety,
                  fmt::format("the program uses axis {}, which machine '{}' does not have", w.letter, model_.name),
                  SourceLocation{input_.name(), block.line, w.span.begin + 1}, std::string(block.text));
    }
    if (solver_ && live_offsets_) keep_offsets_set_from_position(block);
    if (options_.progress && input_.size() > 0) {
      const auto percent =
          static_cast<int>(100.0 * static_cast<double>(line.offset) / static_cast<double>(input_.size()));
      if (percent != last_percent_) {
        last_percent_ = percent;
        options_.progress(percent / 100.0);
      }
    }
  }

  void motion(const gcode::Motion& m) override {
    ++report_.motions;
    live_offsets_ = m.offsets;
    nominal_end_ = m.end;
    last_units_ = m.units;
    if (has_limits_) check_limits(m);
    if (solver_) compensate(m);
  }

  void warning(const std::string& message, std::uint32_t line) override {
    if (options_.warning) options_.warning(message, line);
  }

 private:
  static std::optional<double> literal_of(const gcode::Block& b, char letter) {
    const gcode::Word* w = b.find(letter);
    if (!w || !w->value.is_literal()) return std::nullopt;
    return w->value.literal;
  }

  /// G92 and G10 L20 set an offset so that where the machine is reads the values given;
  /// G10 L10/L11 set a tool's offsets so (a touch-off). After a compensated move the machine is where the
  /// rewritten program sent it, off the nominal point by the correction: the new offset
  /// would take the correction in, and every move after it would be off by as much. So
  /// each value given is moved by what the machine's position reads beyond the nominal one,
  /// and the offset comes out as the original's. What cannot be rewritten so is refused.
  void keep_offsets_set_from_position(const gcode::Block& b) {
    bool g92 = false, g10 = false;
    for (const gcode::Word& w : b.words)
      if (w.letter == 'G' && w.value.is_literal()) {
        g92 = g92 || w.value.literal == 92;
        g10 = g10 || w.value.literal == 10;
      }
    // G10's L, NaN when it is not a number as written (then what it is shows only as it runs)
    const double l = g10 ? literal_of(b, 'L').value_or(std::nan("")) : std::nan("");
    if (!g92 && !(g10 && (std::isnan(l) || l == 20 || l == 10 || l == 11))) return;
    drain();
    const gcode::Offsets& o = *live_offsets_;
    gcode::Units units = last_units_;
    for (const gcode::Word& w : b.words)
      if (w.letter == 'G' && w.value.is_literal() && (w.value.literal == 20 || w.value.literal == 21))
        units = w.value.literal == 20 ? gcode::Units::inch : gcode::Units::mm;
    const bool inch = units == gcode::Units::inch;
    const double unit = inch ? kMmPerInch : 1.0;
    const gcode::Axes written = program_of(chain_of(commanded_, o), o, unit),
                      nominal = program_of(chain_of(nominal_end_, o), o, unit);
    gcode::Axes off{};  // program units: where the machine is, beyond where the original has it
    bool off_xy = false, off_any = false;
    for (std::size_t i = 0; i < gcode::kAxisCount; ++i) {
      off[i] = written[i] + rounding_[i] - nominal[i];
      const bool moved = std::abs(off[i]) * (gcode::is_rotary(i) ? 1.0 : unit) > 1e-7;  // mm or deg
      off_any = off_any || moved;
      off_xy = off_xy || (moved && i < 2);
    }
    if (!off_any) return;
    const std::string what = g92 ? "G92" : std::isnan(l) ? "G10" : fmt::format("G10 L{:g}", l);
    auto refuse_here = [&](const std::string& why) {
      refuse(ErrorKind::unsupported,
             fmt::format("{} sets an offset from where the machine is, which the compensation has moved by up to "
                         "{:.2f} um here; {}",
                         what, 1000.0 * unit * std::max(std::abs(off[0]), std::max(std::abs(off[1]), std::abs(off[2]))),
                         why));
    };
    if (repeated_ || elsewhere_)
      refuse_here("its line runs more than once or is in another file: --flatten writes it once per run");
    if (g10 && std::isnan(l)) refuse_here("its L, an expression, shows what it sets only as the program runs");
    if (g10 && l == 11 && off_xy)
      refuse_here(
          "L11 counts in G59.3's frame, whose rotation would couple X and Y; give it before the first "
          "compensated move");
    if (g10 && l == 20) {  // a rotation couples X and Y, known here only for the system in force
      const std::optional<double> p = literal_of(b, 'P');
      const bool system_in_force = p && (*p == 0 || *p == o.coordinate_system);
      if (off_xy && (b.find('R') || !system_in_force))
        refuse_here(
            "with a rotation (R) or another coordinate system than the one in force, its X and Y cannot be "
            "rewritten to match; give it before the first compensated move");
    }
    std::vector<gcode::Edit> edits;
    for (const gcode::Word& w : b.words) {
      const auto axis = gcode::axis_index(w.letter);
      if (!axis || std::abs(off[*axis]) == 0.0) continue;
      const bool rotary = gcode::is_rotary(*axis);
      const std::string_view text = b.slice(w.value_span);
      const NumberStyle style = style_of(text, inch && !rotary, rotary, decimals_for(rotary));
      if (w.value.is_literal()) {
        edits.push_back(gcode::Edit{w.value_span, format_value(w.value.literal + off[*axis], style).text});
      } else {  // an expression, a parameter: the same, moved
        const std::string by = format_value(std::abs(off[*axis]), style).text;
        edits.push_back(gcode::Edit{w.value_span, fmt::format("[{} {} {}]", text, off[*axis] < 0 ? '-' : '+', by)});
      }
    }
    if (!edits.empty()) writer_.edit(line_.offset, std::move(edits));
  }

  [[noreturn]] void refuse(ErrorKind kind, const std::string& message) const {
    throw Error(kind, message, SourceLocation{input_.name(), block_->line, 0}, std::string(block_->text));
  }

  /// Program coordinates (program units, degrees) of chain values.
  static gcode::Axes program_of(const model::ChainQ& q, const gcode::Offsets& offsets, double unit) {
    gcode::Axes p = offsets.program_of(controlled_of_chain(q, offsets));
    for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
      if (!gcode::is_rotary(i)) p[i] /= unit;
    return p;
  }

  void compensate(const gcode::Motion& m) {
    using gcode::MotionKind;
    using gcode::MotionSource;
    const bool machine = m.source == MotionSource::machine_coordinates || m.source == MotionSource::reference_return;
    if (!machine && m.kind != MotionKind::probe && m.source != MotionSource::canned_cycle && !repeated_ &&
        !elsewhere_) {
      queue_move(m);
      return;
    }
    // The rest is rare, and done here once every move before it is written.
    drain();
    if (!started_) {  // the play is followed from where the program starts
      compensator_->moved(chain_of(m.start, *m.offsets));
      started_ = true;
    }
    // Moves in machine coordinates (G53, G28/G30) go where they say: they are not part of
    // the workpiece's geometry. Nothing else may go uncompensated.
    if (machine) {
      commanded_ = m.end;
      rounding_ = {};  // the block's own words, as written
      compensator_->moved(chain_of(m.end, *m.offsets));
      return;
    }
    if (m.kind == MotionKind::probe) refuse(ErrorKind::unsupported, "a probe move (G38.x) cannot be compensated");
    if (elsewhere_)
      throw Error(ErrorKind::unsupported,
                  fmt::format("this line is in the subroutine file '{}', which the compensated program does not "
                              "include: --flatten writes the program as it runs, the subroutine's lines in it",
                              line_.file),
                  SourceLocation{std::string(line_.file), block_->line, 0}, std::string(block_->text));
    if (m.source == MotionSource::canned_cycle) {
      if (m.incremental && !options_.expand_cycles)
        refuse(ErrorKind::unsupported,
               "compensating incremental (G91) canned cycles in the block's words is not "
               "implemented; --expand-cycles writes them as compensated moves");
      if (cycle_.motions.empty()) {
        cycle_.code = cycle_code_;
        cycle_.terminator = std::string(line_.terminator);
        cycle_.incremental = m.incremental;
        cycle_.text = std::string(block_->text);
        cycle_.words = block_->words;
        cycle_.offset = line_.offset;
        cycle_.line = block_->line;
        cycle_.offsets = *m.offsets;
        cycle_.units = m.units;
        cycle_.repeated = repeated_;
      }
      cycle_.motions.push_back(m);
      return;
    }
    refuse(ErrorKind::unsupported,
           "this line runs more than once (a loop or a subroutine), and each run needs its own "
           "correction: --flatten writes the program as it runs, loops and subroutines unrolled");
  }

  // The pipeline of moves. The interpreter fills a batch of moves while those before it are
  // compensated (on the worker thread, or here), then the compensated batches are written
  // here, in order; so the compensator sees the same moves in the same order either way.
  // Three batches: while one fills, two may wait for or be in compensation, so that a
  // batch the reading thread took longer over does not leave the worker idle.
  // A batch holds at most kBatch moves and about kBatchPoints compensated points (arcs'
  // chords, long moves' checks, as expected_points() foresees them): a program of full
  // circles at 1 um gives thousands of points a move, and memory must not grow with that.
  static constexpr std::size_t kBatch = 4096;
  static constexpr std::size_t kBatchPoints = 4 * kBatch;
  static constexpr std::size_t kBatches = 3;
  /// An arc of more chords is compensated and written in parts of this many: a helix of a
  /// thousand turns must not hold a million points.
  static constexpr std::size_t kPartChords = kBatchPoints / 2;

  /// The points a move is expected to give: its chords (half the tolerance, as solve()
  /// takes them), else the points the model checks it at.
  [[nodiscard]] std::size_t expected_points(const gcode::Motion& m, const model::ChainQ& end) const {
    if (m.kind == gcode::MotionKind::arc && !m.radius_compensation)
      return arc_chord_count(gcode::arc_geometry(m), options_.tolerance / 2.0);
    return static_cast<std::size_t>(forward_->check_points(chain_of(m.start, *m.offsets), end, 1));
  }

  void queue_move(const gcode::Motion& m) {
    if (m.kind == gcode::MotionKind::arc && !m.radius_compensation) {
      const std::size_t n = arc_chord_count(gcode::arc_geometry(m), options_.tolerance / 2.0);
      if (n > kPartChords) {
        for (std::size_t begin = 0; begin < n; begin += kPartChords)
          queue_task(m, ChordRange{begin, std::min(n, begin + kPartChords), n});
        return;
      }
    }
    queue_task(m, {});
  }

  void queue_task(const gcode::Motion& m, const ChordRange& chords) {
    MoveBatch& batch = batches_[filling_];
    if (batch.tasks.empty()) batch.tasks.resize(kBatch);
    MoveTask& t = batch.tasks[batch.filled++];
    t.first = !started_;
    started_ = true;
    t.offsets = *m.offsets;
    t.motion = m;
    t.motion.offsets = &t.offsets;
    t.text.assign(block_->text);
    t.block.text = t.text;
    t.block.words = block_->words;
    t.block.line = block_->line;
    t.offset = line_.offset;
    t.terminator.assign(line_.terminator);
    t.chords = chords;
    // The nominal pose at its end, here: it balances the two threads' work.
    const model::ChainQ end = chain_of(m.end, t.offsets);
    model::forward(*forward_, *nominal_, end, {}, false, model::Evaluate::nominal);
    t.end_pose = {nominal_->nominal, nominal_->R_nominal};
    batch_points_ += chords.whole() ? expected_points(m, end) : chords.end - chords.begin;
    if (batch.filled == kBatch || batch_points_ >= kBatchPoints) pass_batch();
  }

  /// The filled batch goes to be compensated; when no batch is left to fill, the oldest is
  /// written once compensated, and filled next.
  void pass_batch() {
    const std::size_t b = filling_;
    batch_points_ = 0;
    std::size_t ticket = 0;
    if (worker_)
      ticket = worker_->run([this, b] { solver_->solve_batch(batches_[b]); });
    else
      solver_->solve_batch(batches_[b]);
    in_flight_.push_back({b, ticket});
    filling_ = (filling_ + 1) % kBatches;  // the ring's order: the oldest batch is next
    if (in_flight_.size() == kBatches) write_oldest();
  }

  void write_oldest() {
    const InFlight oldest = in_flight_.front();
    if (worker_) worker_->wait(oldest.ticket);
    in_flight_.pop_front();
    write_batch(oldest.batch);
  }

 public:
  /// Compensates and writes every move queued so far.
  void drain() {
    if (batches_[filling_].filled > 0) pass_batch();
    while (!in_flight_.empty()) write_oldest();
  }

  /// The job stopped with an error: a move queued before it may have failed first (its
  /// error is the one to report), unless the error came from writing the moves.
  void abandon() {
    if (worker_) worker_->wait();
    if (!failed_) drain();
  }

  /// Finishes the program: the moves still queued, then a cycle still open.
  void finish() {
    drain();
    finish_cycle();
  }

 private:
  void write_batch(std::size_t b) {
    try {
      for (std::size_t k = 0; k < batches_[b].filled; ++k) write_move(batches_[b].tasks[k]);
    } catch (...) {
      failed_ = true;
      throw;
    }
    batches_[b].filled = 0;
  }

  void write_move(MoveTask& t) {
    if (t.error) {
      try {
        std::rethrow_exception(t.error);
      } catch (const Error& e) {
        if (!e.where().file.empty() || e.where().line != 0) throw;
        throw Error(e.kind(), e.message(), SourceLocation{input_.name(), t.block.line, 0}, t.text);
      }
    }
    writer_.advance_to(t.offset);
    for (const ErrorProbe& p : t.probes) {
      // Only what may raise the program's maximum is evaluated (the rest is bounded below it).
      const double at_least = std::max(report_.max_error_before, t.report.max_deviation_before);
      t.report.max_deviation_before = std::max(t.report.max_deviation_before, error_before_->error_at(p, at_least));
    }
    const gcode::Block* reading = block_;
    block_ = &t.block;
    account(t.report, t.motion.units, t.block.line, t.text, t.chords.last());
    write_edits(t.motion, t.points, t.offset, t.terminator, t.chords);
    block_ = reading;
    // A slot keeps its storage for the next move, but not what an unusual move needed (a
    // split, a long line): else over a long program every slot would come to hold the
    // most any of its moves needed.
    if (t.points.capacity() > 2) std::vector<CompensatedPoint>().swap(t.points);
    if (t.probes.capacity() > 2) std::vector<ErrorProbe>().swap(t.probes);
    if (t.block.words.capacity() > 8) std::vector<gcode::Word>().swap(t.block.words);
    if (t.text.capacity() > 64) std::string().swap(t.text);
  }

  /// Solves a move on this thread (a cycle's), its error before taken at once.
  void solve_move_here(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move) {
    probes_.clear();
    compensator_->defer_error_before(&probes_);
    solver_->solve(m, offsets, move, points_);
    compensator_->defer_error_before(nullptr);
    for (const ErrorProbe& p : probes_) {
      const double at_least = std::max(report_.max_error_before, move.max_deviation_before);
      move.max_deviation_before = std::max(move.max_deviation_before, error_before_->error_at(p, at_least));
    }
  }

  /// A canned-cycle block, kept until its last move: its holes' X Y R Z are compensated
  /// together. The drill feeds along the cycle's axis from R to the bottom; the block can
  /// take one X Y, so it takes the mean of the R point's and the bottom's corrections and
  /// reports half their difference as what is left.
  struct PendingCycle {
    std::string text;
    std::vector<gcode::Word> words;
    std::uint64_t offset = 0;
    std::uint32_t line = 0;
    gcode::Offsets offsets;
    gcode::Units units = gcode::Units::mm;
    std::vector<gcode::Motion> motions;
    double code = 0;  ///< the cycle's G number
    std::string terminator;
    bool incremental = false;
    bool repeated = false;  ///< its line ran before
  };

 public:
  /// Compensates a cycle still waiting for its block's end (call before the writer finishes).
  void finish_cycle() {
    if (cycle_.motions.empty()) return;
    drain();
    PendingCycle c = std::move(cycle_);
    cycle_ = PendingCycle{};
    if (c.repeated)
      throw Error(ErrorKind::unsupported,
                  "this canned cycle runs more than once (a loop or a subroutine), and each run needs its "
                  "own correction: --flatten writes the program as it runs, loops and subroutines unrolled",
                  SourceLocation{input_.name(), c.line, 0}, c.text);
    // The feeds: the first starts at the R point, the last ends at the bottom.
    const gcode::Motion* first = nullptr;
    const gcode::Motion* last = nullptr;
    int holes = 0;
    for (const gcode::Motion& m : c.motions) {
      if (m.kind != gcode::MotionKind::feed) continue;
      if (!first || (last && last->end[0] != m.start[0]) || (last && last->end[1] != m.start[1])) ++holes;
      if (!first) first = &m;
      last = &m;
    }
    if (!first) return;
    if (options_.expand_cycles) {
      expand_cycle(c);
      return;
    }
    if (holes > 1)
      throw Error(ErrorKind::unsupported,
                  "a canned cycle with L repeats drills several holes in one block; "
                  "compensating it in the block's words is not implemented; --expand-cycles writes it as "
                  "compensated moves",
                  SourceLocation{input_.name(), c.line, 0}, c.text);
    MoveReport move;
    const model::ChainQ r_nominal = chain_of(first->start, c.offsets), bottom_nominal = chain_of(last->end, c.offsets);
    // The hole is approached the way the cycle travels to it: across to it, then down.
    compensator_->approach(chain_of(c.motions.front().start, c.offsets), bottom_nominal);
    move.max_deviation_before = std::max(compensator_->error_at(r_nominal), compensator_->error_at(bottom_nominal));
    const bool inch = c.units == gcode::Units::inch;
    const double unit = inch ? kMmPerInch : 1.0;
    // The cycle's axis is the normal of its plane; the hole's position is in the plane.
    std::size_t normal = 2;
    for (std::size_t i = 0; i < 3; ++i)
      if (std::abs(last->end[i] - first->start[i]) > 1e-9) normal = i;
    model::ChainQ r_comp, bottom_comp;
    gcode::Axes r_prog{}, bottom_prog{}, hole{};
    double left = 0.0;
    // The block's one X Y cannot carry a take-up: an axis that stands still from the last
    // hole still travels by the change of its correction, and that travel decides its
    // approach (a micrometre against the approach is only reached through the whole play).
    // Solved again under the approach the compensated travel gives, until it stays.
    for (int pass = 0; pass < 3; ++pass) {
      MoveReport scratch;
      MoveReport& solved = pass == 2 ? move : scratch;  // the last pass is the one written
      r_comp = compensator_->point(r_nominal, solved);
      bottom_comp = compensator_->point(bottom_nominal, solved);
      r_prog = program_of(r_comp, c.offsets, unit);
      bottom_prog = program_of(bottom_comp, c.offsets, unit);
      hole = bottom_prog;
      left = 0.0;
      for (std::size_t i = 0; i < 3; ++i) {
        if (i == normal) continue;
        hole[i] = 0.5 * (r_prog[i] + bottom_prog[i]);
        left = std::max(left, 0.5 * std::abs(r_prog[i] - bottom_prog[i]) * unit);
      }
      const model::ChainQ from = compensator_->commanded();
      if (pass == 2 || !from.allFinite() ||
          !compensator_->approach_by_travel(from, chain_of(controlled_of_program(hole, c.offsets, unit), c.offsets))) {
        if (pass < 2) {  // settled: the points already solved are the ones written
          move.max_correction = std::max(move.max_correction, scratch.max_correction);
          move.max_orientation_error = std::max(move.max_orientation_error, scratch.max_orientation_error);
        }
        break;
      }
    }
    move.max_deviation_after = left;
    account(move, c.units, c.line, c.text);
    std::vector<gcode::Edit> edits;
    std::uint32_t insert_at = 0;
    for (const gcode::Word& w : c.words) insert_at = std::max(insert_at, w.span.end);
    auto set = [&](char letter, double value, bool rotary) {
      const gcode::Word* word = nullptr;
      for (const gcode::Word& w : c.words)
        if (w.letter == letter) word = &w;
      const std::string original = word ? c.text.substr(word->value_span.begin, word->value_span.size()) : "";
      const WrittenValue written = format_value(value, original, inch && !rotary, rotary, decimals_for(rotary));
      if (word)
        edits.push_back(gcode::Edit{word->value_span, written.text});
      else
        edits.push_back(gcode::Edit{{insert_at, insert_at}, std::string(" ") + letter + written.text});
      return written.value;
    };
    gcode::Axes written{};
    for (std::size_t i = 0; i < 3; ++i)
      written[i] = set(gcode::kAxisLetters[i], i == normal ? bottom_prog[i] : hole[i], false);
    const double written_r = set('R', r_prog[normal], false);
    writer_.edit(c.offset, std::move(edits));
    // Where the rewritten cycle leaves the machine, for the words after it (G91 counts from
    // there): over the hole as written, and along the cycle's axis at the R plane as written
    // (G99) or back at the level it started from (G98), which the block does not change.
    gcode::Axes at = program_of(chain_of(commanded_, c.offsets), c.offsets, unit);
    for (std::size_t i = 0; i < 3; ++i)
      if (i != normal) at[i] = written[i], rounding_[i] = 0.0;
    if (std::abs(c.motions.back().end[normal] - first->start[normal]) < 1e-9) {
      at[normal] = written_r;
      rounding_[normal] = 0.0;
    }
    commanded_ = controlled_of_program(at, c.offsets, unit);
    // The machine follows the cycle's motions, shifted by the hole's correction.
    const model::ChainQ shift = bottom_comp - bottom_nominal;
    for (const gcode::Motion& m : c.motions) compensator_->moved(chain_of(m.end, c.offsets) + shift);
  }

 private:
  PendingCycle cycle_;
  double cycle_code_ = 0;  ///< the last canned cycle's G number

  static bool is_cycle_code(double g) { return g == 73 || g == 74 || g == 76 || (g >= 81 && g <= 89); }

  /// The cycle as the moves it makes: its block keeps every word but the cycle's own (the
  /// G code, the axes, R Q L P), and the compensated moves follow it, one line a point, in
  /// absolute coordinates (G90 around them when the program is in G91).
  void expand_cycle(const PendingCycle& c) {
    const double g = c.code;
    if (g != 73 && g != 81 && g != 83 && g != 85)
      throw Error(ErrorKind::unsupported,
                  fmt::format("--expand-cycles writes G73 G81 G83 G85 as moves; G{:g} also dwells or turns the "
                              "spindle, which moves cannot say (compensate it without --expand-cycles)",
                              g),
                  SourceLocation{input_.name(), c.line, 0}, c.text);
    std::vector<gcode::Span> cycle_words;
    for (const gcode::Word& w : c.words)
      if (std::string_view("XYZABCUVWRQLP").find(w.letter) != std::string_view::npos ||
          (w.letter == 'G' && w.value.is_literal() && is_cycle_code(w.value.literal)))
        cycle_words.push_back(w.span);
    std::vector<gcode::Edit> edits;
    gcode::removal_edits(c.text, cycle_words, edits);
    const bool inch = c.units == gcode::Units::inch;
    const double unit = inch ? kMmPerInch : 1.0;
    const std::string eol = c.terminator.empty() ? "\n" : c.terminator;
    std::string appended;
    if (c.incremental) appended += eol + "G90";
    for (const gcode::Motion& m : c.motions) {
      MoveReport move;
      solve_move_here(m, c.offsets, move);
      account(move, c.units, c.line, c.text);
      for (const CompensatedPoint& point : points_) {
        const gcode::Axes p = program_of(point.q, c.offsets, unit);
        const gcode::Axes last = program_of(chain_of(commanded_, c.offsets), c.offsets, unit);
        std::string text = m.kind == gcode::MotionKind::traverse ? "G0" : "G1";
        const std::size_t bare = text.size();
        for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
          if (model_.axis(gcode::kAxisLetters[i]))
            if (const auto word = axis_word(i, p[i], last[i], false, false, {}, inch))
              text += std::string(" ") + gcode::kAxisLetters[i] + *word;
        if (text.size() > bare) appended += eol + text, ++report_.added_lines;
        if (point.take_up) ++report_.take_up_moves;
        commanded_ = controlled_of(point.q, c.offsets);
      }
    }
    if (c.incremental) appended += eol + "G91";
    edits.push_back(
        gcode::Edit{{static_cast<std::uint32_t>(c.text.size()), static_cast<std::uint32_t>(c.text.size())}, appended});
    writer_.edit(c.offset, std::move(edits));
  }

  /// The controlled point of program coordinates (program units, degrees): program_of()'s inverse.
  static gcode::Axes controlled_of_program(const gcode::Axes& p, const gcode::Offsets& offsets, double unit) {
    gcode::Axes controlled{};
    for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
      controlled[i] = (gcode::is_rotary(i) ? p[i] : p[i] * unit) + offsets.origin(i);
    return offsets.to_machine(controlled);
  }

  /// The controlled point (program frame, machine units) the machine is at after commanding q.
  static gcode::Axes controlled_of(const model::ChainQ& q, const gcode::Offsets& offsets) {
    return offsets.from_machine(offsets.to_machine(controlled_of_chain(q, offsets)));
  }

  /// Adds a move's figures to the report and refuses a correction beyond the model's bound.
  void account(const MoveReport& move, gcode::Units units, std::uint32_t line, const std::string& text,
               bool whole_move = true) {
    check_rounding(units, line, text);
    if (move.max_correction > model_.max_correction)
      throw Error(ErrorKind::safety,
                  fmt::format("the correction is {:.4f} mm, beyond the model's bound of {} mm (max_correction): is "
                              "the model right for this machine?",
                              move.max_correction, model_.max_correction),
                  SourceLocation{input_.name(), line, 0}, text);
    report_.max_error_before = std::max(report_.max_error_before, move.max_deviation_before);
    report_.max_error_after = std::max(report_.max_error_after, move.max_deviation_after);
    report_.max_correction = std::max(report_.max_correction, move.max_correction);
    report_.max_orientation_error = std::max(report_.max_orientation_error, move.max_orientation_error);
    warn_unhidden_reversals(move.unhidden_reversals);
    if (move.jogs_withheld && !warned_jogs_ && options_.warning) {
      warned_jogs_ = true;
      options_.warning(
          "cutter radius compensation (G41/G42) is on: the control offsets each line as a piece of its "
          "own, and refuses or gouges short ones at inside corners, so ccomp neither splits straight moves "
          "there nor writes take-up moves; what that leaves is in the summary's 'after' (said once)",
          line);
    }
    if (move.start_error > 0.0 && !warned_start_error_ && options_.warning) {
      warned_start_error_ = true;
      options_.warning(fmt::format("this cut starts where a move in machine coordinates (G53, G28, G30) or a canned "
                                   "cycle left the machine, uncompensated: the tool is {:.2f} um off the cut's start "
                                   "there; ccomp moves it to the compensated start first. A rapid to the start "
                                   "before the cut avoids cutting from there (said once)",
                                   move.start_error * 1000.0),
                       line);
    }
    if (whole_move) ++report_.compensated_moves;  // a move in parts counts at its last
  }

  [[nodiscard]] int decimals_for(bool rotary) const { return rotary ? options_.rotary_decimals : options_.decimals; }

  /// The written digits round each linear axis by up to half their last place, so the tool
  /// by up to sqrt(axes) times that. Once per unit system: a --decimals that may take the
  /// whole tolerance is refused (no written program could meet it), and digits that may
  /// take a quarter of it are warned of, the program's own included. A rotary axis' rounding
  /// moves the tool by its distance from the axis, which only the model's limits bound: a
  /// --rotary-decimals too coarse at that distance is warned of.
  void check_rounding(gcode::Units units, std::uint32_t line, const std::string& text) {
    if (!rotary_checked_ && options_.rotary_decimals >= 0 && options_.warning) {
      rotary_checked_ = true;
      const double angle = 0.5 * std::pow(10.0, -options_.rotary_decimals) * kRadPerDeg;
      if (angle * rotary_lever_ > 0.25 * options_.tolerance)
        options_.warning(fmt::format("rotary coordinates written to {} decimals in degrees may turn the part by up to "
                                     "{:.3g} urad, {:.3g} um at {:g} mm from the axis (the farthest linear axis "
                                     "limit), more than a quarter of the tolerance of {:.3g} um",
                                     options_.rotary_decimals, angle * 1e6, angle * rotary_lever_ * 1000.0,
                                     rotary_lever_, options_.tolerance * 1000.0),
                         line);
    }
    const bool inch = units == gcode::Units::inch;
    bool& checked = rounding_checked_[inch ? 1 : 0];
    if (checked || linear_axes_ == 0) return;
    checked = true;
    const bool forced = options_.decimals >= 0;
    const int decimals = forced ? options_.decimals : inch ? kDefaultInchDecimals : kDefaultDecimals;
    const double place = std::pow(10.0, -decimals) * (inch ? kMmPerInch : 1.0);  // mm
    const double worst = 0.5 * place * std::sqrt(static_cast<double>(linear_axes_));
    const std::string digits =
        fmt::format("{} decimal{} in {}", decimals, decimals == 1 ? "" : "s", inch ? "inch" : "mm");
    if (forced && worst > options_.tolerance)
      throw Error(ErrorKind::usage,
                  fmt::format("--decimals {}: coordinates written to {} may put the tool up to {:.3g} um from the "
                              "compensated point, more than the tolerance of {:.3g} um",
                              decimals, digits, worst * 1000.0, options_.tolerance * 1000.0),
                  SourceLocation{input_.name(), line, 0}, text);
    if (worst > 0.25 * options_.tolerance && options_.warning)
      options_.warning(fmt::format("coordinates written to {}{} may put the tool up to {:.3g} um from the compensated "
                                   "point, more than a quarter of the tolerance of {:.3g} um{}",
                                   forced ? "" : "at least ", digits, worst * 1000.0, options_.tolerance * 1000.0,
                                   forced ? "" : "; --decimals writes more"),
                       line);
  }

  /// The word for axis i at program value p (program units, degrees), or nothing for an
  /// axis the block did not name that need not move; written in the style of `styled` (the
  /// block's own value for the axis, for its line and the lines a split adds). Counted from
  /// where the written digits put the machine (commanded_ at `last`, plus rounding_):
  /// incremental distances carry their rounding instead of summing it over a split move's
  /// pieces.
  std::optional<std::string> axis_word(std::size_t i, double p, double last, bool incremental, bool named,
                                       std::string_view styled, bool inch) {
    const bool rotary = gcode::is_rotary(i);
    const double value = incremental ? p - last - rounding_[i] : p;
    const NumberStyle style = style_of(styled, inch && !rotary, rotary, decimals_for(rotary));
    if (!named) {
      const double unmoved = incremental ? 0.0 : last + rounding_[i];
      if (written_alike(value, unmoved, style)) {
        rounding_[i] += last - p;
        return std::nullopt;
      }
    }
    WrittenValue written = format_value(value, style);
    rounding_[i] = incremental ? rounding_[i] + written.value - (p - last) : written.value - p;
    return std::move(written.text);
  }

  /// Writes a move's points as edits of its line and lines after it, and counts the lines
  /// and take-up moves it added (those it wrote: a take-up too fine for the digits is not).
  void write_edits(const gcode::Motion& m, const std::vector<CompensatedPoint>& points, std::uint64_t offset,
                   std::string_view terminator, const ChordRange& part = {}) {
    const gcode::Block& b = *block_;
    const bool inch = m.units == gcode::Units::inch;
    const double unit = inch ? kMmPerInch : 1.0;
    const bool incremental = m.incremental;
    std::vector<gcode::Edit>& edits = edits_;  // its storage kept from move to move
    edits.clear();
    std::string appended;
    // A part after the first adds lines only: its first point is not the block's own.
    const std::size_t own_line = part.first() ? 0 : static_cast<std::size_t>(-1);
    double previous_s = part.whole() ? 0.0 : static_cast<double>(part.begin) / static_cast<double>(part.count);
    // Words the block lacks go right after its last axis word (or its last word).
    std::uint32_t insert_at = 0, after_axes = 0;
    for (const gcode::Word& w : b.words) {
      insert_at = std::max(insert_at, w.span.end);
      if (gcode::axis_index(w.letter)) after_axes = std::max(after_axes, w.span.end);
    }
    if (after_axes > 0) insert_at = after_axes;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const gcode::Axes p = program_of(points[k].q, *m.offsets, unit);
      std::string segment = k == own_line ? "" : (m.kind == gcode::MotionKind::traverse ? "G0" : "G1");
      const std::size_t bare = segment.size();
      const gcode::Axes last = program_of(chain_of(commanded_, *m.offsets), *m.offsets, unit);
      for (std::size_t i = 0; i < gcode::kAxisCount; ++i) {
        const char letter = gcode::kAxisLetters[i];
        if (!model_.axis(letter)) continue;
        const gcode::Word* own = b.find(letter);
        const gcode::Word* word = k == own_line ? own : nullptr;
        const std::optional<std::string> text = axis_word(i, p[i], last[i], incremental, word != nullptr,
                                                          own ? b.slice(own->value_span) : std::string_view(), inch);
        if (!text) continue;
        if (word)
          edits.push_back(gcode::Edit{word->value_span, *text});
        else if (k == own_line)
          edits.push_back(gcode::Edit{{insert_at, insert_at}, std::string(" ") + letter + *text});
        else
          segment += std::string(" ") + letter + *text;
      }
      // A take-up finer than the program's digits moves nothing: no line for it.
      if (k != own_line && points[k].take_up && segment.size() == bare) continue;
      // Inverse time: each piece keeps its share of the block's duration; a take-up move
      // of a few micrometres gets a thousandth of it.
      if (m.feed_mode == gcode::FeedMode::inverse_time && m.kind != gcode::MotionKind::traverse) {
        const double share = points[k].take_up ? 1e-3 : points[k].s - previous_s;
        const std::string f = fmt::format("{:.4f}", m.feed / share);
        if (k == own_line) {
          if (const gcode::Word* fw = b.find('F')) edits.push_back(gcode::Edit{fw->value_span, f});
        } else {
          segment += " F" + f;
        }
      }
      previous_s = points[k].s;
      // The machine is now at the compensated point: incremental words count from there.
      commanded_ = controlled_of(points[k].q, *m.offsets);
      if (k != own_line) {
        appended += std::string(terminator.empty() ? "\n" : terminator) + segment;
        ++report_.added_lines;
      }
      if (points[k].take_up) ++report_.take_up_moves;
    }
    if ((points.size() > 1 || !part.whole()) && has_stop_code(b))
      refuse(ErrorKind::unsupported,
             "a move that must be split shares its block with a program stop (M0 M1 M2 M30 M60)");
    if (!part.first()) {  // the line is open: the lines go straight out
      writer_.append(appended);
      if (part.last()) writer_.close_line();
      return;
    }
    if (m.kind == gcode::MotionKind::arc && !m.radius_compensation) arc_to_line_edits(b, edits);
    if (!appended.empty())
      edits.push_back(gcode::Edit{
          {static_cast<std::uint32_t>(b.text.size()), static_cast<std::uint32_t>(b.text.size())}, appended});
    // Inserted words go before any trailing comment: after the last word.
    if (!part.last())
      writer_.write_open(offset, std::span<gcode::Edit>(edits));
    else if (!edits.empty())
      writer_.edit(offset, std::span<gcode::Edit>(edits));
  }

  /// An arc block becomes the first of its lines: G2/G3 turns into G1 (written in front when
  /// the arc was modal), the centre, radius and turns words go.
  static void arc_to_line_edits(const gcode::Block& b, std::vector<gcode::Edit>& edits) {
    bool has_motion_code = false;
    std::vector<gcode::Span> arc_words;
    for (const gcode::Word& w : b.words) {
      if (w.letter == 'G' && w.value.is_literal() && (w.value.literal == 2 || w.value.literal == 3)) {
        edits.push_back(gcode::Edit{w.value_span, "1"});
        has_motion_code = true;
      }
      if (w.letter == 'I' || w.letter == 'J' || w.letter == 'K' || w.letter == 'R' || w.letter == 'P')
        arc_words.push_back(w.span);
    }
    gcode::removal_edits(b.text, arc_words, edits);
    if (!has_motion_code && !b.words.empty())
      edits.push_back(gcode::Edit{{b.words.front().span.begin, b.words.front().span.begin}, "G1 "});
  }

  static bool has_stop_code(const gcode::Block& b) {
    for (const gcode::Word& w : b.words)
      if (w.letter == 'M' && w.value.is_literal() &&
          (w.value.literal == 0 || w.value.literal == 1 || w.value.literal == 2 || w.value.literal == 30 ||
           w.value.literal == 60))
        return true;
    return false;
  }

  /// The machine axes (controlled point plus tool offset) must stay within the model's
  /// limits: at every move's end, and for arcs at the extremes they pass through.
  void check_limits(const gcode::Motion& m) const {
    gcode::Axes low = m.end, high = m.end;
    if (m.kind == gcode::MotionKind::arc) arc_extremes(m, low, high);
    for (const model::AxisSpec& a : model_.axes) {
      const auto i = *gcode::axis_index(a.letter);
      const double tool = m.offsets ? m.offsets->tool[i] : 0.0;
      const double lo = low[i] + tool, hi = high[i] + tool;
      if (lo >= a.min - 1e-9 && hi <= a.max + 1e-9) continue;
      const double bad = lo < a.min - 1e-9 ? lo : hi;
      throw Error(ErrorKind::safety,
                  fmt::format("axis {} would go to {:.4f}, outside its limits [{}, {}] of machine '{}'", a.letter, bad,
                              a.min, a.max, model_.name),
                  SourceLocation{input_.name(), m.line, 0});
    }
  }
  /// Widens [low, high] by the points of the arc where its in-plane axes are extreme.
  static void arc_extremes(const gcode::Motion& m, gcode::Axes& low, gcode::Axes& high) {
    const gcode::ArcGeometry g = gcode::arc_geometry(m);
    const gcode::PlaneAxes pa = g.axes;
    const double c1 = m.arc.center_first, c2 = m.arc.center_second;
    const double r = g.r_start, a0 = g.a_start, sweep = g.sweep;
    const bool ccw = g.ccw;
    constexpr double kTurn = 2.0 * std::numbers::pi;
    for (std::size_t axis : {pa.first, pa.second, pa.normal}) {
      low[axis] = std::min({low[axis], m.start[axis], m.end[axis]});
      high[axis] = std::max({high[axis], m.start[axis], m.end[axis]});
    }
    for (int k = 0; k < 4; ++k) {  // the four quadrant points, where the arc passes them
      const double angle = k * kTurn / 4.0;
      double delta = ccw ? angle - a0 : a0 - angle;
      while (delta < 0) delta += kTurn;
      if (delta > sweep) continue;
      const double p1 = c1 + r * std::cos(angle), p2 = c2 + r * std::sin(angle);
      low[pa.first] = std::min(low[pa.first], p1);
      high[pa.first] = std::max(high[pa.first], p1);
      low[pa.second] = std::min(low[pa.second], p2);
      high[pa.second] = std::max(high[pa.second], p2);
    }
  }

  /// Once per axis: a reversal the take-up cannot hide stays in the output.
  void warn_unhidden_reversals(unsigned axes) {
    axes &= ~warned_reversals_;
    warned_reversals_ |= axes;
    for (std::size_t i = 0; i < gcode::kAxisCount && options_.warning; ++i)
      if (axes >> i & 1U)
        options_.warning(fmt::format("axis {}'s reversal cannot be fully taken up, so part of each turn's error "
                                     "stays in the output: the reversal leads the command (a lag, backlash, is "
                                     "negative), or the axis has no positioning reversal (lost motion) of its own, "
                                     "or error motions switching with it act along it by more than its lost motion",
                                     gcode::kAxisLetters[i]),
                         block_->line);
  }

  unsigned warned_reversals_ = 0;
  bool warned_start_error_ = false;
  bool warned_jogs_ = false;
  bool started_ = false;
  int last_percent_ = -1;
  bool has_limits_ = false;
  int linear_axes_ = 0;
  std::uint32_t machine_axes_ = 0;  ///< bit (letter - 'A') for each axis the machine has
  gcode::ProgramWriter& writer_;
  const model::MachineModel& model_;
  const JobOptions& options_;
  const gcode::LineSource& input_;
  JobReport& report_;
  std::unique_ptr<model::ForwardModel> forward_;
  std::unique_ptr<MoveSolver> solver_;
  Compensator* compensator_ = nullptr;  ///< the solver's: only while no batch is in flight
  const gcode::Block* block_ = nullptr;
  gcode::SourceLine line_;
  std::vector<CompensatedPoint> points_;  ///< a cycle's move's points
  std::vector<ErrorProbe> probes_;
  std::vector<gcode::Edit> edits_;
  gcode::Axes commanded_{};  ///< where the rewritten program has sent the controlled point
  /// Per axis, program units: where the written digits put the machine less commanded_.
  gcode::Axes rounding_{};
  std::array<bool, 2> rounding_checked_{};  ///< check_rounding() done, for mm and for inch
  bool rotary_checked_ = false;
  /// mm: how far the tool may be from a rotary axis, for its rounding (the farthest limit).
  double rotary_lever_ = 100.0;
  std::uint64_t furthest_ = 0;                    ///< the offset of the furthest line read
  bool repeated_ = false;                         ///< the current line is before it
  bool elsewhere_ = false;                        ///< the current line is in another file (a subroutine's)
  const gcode::Offsets* live_offsets_ = nullptr;  ///< the interpreter's, as it runs (from its motions)
  gcode::Axes nominal_end_{};                     ///< where the original's last motion ended
  gcode::Units last_units_ = gcode::Units::mm;    ///< the units of the original's last motion
  /// The uncompensated machine's error, for the report, is taken by a compensator of its own
  /// on the writing side (it changes nothing the compensation decides).
  std::unique_ptr<Compensator> error_before_;
  std::unique_ptr<model::ForwardData> nominal_;  ///< scratch for the moves' nominal ends
  std::array<MoveBatch, kBatches> batches_;
  std::size_t filling_ = 0;       ///< the batch the interpreter fills
  std::size_t batch_points_ = 0;  ///< the points expected of the batch being filled
  struct InFlight {
    std::size_t batch = 0;   ///< index into batches_
    std::size_t ticket = 0;  ///< the worker's, for its compensation
  };
  std::deque<InFlight> in_flight_;  ///< filled batches in program order, to be written
  bool failed_ = false;             ///< writing a move failed: nothing more is written
  /// Last: destroyed (joined) first, while what it works on still exists.
  std::unique_ptr<util::BackgroundThread> worker_;
};

std::string sanitize(std::string_view s) {
  std::string out;
  for (char c : s) out.push_back(c == '(' || c == ')' || c == '\n' || c == '\r' ? '_' : c);
  return out;
}

}  // namespace

std::string header_line(const model::MachineModel& model, double tolerance) {
  return fmt::format("{}{} compensated for machine '{}' model sha256:{} at {:g} um)", kHeaderPrefix, kVersion,
                     sanitize(model.name), model.sha256, tolerance * 1000.0);
}

std::optional<HeaderFacts> read_header(std::string_view line) {
  if (!is_header_line(line)) return std::nullopt;
  HeaderFacts facts;
  constexpr std::string_view kSha = "model sha256:", kAt = " at ";
  if (const auto sha = line.rfind(kSha); sha != std::string_view::npos) {
    const auto begin = sha + kSha.size();
    const auto end = line.find_first_not_of("0123456789abcdef", begin);
    facts.model_sha256 = std::string(line.substr(begin, end == std::string_view::npos ? end : end - begin));
    if (end != std::string_view::npos && line.substr(end).starts_with(kAt)) {
      double um = 0.0;
      const std::string_view number = line.substr(end + kAt.size());
      if (const auto [p, ec] = std::from_chars(number.data(), number.data() + number.size(), um);
          ec == std::errc() && std::string_view(p, number.data() + number.size()).starts_with(" um)"))
        facts.tolerance = um / 1000.0;
    }
  }
  return facts;
}

bool is_header_line(std::string_view line) {
  if (line.starts_with("\xEF\xBB\xBF")) line.remove_prefix(3);  // a byte-order mark before it
  const auto first = line.find_first_not_of(" \t");
  return first != std::string_view::npos && line.substr(first).starts_with(kHeaderPrefix) &&
         line.find("compensated for machine") != std::string_view::npos;
}

void validate(const JobOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance))
    throw Error(ErrorKind::usage,
                fmt::format("the tolerance must be a positive number of mm, not {}", options.tolerance));
  for (const auto& [name, decimals] :
       {std::pair{"decimals", options.decimals}, {"rotary_decimals", options.rotary_decimals}})
    if (decimals < -1 || decimals > 9)
      throw Error(ErrorKind::usage,
                  fmt::format("{} must be 0 to 9 (or -1: the program's own), not {}", name, decimals));
  if (options.threads != 1 && options.threads != 2)
    throw Error(ErrorKind::usage, fmt::format("threads must be 1 or 2, not {}", options.threads));
  if (!std::isfinite(options.time))
    throw Error(ErrorKind::usage, fmt::format("the time must be finite, not {}", options.time));
  for (const auto& [name, value] : options.sensors)
    if (!std::isfinite(value))
      throw Error(ErrorKind::usage, fmt::format("sensor '{}' must read a finite temperature, not {}", name, value));
}

namespace {

/// The job on the program as it runs: flattened into an unnamed temporary file, which is
/// then compensated line for line; what goes wrong is reported at the original's lines.
JobReport run_flattened_job(gcode::LineSource& input, std::FILE* out, const model::MachineModel& model,
                            const JobOptions& options) {
  std::string path = (std::filesystem::temp_directory_path() / "ccomp-flat-XXXXXX").string();
  const int fd = ::mkstemp(path.data());
  if (fd < 0)
    throw Error(ErrorKind::io, fmt::format("cannot create a temporary file for flattening '{}'", input.name()));
  std::FILE* spool = ::fdopen(fd, "w+b");
  gcode::LineOrigins origins;
  try {
    origins = gcode::flatten(input, spool, options.interpreter);
  } catch (...) {
    std::fclose(spool);
    std::remove(path.c_str());
    throw;
  }
  std::fclose(spool);
  gcode::LineSource flat = gcode::LineSource::open(path);
  std::remove(path.c_str());  // the reader holds it open; nothing is left behind
  JobOptions inner = options;
  inner.flatten = false;
  if (options.warning)
    inner.warning = [&](const std::string& message, std::uint32_t line) {
      options.warning(message, origins.at(line).line);
    };
  try {
    JobReport report = run_program_job(flat, out, model, inner);
    report.bytes = input.size();
    return report;
  } catch (const Error& e) {
    if (e.where().file != flat.name()) throw;
    SourceLocation at = origins.at(e.where().line);
    if (at.file.empty()) at.file = input.name();
    throw Error(e.kind(), e.source_line().empty() ? e.message() : e.message() + " (the line as it runs is shown)", at,
                e.source_line());
  }
}

}  // namespace

JobReport run_program_job(gcode::LineSource& input, std::FILE* out, const model::MachineModel& model,
                          const JobOptions& options) {
  validate(options);
  if (options.flatten) return run_flattened_job(input, out, model, options);
  JobReport report;
  report.bytes = input.size();
  {
    // Double compensation would apply the correction twice: look at the first lines.
    gcode::LineSource peek = input.another_reader();
    gcode::SourceLine line;
    for (int i = 0; i < 3 && peek.next(line); ++i) {
      if (is_header_line(line.text) && !options.force)
        throw Error(ErrorKind::safety,
                    "the program is already compensated by ccomp (its header is on this line); "
                    "compensating again would apply the correction twice (--force overrides)",
                    SourceLocation{input.name(), line.number, 1}, std::string(line.text));
    }
  }
  gcode::ProgramWriter writer(input.another_reader(), out, header_line(model, options.tolerance));
  JobSink sink(writer, model, options, input, report);
  gcode::Interpreter interpreter(options.interpreter);
  try {
    interpreter.run(input, sink);
    sink.finish();
  } catch (...) {
    sink.abandon();
    throw;
  }
  writer.finish();
  if (options.progress) options.progress(1.0);
  return report;
}

}  // namespace ccomp::compensate
