#include "job_events.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "canned_cycles.hpp"
#include "ccomp/error.hpp"
#include "ccomp/compensate/machine_coordinates.hpp"
#include "ccomp/compensate/tcp_kinematics.hpp"
#include "ccomp/model/conditions.hpp"
#include "job_guards.hpp"
#include "move_pipeline.hpp"
#include "move_rewriter.hpp"
#include "move_solver.hpp"
#include "offset_keeping.hpp"

namespace ccomp::compensate {


namespace {

/// The compensation's options from the job's: the tolerance, and the conditions the
/// thermal terms are evaluated at (model/conditions.hpp checks the readings).
CompensationOptions compensation_options(const model::MachineModel& model, const JobOptions& options) {
  CompensationOptions c;
  c.tolerance = options.tolerance;
  c.exact = options.exact;
  c.conditions = model::conditions_for(model, options.sensors, options.time);
  for (const model::AxisSpec& a : model.axes)
    if (a.type == model::AxisType::rotary)
      c.hold[a.axis()] = a.hold;
  return c;
}

}  // namespace

/// The stages after reading, in the order a move passes them; built only for a model with
/// terms (without, the program is written as it was, with the header).
struct CompensationStages {
  CompensationStages(const model::MachineModel& machine, const JobOptions& options, const CompensationOptions& c,
                     gcode::ProgramWriter& writer, JobReport& report, std::string_view file, MovePipeline::Writer write)
      : forward(machine),
        nominal(forward),
        solver(forward, c),
        error_before(forward, c),
        guards(machine, options, report, file),
        rewriter(writer, machine, DecimalsOption{options.decimals, options.rotary_decimals}, report, file),
        cycles(CycleStages{solver, error_before, rewriter, guards, writer, report}, machine, options.expand_cycles,
               file),
        pipeline(solver, options.threads > 1, options.split, std::move(write)) {}

  model::ForwardModel forward;
  model::ForwardData nominal;  ///< scratch for the moves' nominal ends, on the reading thread

  /// The control's TCP kinematics, built at the first move under TCP (ccomp::Error,
  /// unsupported, for a machine it does not apply to), shared with the rewriter: both
  /// work on the reading thread.
  TcpKinematics& tcp_kinematics() {
    if (!tcp) {
      tcp.emplace(forward);
      rewriter.follow_tcp(&*tcp);
    }
    return *tcp;
  }
  std::optional<TcpKinematics> tcp;
  MoveSolver solver;
  /// The uncompensated machine's error, for the report, is taken by a compensator of its own
  /// on the writing side (it changes nothing the compensation decides), or by the worker's
  /// (MovePipeline::reader_helps()).
  Compensator error_before;
  JobGuards guards;
  MoveRewriter rewriter;
  CannedCycles cycles;
  /// Last: destroyed (its worker joined) first, while what it works on still exists.
  MovePipeline pipeline;
};

JobSink::JobSink(gcode::ProgramWriter& writer, const model::MachineModel& model, const JobOptions& options,
                 const gcode::LineSource& input, JobReport& report)
    : writer_(writer), model_(model), options_(options), input_(input), report_(report), spans_(model) {
  for (const model::AxisSpec& a : model.axes) {
    machine_axes_ |= 1U << (a.letter - 'A');
    has_limits_ = has_limits_ || std::isfinite(a.min) || std::isfinite(a.max);
  }
  if (!model.terms.empty())
    stages_ = std::make_unique<CompensationStages>(model, options, compensation_options(model, options), writer, report,
                                                   input.name(), [this](MoveTask& t) { write_move(t); });
  if (!spans_.empty()) span_conditions_ = compensation_options(model, options).conditions;
}

JobSink::~JobSink() = default;

void JobSink::block(const gcode::Block& block, const gcode::SourceLine& line) {
  finish_cycle();
  if (stages_) stages_->cycles.note_block(block);
  ++report_.blocks;
  block_ = &block;
  line_ = line;
  moves_in_block_ = 0;
  note_line(line);
  if (options_.resolve_cutter_comp) take_out_offset(block);
  check_axes(block);
  if (stages_ && live_offsets_) keep_offsets(block);
  report_progress(line);
}

/// A line of another file (a subroutine file on the path) is not in the program written
/// here; a line before the furthest one read runs again (a loop, a subroutine).
void JobSink::note_line(const gcode::SourceLine& line) {
  elsewhere_ = line.file.data() != input_.name().data() && line.file != input_.name();
  repeated_ = !elsewhere_ && line.offset < furthest_;
  if (!elsewhere_) furthest_ = std::max(furthest_, line.offset);
}

/// --resolve-cutter-comp: the offset path is written, so the control's offset goes (G41,
/// G42, G41.1, G42.1 and their D word); G40 stays, harmless.
void JobSink::take_out_offset(const gcode::Block& block) {
  std::vector<gcode::Span> words;
  bool turns_on = false;
  for (const gcode::Word& w : block.words) {
    if (w.letter != 'G') continue;
    if (!w.value.is_literal())
      throw Error(ErrorKind::unsupported,
                  "--resolve-cutter-comp takes G41/G42 out of the program, and this G code is an expression that "
                  "may be one: --flatten writes the program with its values",
                  SourceLocation{input_.name(), block.line, w.span.begin + 1}, std::string(block.text));
    if (std::floor(w.value.literal) >= 41 && w.value.literal < 43) {
      words.push_back(w.span);
      turns_on = true;
    }
  }
  if (!turns_on || repeated_ || elsewhere_) return;
  // (Siemens' D is the tool's cutting edge, its length as much as its radius: it stays.)
  if (const gcode::Word* d = block.find('D'); d && !options_.interpreter.dialect.d_selects_cutting_edge)
    words.push_back(d->span);
  if (stages_) stages_->pipeline.drain();  // the lines before it are written first
  std::vector<gcode::Edit> edits;
  gcode::removal_edits(block.text, words, edits);
  writer_.edit(line_.offset, edits);
}

void JobSink::check_axes(const gcode::Block& block) const {
  for (const gcode::Word& w : block.words) {
    // (A lone letter, which the interpreter ignores, names no axis it moves.)
    // (Nor does an extended address, Siemens' A3=: the interpreter refuses it at its column.)
    if (!w.has_value || w.extension != 0 || w.letter < 'A' || w.letter > 'Z' || ((machine_axes_ >> (w.letter - 'A')) & 1U) ||
        !gcode::axis_index(w.letter))
      continue;
    throw Error(ErrorKind::safety,
                fmt::format("the program uses axis {}, which machine '{}' does not have", w.letter, model_.name),
                SourceLocation{input_.name(), block.line, w.span.begin + 1}, std::string(block.text));
  }
}

void JobSink::report_progress(const gcode::SourceLine& line) {
  if (!options_.progress || input_.size() == 0) return;
  const auto percent = static_cast<int>(100.0 * static_cast<double>(line.offset) / static_cast<double>(input_.size()));
  if (percent == last_percent_) return;
  last_percent_ = percent;
  options_.progress(percent / 100.0);
}

void JobSink::keep_offsets(const gcode::Block& block) {
  if (!sets_offset_from_position(block)) return;
  if (last_tcp_)
    refuse(ErrorKind::unsupported,
           "an offset set from the position (G92, G10 L20) under tool centre point control: the control sets it in "
           "the tip's coordinates, which ccomp does not follow yet");
  stages_->pipeline.drain();
  if (live_offsets_) stages_->rewriter.position_in(false, *live_offsets_);  // (after moves under TCP)
  const OffsetContext at{*live_offsets_,
                         last_units_,
                         nominal_end_,
                         stages_->rewriter.position(),
                         repeated_ || elsewhere_,
                         stages_->rewriter.decimals(),
                         input_.name()};
  std::vector<gcode::Edit> edits = offset_keeping_edits(block, at);
  if (!edits.empty()) writer_.edit(line_.offset, std::move(edits));
}

void JobSink::motion(const gcode::Motion& m) {
  ++report_.motions;
  last_tcp_ = m.tcp;
  if (!m.tcp) return joint_motion(m);
  // (Without an error term nothing is corrected: the program is written back as it is.)
  if (stages_) tcp_motion(m);
}

void JobSink::joint_motion(const gcode::Motion& m) {
  live_offsets_ = m.offsets;
  nominal_end_ = m.end;
  last_units_ = m.units;
  if (has_limits_) check_limits(m, model_, input_.name(), block_ ? block_->text : std::string_view());
  if (!spans_.empty()) warn_beyond_spans(m);
  if (stages_) compensate(m);
}

gcode::Axes JobSink::tcp_switch(const gcode::Axes& position, const gcode::Offsets& offsets, bool to_tcp) {
  if (!stages_) return position;  // nothing is corrected: the numbers as they are
  try {
    return stages_->tcp_kinematics().switched(position, offsets, to_tcp);
  } catch (const Error& e) {
    refuse(e.kind(), e.message());
  }
}

std::optional<gcode::Axes> JobSink::tcp_direction(const std::array<double, 3>& direction,
                                                  const gcode::Axes& position, const gcode::Offsets& offsets) {
  if (!stages_) return position;
  try {
    return stages_->tcp_kinematics().turned_to(direction, position, offsets);
  } catch (const Error& e) {
    refuse(e.kind(), e.message());
  }
}

/// A move under tool centre point control: the axes' positions the control's kinematics
/// command (tcp_kinematics.hpp), in pieces the axes move straight along within half the
/// tolerance of the control's line or arc (a rapid's path is the control's: one piece), each
/// a move of the block compensated within the other half and written as TCP words (an arc's
/// as G1 lines).
void JobSink::tcp_motion(const gcode::Motion& m) {
  try {
    tcp_pieces(stages_->tcp_kinematics(), m, options_.tolerance / 2.0, tcp_pieces_);
  } catch (const Error& e) {
    refuse(e.kind(), e.message());
  }
  for (const TcpPiece& p : tcp_pieces_) {
    piece_ = MovePiece{p.from, p.to, true, p.deviation, m.kind == gcode::MotionKind::arc};
    joint_motion(p.motion);
  }
  piece_ = {};
}

/// A term used beyond where it was fitted holds its value there (forward.hpp): said once a
/// term, at the first line that takes it there.
void JobSink::warn_beyond_spans(const gcode::Motion& m) {
  gcode::Axes low, high;
  motion_extent(m, low, high);
  const model::ChainQ a = chain_of(low, *m.offsets), b = chain_of(high, *m.offsets);
  for (const std::string& message : spans_.beyond(a.cwiseMin(b), a.cwiseMax(b), span_conditions_))
    warning(message, m.line);
}

void JobSink::warning(const std::string& message, std::uint32_t line) {
  if (options_.warning) options_.warning(message, line);
}

namespace {

/// Whether the block has a G code whose axis words are its own (G10, G28, G30, G52, G92):
/// a motion code beside it has none (the interpreter refuses both with axis words), and
/// moves nowhere.
bool axis_words_are_another_codes(const gcode::Block& b) {
  for (const gcode::Word& w : b.words)
    if (w.letter == 'G' && w.has_value && w.value.is_literal())
      for (const double code : {10.0, 28.0, 30.0, 52.0, 92.0})
        if (w.value.literal == code) return true;
  return false;
}

}  // namespace

void JobSink::compensate(const gcode::Motion& m) {
  using gcode::MotionKind;
  using gcode::MotionSource;
  // `G0 G28`: the G0 is a move of no length that the block's words cannot be written into
  // (axis words there would be G28's intermediate point). The machine stays where the
  // reference return, or the line before, left it.
  if (m.source == MotionSource::program && m.start == m.end && block_ && axis_words_are_another_codes(*block_)) return;
  const bool machine = m.source == MotionSource::machine_coordinates || m.source == MotionSource::reference_return;
  if (!machine && m.kind != MotionKind::probe && m.source != MotionSource::canned_cycle && !repeated_ && !elsewhere_) {
    queue_move(m);
    return;
  }
  // The rest is rare, and done here once every move before it is written.
  stages_->pipeline.drain();
  stages_->rewriter.position_in(false, *m.offsets);  // (after moves under TCP)
  if (!started_) {  // the play is followed from where the program starts
    stages_->solver.compensator.moved(chain_of(m.start, *m.offsets));
    started_ = true;
  }
  if (machine) return follow_machine_move(m);
  if (m.kind == MotionKind::probe) refuse(ErrorKind::unsupported, "a probe move (G38.x) cannot be compensated");
  if (elsewhere_)
    throw Error(ErrorKind::unsupported,
                fmt::format("this line is in the subroutine file '{}', which the compensated program does not "
                            "include: --flatten writes the program as it runs, the subroutine's lines in it",
                            line_.file),
                SourceLocation{std::string(line_.file), block_->line, 0}, std::string(block_->text));
  if (m.source == MotionSource::canned_cycle) return stages_->cycles.add(m, *block_, line_, repeated_);
  refuse(ErrorKind::unsupported,
         "this line runs more than once (a loop or a subroutine), and each run needs its own "
         "correction: --flatten writes the program as it runs, loops and subroutines unrolled");
}

/// Moves in machine coordinates (G53, G28/G30) go where they say: they are not part of the
/// workpiece's geometry. Nothing else may go uncompensated.
void JobSink::follow_machine_move(const gcode::Motion& m) {
  WrittenPosition& position = stages_->rewriter.position();
  position.commanded = m.end;
  position.tcp = false;
  position.rounding = {};  // the block's own words, as written
  stages_->solver.compensator.moved(chain_of(m.end, *m.offsets));
}

/// An arc's chords, at half the tolerance (as the solver takes them); a count beyond the
/// cap refused at the arc's block.
std::size_t JobSink::chord_count(const gcode::Motion& m) const {
  try {
    return arc_chord_count(gcode::arc_geometry(m), options_.tolerance / 2.0);
  } catch (const Error& e) {
    refuse(e.kind(), e.message());
  }
}

void JobSink::queue_move(const gcode::Motion& m) {
  if (m.kind == gcode::MotionKind::arc && !m.radius_compensation) {
    const std::size_t n = chord_count(m);
    if (n > MovePipeline::kPartChords) {
      for (std::size_t begin = 0; begin < n; begin += MovePipeline::kPartChords)
        queue_task(m, ChordRange{begin, std::min(n, begin + MovePipeline::kPartChords), n});
      ++moves_in_block_;
      return;
    }
  }
  queue_task(m, {});
  ++moves_in_block_;
}

void JobSink::queue_task(const gcode::Motion& m, const ChordRange& chords) {
  MoveTask& t = stages_->pipeline.next_task();
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
  t.piece = piece_;
  t.adds_lines_only = moves_in_block_ > 0;
  // The nominal pose at its end, here or on the worker: whichever has time to spare.
  const model::ChainQ end = chain_of(m.end, t.offsets);
  t.end_pose_known = stages_->pipeline.reader_helps();
  if (t.end_pose_known) {
    model::forward(stages_->forward, stages_->nominal, end, {}, false, model::Evaluate::nominal);
    t.end_pose = {stages_->nominal.nominal, stages_->nominal.R_nominal};
  }
  // The points it is expected to give: its chords (half the tolerance, as the solver takes
  // them), else the points the model checks it at.
  std::size_t points = chords.end - chords.begin;
  if (chords.whole())
    points = m.kind == gcode::MotionKind::arc && !m.radius_compensation
                 ? chord_count(m)
                 : static_cast<std::size_t>(stages_->forward.check_points(chain_of(m.start, t.offsets), end, 1));
  stages_->pipeline.queued(points);
}

/// A compensated move, in program order: its error is reported at its line, its figures
/// counted, its points written.
void JobSink::write_move(MoveTask& t) {
  if (t.error) {
    try {
      std::rethrow_exception(t.error);
    } catch (const Error& e) {
      if (!e.where().file.empty() || e.where().line != 0) throw;
      throw Error(e.kind(), e.message(), SourceLocation{input_.name(), t.block.line, 0}, t.text);
    }
  }
  writer_.advance_to(t.offset);
  // (None are left where the worker took them: MoveBatch::probes_on_worker.)
  take_error_before(stages_->error_before, report_.max_error_before, t.probes, t.report);
  // (A move in parts, an arc's chords or the pieces of a move under TCP, counts at its last.)
  stages_->guards.account(t.report, t.motion.units, t.block.line, t.text, t.chords.last() && t.piece.to == 1.0);
  stages_->rewriter.rewrite(t.motion, t.block, t.points, t.offset, t.terminator, t.chords, t.arc_starts,
                            t.adds_lines_only, t.piece);
}

/// Compensates a cycle still waiting for its block's end, once every move before it is written.
void JobSink::finish_cycle() {
  if (!stages_ || !stages_->cycles.pending()) return;
  stages_->pipeline.drain();
  stages_->cycles.finish();
}

void JobSink::finish() {
  if (stages_) stages_->pipeline.drain();
  finish_cycle();
}

void JobSink::abandon() {
  if (stages_) stages_->pipeline.abandon();
}

void JobSink::refuse(ErrorKind kind, const std::string& message) const {
  throw Error(kind, message, SourceLocation{input_.name(), block_->line, 0}, std::string(block_->text));
}

}  // namespace ccomp::compensate
