#pragma once
// The forward model: where the tool tip really is, relative to the workpiece, for axis
// values q, a tool length, temperatures, a time and approach directions; with the exact
// Jacobians the inverse solve and the fit need. Built once from a MachineModel
// (ForwardModel, immutable) and evaluated with a scratch ForwardData.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "ccomp/axis.hpp"
#include "ccomp/kinematics/chain.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::model {

/// Axis values of the chain: X Y Z A B C U V W, then the tool length L (index 9).
/// Linear axes and L in mm, rotary axes in rad.
inline constexpr std::size_t kToolLengthIndex = 9;
inline constexpr std::size_t kChainVariables = 10;
using ChainQ = Eigen::Matrix<double, kChainVariables, 1>;

/// What terms depend on besides the axes.
struct Conditions {
  double time = 0.0;                 ///< s since the start
  std::vector<double> temperatures;  ///< degC, one per sensor of the model
  /// Approach state of each axis, what reversal terms depend on: +1 after travelling up,
  /// -1 after travelling down, in between while the axis takes up its lost motion after
  /// turning round; 0 unknown (the middle of the play).
  AxisArray<double> directions{};
};

/// mm: the lever through which the compensation's estimates see an angle (an angular
/// switch in reversal_size(), a rotary axis' travel): a tool point that far from the axis.
inline constexpr double kSwitchLever = 500.0;

class ForwardModel {
 public:
  explicit ForwardModel(const MachineModel& model);

  [[nodiscard]] const MachineModel& machine() const { return machine_; }
  [[nodiscard]] const kinematics::ChainModel& chain() const { return chain_; }
  /// All free and fixed parameters of all terms, concatenated in file order.
  [[nodiscard]] std::size_t parameter_count() const { return parameter_count_; }
  [[nodiscard]] std::size_t parameter_offset(std::size_t term) const { return offsets_[term]; }
  /// Where each term's error enters: side (0 workpiece, 1 tool) and joint index.
  struct Site {
    int side = 0;
    std::size_t joint = 0;
  };
  [[nodiscard]] const Site& site(std::size_t term) const { return sites_[term]; }
  /// Index of the last workpiece-side joint before the workpiece point: the table frame.
  [[nodiscard]] std::size_t table_joint() const { return chain_.workpiece.joints.size() - 1; }
  /// How many points a move from a to b must be checked at so that no error feature is
  /// missed between them: the shortest feature along each axis (a periodic term's period
  /// over 8, a table's knot spacing over 4) sets the spacing. At least `minimum`.
  [[nodiscard]] int check_points(const ChainQ& a, const ChainQ& b, int minimum, int maximum = 1024) const;
  /// Lost motion of each axis (mm, rad): the size of its own positioning reversal (EXX's
  /// for X, EBB's for B, of whatever form in the axis' approach). After turning round, the
  /// axis travels this far before the terms of its approach have switched over; 0 means
  /// they switch as soon as it moves.
  [[nodiscard]] const AxisArray<double>& lost_motion() const { return lost_motion_; }
  /// The sum of the sizes of the terms switched by axis i's approach (a reversal's size,
  /// another form's value at +1 less its value at -1; all are linear in the approach), in
  /// mm at the tool: an angular one seen kSwitchLever out. About what a turn of the axis changes.
  [[nodiscard]] const AxisArray<double>& reversal_size() const { return reversal_size_; }
  /// Whether any term reads axis i's approach state (a reversal's, or any form given it as
  /// a variable): where none does, the axis may turn round without changing the error.
  [[nodiscard]] bool reads_approach(std::size_t axis) const { return approach_axes_ >> axis & 1U; }

  /// A term as forward()'s loop without Jacobians reads it: its inputs as indices into one
  /// vector of variables (see variables_of()), where its value goes, and whether it depends on
  /// the axes at all. One that does not (a thermal drift, a reversal, a constant) keeps its
  /// value while the conditions and parameters stand still: in a program, nearly always.
  struct TermSlot {
    TermForm form = TermForm::constant;
    bool on_axes = true;                        ///< depends on a chain variable (an axis or the tool length)
    bool on_approach = false;                   ///< depends on an axis' approach state (a reversal)
    std::int16_t primary = -1, secondary = -1;  ///< into the variables; -1: none (0)
    /// The primary variable is held within [span_from, span_to] (the term's span; the
    /// whole line without one).
    double span_from = -std::numeric_limits<double>::infinity(), span_to = std::numeric_limits<double>::infinity();
    std::size_t offset = 0;                     ///< its first parameter
    /// Its link's error component, in one array of 12 per link (the error motion's six,
    /// then the location's; the workpiece side's links, then the tool side's), and the
    /// sign it enters with.
    std::size_t error_index = 0;
    double sign = 1.0;
    int order = 0;  ///< a polynomial's degree (the commonest form, evaluated in the loop itself)
    /// A periodic term on the axes: an earlier one of the same variable and period, whose
    /// phase it takes where the periods still match (-1: none).
    std::int32_t phase_source = -1;
  };
  [[nodiscard]] const std::vector<TermSlot>& slots() const { return slots_; }
  /// A link's polynomials in one chain variable (the commonest terms: six error motions of
  /// a carriage along its axis), evaluated together as one polynomial with six components.
  struct PolynomialGroup {
    std::int16_t variable = 0;  ///< into the variables (a chain variable)
    int degree = 0;
    /// Where its (degree + 1) x 6 coefficients (the terms' own, signed and summed per link
    /// component, power by power) start in ForwardData::group_coefficients.
    std::size_t coefficients = 0;
    std::vector<std::size_t> terms;
  };
  /// Per link (the workpiece side's joints, then the tool side's): the terms on the axes
  /// that its error motion sums, the polynomials in one variable grouped, the others in
  /// file order; and the chain variables they read (bit i: q[i]). A link none of whose
  /// variables moved keeps its error pose.
  struct LinkTerms {
    std::vector<PolynomialGroup> polynomials;
    std::vector<std::size_t> terms;
    std::uint32_t variables = 0;
    bool off_axes_approach = false;  ///< a term off the axes on its error motion reads an approach state
  };
  /// The terms off the axes that read an approach state (`approach`) or that do not, in
  /// file order: what the forward model sums once for the conditions (the first when an
  /// approach changes, at every point where a play is being taken up).
  [[nodiscard]] const std::vector<std::size_t>& off_axes_terms(bool approach) const {
    return off_axes_terms_[approach ? 1 : 0];
  }
  /// Whether a term reading an approach state acts on a link's location (none of the forms
  /// a location takes does: it is then posed again whenever an approach changes).
  [[nodiscard]] bool location_reads_approach() const { return location_reads_approach_; }
  /// How many coefficients the polynomial groups have together.
  [[nodiscard]] std::size_t group_coefficient_count() const { return group_coefficient_count_; }
  [[nodiscard]] const std::vector<LinkTerms>& link_terms() const { return link_terms_; }
  /// Where TermSlot's variable indices point: q (10), the time, the 9 directions, then one
  /// temperature per sensor.
  static constexpr std::size_t kTimeVariable = kChainVariables;
  static constexpr std::size_t kFirstDirectionVariable = kTimeVariable + 1;
  static constexpr std::size_t kFirstTemperatureVariable = kFirstDirectionVariable + 9;

 private:
  MachineModel machine_;
  kinematics::ChainModel chain_;
  std::vector<Site> sites_;
  std::vector<TermSlot> slots_;
  std::vector<LinkTerms> link_terms_;
  std::array<std::vector<std::size_t>, 2> off_axes_terms_;
  std::size_t group_coefficient_count_ = 0;
  bool location_reads_approach_ = false;
  std::vector<std::size_t> offsets_;
  std::size_t parameter_count_ = 0;
  ChainQ feature_;  ///< shortest error feature along each chain variable (mm, rad), or +inf
  AxisArray<double> lost_motion_{}, reversal_size_{};
  unsigned approach_axes_ = 0;  ///< bit i: some term reads axis i's approach state
};

struct ForwardData {
  explicit ForwardData(const ForwardModel& model);

  /// The terms' parameters (they start as the model's). forward() keeps what it derives
  /// from them (sums, a table's spline) until they change, which it learns from their
  /// revision instead of comparing them all at every evaluation.
  [[nodiscard]] const Eigen::VectorXd& parameters() const { return parameters_; }
  /// Takes `p` (a revision only where it differs, bit for bit: a caller may set the same
  /// parameters at every point).
  void set_parameters(const Eigen::VectorXd& p);
  /// For changing some in place: a new revision. Not to be kept past the next forward().
  [[nodiscard]] Eigen::VectorXd& edit_parameters() {
    ++parameters_revision_;
    return parameters_;
  }
  [[nodiscard]] std::uint64_t parameters_revision() const { return parameters_revision_; }

  // results
  Eigen::Vector3d actual = Eigen::Vector3d::Zero();       ///< tool tip in the table frame, with errors
  Eigen::Vector3d nominal = Eigen::Vector3d::Zero();      ///< the same without errors
  Eigen::Matrix3d R_actual, R_nominal;                    ///< the tool's orientation in the table frame
  Eigen::Matrix<double, 3, kChainVariables> J_q;          ///< d actual / d q
  Eigen::Matrix<double, 3, Eigen::Dynamic> J_parameters;  ///< d actual / d parameters
  // scratch
  kinematics::ChainData actual_chain;
  kinematics::NominalData nominal_chain;  ///< the perfect machine
  /// Per joint: delta, epsilon of its error motion and of its location.
  std::vector<Eigen::Matrix<double, 6, 1>> work_error, tool_error, work_location, tool_location;
  /// The axis values of the last evaluation without Jacobians (NaN before it): a link
  /// whose terms read none that moved since keeps its errors and its pose.
  ChainQ evaluated_q = ChainQ::Constant(std::numeric_limits<double>::quiet_NaN());
  /// What the poses in actual_chain were built from: a link whose errors did not change
  /// since (an axis standing still, a thermal drift) keeps its pose.
  std::vector<Eigen::Matrix<double, 6, 1>> posed_work_error, posed_tool_error, posed_work_location, posed_tool_location;
  std::vector<TermValue> values;
  /// Each cubic table's spline moments under the parameters' key below (a table's values
  /// change only in a fit): evaluating it is then a binary search and a few products,
  /// however long the table. Empty for the other terms.
  std::vector<std::vector<double>> table_moments;
  /// What each term's value was last evaluated from: a term whose inputs are unchanged, and
  /// the parameters too (the key below), keeps its value.
  std::vector<TermInputs> evaluated_inputs;
  /// Each periodic term's last phase (the forward loop's; its source's serves it).
  std::vector<PeriodicPhase> phases;
  /// The variables the terms read (ForwardModel::TermSlot), as the last evaluation had
  /// them: its conditions (time, directions, temperatures) are what the next compares with
  /// (the key, with key_parameters_revision for the parameters).
  std::vector<double> variables;
  /// The off-axes terms' errors summed per link component (TermSlot::error_index): all,
  /// those not reading an approach state, those reading one; and the sum with the others.
  std::vector<double> off_axes_errors, off_axes_fixed, off_axes_approach, errors;
  /// The polynomial groups' coefficients (ForwardModel::PolynomialGroup), from the
  /// parameters under the key.
  std::vector<double> group_coefficients;
  bool key_valid = false;  ///< false after an evaluation with Jacobians (it keeps no key)
  std::uint64_t key_parameters_revision = 0;  ///< the parameters' revision under the key
  std::vector<Eigen::Matrix<double, 6, 6>> J_work_pose, J_tool_pose, J_work_location_pose, J_tool_location_pose;

 private:
  Eigen::VectorXd parameters_;
  std::uint64_t parameters_revision_ = 0;
};

/// Which poses forward() computes: both, or only the one a caller needs.
enum class Evaluate : std::uint8_t { both, actual, nominal };

/// Moves the approach state of each axis as the command travels from a to b, the way play
/// in a drive behaves: the state moves toward the direction of travel by 2 |b - a| / w
/// (w the axis' lost motion) and stops at +-1, so a reversal completes once the axis has
/// travelled w the other way, and a small move back only eats into the play. An axis
/// without lost motion switches as soon as it moves (by more than 1 nm or 1e-8 rad).
void take_up_play(const ForwardModel& model, Conditions& conditions, const ChainQ& a, const ChainQ& b);
/// The same of the approach states alone.
void take_up_play(const ForwardModel& model, AxisArray<double>& directions, const ChainQ& a, const ChainQ& b);

/// Evaluates the model at q. With `jacobians`, fills J_q and J_parameters.
/// With `jacobians`, fills J_q and (unless `parameter_jacobian` is false: the inverse
/// needs only J_q) J_parameters.
void forward(const ForwardModel& model, ForwardData& data, const ChainQ& q, const Conditions& conditions,
             bool jacobians = false, Evaluate which = Evaluate::both, bool parameter_jacobian = true);

/// The deviation of the tool tip (actual - nominal) in machine-axis directions, mm.
[[nodiscard]] Eigen::Vector3d deviation(const ForwardData& data);

}  // namespace ccomp::model
