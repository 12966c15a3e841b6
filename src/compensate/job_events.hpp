#pragma once
// The job's first stage: the interpreter's events (blocks, motions, warnings) read into
// moves. Each motion goes where it belongs: a move of the program's own lines to the
// pipeline (solving, then rewriting), a canned cycle's to the cycles, a move in machine
// coordinates straight to the compensator; what cannot be compensated line for line is
// refused here. The stages it feeds are built here too, once, from the model.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/tcp_kinematics.hpp"
#include "ccomp/error.hpp"
#include "ccomp/gcode/canon.hpp"
#include "ccomp/gcode/source.hpp"
#include "ccomp/gcode/writer.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/term_span.hpp"
#include "move_task.hpp"

namespace ccomp::compensate {

struct CompensationStages;

class JobSink : public gcode::CanonSink {
 public:
  JobSink(gcode::ProgramWriter& writer, const model::MachineModel& model, const JobOptions& options,
          const gcode::LineSource& input, JobReport& report);
  ~JobSink() override;
  JobSink(const JobSink&) = delete;
  JobSink& operator=(const JobSink&) = delete;

  void block(const gcode::Block& block, const gcode::SourceLine& line) override;
  void motion(const gcode::Motion& m) override;
  void warning(const std::string& message, std::uint32_t line) override;

  /// Where the machine is in the other coordinates when TCP switches (the interpreter's
  /// InterpreterOptions::tcp_switch): through the control's kinematics.
  [[nodiscard]] gcode::Axes tcp_switch(const gcode::Axes& position, const gcode::Offsets& offsets, bool to_tcp);
  /// The angles for a G43.5 direction (InterpreterOptions::tcp_direction): the control's
  /// kinematics'; without an error term the position as it is (nothing is corrected).
  [[nodiscard]] std::optional<gcode::Axes> tcp_direction(const std::array<double, 3>& direction,
                                                         const gcode::Axes& position, const gcode::Offsets& offsets);

  /// Finishes the program: the moves still queued, then a cycle still open.
  void finish();
  /// The job stopped with an error: a move queued before it may have failed first (its
  /// error is the one to report), unless the error came from writing the moves.
  void abandon();

 private:
  void note_line(const gcode::SourceLine& line);
  void check_axes(const gcode::Block& block) const;
  void take_out_offset(const gcode::Block& block);
  void report_progress(const gcode::SourceLine& line);
  void keep_offsets(const gcode::Block& block);
  void joint_motion(const gcode::Motion& m);
  void tcp_motion(const gcode::Motion& m);
  void compensate(const gcode::Motion& m);
  void warn_beyond_spans(const gcode::Motion& m);
  void follow_machine_move(const gcode::Motion& m);
  void queue_move(const gcode::Motion& m);
  void queue_task(const gcode::Motion& m, const ChordRange& chords);
  [[nodiscard]] std::size_t chord_count(const gcode::Motion& m) const;
  void write_move(MoveTask& t);
  void finish_cycle();
  [[noreturn]] void refuse(ErrorKind kind, const std::string& message) const;

  gcode::ProgramWriter& writer_;
  const model::MachineModel& model_;
  const JobOptions& options_;
  const gcode::LineSource& input_;
  JobReport& report_;
  bool has_limits_ = false;
  std::uint32_t machine_axes_ = 0;  ///< bit (letter - 'A') for each axis the machine has
  int last_percent_ = -1;
  const gcode::Block* block_ = nullptr;  ///< the block being read
  gcode::SourceLine line_;
  std::uint64_t furthest_ = 0;                    ///< the offset of the furthest line read
  bool repeated_ = false;                         ///< the current line is before it
  int moves_in_block_ = 0;                        ///< moves of the current block so far
  MovePiece piece_;                               ///< the share of its move the motion queued is
  std::vector<TcpPiece> tcp_pieces_;              ///< a move under TCP's, storage kept
  bool last_tcp_ = false;                         ///< the last motion was under TCP
  bool elsewhere_ = false;                        ///< the current line is in another file (a subroutine's)
  bool started_ = false;                          ///< a motion was compensated: the play is followed
  const gcode::Offsets* live_offsets_ = nullptr;  ///< the interpreter's, as it runs (from its motions)
  gcode::Axes nominal_end_{};                     ///< where the original's last motion ended
  gcode::Units last_units_ = gcode::Units::mm;    ///< the units of the original's last motion
  std::unique_ptr<CompensationStages> stages_;    ///< none when the model has no terms
  model::SpanWatch spans_;                        ///< terms used beyond where they were fitted, said once
  model::Conditions span_conditions_;             ///< the job's temperatures and time, for the spans
};

}  // namespace ccomp::compensate
