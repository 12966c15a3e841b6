#include "ccomp/identify/physical_scale.hpp"
#include "ccomp/model/term_forms.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace ccomp::identify {
namespace {

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

double term_scale(const model::ErrorTermSpec& t, std::size_t k, Reaches& reaches) {
  const double plausible = t.component < 3 ? kPlausibleTranslation : kPlausibleRotation;
  const model::ReachOf reach = [&reaches](const Variable& v, double reference) { return reaches(v, reference); };
  return model::term_form(t.shape.form).physical_scale(t, k, plausible, reach);
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
