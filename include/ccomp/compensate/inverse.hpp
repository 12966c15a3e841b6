#pragma once
// The inverse of the machine's error: the axis values whose actual tool tip lands on the
// point the program means. Newton's method on the exact forward model, with its analytic
// Jacobian: three position equations, plus the orientation equations the rotary axes can
// answer. With one rotary axis: the table's rotation about that axis (which it corrects
// itself). With two (a five-axis machine): the tool's direction in the part, two equations (a
// turn about the tool's own axis does not move an axisymmetric tool), each rotary line taken
// from the chain at the current pose through the exact Jacobian; near the singular pose
// (the tool along a rotary line) the rotary axes' correction is damped toward the program's
// values, so the branch the program chose is kept (kSingularZone below). The orientation the machine cannot
// correct is reported.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/variation_bound.hpp"

namespace ccomp::compensate {

struct InverseOptions {
  double position_tolerance = 1e-6;  ///< mm: converged below 1 nm
  double angle_tolerance = 1e-9;     ///< rad, for the rotary axes' own equations
  int max_iterations = 20;
  /// The error field's bound, made for the solves' conditions (their time and
  /// temperatures). With it, a point along a path is accepted as predicted, without
  /// evaluating the model, where the last two points evaluated on the path bound its
  /// residual (the tip's distance from the target, with what the rotary axes' residual
  /// turns it through the bound's lever) below `bounded_tolerance`; and an evaluated
  /// iterate whose residual is within a tenth of that stands without a further step.
  const model::VariationBound* bound = nullptr;
  double bounded_tolerance = 0.0;  ///< mm; 0: every point is evaluated
};

struct InverseResult {
  model::ChainQ q;                                              ///< the commanded axis values (mm, rad; L unchanged)
  Eigen::Vector3d target = Eigen::Vector3d::Zero();             ///< the nominal tool tip it lands on (table frame, mm)
  Eigen::Vector3d position_residual = Eigen::Vector3d::Zero();  ///< actual - target, mm
  /// Rotation left, rad (tool frame). With the tool_direction equations only the tool's
  /// tilt (its turn about the tool's own axis, which moves nothing, left out).
  Eigen::Vector3d orientation_error = Eigen::Vector3d::Zero();
  int iterations = 0;
  bool converged = false;
  /// The model was evaluated at q (false: accepted on the bound below, and the residuals
  /// above are the extrapolation's).
  bool evaluated = true;
  /// mm: how far the actual tip can be from the target, the rotary residual's share
  /// included (the position tolerance where the solve converged; an iterate left standing,
  /// its exact residual).
  double residual_bound = 0.0;
};

/// What the orientation equations ask of the tool.
enum class OrientationEquations : std::uint8_t {
  none,            ///< no rotary axis: the orientation is only reported
  about_rotary,    ///< one rotary axis: the turn about its line (the table's own rotation)
  tool_direction,  ///< two or more: the tool's direction in the part (two equations)
};

/// The axes the solve may move: the chain's linear and rotary axes (not the tool length),
/// but the `held` ones, which keep the program's values: a rotary axis the compensation
/// must not turn (model::AxisHold). The orientation equations are those the axes left can
/// answer; what the held ones would have corrected is reported.
struct InverseProblem {
  explicit InverseProblem(const model::ForwardModel& model, AxisSet held = {});
  std::vector<int> unknowns;                       ///< chain variable indices moved by the solve
  std::vector<int> held;                           ///< chain axes the solve keeps at the program's values
  std::vector<Eigen::Vector3d> rotary_directions;  ///< for each rotary unknown: its axis in the table frame at q=0
  std::vector<int> rotary_unknowns;                ///< their indices into q
  /// Where the linear and the rotary unknowns are among `unknowns`.
  std::vector<Eigen::Index> linear_columns, rotary_columns;
  OrientationEquations orientation = OrientationEquations::none;
  /// The tool's axis in the tool frame (its tool-length direction; -Z where the chain gives
  /// none) and two directions across it: the tool_direction equations are the tool frame's
  /// turn about these two.
  Eigen::Vector3d tool_axis = -Eigen::Vector3d::UnitZ();
  std::array<Eigen::Vector3d, 2> across_tool{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
};

/// The tool_direction solve near the singular pose. The rotary axes turn the tool's direction
/// by sigma (rad per rad) in their weakest combination (sin A on an AC table). Where sigma is
/// below kSingularZone (A within 5.7 degrees of 0) the correction of that direction gives way
/// to keeping the program's rotary values: the solve minimises |direction left|^2 +
/// lambda^2 |rotary - program|^2 with lambda^2 = kSingularDamping^2 (1 - (sigma /
/// kSingularZone)^2), which leaves lambda^2 / (sigma^2 + lambda^2) of that direction's error
/// and corrects no axis by more than 26 times the error it answers. Beyond the zone lambda is
/// 0 and the solve is exact. (The variable damping of Nakamura and Hanafusa's
/// singularity-robust inverse.)
inline constexpr double kSingularZone = 0.1;
inline constexpr double kSingularDamping = 0.02;

/// The last two points where a solve evaluated the model (its last iterate), under one
/// approach, target orientation, tool length and conditions: the actual tip there and the
/// log of the actual orientation against the target. Along a path the tip moves smoothly,
/// so the line through them extrapolates it to the next points, within what the error
/// field's bound allows (src/compensate/path_nodes.hpp).
struct PathNodes {
  struct Node {
    model::ChainQ q = model::ChainQ::Zero();
    Eigen::Vector3d tip = Eigen::Vector3d::Zero();
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  };
  std::array<Node, 2> nodes{};  ///< the older first
  int count = 0;
  /// With two nodes: the newer less the older, its squared length and the bound's lever
  /// over both (model::VariationBound::lever), kept with them: every extrapolation asks.
  model::ChainQ line = model::ChainQ::Zero();
  double length2 = 0.0, lever = 0.0;
  /// What they were evaluated under.
  AxisArray<double> directions{};
  Eigen::Matrix3d orientation = Eigen::Matrix3d::Zero();
  double time = 0.0;
  std::vector<double> temperatures;
  /// The chord bound of the nodes' line over the nodes, and how far out (in their distance
  /// from the older) an extrapolation goes.
  double line_chord = 0.0, line_reach = 0.0;
  /// The bend the last line missed the newer node by, as a second derivative in the
  /// current line's units: added to its extrapolation (the error field bends alike from
  /// node to node), and its size to the bound.
  Eigen::Vector3d line_bend = Eigen::Vector3d::Zero(), line_turn_bend = Eigen::Vector3d::Zero();
  /// The perfect machine's slopes where the nodes are, for a prediction off their line:
  /// the tip per unit of each linear unknown (exact: the tip is affine in them while the
  /// rotary axis stands), the orientation per unit of the rotary one, the largest column,
  /// and the error field's slopes (model::VariationBound::error_slopes), for the tool
  /// length, target orientation and rotary axis value they were taken at.
  struct NominalSlopes {
    bool valid = false;
    double tool_length = 0.0, rotary_value = 0.0, column_norm = 0.0;
    unsigned moving_columns = 0;  ///< bit k: the tip moves with unknown k (its column is not zero)
    Eigen::Matrix3d orientation = Eigen::Matrix3d::Zero();
    Eigen::Matrix<double, 3, model::kChainVariables> tip = Eigen::Matrix<double, 3, model::kChainVariables>::Zero();
    Eigen::Vector3d turn = Eigen::Vector3d::Zero();
    model::VariationBound::ErrorSlopes error_slopes;
  };
  NominalSlopes slopes;
};

/// The solve matrix of the last Jacobian evaluated (its pseudo-inverse), n x m.
using SolveMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 9, 6>;

/// What the path predictor remembers of the last solve: the solution with its target, the
/// approach it was for, the last step's miss, and how the solution moves with each axis'
/// approach.
struct PathMemory {
  model::ChainQ last_solution = model::ChainQ::Constant(std::nan(""));
  model::ChainQ last_nominal = model::ChainQ::Constant(std::nan(""));  ///< the point it was solved for
  Eigen::Vector3d last_target = Eigen::Vector3d::Zero();
  Eigen::Matrix3d last_target_orientation = Eigen::Matrix3d::Zero();
  AxisArray<double> last_directions{};  ///< the approach the last solution was for
  /// The last prediction's miss (solution - prediction) and the target shift it was made
  /// for: along a path of even steps the next miss is alike (the error field's curvature
  /// and the Jacobian's age), so it is added to the next prediction.
  model::ChainQ last_miss = model::ChainQ::Zero();
  Eigen::Vector3d last_shift = Eigen::Vector3d::Zero();
  /// How the solution moves per unit change of each axis' approach variable (its play
  /// taken up, its reversal), learnt where one point was solved again for one axis' changed
  /// approach: a reversal term is linear in it, so the next change is predicted.
  std::array<model::ChainQ, 9> approach_gain{};
  std::array<bool, 9> approach_gain_known{};
  bool last_bounded = false;  ///< the last solution was accepted on the bound
};

/// What one solve leaves for the next, when points come in a stream of neighbours, in the
/// three parts of the solve (src/compensate/inverse_solve.hpp): Newton's solve matrix, the
/// path predictor's memory, the bounded shortcut's nodes. The error field changes slowly, so
/// a Jacobian from a nearby point serves many solves (quasi-Newton: each step costs a
/// forward evaluation without Jacobians), and the last solution predicts the next to first
/// order. A fresh Jacobian is evaluated whenever a step fails to cut the residual tenfold;
/// convergence is always judged on the exact model.
struct InverseWorkspace {
  SolveMatrix solve_matrix;              ///< n x m, empty until a Jacobian
  std::size_t jacobian_evaluations = 0;  ///< how often the exact Jacobian was evaluated
  PathMemory memory;
  /// The last two points evaluated along the path: what bounds a prediction without
  /// evaluating it (InverseOptions::bound).
  PathNodes path;
  std::size_t bounded_points = 0;  ///< how many points were accepted on the bound
  /// The last solution as given to the caller, and its residual bound: the same but where
  /// a point was accepted on the bound or left standing (InverseOptions::bound), whose next
  /// prediction starts from it moved by its known residual (memory.last_solution).
  model::ChainQ last_answer = model::ChainQ::Constant(std::nan(""));
  double last_answer_bound = 0.0;

  /// For another set of unknowns (a rotary axis held or freed): forgets what the problem
  /// shaped (the solve matrix, the path and its predictions, the approach gains) and keeps
  /// the last answer (a move starting where the last ended starts where the machine is)
  /// and the counts.
  void forget_problem();
};

/// The nominal tool pose at a point (table frame): what its solve aims at, when the caller
/// has it already.
struct NominalPose {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  Eigen::Matrix3d orientation = Eigen::Matrix3d::Identity();
};

/// Solves for q' with actual(q') = nominal(q_nominal). `data` is scratch. `guess`, when
/// given, is where Newton starts. With a `workspace`, the solve reuses and updates it (see
/// InverseWorkspace): a prediction from its last solution replaces `guess` where the
/// orientation target is the same and the approach is too, or changed along axes whose
/// effect it has learnt; without a guess the last
/// solution's correction starts it. `nominal`, when given, is the nominal pose at q_nominal
/// (saves its evaluation).
[[nodiscard]] InverseResult solve_inverse(const model::ForwardModel& model, const InverseProblem& problem,
                                          model::ForwardData& data, const model::ChainQ& q_nominal,
                                          const model::Conditions& conditions, const InverseOptions& options = {},
                                          const model::ChainQ* guess = nullptr, InverseWorkspace* workspace = nullptr,
                                          const NominalPose* nominal = nullptr);

}  // namespace ccomp::compensate
