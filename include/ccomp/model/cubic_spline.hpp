#pragma once
// The natural cubic spline through a table's values (a laser run's positioning errors):
// its second derivatives at the knots (the "moments", zero at both ends) from one
// tridiagonal solve, O(n), so a table of any length costs its evaluation a binary search
// and a few products once the moments are known. The spline is linear in the values, so
// its derivatives with respect to them (the fit's columns) are weights, also O(n).
#include <Eigen/Core>
#include <span>
#include <vector>

namespace ccomp::model {

/// The moments M_i = s''(knots[i]) of the natural spline through (knots[i], values[i]).
/// `knots` strictly increasing, at least one. `moments` is resized to knots.size().
void spline_moments(std::span<const double> knots, const double* values, std::vector<double>& moments);

/// The spline's value at v, held constant outside the knots (slope 0 there); its slope
/// into `slope` when given. `moments` from spline_moments() for the same values.
[[nodiscard]] double spline_value(std::span<const double> knots, const double* values, const double* moments,
                                  double v, double* slope = nullptr);

/// d s(v) / d values[j] into `weights` (sized knots.size()), for every j.
void spline_weights(std::span<const double> knots, double v, Eigen::Ref<Eigen::VectorXd> weights);

}  // namespace ccomp::model
