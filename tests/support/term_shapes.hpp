#pragma once
// Test support: term shapes of every form, for the term tests and the Jacobian suite.
#include <initializer_list>

#include "ccomp/model/error_term.hpp"

namespace ccomp::test {

using model::Interpolation;
using model::TermForm;
using model::TermShape;

inline Eigen::VectorXd vec(std::initializer_list<double> v) {
  Eigen::VectorXd x(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double d : v) x[i++] = d;
  return x;
}

inline TermShape shape(TermForm form, int order = 1) {
  TermShape s;
  s.form = form;
  s.order = order;
  return s;
}

inline TermShape table(Interpolation interpolation) {
  TermShape s;
  s.form = TermForm::table;
  s.interpolation = interpolation;
  s.knots = {-200, -100, 0, 50, 150, 300};
  return s;
}

inline TermShape cross() {
  TermShape s;
  s.form = TermForm::cross_axis;
  s.order = 2;
  s.order_primary = 1;
  return s;
}

/// A reversal varying along its axis (a worn screw): quadratic in the position.
inline TermShape reversal_along() {
  TermShape s;
  s.form = TermForm::reversal;
  s.order_primary = 2;
  return s;
}

/// A cross-axis term beyond linear in the other axis (a table sagging with x^2).
inline TermShape cross_quadratic() {
  TermShape s;
  s.form = TermForm::cross_axis;
  s.order = 2;
  s.order_primary = 2;
  return s;
}

}  // namespace ccomp::test
