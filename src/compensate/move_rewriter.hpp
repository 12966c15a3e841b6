#pragma once
// Rewriting, the job's last stage: a compensated move's points become edits of its block
// (its axis words replaced, words it lacks inserted) and lines after it (the pieces of a
// split move, take-ups, an arc's chords), in the program's number style. It follows where
// the written digits put the machine, so incremental words count from there.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/compensate/compensator.hpp"
#include "ccomp/compensate/program_job.hpp"
#include "ccomp/compensate/tcp_kinematics.hpp"
#include "ccomp/gcode/block.hpp"
#include "ccomp/gcode/writer.hpp"
#include "ccomp/model/machine.hpp"
#include "move_task.hpp"
#include "number_style.hpp"
#include "program_coordinates.hpp"

namespace ccomp::compensate {

/// The decimals the user asked for (-1: the program's own style).
/// The most lines the job adds to a program (chords and splits, some 4 GB): beyond, the
/// block that would pass it is refused (exit 3), an output bounded whatever loops --flatten
/// unrolls or turns an arc makes.
inline constexpr std::uint64_t kMostAddedLines = 100'000'000;

struct DecimalsOption {
  int linear = -1;  ///< in the program's units
  int rotary = -1;  ///< in degrees
  [[nodiscard]] int for_axis(bool is_rotary) const { return is_rotary ? rotary : linear; }
};

/// How a take-up's turning axis is written (CompensatedPoint::turns, travel_slack).
struct TurnWord {
  int way = 0;                                             ///< +1, -1; 0: the axis does not turn
  double slack = std::numeric_limits<double>::infinity();  ///< program units, degrees
  double slack_stray = 0.0;                                ///< mm
};

class MoveRewriter {
 public:
  /// `report` counts the lines and take-up moves written; `file` names the program in errors.
  MoveRewriter(gcode::ProgramWriter& writer, const model::MachineModel& model, DecimalsOption decimals,
               JobReport& report, std::string_view file);

  /// Writes a move's points (all of them, or the part `part` of an arc) as edits of its
  /// block, at `offset` in the input, and lines after it ending in `terminator`. An arc
  /// under the control's radius offset in pieces (`arc_starts`: each piece's programmed
  /// start) is written as arcs, each with its centre words. A block's move after its first
  /// (`adds_lines_only`: a corner's arc, then the move) adds lines only.
  /// A piece of a move under tool centre point control (`piece`) is written as TCP words
  /// (its points' tool tips in the part: follow_tcp()), its inverse-time feed as its share
  /// of the block's.
  void rewrite(const gcode::Motion& m, const gcode::Block& b, const std::vector<CompensatedPoint>& points,
               std::uint64_t offset, std::string_view terminator, const ChordRange& part = {},
               std::span<const gcode::Axes> arc_starts = {}, bool adds_lines_only = false,
               const MovePiece& piece = {});

  /// The control's TCP kinematics, which the pieces of moves under TCP are written through.
  void follow_tcp(TcpKinematics* kinematics) { tcp_ = kinematics; }

  /// The word for axis i at program value p (program units, degrees), or nothing for an
  /// axis the block did not name that need not move; written in the style of `styled` (the
  /// block's own value for the axis, for its line and the lines a split adds). Counted from
  /// where the written digits put the machine (`last` plus the rounding): incremental
  /// distances carry their rounding instead of summing it over a split move's pieces.
  /// In a take-up the axis turns in (`turn`), the written travel is no shorter than
  /// p - last its way (rounded out), so the play is taken up whole, and written with up to
  /// two more digits where the plan's slack needs them.
  [[nodiscard]] std::optional<std::string> axis_word(std::size_t i, double p, double last, bool incremental, bool named,
                                                     std::string_view styled, bool inch, const TurnWord& turn = {});

  /// The same into `text` (its storage reused), in `style` (the styled word's, the user's
  /// decimals applied): false for nothing to write.
  bool write_axis_word(std::size_t i, double p, double last, bool incremental, bool named, NumberStyle style,
                       const TurnWord& turn, std::string& text);

  [[nodiscard]] WrittenPosition& position() { return position_; }
  /// The written position in the coordinates of the next move (`tcp`: a TCP program's
  /// point; else the controlled point, what every stage but the TCP pieces reads).
  void position_in(bool tcp, const gcode::Offsets& offsets);
  [[nodiscard]] const DecimalsOption& decimals() const { return decimals_; }

 private:
  struct PointLine;
  void point_words(const gcode::Motion& m, const gcode::Block& b, const CompensatedPoint& point, bool tcp,
                   PointLine& line);
  /// Under G43.5: the tool's direction at the point as the block's I J K (its own words
  /// replaced, or added).
  void direction_words(const gcode::Motion& m, const gcode::Block& b, const CompensatedPoint& point, PointLine& line);
  /// Where q is, as the rewritten program says it: the controlled point, or the TCP point.
  [[nodiscard]] gcode::Axes commanded_of(const model::ChainQ& q, const gcode::Offsets& offsets, bool tcp);
  /// The centre words of an arc piece from `start` (the programmed, nominal point).
  [[nodiscard]] std::string inverse_time_feed(double feed, double share, const gcode::Block& b) const;
  [[nodiscard]] std::string centre_words(const gcode::Motion& m, const gcode::Block& b, const gcode::Axes& start);
  void centre_by_words(const gcode::Motion& m, const gcode::Block& b, const gcode::Axes& start);
  void finish_lines(const gcode::Motion& m, const gcode::Block& b, std::uint64_t offset, const ChordRange& part,
                    std::string& appended, bool adds_lines_only, bool arc_block);

  /// A take-up's word for its turning axis: its travel from `from` (program units), rounded
  /// out from the plan.
  [[nodiscard]] WrittenValue take_up_word(double planned, double from, const TurnWord& turn, const NumberStyle& style);

  /// The most decimals a word gets to stay where a take-up left its axis.
  static constexpr int kMostDecimals = 8;

  gcode::ProgramWriter& writer_;
  DecimalsOption decimals_;
  JobReport& report_;
  std::string_view file_;
  WrittenPosition position_;
  TcpKinematics* tcp_ = nullptr;
  gcode::Offsets position_offsets_;  ///< the offsets of the move that left the position (under TCP)
  std::vector<gcode::Edit> edits_;  ///< the move's line's edits, storage kept from move to move
  std::string word_text_;           ///< an added word's value, storage kept
  /// The machine's axes, in the order words are written (X Y Z A B C U V W).
  std::array<std::uint8_t, gcode::kAxisCount> machine_axes_{};
  std::size_t machine_axis_count_ = 0;
  AxisSet approach_axes_;  ///< the axes whose approach a term reads
};

/// How axis i of a take-up point turns, in program units (`unit`: mm per program unit): no
/// way where it does not turn, or where a rotation of the frame mixes the program's X and Y
/// into the machine's (the word's rounding then says nothing of one machine axis).
[[nodiscard]] TurnWord turn_word(const CompensatedPoint& point, const gcode::Offsets& offsets, std::size_t i,
                                 double unit);

/// An arc block becomes the first of its lines: G2/G3 turns into G1 (written in front when
/// the arc was modal), the centre, radius and turns words go.
void arc_to_line_edits(const gcode::Block& b, std::vector<gcode::Edit>& edits);

/// Whether the block stops the program (M0 M1 M2 M30 M60): a move split into lines cannot
/// share it.
[[nodiscard]] bool has_stop_code(const gcode::Block& b);

}  // namespace ccomp::compensate
