#include "canned_cycles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "ccomp/error.hpp"
#include "ccomp/compensate/machine_coordinates.hpp"
#include "number_style.hpp"
#include "program_coordinates.hpp"

namespace ccomp::compensate {


bool is_cycle_code(double g) {
  return g == 73 || g == 74 || g == 76 || (g >= 81 && g <= 89);
}

namespace {

/// A cycle's feeds: the first starts at the R point, the last ends at the bottom; and how
/// many holes they drill.
struct CycleFeeds {
  const gcode::Motion* first = nullptr;
  const gcode::Motion* last = nullptr;
  int holes = 0;
};

CycleFeeds feeds_of(const PendingCycle& c) {
  CycleFeeds f;
  for (const gcode::Motion& m : c.motions) {
    if (m.kind != gcode::MotionKind::feed) continue;
    if (!f.first || (f.last && f.last->end[0] != m.start[0]) || (f.last && f.last->end[1] != m.start[1])) ++f.holes;
    if (!f.first) f.first = &m;
    f.last = &m;
  }
  return f;
}

[[noreturn]] void refuse_cycle(const PendingCycle& c, const std::string& why, std::string_view file) {
  throw Error(ErrorKind::unsupported, why, SourceLocation{std::string(file), c.line, 0}, c.text);
}

/// A hole as the block's words can carry it: one X Y (the mean of the R point's and the
/// bottom's corrections), the bottom and the R plane along the cycle's axis.
struct HoleWords {
  std::size_t normal = 2;  ///< the cycle's axis, the normal of its plane
  model::ChainQ bottom_nominal, bottom_comp;
  gcode::Axes r_prog{}, bottom_prog{}, hole{};
  double left = 0.0;  ///< mm: half the difference of the R point's and the bottom's corrections
};

}  // namespace

CannedCycles::CannedCycles(const CycleStages& stages, const model::MachineModel& model, bool expand,
                           std::string_view file)
    : stages_(stages), compensator_(stages.solver.compensator), model_(model), expand_(expand), file_(file) {}

void CannedCycles::note_block(const gcode::Block& block) {
  for (const gcode::Word& w : block.words)  // the cycle a modal repeat line drills
    if (w.letter == 'G' && w.value.is_literal() && is_cycle_code(w.value.literal)) cycle_code_ = w.value.literal;
}

void CannedCycles::add(const gcode::Motion& m, const gcode::Block& block, const gcode::SourceLine& line,
                       bool repeated) {
  if (m.incremental && !expand_)
    throw Error(ErrorKind::unsupported,
                "compensating incremental (G91) canned cycles in the block's words is not "
                "implemented; --expand-cycles writes them as compensated moves",
                SourceLocation{std::string(file_), block.line, 0}, std::string(block.text));
  if (cycle_.motions.empty()) {
    cycle_.code = cycle_code_;
    cycle_.terminator = std::string(line.terminator);
    cycle_.incremental = m.incremental;
    cycle_.text = std::string(block.text);
    cycle_.words = block.words;
    cycle_.offset = line.offset;
    cycle_.line = block.line;
    cycle_.offsets = *m.offsets;
    cycle_.units = m.units;
    cycle_.repeated = repeated;
  }
  cycle_.motions.push_back(m);
}

void CannedCycles::finish() {
  if (cycle_.motions.empty()) return;
  const PendingCycle c = std::exchange(cycle_, PendingCycle{});
  if (c.repeated)
    refuse_cycle(c,
                 "this canned cycle runs more than once (a loop or a subroutine), and each run needs its "
                 "own correction: --flatten writes the program as it runs, loops and subroutines unrolled",
                 file_);
  const CycleFeeds feeds = feeds_of(c);
  if (!feeds.first) return;
  if (expand_) {
    expand(c);
    return;
  }
  if (feeds.holes > 1)
    refuse_cycle(c,
                 "a canned cycle with L repeats drills several holes in one block; compensating it in the "
                 "block's words is not implemented; --expand-cycles writes it as compensated moves",
                 file_);
  compensate_words(c, *feeds.first, *feeds.last);
}

namespace {

/// The hole's words, solved under the approach its compensated travel gives. The block's one
/// X Y cannot carry a take-up: an axis that stands still from the last hole still travels by
/// the change of its correction, and that travel decides its approach (a micrometre against
/// the approach is only reached through the whole play). So it is solved again until the
/// approach stays.
HoleWords solve_hole(Compensator& compensator, const PendingCycle& c, const gcode::Motion& first,
                     const gcode::Motion& last, MoveReport& move) {
  HoleWords h;
  const model::ChainQ r_nominal = chain_of(first.start, c.offsets);
  h.bottom_nominal = chain_of(last.end, c.offsets);
  // The hole is approached the way the cycle travels to it: across to it, then down.
  compensator.approach(chain_of(c.motions.front().start, c.offsets), h.bottom_nominal);
  move.max_deviation_before = std::max(compensator.error_at(r_nominal), compensator.error_at(h.bottom_nominal));
  const double unit = mm_per_unit(c.units);
  for (std::size_t i = 0; i < 3; ++i)
    if (std::abs(last.end[i] - first.start[i]) > 1e-9) h.normal = i;
  for (int pass = 0; pass < 3; ++pass) {
    MoveReport scratch;
    MoveReport& solved = pass == 2 ? move : scratch;  // the last pass is the one written
    const model::ChainQ r_comp = compensator.point(r_nominal, solved);
    h.bottom_comp = compensator.point(h.bottom_nominal, solved);
    h.r_prog = program_of(r_comp, c.offsets, unit);
    h.bottom_prog = program_of(h.bottom_comp, c.offsets, unit);
    h.hole = h.bottom_prog;
    h.left = 0.0;
    for (std::size_t i = 0; i < 3; ++i) {
      if (i == h.normal) continue;
      h.hole[i] = 0.5 * (h.r_prog[i] + h.bottom_prog[i]);
      h.left = std::max(h.left, 0.5 * std::abs(h.r_prog[i] - h.bottom_prog[i]) * unit);
    }
    const model::ChainQ from = compensator.commanded();
    if (pass == 2 || !from.allFinite() ||
        !compensator.approach_by_travel(from, chain_of(controlled_of_program(h.hole, c.offsets, unit), c.offsets))) {
      if (pass < 2) {  // settled: the points already solved are the ones written
        move.max_correction = std::max(move.max_correction, scratch.max_correction);
        move.max_rotary_correction = std::max(move.max_rotary_correction, scratch.max_rotary_correction);
        move.max_orientation_error = std::max(move.max_orientation_error, scratch.max_orientation_error);
        move.held_axes |= scratch.held_axes;
      }
      break;
    }
  }
  move.max_deviation_after = h.left;
  // Between them the drill goes straight down the hole's one X Y while the error bends with
  // the depth: how far the hole strays across its line is checked along the stroke, as a
  // move's pieces are (its depth there is the control's, from R: not checked).
  gcode::Axes r_written = h.hole, bottom_written = h.hole;
  r_written[h.normal] = h.r_prog[h.normal];
  bottom_written[h.normal] = h.bottom_prog[h.normal];
  const model::ChainQ r_comp = chain_of(controlled_of_program(r_written, c.offsets, unit), c.offsets);
  const model::ChainQ bottom_comp = chain_of(controlled_of_program(bottom_written, c.offsets, unit), c.offsets);
  const int n = compensator.model().check_points(r_nominal, h.bottom_nominal, 4, 64);
  for (int k = 1; k < n; ++k)
    move.max_deviation_after =
        std::max(move.max_deviation_after, compensator.deviation_across(r_nominal, h.bottom_nominal, r_comp,
                                                                        bottom_comp, static_cast<double>(k) / n));
  return h;
}

/// The values the rewritten block tells the machine: X Y Z as written, and R.
struct WrittenHole {
  gcode::Axes axes{};
  double r = 0.0;
};

/// The edits of the cycle block's X Y Z and R (words it lacks inserted after its last word).
WrittenHole hole_edits(const PendingCycle& c, const HoleWords& h, const DecimalsOption& decimals,
                       std::vector<gcode::Edit>& edits) {
  const bool inch = c.units == gcode::Units::inch;
  std::uint32_t insert_at = 0;
  for (const gcode::Word& w : c.words) insert_at = std::max(insert_at, w.span.end);
  auto set = [&](char letter, double value) {
    const gcode::Word* word = nullptr;
    for (const gcode::Word& w : c.words)
      if (w.letter == letter) word = &w;
    const std::string original = word ? c.text.substr(word->value_span.begin, word->value_span.size()) : "";
    const WrittenValue written = format_value(value, original, inch, false, decimals.for_axis(false));
    if (word)
      edits.push_back(gcode::Edit{word->value_span, written.text});
    else
      edits.push_back(gcode::Edit{{insert_at, insert_at}, std::string(" ") + letter + written.text});
    return written.value;
  };
  WrittenHole written;
  for (std::size_t i = 0; i < 3; ++i)
    written.axes[i] = set(gcode::kAxisLetters[i], i == h.normal ? h.bottom_prog[i] : h.hole[i]);
  written.r = set('R', h.r_prog[h.normal]);
  return written;
}

}  // namespace

void CannedCycles::compensate_words(const PendingCycle& c, const gcode::Motion& first, const gcode::Motion& last) {
  MoveReport move;
  const HoleWords h = solve_hole(compensator_, c, first, last, move);
  stages_.guards.account(move, c.units, c.line, c.text);
  std::vector<gcode::Edit> edits;
  const WrittenHole written = hole_edits(c, h, stages_.rewriter.decimals(), edits);
  stages_.writer.edit(c.offset, std::move(edits));
  // Where the rewritten cycle leaves the machine, for the words after it (G91 counts from
  // there): over the hole as written, and along the cycle's axis at the R plane as written
  // (G99) or back at the level it started from (G98), which the block does not change.
  WrittenPosition& position = stages_.rewriter.position();
  const double unit = mm_per_unit(c.units);
  gcode::Axes at = program_of(chain_of(position.commanded, c.offsets), c.offsets, unit);
  for (std::size_t i = 0; i < 3; ++i)
    if (i != h.normal) at[i] = written.axes[i], position.rounding[i] = 0.0;
  if (std::abs(c.motions.back().end[h.normal] - first.start[h.normal]) < 1e-9) {
    at[h.normal] = written.r;
    position.rounding[h.normal] = 0.0;
  }
  position.commanded = controlled_of_program(at, c.offsets, unit);
  position.tcp = false;
  // The machine follows the cycle's motions, shifted by the hole's correction.
  const model::ChainQ shift = h.bottom_comp - h.bottom_nominal;
  for (const gcode::Motion& m : c.motions) compensator_.moved(chain_of(m.end, c.offsets) + shift);
}

/// The cycle as the moves it makes: its block keeps every word but the cycle's own (the G
/// code, the axes, R Q L P), and the compensated moves follow it, one line a point, in
/// absolute coordinates (G90 around them when the program is in G91).
void CannedCycles::expand(const PendingCycle& c) {
  const double g = c.code;
  if (g != 73 && g != 81 && g != 83 && g != 85)
    refuse_cycle(c,
                 fmt::format("--expand-cycles writes G73 G81 G83 G85 as moves; G{:g} also dwells or turns the "
                             "spindle, which moves cannot say (compensate it without --expand-cycles)",
                             g),
                 file_);
  std::vector<gcode::Span> cycle_words;
  for (const gcode::Word& w : c.words)
    if (std::string_view("XYZABCUVWRQLP").find(w.letter) != std::string_view::npos ||
        (w.letter == 'G' && w.value.is_literal() && is_cycle_code(w.value.literal)))
      cycle_words.push_back(w.span);
  std::vector<gcode::Edit> edits;
  gcode::removal_edits(c.text, cycle_words, edits);
  const std::string eol = c.terminator.empty() ? "\n" : c.terminator;
  std::string appended;
  if (c.incremental) appended += eol + "G90";
  for (const gcode::Motion& m : c.motions) {
    MoveReport move;
    solve_move_here(m, c.offsets, move);
    stages_.guards.account(move, c.units, c.line, c.text);
    for (const CompensatedPoint& point : points_) {
      const std::string line = expanded_line(m, c, point);
      if (!line.empty()) appended += eol + line, ++stages_.report.added_lines;
      if (point.take_up) ++stages_.report.take_up_moves;
      stages_.rewriter.position().commanded = controlled_of(point.q, c.offsets);
      stages_.rewriter.position().tcp = false;
    }
  }
  if (c.incremental) appended += eol + "G91";
  edits.push_back(
      gcode::Edit{{static_cast<std::uint32_t>(c.text.size()), static_cast<std::uint32_t>(c.text.size())}, appended});
  stages_.writer.edit(c.offset, std::move(edits));
}

/// A point of an expanded cycle's move as a G0/G1 line of the axes that move (empty when
/// none does).
std::string CannedCycles::expanded_line(const gcode::Motion& m, const PendingCycle& c, const CompensatedPoint& point) {
  const bool inch = c.units == gcode::Units::inch;
  const double unit = mm_per_unit(c.units);
  const gcode::Axes p = program_of(point.q, c.offsets, unit);
  const gcode::Axes last = program_of(chain_of(stages_.rewriter.position().commanded, c.offsets), c.offsets, unit);
  std::string text = m.kind == gcode::MotionKind::traverse ? "G0" : "G1";
  const std::size_t bare = text.size();
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
    if (model_.axis(gcode::kAxisLetters[i]))
      if (const auto word =
              stages_.rewriter.axis_word(i, p[i], last[i], false, false, {}, inch, turn_word(point, c.offsets, i, unit)))
        text += std::string(" ") + gcode::kAxisLetters[i] + *word;
  return text.size() > bare ? text : std::string();
}

/// Solves a move on this thread (a cycle's), its error before taken at once.
void CannedCycles::solve_move_here(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move) {
  probes_.clear();
  compensator_.defer_error_before(&probes_);
  stages_.solver.solve(m, offsets, move, points_);
  compensator_.defer_error_before(nullptr);
  take_error_before(stages_.error_before, stages_.report.max_error_before, probes_, move);
}

}  // namespace ccomp::compensate
