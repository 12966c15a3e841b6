#include "ccomp/identify/physical_scale.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace ccomp::identify {
namespace {

using model::TermForm;
using model::Variable;
using model::VariableKind;

/// The largest magnitude a variable takes in the data (from `reference` for a temperature
/// a thermal form measures from), at least 1 of its unit.
double reach(const Variable& v, const MeasurementSet& data, double reference = 0.0) {
  double most = 0.0;
  for (const Observation& o : data.observations) {
    double value = 0.0;
    switch (v.kind) {
      case VariableKind::axis:
        value = o.q[static_cast<Eigen::Index>(v.index)];
        break;
      case VariableKind::tool_length:
        value = o.q[static_cast<Eigen::Index>(model::kToolLengthIndex)];
        break;
      case VariableKind::time:
        value = o.time;
        break;
      case VariableKind::temperature:
        value = v.index < o.temperatures.size() ? o.temperatures[v.index] - reference : 0.0;
        break;
      case VariableKind::direction:
      case VariableKind::none:
        value = 1.0;
        break;
    }
    if (std::isfinite(value)) most = std::max(most, std::abs(value));
  }
  return std::max(most, 1.0);
}

/// reach() of each variable (and reference) asked for, computed once: a model has hundreds
/// of parameters over a few variables, and each reach is a pass over the data.
class Reaches {
 public:
  explicit Reaches(const MeasurementSet& data) : data_(data) {}
  double operator()(const Variable& v, double reference = 0.0) {
    const auto key = std::tuple{static_cast<int>(v.kind), v.index, reference};
    const auto it = known_.find(key);
    if (it != known_.end()) return it->second;
    return known_[key] = reach(v, data_, reference);
  }

 private:
  const MeasurementSet& data_;
  std::map<std::tuple<int, std::size_t, double>, double> known_;
};

double term_scale(const model::ErrorTermSpec& t, std::size_t k, Reaches& reach) {
  const double out = t.component < 3 ? kPlausibleTranslation : kPlausibleRotation;
  const auto& p = t.parameters;
  switch (t.shape.form) {
    case TermForm::constant:
    case TermForm::table:
      return out;
    case TermForm::reversal:  // r_k of w^k along its axis
      return k == 0 ? out : out / std::pow(reach(t.secondary), static_cast<double>(k));
    case TermForm::polynomial:
      return out / std::pow(reach(t.primary), static_cast<double>(k));
    case TermForm::periodic:
      return k == 0 ? std::abs(p[0]) : out;
    case TermForm::thermal_linear:
      return out / reach(t.primary, t.shape.reference);
    case TermForm::thermal_warmup:
      return k == 0 ? out : std::abs(p[1]);
    case TermForm::bump:  // its size; where it sits, on the axis' reach; its width
      return k == 0 ? out : k == 1 ? reach(t.primary) : std::abs(p[2]);
    case TermForm::scale_expansion:
      return out / (reach(t.primary) * reach(t.secondary, t.shape.reference));
    case TermForm::cross_axis: {
      const auto order = static_cast<std::size_t>(std::max(1, t.shape.order));
      const auto i = static_cast<double>(k / order), j = static_cast<double>(k % order + 1);
      return out / (std::pow(reach(t.primary), i) * std::pow(reach(t.secondary), j));
    }
  }
  return out;
}

}  // namespace

Eigen::VectorXd physical_scales(const model::ForwardModel& model, const MeasurementSet& data) {
  Eigen::VectorXd scales(static_cast<Eigen::Index>(model.parameter_count()));
  const auto& terms = model.machine().terms;
  Reaches reaches(data);
  for (std::size_t t = 0; t < terms.size(); ++t)
    for (Eigen::Index k = 0; k < terms[t].parameters.size(); ++k)
      scales[static_cast<Eigen::Index>(model.parameter_offset(t)) + k] =
          std::max(term_scale(terms[t], static_cast<std::size_t>(k), reaches), 1e-300);
  return scales;
}

}  // namespace ccomp::identify
