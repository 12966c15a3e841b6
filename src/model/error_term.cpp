#include "ccomp/model/error_term.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ccomp/model/term_forms.hpp"

namespace ccomp::model {

double periodic_value(const double* p, int harmonics, double v, TermValue& cache) {
  PeriodicPhase phase;
  periodic_phase(p[0], v, cache, phase);
  return periodic_sum(p, harmonics, phase);
}

std::size_t parameter_count(const TermShape& s) { return term_form(s.form).parameter_count(s); }

TermValue evaluate(const TermShape& s, const Eigen::VectorXd& p, const TermInputs& in, bool grad) {
  TermValue r;
  evaluate(s, p, in, grad, r);
  return r;
}

void evaluate(const TermShape& s, const Eigen::Ref<const Eigen::VectorXd>& p, const TermInputs& in, bool grad,
              TermValue& r) {
  r.value = r.d_primary = r.d_secondary = 0.0;
  if (grad) {
    r.d_parameters.resize(static_cast<Eigen::Index>(parameter_count(s)));
    r.d_parameters.setZero();
  }
  term_form(s.form).evaluate(s, p, in, grad, r);
}

}  // namespace ccomp::model
