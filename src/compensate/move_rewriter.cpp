#include "move_rewriter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <span>

#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/compensate/machine_coordinates.hpp"
#include "number_style.hpp"

namespace ccomp::compensate {
namespace {

/// Words the block lacks go right after its last axis word (or its last word).
std::uint32_t insertion_point(const gcode::Block& b) {
  std::uint32_t insert_at = 0, after_axes = 0;
  for (const gcode::Word& w : b.words) {
    insert_at = std::max(insert_at, w.span.end);
    if (gcode::axis_index(w.letter)) after_axes = std::max(after_axes, w.span.end);
  }
  return after_axes > 0 ? after_axes : insert_at;
}

/// The unit of the last digit written.
double quantum(const NumberStyle& style) {
  return std::pow(10.0, -style.decimals);
}

}  // namespace

TurnWord turn_word(const CompensatedPoint& point, const gcode::Offsets& offsets, std::size_t i, double unit) {
  // A program axis is the machine's own where no rotation about Z mixes X with Y.
  if (i >= point.turns.size() || point.turns[i] == 0 || (offsets.rotation != 0.0 && i < 2)) return {};
  return {point.turns[i], point.travel_slack / (gcode::is_rotary(i) ? kRadPerDeg : unit), point.slack_stray};
}

/// One point of a move as it is written: on the block's own line (its words edited) or on a
/// line added after it.
struct MoveRewriter::PointLine {
  bool own = false;      ///< the block's own line
  std::string segment;   ///< an added line's text
  std::size_t bare = 0;  ///< the segment's length before any axis word
  std::uint32_t insert_at = 0;
};

MoveRewriter::MoveRewriter(gcode::ProgramWriter& writer, const model::MachineModel& model, DecimalsOption decimals,
                           JobReport& report, std::string_view file)
    : writer_(writer), decimals_(decimals), report_(report), file_(file) {
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
    if (model.axis(gcode::kAxisLetters[i]) != nullptr)
      machine_axes_[machine_axis_count_++] = static_cast<std::uint8_t>(i);
  for (const model::ErrorTermSpec& t : model.terms)
    if (t.primary.kind == model::VariableKind::direction) approach_axes_.insert_at(t.primary.index);
}

std::optional<std::string> MoveRewriter::axis_word(std::size_t i, double p, double last, bool incremental, bool named,
                                                   std::string_view styled, bool inch, const TurnWord& turn) {
  std::string text;
  const bool rotary = gcode::is_rotary(i);
  const NumberStyle style = style_of(styled, inch && !rotary, rotary, decimals_.for_axis(rotary));
  if (!write_axis_word(i, p, last, incremental, named, style, turn, text)) return std::nullopt;
  return text;
}

bool MoveRewriter::write_axis_word(std::size_t i, double p, double last, bool incremental, bool named,
                                   NumberStyle style, const TurnWord& turn, std::string& text) {
  gcode::Axes& rounding = position_.rounding;
  const bool own_digits = decimals_.for_axis(gcode::is_rotary(i)) < 0;
  // Where the written digits left the machine, what the word's value counts from (an
  // incremental word's is its travel from there), and the travel planned.
  const double at = last + rounding[i], from = incremental ? 0.0 : at, planned = p - last;
  // (A take-up that sends the axis against its turn, as one of a reversal that leads the
  // command can, is written as any move.)
  const bool turning = turn.way != 0 && turn.way * planned > -1e-9;
  const int style_decimals = style.decimals;
  if (turning && own_digits)
    for (const int most = style.decimals + 2; style.decimals < most && 1.5 * quantum(style) > turn.slack;)
      ++style.decimals;
  const double value = incremental ? p - last - rounding[i] : p;
  // The digits would send an axis whose approach a term reads back against its travel (a
  // take-up rounded out before it), and so open its play again: it stays where it is.
  const bool approach = approach_axes_.contains_at(i);
  auto against = [&](double written_value) {
    return approach && (planned >= 0.0 ? written_value < from : written_value > from);
  };
  if (!named && !turning &&
      (written_alike(value, from, style) || (approach && against(written_number(value, style))))) {
    rounding[i] += last - p;  // (checked before the text is made: most unnamed axes stay)
    return false;
  }
  // (Written straight into `text`: the edit's own string.)
  double written = 0.0;
  if (turning) {
    WrittenValue taken = take_up_word(planned, from, turn, style);
    text = std::move(taken.text);
    written = taken.value;
  } else {
    written = format_value(value, style, text);
  }
  if (!turning && against(written)) {
    written = format_value(from, style, text);  // to as many digits as that takes
    while (own_digits && written != from && style.decimals < kMostDecimals)
      ++style.decimals, written = format_value(from, style, text);
  }
  // Digits added and not needed ("X-30.02060") go again.
  while (style.decimals > style_decimals && text.ends_with('0'))
    --style.decimals, written = format_value(written, style, text);
  rounding[i] = incremental ? rounding[i] + written - planned : written - p;
  return true;
}

WrittenValue MoveRewriter::take_up_word(double planned, double from, const TurnWord& turn, const NumberStyle& style) {
  // The travel as written, one unit of the last digit further at a time until it falls
  // short of the plan by no more than its slack (the digits before may have left it up to
  // one and a half units behind), and at least one unit its way: the play is taken up whole.
  const double unit = quantum(style), way = turn.way > 0 ? 1.0 : -1.0;
  const double wanted = way * std::max(way * planned, 0.0), slack = std::min(turn.slack, 0.5 * unit);
  WrittenValue written = format_value(from + wanted, style);
  auto travel = [&] { return written.value - from; };
  for (int k = 0; k < 3 && way * (travel() - wanted) < -slack; ++k)
    written = format_value(written.value + way * unit, style);
  if (way * travel() < 0.5 * unit) written = format_value(written.value + way * unit, style);
  // What the travel off the plan leaves, the terms switching over more or less of it than
  // the axis goes: counted in what the job says is left.
  if (std::isfinite(turn.slack))
    report_.max_error_after =
        std::max(report_.max_error_after, turn.slack_stray * std::abs(travel() - wanted) / turn.slack);
  return written;
}

namespace {

/// A point in mm and deg in the program's units (`unit`: mm per unit).
gcode::Axes in_program_units(gcode::Axes p, double unit) {
  for (std::size_t i = 0; i < gcode::kAxisCount; ++i)
    if (!gcode::is_rotary(i)) p[i] /= unit;
  return p;
}

}  // namespace

gcode::Axes MoveRewriter::commanded_of(const model::ChainQ& q, const gcode::Offsets& offsets, bool tcp) {
  if (!tcp) return controlled_of(q, offsets);
  return offsets.from_machine(offsets.to_machine(tcp_->world_of(q, offsets)));
}

void MoveRewriter::position_in(bool tcp, const gcode::Offsets& offsets) {
  if (position_.tcp == tcp) return;
  // The control switched kinematics where the machine stands: the axes' positions as the
  // move that left them commanded them (its offsets: a G49 that ends TCP has taken the
  // tool's length away since), in the other coordinates under the offsets now. The written
  // digits' rounding, per axis of the old coordinates, starts anew (at most half a digit).
  const model::ChainQ q = position_.tcp ? tcp_->joints_of(position_.commanded, position_offsets_)
                                        : chain_of(position_.commanded, offsets);
  position_.commanded = commanded_of(q, offsets, tcp);
  position_.rounding = {};
  position_.tcp = tcp;
}

void MoveRewriter::point_words(const gcode::Motion& m, const gcode::Block& b, const CompensatedPoint& point,
                               bool tcp, PointLine& line) {
  const bool inch = m.units == gcode::Units::inch;
  const double unit = mm_per_unit(m.units);
  gcode::Axes p, last;
  if (!tcp) {
    p = program_of(point.q, *m.offsets, unit);
    last = program_of(chain_of(position_.commanded, *m.offsets), *m.offsets, unit);
  } else {
    p = in_program_units(m.offsets->program_of(commanded_of(point.q, *m.offsets, true)), unit);
    last = in_program_units(m.offsets->program_of(position_.commanded), unit);
  }
  // The block's first word of each axis, in one pass over its words (a lone letter, which
  // the interpreter ignores, is not one: a value written into it would be a second word).
  std::array<const gcode::Word*, gcode::kAxisCount> words{};
  for (const gcode::Word& w : b.words)
    if (const std::optional<std::size_t> axis = gcode::axis_index(w.letter);
        axis && w.has_value && w.extension == 0 && !words[*axis])
      words[*axis] = &w;
  for (std::size_t n = 0; n < machine_axis_count_; ++n) {
    const std::size_t i = machine_axes_[n];
    const char letter = gcode::kAxisLetters[i];
    const gcode::Word* own = words[i];
    const gcode::Word* word = line.own ? own : nullptr;
    const bool rotary = gcode::is_rotary(i);
    // (A program that gives the direction: its words say where the rotary axes go.)
    if (tcp && rotary && m.direction_words != gcode::DirectionWords::none) continue;
    const NumberStyle style = style_of(own, b.text, inch && !rotary, rotary, decimals_.for_axis(rotary));
    // (Under TCP a linear axis' word is the tip's, not the axis': no way to turn it.)
    const TurnWord turn = tcp && !rotary ? TurnWord{} : turn_word(point, *m.offsets, i, unit);
    if (word) {  // the block's own word: its value replaced, the text made in the edit
      gcode::Edit& edit = edits_.emplace_back(gcode::Edit{word->value_span, {}});
      if (!write_axis_word(i, p[i], last[i], m.incremental, true, style, turn, edit.text)) edits_.pop_back();
      continue;
    }
    if (!write_axis_word(i, p[i], last[i], m.incremental, false, style, turn, word_text_)) continue;
    // (An added word: into an insertion on the block's own line, or onto an added line.)
    std::string& into =
        line.own ? edits_.emplace_back(gcode::Edit{{line.insert_at, line.insert_at}, {}}).text : line.segment;
    into.append(1, ' ').append(1, letter).append(word_text_);
  }
  if (tcp && m.direction_words != gcode::DirectionWords::none) direction_words(m, b, point, line);
}

void MoveRewriter::direction_words(const gcode::Motion& m, const gcode::Block& b, const CompensatedPoint& point,
                                   PointLine& line) {
  const Eigen::Vector3d d = tcp_->direction(point.q);
  const bool siemens = m.direction_words == gcode::DirectionWords::siemens_vector;
  const std::array<std::string_view, 3> addresses =
      siemens ? std::array<std::string_view, 3>{"A3=", "B3=", "C3="} : std::array<std::string_view, 3>{"I", "J", "K"};
  auto own_word = [&](std::size_t k) -> const gcode::Word* {
    for (const gcode::Word& w : b.words)
      if (w.has_value && w.letter == addresses[k][0] && w.extension == (siemens ? 3 : 0)) return &w;
    return nullptr;
  };
  for (std::size_t k = 0; k < addresses.size(); ++k) {
    // Seven decimals: a tenth of a microradian.
    std::string value = fmt::format("{:.7f}", d[static_cast<Eigen::Index>(k)]);
    if (value == "-0.0000000") value.erase(0, 1);
    const gcode::Word* own = line.own ? own_word(k) : nullptr;
    if (own) {
      edits_.push_back(gcode::Edit{own->value_span, std::move(value)});
      continue;
    }
    std::string& into =
        line.own ? edits_.emplace_back(gcode::Edit{{line.insert_at, line.insert_at}, {}}).text : line.segment;
    into.append(1, ' ').append(addresses[k]).append(value);
  }
}

/// A piece's inverse-time F word: the block's F over the piece's share of its length, with
/// the digits its duration needs (at least 4 decimals, and 7 significant digits: F0.00004 is
/// 25,000 minutes, which 4 decimals wrote as F0.0000). A share of nothing (a piece of no
/// length) still takes no less than a millionth of the block's time.
std::string MoveRewriter::inverse_time_feed(double feed, double share, const gcode::Block& b) const {
  const double f = feed / std::max(share, 1e-6);
  if (!std::isfinite(f) || !(f >= 0.0))
    throw Error(ErrorKind::program,
                fmt::format("under G93 this piece's feed (F{:g} over {:.3g} of the move) is not a usable number", feed,
                            share),
                SourceLocation{std::string(file_), b.line, 0}, std::string(b.text));
  const int magnitude = f > 0.0 ? static_cast<int>(std::floor(std::log10(f))) : 0;  // 10^magnitude <= f
  const int decimals = std::clamp(6 - magnitude, 4, 340);
  std::string text = fmt::format("{:.{}f}", f, decimals);
  // (zeros past the fourth decimal say nothing)
  const std::size_t point = text.find('.');
  while (text.size() > point + 5 && text.back() == '0') text.pop_back();
  return text;
}

void MoveRewriter::rewrite(const gcode::Motion& m, const gcode::Block& b, const std::vector<CompensatedPoint>& points,
                           std::uint64_t offset, std::string_view terminator, const ChordRange& part,
                           std::span<const gcode::Axes> arc_starts, bool adds_lines_only, const MovePiece& piece) {
  edits_.clear();
  if (tcp_) position_in(piece.tcp, *m.offsets);
  const bool arc_pieces = arc_starts.size() == points.size() && points.size() > 1;
  if (arc_pieces) centre_by_words(m, b, arc_starts.front());
  std::string appended;
  // A part after the first adds lines only: its first point is not the block's own.
  const std::size_t own_line = part.first() && !adds_lines_only ? 0 : static_cast<std::size_t>(-1);
  double previous_s = part.whole() ? piece.from : static_cast<double>(part.begin) / static_cast<double>(part.count);
  const double piece_share = piece.to - piece.from;  // a point's s is of its piece: of the block's move, this
  const std::uint32_t insert_at = insertion_point(b);
  for (std::size_t k = 0; k < points.size(); ++k) {
    // (The block's own line, nearly every move's only point, makes no string of its own.)
    const bool own = k == own_line;
    const std::string_view motion_code = own                                     ? ""
                                         : arc_pieces                            ? (m.arc.turns > 0 ? "G3" : "G2")
                                         : m.kind == gcode::MotionKind::traverse ? "G0"
                                                                                 : "G1";
    PointLine line{own, own ? std::string() : std::string(motion_code), motion_code.size(), insert_at};
    // Its centre words count from where the piece starts: the machine, before its words move it.
    std::string centre;
    if (arc_pieces && !own) centre = centre_words(m, b, arc_starts[k]);
    point_words(m, b, points[k], piece.tcp, line);
    if (!centre.empty()) line.segment += centre;
    // A take-up finer than the program's digits moves nothing: no line for it.
    if (!line.own && points[k].take_up && line.segment.size() == line.bare) continue;
    // Inverse time: each piece keeps its share of the block's duration; a take-up move
    // of a few micrometres gets a thousandth of it.
    if (m.feed_mode == gcode::FeedMode::inverse_time && m.kind != gcode::MotionKind::traverse) {
      const double s = piece.from + points[k].s * piece_share;
      const double share = points[k].take_up ? 1e-3 : s - previous_s;
      const std::string f = inverse_time_feed(m.feed, share, b);
      if (!line.own)
        line.segment += " F" + f;
      else if (const gcode::Word* fw = b.find('F'))
        edits_.push_back(gcode::Edit{fw->value_span, f});
    }
    previous_s = piece.from + points[k].s * piece_share;
    // The machine is now at the compensated point: incremental words count from there.
    position_.commanded = commanded_of(points[k].q, *m.offsets, piece.tcp);
    position_.tcp = piece.tcp;
    if (!line.own) {
      appended += std::string(terminator.empty() ? "\n" : terminator) + line.segment;
      if (++report_.added_lines > kMostAddedLines)
        throw Error(ErrorKind::program,
                    fmt::format("the compensated program would be more than {} lines longer than the program (arcs "
                                "written as chords, moves split): a larger --tolerance, or fewer turns",
                                kMostAddedLines),
                    SourceLocation{std::string(file_), b.line, 0}, std::string(b.text));
    }
    if (points[k].take_up) ++report_.take_up_moves;
  }
  if (piece.tcp) position_offsets_ = *m.offsets;
  if ((points.size() > 1 || !part.whole() || piece.from > 0.0 || piece.to < 1.0) && has_stop_code(b))
    throw Error(ErrorKind::unsupported,
                "a move that must be split shares its block with a program stop (M0 M1 M2 M30 M60)",
                SourceLocation{std::string(file_), b.line, 0}, std::string(b.text));
  finish_lines(m, b, offset, part, appended, adds_lines_only, piece.of_arc);
}

/// Hands the move's edits and added lines to the writer. A part after the first is written
/// straight out; a part before the last leaves the block's line open for the next.
std::string MoveRewriter::centre_words(const gcode::Motion& m, const gcode::Block& b, const gcode::Axes& start) {
  // (plane axes: XY -> I J, ZX -> K I, YZ -> J K)
  const gcode::PlaneAxes pa = gcode::plane_axes(m.arc.plane);
  const double unit = mm_per_unit(m.units);
  gcode::Axes centre = m.end;
  centre[pa.first] = m.arc.center_first;
  centre[pa.second] = m.arc.center_second;
  const gcode::Axes c = m.offsets->program_of(centre), p = m.offsets->program_of(start);
  // Absolute centres move with the piece's start as written, as incremental ones do.
  const gcode::Axes written = program_of(chain_of(position_.commanded, *m.offsets), *m.offsets, unit);
  std::string words;
  for (std::size_t axis : {pa.first, pa.second}) {
    const char letter = "IJK"[axis];
    const double value =
        m.absolute_centre ? c[axis] / unit + written[axis] - p[axis] / unit : (c[axis] - p[axis]) / unit;
    const gcode::Word* own = b.find(letter);
    const gcode::Word* styled = own ? own : b.find(gcode::kAxisLetters[axis]);
    words += std::string(" ") + letter +
             format_value(value, styled ? b.slice(styled->value_span) : std::string_view(),
                          m.units == gcode::Units::inch, false, decimals_.linear)
                 .text;
  }
  return words;
}

/// The block's own line is the first piece: a radius word becomes centre words (a negative
/// radius, the long way round, would be wrong for a piece of it).
void MoveRewriter::centre_by_words(const gcode::Motion& m, const gcode::Block& b, const gcode::Axes& start) {
  const gcode::Word* r = b.find('R');
  if (!r) return;
  std::vector<gcode::Span> radius{r->span};
  gcode::removal_edits(b.text, radius, edits_);
  const std::string words = centre_words(m, b, start);
  edits_.push_back(gcode::Edit{{r->span.end, r->span.end}, words});
}

void MoveRewriter::finish_lines(const gcode::Motion& m, const gcode::Block& b, std::uint64_t offset,
                                const ChordRange& part, std::string& appended, bool adds_lines_only,
                                bool arc_block) {
  if (!part.first()) {  // the line is open: the lines go straight out
    writer_.append(appended);
    if (part.last()) writer_.close_line();
    return;
  }
  if ((m.kind == gcode::MotionKind::arc || arc_block) && !m.radius_compensation && !adds_lines_only)
    arc_to_line_edits(b, edits_);
  if (!appended.empty())
    edits_.push_back(
        gcode::Edit{{static_cast<std::uint32_t>(b.text.size()), static_cast<std::uint32_t>(b.text.size())}, appended});
  // Inserted words go before any trailing comment: after the last word.
  if (!part.last())
    writer_.write_open(offset, std::span<gcode::Edit>(edits_));
  else if (!edits_.empty())
    writer_.take_edits(offset, edits_);
}

void arc_to_line_edits(const gcode::Block& b, std::vector<gcode::Edit>& edits) {
  bool has_motion_code = false;
  std::vector<gcode::Span> arc_words;
  for (const gcode::Word& w : b.words) {
    if (w.letter == 'G' && w.value.is_literal() && (w.value.literal == 2 || w.value.literal == 3)) {
      edits.push_back(gcode::Edit{w.value_span, "1"});
      has_motion_code = true;
    }
    // (a corner's arc written on a G1 block, the offset path resolved)
    if (w.letter == 'G' && w.value.is_literal() && w.value.literal == 1) has_motion_code = true;
    if (w.letter == 'I' || w.letter == 'J' || w.letter == 'K' || w.letter == 'R' || w.letter == 'P')
      arc_words.push_back(w.span);
  }
  gcode::removal_edits(b.text, arc_words, edits);
  if (!has_motion_code && !b.words.empty())
    edits.push_back(gcode::Edit{{b.words.front().span.begin, b.words.front().span.begin}, "G1 "});
}

bool has_stop_code(const gcode::Block& b) {
  for (const gcode::Word& w : b.words)
    if (w.letter == 'M' && w.value.is_literal() &&
        (w.value.literal == 0 || w.value.literal == 1 || w.value.literal == 2 || w.value.literal == 30 ||
         w.value.literal == 60))
      return true;
  return false;
}

}  // namespace ccomp::compensate
