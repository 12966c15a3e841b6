#include "ccomp/model/forward.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>

#include "ccomp/axis.hpp"
#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/model/cubic_spline.hpp"
#include "ccomp/model/term_forms.hpp"

namespace ccomp::model {

using kinematics::Joint;
using kinematics::JointType;
using kinematics::Pose;

namespace {

/// Per link, the six components of its error motion, then the six of its location.
constexpr std::size_t kLinkErrorSize = 12;

/// The sign a term's value enters its link's pose with. ISO 230-1 errors are the tool's
/// relative to the workpiece: a link on the workpiece side moves the workpiece, so its error
/// motion, and the displacement of its line, carry the opposite sign. A tilt of a line does
/// not: the tool travels relative to the workpiece along the same line, whichever moves.
double link_sign(int side, const ErrorTermSpec& t) {
  if (t.placement == ErrorPlacement::location && t.component >= 3) return 1.0;
  return side == 0 ? -1.0 : 1.0;
}

/// The chain's joints for `links`: a linear or rotary joint per moving link, the tool
/// length as an axis of its own, a fixed joint for the rest.
void add_joints(const MachineModel& machine, const std::vector<LinkSpec>& links, kinematics::Chain& chain) {
  for (const LinkSpec& l : links) {
    Joint j;
    j.name = l.name;
    j.placement = Pose::translation(l.offset);
    j.direction = l.direction;
    if (l.tool) {
      j.type = JointType::linear;  // the tool length is an axis of its own: L along the tool
      j.axis = kToolLengthIndex;
    } else if (l.axis) {
      const auto* a = machine.axis(*l.axis);
      j.type = a && a->type == AxisType::rotary ? JointType::rotary : JointType::linear;
      j.axis = index_of_letter(*l.axis);
    }
    chain.joints.push_back(j);
  }
}

/// Where term t's error enters the chains: its link's side and joint.
ForwardModel::Site site_of(const kinematics::ChainModel& chain, const ErrorTermSpec& t) {
  for (int side = 0; side < 2; ++side) {
    const auto& joints = side == 0 ? chain.workpiece.joints : chain.tool.joints;
    for (std::size_t j = 0; j < joints.size(); ++j)
      if (joints[j].name == t.link) return ForwardModel::Site{side, j};
  }
  throw Error(ErrorKind::model, fmt::format("term {}: no link {} in the chains", t.name, t.link));
}

/// A variable's index into forward()'s vector of variables (ForwardModel::TermSlot); -1
/// for none.
std::int16_t variable_slot(const Variable& v) {
  switch (v.kind) {
    case VariableKind::axis:
      return static_cast<std::int16_t>(v.index);
    case VariableKind::tool_length:
      return static_cast<std::int16_t>(kToolLengthIndex);
    case VariableKind::time:
      return static_cast<std::int16_t>(ForwardModel::kTimeVariable);
    case VariableKind::direction:
      return static_cast<std::int16_t>(ForwardModel::kFirstDirectionVariable + v.index);
    case VariableKind::temperature:
      return static_cast<std::int16_t>(ForwardModel::kFirstTemperatureVariable + v.index);
    case VariableKind::none:
      break;
  }
  return -1;
}

/// The axis whose approach state variable slot v is, or -1 (another variable, none).
int direction_axis(std::int16_t v) {
  const int axis = v - static_cast<int>(ForwardModel::kFirstDirectionVariable);
  return axis >= 0 && v < static_cast<int>(ForwardModel::kFirstTemperatureVariable) ? axis : -1;
}

/// The six components of a link's error motion (delta x y z, epsilon a b c).
constexpr std::size_t kMotionComponents = 6;

/// Adds term `index` (its slot, on the axes) to its link's terms: a polynomial in one
/// chain variable to the group of that variable, any other to the rest. (Location terms
/// are constants: only error motions are on the axes.)
void add_link_term(ForwardModel::LinkTerms& link, const ForwardModel::TermSlot& slot, std::size_t index) {
  for (const std::int16_t v : {slot.primary, slot.secondary})
    if (v >= 0 && v < static_cast<int>(kChainVariables)) link.variables |= 1U << static_cast<unsigned>(v);
  // A polynomial held beyond its span is not one polynomial of its variable everywhere:
  // evaluated on its own.
  if (slot.form != TermForm::polynomial || slot.secondary >= 0 || std::isfinite(slot.span_from)) {
    link.terms.push_back(index);
    return;
  }
  ForwardModel::PolynomialGroup* group = nullptr;
  for (ForwardModel::PolynomialGroup& g : link.polynomials)
    if (g.variable == slot.primary) group = &g;
  if (!group) group = &link.polynomials.emplace_back(ForwardModel::PolynomialGroup{slot.primary, 0, 0, {}});
  group->degree = std::max(group->degree, slot.order);
  group->terms.push_back(index);
}

/// Term t's slot, at site s, its parameters from `offset` on (phase_source left at none).
ForwardModel::TermSlot slot_of(const kinematics::ChainModel& chain, const ForwardModel::Site& s, const ErrorTermSpec& t,
                               std::size_t offset) {
  ForwardModel::TermSlot slot;
  slot.form = t.shape.form;
  slot.primary = variable_slot(t.primary);
  slot.secondary = variable_slot(t.secondary);
  if (t.span) slot.span_from = t.span->from, slot.span_to = t.span->to;
  slot.on_axes = (slot.primary >= 0 && slot.primary < static_cast<int>(kChainVariables)) ||
                 (slot.secondary >= 0 && slot.secondary < static_cast<int>(kChainVariables));
  slot.on_approach = direction_axis(slot.primary) >= 0 || direction_axis(slot.secondary) >= 0;
  slot.offset = offset;
  const std::size_t link = s.side == 0 ? s.joint : chain.workpiece.joints.size() + s.joint;
  const bool location = t.placement == ErrorPlacement::location;
  slot.error_index = kLinkErrorSize * link + (location ? 6 : 0) + static_cast<std::size_t>(t.component);
  slot.sign = link_sign(s.side, t);
  slot.order = t.shape.order;
  return slot;
}

/// An earlier periodic term on the axes of the same variable and period as `slot` (term
/// t): the one whose phase it can take; -1 for none.
std::int32_t phase_source(const std::vector<ForwardModel::TermSlot>& slots, const std::vector<ErrorTermSpec>& terms,
                          const ForwardModel::TermSlot& slot, const ErrorTermSpec& t) {
  // A term held beyond a span turns with its own (held) phase.
  if (!slot.on_axes || slot.form != TermForm::periodic || std::isfinite(slot.span_from)) return -1;
  // Its source must be evaluated before it: links are summed in chain order.
  const std::size_t link = slot.error_index / kLinkErrorSize;
  for (std::size_t j = 0; j < slots.size(); ++j)
    if (slots[j].on_axes && slots[j].form == TermForm::periodic && slots[j].primary == slot.primary &&
        !std::isfinite(slots[j].span_from) &&
        terms[j].parameters[0] == t.parameters[0] && slots[j].error_index / kLinkErrorSize <= link)
      return static_cast<std::int32_t>(j);
  return -1;
}

/// The shortest error feature along each chain variable (mm, rad), or +inf: what
/// check_points() spaces its points by.
ChainQ shortest_features(const std::vector<ErrorTermSpec>& terms) {
  ChainQ shortest = ChainQ::Constant(std::numeric_limits<double>::infinity());
  for (const ErrorTermSpec& t : terms) {
    if (t.primary.kind != VariableKind::axis) continue;
    const double feature = term_form(t.shape.form).shortest_feature(t);
    auto& f = shortest[static_cast<Eigen::Index>(t.primary.index)];
    f = std::min(f, std::abs(feature));
  }
  return shortest;
}

/// What the terms switched by each axis' approach add up to, and the axis' lost motion.
struct Reversals {
  AxisArray<double> size{}, lost_motion{};
};

/// How much term t (its variable an approach, in which it is linear: the model file refuses
/// others) changes from the approach -1 to +1: a reversal's value. One that varies along an
/// axis (a worn screw) is taken where it is largest over that axis' limits (or its span, or
/// 1 m either side where neither bounds it): the switch no travel outgrows.
double switch_of(const MachineModel& m, const ErrorTermSpec& t) {
  auto at = [&t](double along) {
    TermValue up, down;
    evaluate(t.shape, t.parameters, TermInputs{1.0, along}, false, up);
    evaluate(t.shape, t.parameters, TermInputs{-1.0, along}, false, down);
    return up.value - down.value;
  };
  if (t.shape.form != TermForm::reversal || t.shape.order_primary == 0 || t.secondary.kind != VariableKind::axis)
    return at(0.0);
  double lo = -1000.0, hi = 1000.0;
  const AxisSpec* axis = m.axis(kAxisLetters[t.secondary.index]);
  const double unit = axis && axis->type == AxisType::rotary ? kRadPerDeg : 1.0;
  if (axis && std::isfinite(axis->min) && std::isfinite(axis->max)) lo = axis->min * unit, hi = axis->max * unit;
  double largest = 0.0;
  for (int k = 0; k <= 16; ++k)
    if (const double r = at(lo + (hi - lo) * k / 16.0); std::abs(r) > std::abs(largest)) largest = r;
  return largest;
}

/// An axis' lost motion is its own positioning reversal: a term on the axis' link, along
/// (or about) the axis' direction, switched by that axis' approach.
Reversals reversals_of(const MachineModel& m, const std::vector<ForwardModel::Site>& sites,
                       const kinematics::ChainModel& chain) {
  const std::vector<ErrorTermSpec>& terms = m.terms;
  Reversals r;
  AxisArray<double> own_reversal{};
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const ErrorTermSpec& t = terms[i];
    if (t.primary.kind != VariableKind::direction) continue;
    const double switched = switch_of(m, t);
    r.size[t.primary.index] += std::abs(switched) * (t.component >= 3 ? kSwitchLever : 1.0);
    const auto& joints = sites[i].side == 0 ? chain.workpiece.joints : chain.tool.joints;
    const Joint& j = joints[sites[i].joint];
    if (j.type == JointType::fixed || j.axis != t.primary.index) continue;
    Eigen::Index along = 0;
    j.direction.cwiseAbs().maxCoeff(&along);
    if (t.component == static_cast<int>(along) + (j.type == JointType::rotary ? 3 : 0))
      own_reversal[t.primary.index] += switched;
  }
  for (std::size_t i = 0; i < r.lost_motion.size(); ++i) r.lost_motion[i] = std::abs(own_reversal[i]);
  return r;
}

}  // namespace

ForwardModel::ForwardModel(const MachineModel& model) : machine_(model) {
  chain_.nq = kChainVariables;
  add_joints(machine_, machine_.workpiece_chain, chain_.workpiece);
  add_joints(machine_, machine_.tool_chain, chain_.tool);
  // The workpiece point: the table frame itself (program coordinates are table coordinates).
  chain_.workpiece.joints.push_back(Joint{"p", JointType::fixed, 0, Eigen::Vector3d::UnitX(), Pose{}});
  link_terms_.resize(chain_.workpiece.joints.size() + chain_.tool.joints.size());
  for (const ErrorTermSpec& t : machine_.terms) {
    const Site s = site_of(chain_, t);
    sites_.push_back(s);
    TermSlot slot = slot_of(chain_, s, t, parameter_count_);
    slot.phase_source = phase_source(slots_, machine_.terms, slot, t);
    if (slot.on_axes) {
      // (The model file makes only constants locations; one built otherwise is refused.)
      if (slot.error_index % kLinkErrorSize >= kMotionComponents)
        throw Error(ErrorKind::model, fmt::format("term {}: a location error is a constant, not a function of an axis",
                                                  t.name));
      add_link_term(link_terms_[slot.error_index / kLinkErrorSize], slot, slots_.size());
      // (A reversal varying along an axis reads an approach too: its link is summed again
      // when a play is taken up, as for those off the axes; off_axes_approach means "a term
      // on its error motion reads an approach state".)
      if (slot.on_approach) link_terms_[slot.error_index / kLinkErrorSize].off_axes_approach = true;
    } else {
      off_axes_terms_[slot.on_approach ? 1 : 0].push_back(slots_.size());
      const bool on_motion = slot.error_index % kLinkErrorSize < kMotionComponents;
      if (slot.on_approach && on_motion) link_terms_[slot.error_index / kLinkErrorSize].off_axes_approach = true;
      if (slot.on_approach && !on_motion) location_reads_approach_ = true;
    }
    for (const std::int16_t v : {slot.primary, slot.secondary})
      if (const int axis = direction_axis(v); axis >= 0) approach_axes_ |= 1U << static_cast<unsigned>(axis);
    slots_.push_back(slot);
    offsets_.push_back(parameter_count_);
    parameter_count_ += static_cast<std::size_t>(t.parameters.size());
  }
  for (LinkTerms& link : link_terms_)
    for (PolynomialGroup& group : link.polynomials) {
      group.coefficients = group_coefficient_count_;
      group_coefficient_count_ += kMotionComponents * static_cast<std::size_t>(group.degree + 1);
    }
  feature_ = shortest_features(machine_.terms);
  const Reversals reversals = reversals_of(machine_, sites_, chain_);
  reversal_size_ = reversals.size;
  lost_motion_ = reversals.lost_motion;
}

int ForwardModel::check_points(const ChainQ& a, const ChainQ& b, int minimum, int maximum) const {
  double n = minimum;
  for (Eigen::Index i = 0; i < feature_.size(); ++i)
    if (std::isfinite(feature_[i])) n = std::max(n, std::ceil(std::abs(b[i] - a[i]) / feature_[i]));
  return static_cast<int>(std::min<double>(n, maximum));
}

ForwardData::ForwardData(const ForwardModel& model)
    : J_parameters(3, static_cast<Eigen::Index>(model.parameter_count())),
      actual_chain(model.chain()),
      nominal_chain(model.chain()),
      work_error(model.chain().workpiece.joints.size()),
      tool_error(model.chain().tool.joints.size()),
      work_location(work_error.size()),
      tool_location(tool_error.size()),
      posed_work_error(work_error.size(), Eigen::Matrix<double, 6, 1>::Constant(std::nan(""))),
      posed_tool_error(tool_error.size(), Eigen::Matrix<double, 6, 1>::Constant(std::nan(""))),
      posed_work_location(work_error.size(), Eigen::Matrix<double, 6, 1>::Constant(std::nan(""))),
      posed_tool_location(tool_error.size(), Eigen::Matrix<double, 6, 1>::Constant(std::nan(""))),
      values(model.machine().terms.size()),
      table_moments(values.size()),
      evaluated_inputs(values.size(), TermInputs{std::nan(""), std::nan("")}),
      phases(values.size()),
      variables(ForwardModel::kFirstTemperatureVariable + model.machine().sensors.size(), 0.0),
      off_axes_errors(kLinkErrorSize * (model.chain().workpiece.joints.size() + model.chain().tool.joints.size())),
      off_axes_fixed(off_axes_errors.size()),
      off_axes_approach(off_axes_errors.size()),
      errors(off_axes_errors.size()),
      group_coefficients(model.group_coefficient_count()),
      J_work_pose(model.chain().workpiece.joints.size()),
      J_tool_pose(model.chain().tool.joints.size()),
      J_work_location_pose(model.chain().workpiece.joints.size()),
      J_tool_location_pose(model.chain().tool.joints.size()),
      parameters_(static_cast<Eigen::Index>(model.parameter_count())) {
  for (std::size_t i = 0; i < model.machine().terms.size(); ++i)
    parameters_.segment(static_cast<Eigen::Index>(model.parameter_offset(i)),
                        model.machine().terms[i].parameters.size()) = model.machine().terms[i].parameters;
}

void ForwardData::set_parameters(const Eigen::VectorXd& p) {
  // (Compared as bits, as a key is: a NaN set again is the same.)
  const bool same = p.size() == parameters_.size() &&
                    (p.size() == 0 || std::memcmp(p.data(), parameters_.data(), sizeof(double) * p.size()) == 0);
  if (same) return;
  parameters_ = p;
  ++parameters_revision_;
}

namespace {

double variable_value(const Variable& v, const ChainQ& q, const Conditions& c) {
  switch (v.kind) {
    case VariableKind::axis:
      return q[static_cast<Eigen::Index>(v.index)];
    case VariableKind::tool_length:
      return q[static_cast<Eigen::Index>(kToolLengthIndex)];
    case VariableKind::time:
      return c.time;
    case VariableKind::temperature:
      return v.index < c.temperatures.size() ? c.temperatures[v.index] : 20.0;
    case VariableKind::direction:
      return c.directions[v.index];
    case VariableKind::none:
      return 0.0;
  }
  return 0.0;
}

/// The value of a term of a cheap form (constant, polynomial by Horner, reversal, thermal,
/// scale expansion); false for the others, which evaluate() takes.
bool inline_value(const ErrorTermSpec& t, const double* p, const TermInputs& in, double& value) {
  const double v = in.primary;
  switch (t.shape.form) {
    case TermForm::constant:
      value = p[0];
      return true;
    case TermForm::polynomial:
      value = p[t.shape.order];
      for (int k = t.shape.order - 1; k >= 0; --k) value = value * v + p[k];
      return true;
    case TermForm::reversal: {
      double reversal = p[t.shape.order_primary];  // along its axis by Horner (r_0 alone without one)
      for (int k = t.shape.order_primary - 1; k >= 0; --k) reversal = reversal * in.secondary + p[k];
      value = 0.5 * reversal * v;
      return true;
    }
    case TermForm::thermal_linear:
      value = p[0] * (v - t.shape.reference);
      return true;
    case TermForm::scale_expansion:
      value = p[0] * v * (in.secondary - t.shape.reference);
      return true;
    default:
      return false;
  }
}

/// The chain variable a term variable is, or -1 when it is not one (time, temperature...).
int chain_index(const Variable& v) {
  if (v.kind == VariableKind::axis) return static_cast<int>(v.index);
  if (v.kind == VariableKind::tool_length) return static_cast<int>(kToolLengthIndex);
  return -1;
}

/// A term's value without derivatives: a cheap form at once, the others through
/// evaluate(), kept while their inputs and (`same_parameters`) parameters stand still.
double term_value(const ErrorTermSpec& t, std::size_t offset, ForwardData& d, std::size_t i, const TermInputs& in,
                  bool same_parameters) {
  double value = 0.0;
  if (inline_value(t, d.parameters().data() + offset, in, value)) return value;
  TermInputs& last = d.evaluated_inputs[i];
  if (!same_parameters || in.primary != last.primary || in.secondary != last.secondary) {
    if (t.shape.form == TermForm::table && t.shape.interpolation == Interpolation::cubic) {
      // Solved again whenever the parameters' key changed: every term passes here then (as
      // for the values kept above), so moments kept under the same key are this table's.
      const double* p = d.parameters().data() + offset;
      std::vector<double>& moments = d.table_moments[i];
      if (!same_parameters || moments.empty()) spline_moments(t.shape.knots, p, moments);
      d.values[i].value = spline_value(t.shape.knots, p, moments.data(), in.primary, &d.values[i].d_primary);
    } else {
      evaluate(t.shape, d.parameters().segment(static_cast<Eigen::Index>(offset), t.parameters.size()), in, false,
               d.values[i]);
    }
    last = in;
  }
  return d.values[i].value;
}

/// Whether the approach states, the rest of the conditions (time, temperatures) and the
/// parameters are those of the last evaluation's key.
struct KeyMatch {
  bool directions = false, rest = false, parameters = false;
};

/// Fills d.variables for q and c. The conditions are compared with the last evaluation's,
/// which the variables still hold (as bits: conditions that compare equal give the same
/// values), and written only where they differ.
KeyMatch update_variables(ForwardData& d, const ChainQ& q, const Conditions& c) {
  double* v = d.variables.data();
  for (std::size_t i = 0; i < kChainVariables; ++i) v[i] = q[static_cast<Eigen::Index>(i)];
  constexpr std::size_t kDirections = ForwardModel::kFirstTemperatureVariable - ForwardModel::kFirstDirectionVariable;
  static_assert(kDirections == kAxisCount);
  const auto differs = [](const double* a, const double* b, std::size_t n) {
    return std::memcmp(a, b, n * sizeof(double)) != 0;
  };
  KeyMatch match;
  double* directions = v + ForwardModel::kFirstDirectionVariable;
  match.directions = d.key_valid && !differs(directions, c.directions.data(), kDirections);
  if (!match.directions) std::memcpy(directions, c.directions.data(), kDirections * sizeof(double));
  bool rest = !differs(v + ForwardModel::kTimeVariable, &c.time, 1);
  v[ForwardModel::kTimeVariable] = c.time;
  for (std::size_t i = ForwardModel::kFirstTemperatureVariable; i < d.variables.size(); ++i) {
    const std::size_t sensor = i - ForwardModel::kFirstTemperatureVariable;
    const double t = sensor < c.temperatures.size() ? c.temperatures[sensor] : 20.0;
    if (differs(v + i, &t, 1)) v[i] = t, rest = false;
  }
  match.rest = d.key_valid && rest;
  match.parameters = d.key_valid && d.key_parameters_revision == d.parameters_revision();
  d.key_parameters_revision = d.parameters_revision();
  d.key_valid = true;
  return match;
}

}  // namespace

namespace {

/// Evaluates every term with its derivatives (for the Jacobians) and sums the values per
/// link component into d.errors.
void evaluate_terms_with_derivatives(const ForwardModel& model, ForwardData& d, const ChainQ& q, const Conditions& c,
                                     bool gradient) {
  const auto& terms = model.machine().terms;
  const auto& slots = model.slots();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const ErrorTermSpec& t = terms[i];
    const double primary = variable_value(t.primary, q, c);
    const TermInputs in{std::clamp(primary, slots[i].span_from, slots[i].span_to), variable_value(t.secondary, q, c)};
    const auto params = d.parameters().segment(static_cast<Eigen::Index>(model.parameter_offset(i)), t.parameters.size());
    evaluate(t.shape, params, in, gradient, d.values[i]);
    if (in.primary != primary) d.values[i].d_primary = 0.0;  // held beyond its span
    d.evaluated_inputs[i] = in;
    d.errors[slots[i].error_index] += slots[i].sign * d.values[i].value;
  }
  d.key_valid = false;  // the values were evaluated with parameters it does not record
}

TermInputs slot_inputs(const ForwardData& d, const ForwardModel::TermSlot& s) {
  return TermInputs{s.primary >= 0 ? std::clamp(d.variables[static_cast<std::size_t>(s.primary)], s.span_from, s.span_to)
                                   : 0.0,
                    s.secondary >= 0 ? d.variables[static_cast<std::size_t>(s.secondary)] : 0.0};
}

/// A cross-axis term's value alone: the sum evaluate() makes, in its order (an Abbe term
/// of two axes changes at nearly every point, and evaluate() works out its derivatives too).
double cross_axis_value(const TermShape& shape, const double* p, const TermInputs& in) {
  double value = 0.0, ui = 1.0;  // v^i
  std::size_t index = 0;
  for (int i = 0; i <= shape.order_primary; ++i) {
    double wj = 1.0;  // w^j
    for (int j = 1; j <= shape.order; ++j, ++index) {
      wj *= in.secondary;
      value += p[index] * ui * wj;
    }
    ui *= in.primary;
  }
  return value;
}

/// The value of term i, one that depends on the axes, at d's variables.
double on_axes_value(const ForwardModel& model, ForwardData& d, std::size_t i, bool same_parameters) {
  const ForwardModel::TermSlot& s = model.slots()[i];
  const double* parameters = d.parameters().data();
  if (s.form == TermForm::polynomial) {  // Horner, as inline_value() does
    const double v = std::clamp(d.variables[static_cast<std::size_t>(s.primary)], s.span_from, s.span_to);
    const double* p = parameters + s.offset;
    double value = p[s.order];
    for (int k = s.order - 1; k >= 0; --k) value = value * v + p[k];
    return value;
  }
  if (s.form == TermForm::periodic) {  // a lead screw's error: its value alone
    const double v = std::clamp(d.variables[static_cast<std::size_t>(s.primary)], s.span_from, s.span_to);
    TermInputs& last = d.evaluated_inputs[i];
    if (!same_parameters || v != last.primary || last.secondary != 0.0) {
      const double* p = parameters + s.offset;
      PeriodicPhase& phase = d.phases[i];
      const PeriodicPhase* shared = s.phase_source >= 0 ? &d.phases[static_cast<std::size_t>(s.phase_source)] : nullptr;
      if (shared && shared->at == v && shared->period == p[0])
        phase = *shared;
      else
        periodic_phase(p[0], v, d.values[i], phase);
      d.values[i].value = periodic_sum(p, s.order, phase);
      last = TermInputs{v, 0.0};
    }
    return d.values[i].value;
  }
  if (s.form == TermForm::cross_axis) return cross_axis_value(model.machine().terms[i].shape, parameters + s.offset,
                                                               slot_inputs(d, s));
  return term_value(model.machine().terms[i], s.offset, d, i, slot_inputs(d, s), same_parameters);
}

/// Sums the values of the terms off the axes that read an approach state (`approach`) or
/// those that do not, per link component, into `sums`.
void sum_off_axes(const ForwardModel& model, ForwardData& d, bool approach, bool same_parameters,
                  std::vector<double>& sums) {
  const auto& terms = model.machine().terms;
  const auto& slots = model.slots();
  std::fill(sums.begin(), sums.end(), 0.0);
  for (const std::size_t i : model.off_axes_terms(approach))
    sums[slots[i].error_index] +=
        slots[i].sign * term_value(terms[i], slots[i].offset, d, i, slot_inputs(d, slots[i]), same_parameters);
}

/// Each polynomial group's coefficients from the parameters: its terms', signed, summed
/// per link component and power.
void group_polynomials(const ForwardModel& model, ForwardData& d) {
  std::fill(d.group_coefficients.begin(), d.group_coefficients.end(), 0.0);
  for (const ForwardModel::LinkTerms& link : model.link_terms())
    for (const ForwardModel::PolynomialGroup& g : link.polynomials)
      for (const std::size_t i : g.terms) {
        const ForwardModel::TermSlot& s = model.slots()[i];
        const double* p = d.parameters().data() + s.offset;
        const std::size_t component = s.error_index % kLinkErrorSize;
        for (int k = 0; k <= s.order; ++k)
          d.group_coefficients[g.coefficients + kMotionComponents * static_cast<std::size_t>(k) + component] +=
              s.sign * p[k];
      }
}

/// Adds group g's six components at d's variables to a link's error motion `errors`: one
/// Horner's scheme for all (a carriage's six error motions along its axis).
void add_polynomial_group(const ForwardModel::PolynomialGroup& g, const ForwardData& d, double* errors) {
  const double v = d.variables[static_cast<std::size_t>(g.variable)];
  const double* c = d.group_coefficients.data() + g.coefficients;
  std::array<double, kMotionComponents> sum;
  std::copy_n(c + kMotionComponents * static_cast<std::size_t>(g.degree), kMotionComponents, sum.begin());
  for (int k = g.degree - 1; k >= 0; --k)
    for (std::size_t j = 0; j < kMotionComponents; ++j)
      sum[j] = sum[j] * v + c[kMotionComponents * static_cast<std::size_t>(k) + j];
  for (std::size_t j = 0; j < kMotionComponents; ++j) errors[j] += sum[j];
}

static_assert(kChainVariables <= 32, "LinkTerms::variables holds a bit per chain variable");

/// How many links an evaluation tracks one by one (the bits of PoseChanges).
constexpr std::size_t kTrackedLinks = 64;

/// Sums the terms' values per link component into d.errors, without derivatives, for the
/// links `summed` sets (bit k: link k of ForwardModel::link_terms(); the others keep their
/// sums). The forward model runs this at every point the compensation checks: the terms off
/// the axes are summed once for the conditions and parameters, the others at each point, a
/// link's only where an axis it reads moved (or an approach its terms read changed). True
/// when the location poses must be posed again.
bool sum_term_values(const ForwardModel& model, ForwardData& d, const ChainQ& q, const Conditions& c, bool tracked,
                     std::uint64_t& summed) {
  const auto& slots = model.slots();
  const KeyMatch same = update_variables(d, q, c);
  // Every sum off the axes is stale when the parameters, the time or a temperature changed;
  // where only an approach state did (a play being taken up), those of the terms reading one.
  const bool stale = !same.rest || !same.parameters;
  const bool turned = stale || !same.directions;
  if (stale) sum_off_axes(model, d, false, same.parameters, d.off_axes_fixed);
  if (turned) {
    sum_off_axes(model, d, true, same.parameters, d.off_axes_approach);
    for (std::size_t i = 0; i < d.off_axes_errors.size(); ++i)
      d.off_axes_errors[i] = d.off_axes_fixed[i] + d.off_axes_approach[i];
  }
  if (!same.parameters) group_polynomials(model, d);
  std::uint32_t moved = 0;  // (NaN, before the first evaluation, moves every axis)
  for (Eigen::Index i = 0; i < q.size(); ++i)
    if (!(q[i] == d.evaluated_q[i])) moved |= 1U << static_cast<unsigned>(i);
  d.evaluated_q = q;
  const auto& links = model.link_terms();
  summed = 0;
  for (std::size_t k = 0; k < links.size(); ++k) {
    // (A chain longer than the mask is summed whole: each link at every evaluation.)
    const bool redo =
        !tracked || stale || (turned && links[k].off_axes_approach) || (links[k].variables & moved) != 0;
    if (!redo) continue;
    if (tracked) summed |= std::uint64_t{1} << k;
    // Each component from its sum off the axes, then the polynomial groups, then the other
    // terms on the axes in file order (the same sums as evaluating each term alone, to
    // their rounding).
    // (memcpy of a constant size is inlined; std::copy_n of these iterators was a call)
    std::memcpy(d.errors.data() + kLinkErrorSize * k, d.off_axes_errors.data() + kLinkErrorSize * k,
                kLinkErrorSize * sizeof(double));
    for (const ForwardModel::PolynomialGroup& g : links[k].polynomials)
      add_polynomial_group(g, d, d.errors.data() + kLinkErrorSize * k);
    for (const std::size_t i : links[k].terms) {
      const ForwardModel::TermSlot& s = slots[i];
      const double value = on_axes_value(model, d, i, same.parameters);
      d.errors[s.error_index] += s.sign * value;
    }
  }
  return stale || (turned && model.location_reads_approach());
}

using Vec6 = Eigen::Matrix<double, 6, 1>;

/// Link k's error motion (`part` 0) or location (6) in d.errors.
Eigen::Map<const Vec6> link_part(const ForwardData& d, std::size_t k, std::size_t part) {
  return Eigen::Map<const Vec6>(d.errors.data() + kLinkErrorSize * k + part);
}

/// d.errors as each link's location.
void split_link_locations(ForwardData& d) {
  const std::size_t work_links = d.work_error.size();
  for (std::size_t j = 0; j < work_links; ++j) d.work_location[j] = link_part(d, j, kMotionComponents);
  for (std::size_t j = 0; j < d.tool_error.size(); ++j) d.tool_location[j] = link_part(d, work_links + j, kMotionComponents);
}

/// d.errors as each link's error motion and location.
void split_link_errors(ForwardData& d) {
  const std::size_t work_links = d.work_error.size();
  for (std::size_t j = 0; j < work_links; ++j) d.work_error[j] = link_part(d, j, 0);
  for (std::size_t j = 0; j < d.tool_error.size(); ++j) d.tool_error[j] = link_part(d, work_links + j, 0);
  split_link_locations(d);
}

/// Error (or location) poses of the links, with their Jacobians w.r.t. (delta, epsilon)
/// when J is given; without, only the links whose errors changed since they were posed.
void set_poses(const std::vector<Vec6>& errors, std::vector<Pose>& poses, std::vector<Vec6>& posed,
               std::vector<Eigen::Matrix<double, 6, 6>>* J) {
  for (std::size_t j = 0; j < errors.size(); ++j) {
    if (!J && errors[j] == posed[j]) continue;
    posed[j] = errors[j];
    if (!J) {
      poses[j] = kinematics::error_pose(errors[j].head<3>(), errors[j].tail<3>());
      continue;
    }
    Eigen::Matrix<double, 6, 3> Jd, Je;
    poses[j] = kinematics::error_pose(errors[j].head<3>(), errors[j].tail<3>(), &Jd, &Je);
    (*J)[j] << Jd, Je;
  }
}

/// Without Jacobians: the error poses of the links `summed` sets (bit k: ForwardModel::
/// link_terms()'s link k) whose errors changed, and (with `locations`) the location poses;
/// what error_matrix() need compare. Without a mask (a chain too long for one), all.
kinematics::PoseChanges pose_summed_links(ForwardData& d, std::uint64_t summed, bool locations, bool tracked) {
  kinematics::PoseChanges changes;
  changes.locations = locations;
  const std::size_t work_links = d.work_error.size();
  auto pose = [&](std::size_t k, Vec6& error, Vec6& posed, Pose& out) {
    if (tracked && (summed >> k & 1U) == 0) return false;  // (untracked: every link)
    error = link_part(d, k, 0);
    if (error == posed) return false;
    posed = error;
    out.R = kinematics::so3_exp(error.tail<3>());  // (error_pose(), built in place)
    out.t = error.head<3>();
    return true;
  };
  // (Untracked, the changes are not passed on: no bits past the mask's are set.)
  auto bit = [&](std::size_t j) { return tracked ? std::uint64_t{1} << j : 0U; };
  for (std::size_t j = 0; j < work_links; ++j)
    if (pose(j, d.work_error[j], d.posed_work_error[j], d.actual_chain.work_error[j])) changes.work_error |= bit(j);
  for (std::size_t j = 0; j < d.tool_error.size(); ++j)
    if (pose(work_links + j, d.tool_error[j], d.posed_tool_error[j], d.actual_chain.tool_error[j]))
      changes.tool_error |= bit(j);
  if (locations) {
    split_link_locations(d);
    set_poses(d.work_location, d.actual_chain.work_location, d.posed_work_location, nullptr);
    set_poses(d.tool_location, d.actual_chain.tool_location, d.posed_tool_location, nullptr);
  }
  return changes;
}

/// Every link's error and location poses, with their Jacobians.
void pose_links_with_jacobians(ForwardData& d) {
  set_poses(d.work_error, d.actual_chain.work_error, d.posed_work_error, &d.J_work_pose);
  set_poses(d.tool_error, d.actual_chain.tool_error, d.posed_tool_error, &d.J_tool_pose);
  set_poses(d.work_location, d.actual_chain.work_location, d.posed_work_location, &d.J_work_location_pose);
  set_poses(d.tool_location, d.actual_chain.tool_location, d.posed_tool_location, &d.J_tool_location_pose);
}

/// d.J_q and (with `parameter_jacobian`) d.J_parameters, from the chain's Jacobians and the
/// terms' derivatives.
void fill_jacobians(const ForwardModel& model, ForwardData& d, bool parameter_jacobian) {
  const auto& terms = model.machine().terms;
  const auto& slots = model.slots();
  // The translation of E moves by R * rho for a right perturbation (rho, theta).
  const Eigen::Matrix3d R = d.actual_chain.E.R;
  auto position_rows = [&](const Eigen::Matrix<double, 6, Eigen::Dynamic>& J6) {
    return Eigen::Matrix<double, 3, Eigen::Dynamic>(R * J6.topRows<3>());
  };
  d.J_q = position_rows(d.actual_chain.J_q);
  if (parameter_jacobian) d.J_parameters.setZero();
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const ErrorTermSpec& t = terms[i];
    const auto& site = model.site(i);
    const bool location = t.placement == ErrorPlacement::location;
    if (location && !parameter_jacobian) continue;  // a constant: nothing for J_q
    const auto& chain = d.actual_chain;
    const Eigen::Matrix<double, 6, 6>& J_link =
        site.side == 0 ? (location ? chain.J_work_location : chain.J_work_error)[site.joint]
                       : (location ? chain.J_tool_location : chain.J_tool_error)[site.joint];
    const Eigen::Matrix<double, 6, 6>& J_pose = site.side == 0
                                                    ? (location ? d.J_work_location_pose : d.J_work_pose)[site.joint]
                                                    : (location ? d.J_tool_location_pose : d.J_tool_pose)[site.joint];
    // d actual / d (this term's value): through its component of the link's pose.
    const Eigen::Vector3d column = slots[i].sign * R * (J_link * J_pose.col(t.component)).head<3>();
    if (parameter_jacobian)
      d.J_parameters.middleCols(static_cast<Eigen::Index>(model.parameter_offset(i)), t.parameters.size()) =
          column * d.values[i].d_parameters.transpose();
    if (const int k = chain_index(t.primary); k >= 0) d.J_q.col(k) += column * d.values[i].d_primary;
    if (const int k = chain_index(t.secondary); k >= 0) d.J_q.col(k) += column * d.values[i].d_secondary;
  }
}

void set_nominal(const ForwardModel& model, ForwardData& d, const ChainQ& q) {
  kinematics::nominal_poses(model.chain(), d.nominal_chain, q);
  d.nominal = d.nominal_chain.E.t;
  d.R_nominal = d.nominal_chain.E.R;
}

}  // namespace

void forward(const ForwardModel& model, ForwardData& d, const ChainQ& q, const Conditions& c, bool jacobians,
             Evaluate which, bool parameter_jacobian) {
  if (which == Evaluate::nominal) {  // the perfect machine: no terms to evaluate
    set_nominal(model, d, q);
    return;
  }
  // Term values, summed per link component (delta x y z in mm, epsilon a b c in rad).
  // Location terms are constants: their poses change only with the parameters and the
  // conditions (or after an evaluation with Jacobians, which keeps no key).
  using kinematics::ChainJacobians;
  if (jacobians) {
    std::fill(d.errors.begin(), d.errors.end(), 0.0);
    evaluate_terms_with_derivatives(model, d, q, c, parameter_jacobian);
    split_link_errors(d);
    pose_links_with_jacobians(d);
    kinematics::error_matrix(model.chain(), d.actual_chain, q,
                             parameter_jacobian ? ChainJacobians::all : ChainJacobians::axes);
  } else {
    // Each link a bit of one mask (each side's joints of a side's): a longer chain is
    // summed and compared whole.
    const bool tracked = model.link_terms().size() <= kTrackedLinks;
    std::uint64_t summed = 0;
    const bool locations_stale = sum_term_values(model, d, q, c, tracked, summed);  // from the sums off the axes
    const kinematics::PoseChanges changes = pose_summed_links(d, summed, locations_stale, tracked);
    kinematics::error_matrix(model.chain(), d.actual_chain, q, ChainJacobians::none, tracked ? &changes : nullptr);
  }
  d.actual = d.actual_chain.E.t;
  d.R_actual = d.actual_chain.E.R;
  if (which == Evaluate::both) set_nominal(model, d, q);
  if (jacobians) fill_jacobians(model, d, parameter_jacobian);
}

void take_up_play(const ForwardModel& model, Conditions& c, const ChainQ& a, const ChainQ& b) {
  take_up_play(model, c.directions, a, b);
}

void take_up_play(const ForwardModel& model, AxisArray<double>& directions, const ChainQ& a, const ChainQ& b) {
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const double delta = b[static_cast<Eigen::Index>(i)] - a[static_cast<Eigen::Index>(i)];
    const double w = model.lost_motion()[i];
    if (w > 0) {
      directions[i] = std::clamp(directions[i] + 2.0 * delta / w, -1.0, 1.0);
    } else {
      const bool rotary = angular_at(i);
      if (std::abs(delta) > (rotary ? 1e-8 : 1e-6)) directions[i] = delta > 0 ? 1.0 : -1.0;
    }
  }
}

Eigen::Vector3d deviation(const ForwardData& d) {
  // In the table frame; turned into machine-axis directions by the table's nominal
  // orientation relative to the machine base.
  const Pose& oMtable = d.nominal_chain.oMp;
  return oMtable.R * (d.actual - d.nominal);
}

}  // namespace ccomp::model
