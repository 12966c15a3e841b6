#pragma once
// The control's tool-centre-point kinematics, as ccomp takes them: the perfect machine of
// the model. Under TCP (G43.4, M128, M428: gcode/tcp_mode.hpp) a program's X Y Z are the
// tool tip in the part and its A B C the rotary axes' angles; the control works out the
// axes' positions that put the perfect machine's tip there, and moves the words in a
// straight line.
//
// "The tip in the part" is the point of the part, fixed to the table, that the tip would be
// at with these X Y Z in a joint-coordinate program with every rotary axis at zero: the
// two kinds of program agree where the rotary axes are at zero, and the work offsets and
// the program's zero mean the same in both. The rotary axes' lines are the model's, so
// whatever offsets of the pivots the control holds must be the model's (what compensation
// assumes of a joint-coordinate program too).
//
// Both maps are one affine solve each: with the rotary axes at given angles the perfect
// machine's tip is affine in the linear axes' positions.
#include <Eigen/Core>
#include <map>
#include <optional>
#include <vector>

#include "ccomp/gcode/canon.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::compensate {

class TcpKinematics {
 public:
  /// Throws ccomp::Error (unsupported) where the model's chain has rotary axes and other than
  /// three linear axes moving the tip in three independent directions. Without a rotary axis
  /// the kinematics are the identity: the tip in the part is where the axes put it.
  explicit TcpKinematics(const model::ForwardModel& model);

  /// No rotary axis: a TCP program's points are the axes' positions.
  [[nodiscard]] bool identity() const { return rotary_.empty(); }

  /// The chain values (mm, rad, the tool length) the control commands for a point of a TCP
  /// program (machine frame, mm and deg, the tool's offsets apart), under its offsets.
  [[nodiscard]] model::ChainQ joints_of(const gcode::Axes& world, const gcode::Offsets& offsets);
  /// joints_of()'s inverse: the TCP program's point for chain values.
  [[nodiscard]] gcode::Axes world_of(const model::ChainQ& q, const gcode::Offsets& offsets);

  /// Where the machine is in the other coordinates when TCP switches on (`to_tcp`: the
  /// controlled point as a TCP point) or off (gcode::InterpreterOptions::tcp_switch).
  [[nodiscard]] gcode::Axes switched(const gcode::Axes& position, const gcode::Offsets& offsets, bool to_tcp);

  /// The point of the part (table frame, mm) a TCP program's point puts the tip at.
  [[nodiscard]] Eigen::Vector3d part_point(const gcode::Axes& world, const gcode::Offsets& offsets);
  /// The perfect machine's tool tip in the table frame at q.
  [[nodiscard]] Eigen::Vector3d tip(const model::ChainQ& q);
  /// The perfect machine's tool direction in the part (table frame, unit) at q, as a program
  /// gives it: from the tip towards the spindle (Fanuc's G43.5 I J K).
  [[nodiscard]] Eigen::Vector3d direction(const model::ChainQ& q);
  /// q with its rotary axes turned so that the tool's direction is `target` (any length),
  /// the angles nearest q's own: damped Gauss-Newton on the rotary axes, so that at the
  /// singular pose (the direction along the last rotary line) that axis stays where it is;
  /// where it gets nowhere from q (a start at the singular pose), from q turned 0.2 rad each
  /// way about each rotary axis, the angles nearest q's of those found. Throws ccomp::Error
  /// (unsupported, no position) where two sets of angles found there are as near (a tie a
  /// control breaks by its own setting).
  /// nullopt where no angles come within 1e-12 rad of it (a direction the machine cannot
  /// take, a machine with one rotary axis), or `target` is no direction.
  [[nodiscard]] std::optional<model::ChainQ> rotary_for(const Eigen::Vector3d& target, model::ChainQ q);
  /// `position` (a TCP point) with its rotary axes' angles turned so that the tool's
  /// direction is `direction`: gcode::InterpreterOptions::tcp_direction. The angles follow
  /// the great circle from the direction now to it in steps of at most 0.1 rad (rotary_for()
  /// from the step before), so a large turn ends on the branch the control's continuous
  /// interpolation reaches.
  [[nodiscard]] std::optional<gcode::Axes> turned_to(const std::array<double, 3>& direction,
                                                     const gcode::Axes& position, const gcode::Offsets& offsets);

 private:
  /// The tip's move per unit of each linear axis at q (`at`: the tip there).
  [[nodiscard]] Eigen::Matrix3d linear_columns(const model::ChainQ& q, const Eigen::Vector3d& at);
  /// rotary_for() from q alone: nullopt where its steps do not get there.
  [[nodiscard]] std::optional<model::ChainQ> solve_rotary(const Eigen::Vector3d& want, model::ChainQ q);
  /// The linear axes' values that put the tip at `target` with the rest of q as given.
  [[nodiscard]] model::ChainQ solve_linear(model::ChainQ q, const Eigen::Vector3d& target);

  const model::ForwardModel& model_;
  model::ForwardData data_;
  Eigen::Vector3d tool_axis_;  ///< the tool's axis in the tool frame, from the spindle to the tip
  model::Conditions conditions_;
  std::vector<int> linear_, rotary_;  ///< the chain's linear and rotary axes (chain variables)
};

/// A straight TCP move's point at a fraction, as the control moves it: the tip along the line,
/// and the rotary axes' angles lerped (G43.4) or, under G43.5 (`great_circle`), where the
/// control's kinematics put the tool's direction on the great circle from the start's to the
/// end's (the angles nearest the lerped ones).
class TcpLine {
 public:
  TcpLine(TcpKinematics& kinematics, const gcode::Axes& start, const gcode::Axes& end, const gcode::Offsets& offsets,
          bool great_circle);
  /// Throws ccomp::Error (program, no position) where the direction is none the machine takes.
  [[nodiscard]] gcode::Axes at(double f);
  /// Under G43.5: the tool's direction meant at f (throws for a turn to the opposite).
  [[nodiscard]] Eigen::Vector3d direction_at(double f) const;

 private:
  TcpKinematics& kinematics_;
  gcode::Axes start_, end_;
  const gcode::Offsets& offsets_;
  bool great_circle_;
  Eigen::Vector3d from_ = Eigen::Vector3d::UnitZ(), to_ = Eigen::Vector3d::UnitZ();
  /// The angles found so far, by fraction: each solve starts from the nearest one before it,
  /// so the angles follow the great circle continuously, as a control's do.
  std::map<double, gcode::Axes> solved_;
};

/// The points (fractions of the move, 0 and 1 included, increasing) at which a straight TCP
/// move from `start` to `end` is split so that, between two of them, the axes moving in a
/// straight line (as a joint-coordinate move) keep the perfect machine's tip within
/// `tolerance` (mm) of the straight line the control draws: none inside where no rotary
/// axis turns. At most `most` pieces, and none shorter than a billionth of the move
/// (ccomp::Error, program, beyond, or where the tip is not a finite number: the caller names
/// the line).
/// `deviations`, when given, gets each piece's largest distance found between the two (mm).
/// Under G43.5 (`great_circle`: TcpLine) the axes' straight moves also keep the tool within
/// the angular tolerance that goes with `tolerance` (default_angular_tolerance()) of the
/// great circle.
[[nodiscard]] std::vector<double> tcp_split(TcpKinematics& kinematics, const gcode::Axes& start,
                                            const gcode::Axes& end, const gcode::Offsets& offsets, double tolerance,
                                            std::size_t most = 100000, std::vector<double>* deviations = nullptr,
                                            bool great_circle = false);

/// A piece of a move under TCP: a move of the axes (`motion`, joint coordinates, `tcp` off)
/// and the share of the TCP move it makes.
struct TcpPiece {
  gcode::Motion motion;
  double from = 0.0, to = 1.0;
  double deviation = 0.0;  ///< mm: how far its straight move leaves the control's line (tcp_split())
};

/// A move under TCP as the axes' moves that follow it: a feed move in pieces within
/// `tolerance` (tcp_split()), a rapid in one (its path is the control's), an arc (the tip
/// along it in the part) as chords within half the tolerance, each chord a straight TCP move
/// in pieces within the other half: each piece a straight feed move of the axes, its
/// deviation the chord's sagitta beside its own. Throws ccomp::Error (unsupported, no
/// position: the caller's line gives it) for what is not followed under TCP: probes, canned
/// cycles, G28/G30/G53, cutter radius compensation. On a machine without rotary axes the
/// move is its own piece, whatever it is.
void tcp_pieces(TcpKinematics& kinematics, const gcode::Motion& m, double tolerance, std::vector<TcpPiece>& out,
                std::size_t most = 100000);

}  // namespace ccomp::compensate
