#pragma once
// Canned cycles, a stage of their own: a cycle block (G73 G81 G83 G85 ...) is kept until its
// last move, then its hole's X Y R Z are compensated together in the block's words, or
// (--expand-cycles) the cycle is written as the compensated moves it makes.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/compensate/compensator.hpp"
#include "ccomp/compensate/program_job.hpp"
#include "ccomp/gcode/block.hpp"
#include "ccomp/gcode/canon.hpp"
#include "ccomp/gcode/source.hpp"
#include "ccomp/gcode/writer.hpp"
#include "job_guards.hpp"
#include "move_rewriter.hpp"
#include "move_solver.hpp"

namespace ccomp::compensate {

/// Whether G<g> is a canned cycle (G73 G74 G76 G81-G89).
[[nodiscard]] bool is_cycle_code(double g);

/// A canned-cycle block and the motions it made, kept until the block ends.
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

/// The stages a cycle's compensation works with, the job's own.
struct CycleStages {
  MoveSolver& solver;         ///< its compensator follows the machine through the cycle
  Compensator& error_before;  ///< the uncompensated machine's error, for the report
  MoveRewriter& rewriter;
  JobGuards& guards;
  gcode::ProgramWriter& writer;
  JobReport& report;
};

class CannedCycles {
 public:
  CannedCycles(const CycleStages& stages, const model::MachineModel& model, bool expand, std::string_view file);

  /// Notes the cycle a block names, for the modal repeats after it.
  void note_block(const gcode::Block& block);
  /// A motion of the cycle block `block` (a line that ran before: `repeated`).
  void add(const gcode::Motion& m, const gcode::Block& block, const gcode::SourceLine& line, bool repeated);
  /// Whether a cycle waits for its block's end.
  [[nodiscard]] bool pending() const { return !cycle_.motions.empty(); }
  /// Compensates and writes the cycle waiting (every move before it must be written).
  void finish();

 private:
  void compensate_words(const PendingCycle& c, const gcode::Motion& first, const gcode::Motion& last);
  void expand(const PendingCycle& c);
  void solve_move_here(const gcode::Motion& m, const gcode::Offsets& offsets, MoveReport& move);
  [[nodiscard]] std::string expanded_line(const gcode::Motion& m, const PendingCycle& c, const CompensatedPoint& point);

  CycleStages stages_;
  Compensator& compensator_;
  const model::MachineModel& model_;
  bool expand_;
  std::string_view file_;
  PendingCycle cycle_;
  double cycle_code_ = 0;                 ///< the last canned cycle's G number
  std::vector<CompensatedPoint> points_;  ///< a cycle's move's points
  std::vector<ErrorProbe> probes_;
};

}  // namespace ccomp::compensate
