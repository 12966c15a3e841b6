#include "ccomp/model/cubic_spline.hpp"

#include <algorithm>

namespace ccomp::model {
namespace {

/// The knot interval holding v (clamped to the table): its index and the weights
/// a = (x1 - v) / h, b = (v - x0) / h.
struct Interval {
  std::size_t k = 0;
  double h = 0.0, a = 1.0, b = 0.0;
  bool inside = true;  ///< v within the knots (else the spline is held constant)
};

Interval interval_of(std::span<const double> x, double v) {
  Interval in;
  const double vc = std::clamp(v, x.front(), x.back());
  in.inside = vc == v;
  const auto upper = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), vc) - x.begin());
  in.k = std::min(upper == 0 ? 0 : upper - 1, x.size() - 2);
  in.h = x[in.k + 1] - x[in.k];
  in.a = (x[in.k + 1] - vc) / in.h;
  in.b = (vc - x[in.k]) / in.h;
  return in;
}

/// Solves the moment equations T m = r of the interior knots 1..n-2 in place (r[0] and
/// r[n-1] are ignored and set to 0: the natural ends). T is symmetric tridiagonal:
/// (h[i-1] + h[i]) / 3 on the diagonal, h[i] / 6 beside it; diagonally dominant, so the
/// elimination needs no pivoting. `scratch` holds n values.
void solve_moment_system(std::span<const double> x, double* r, std::vector<double>& scratch) {
  const std::size_t n = x.size();
  r[0] = 0.0;
  r[n - 1] = 0.0;
  if (n < 3) return;
  scratch.resize(n);
  double* upper = scratch.data();  // the eliminated rows' super-diagonal
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
    const double sub = i > 1 ? h0 / 6.0 : 0.0;
    const double pivot = (h0 + h1) / 3.0 - sub * (i > 1 ? upper[i - 1] : 0.0);
    upper[i] = h1 / 6.0 / pivot;
    r[i] = (r[i] - sub * (i > 1 ? r[i - 1] : 0.0)) / pivot;
  }
  for (std::size_t i = n - 2; i-- > 1;) r[i] -= upper[i] * r[i + 1];
}

/// w += D^T z over the knots, D the second-difference operator of the moment equations'
/// right side, (D y)_i = (y[i+1] - y[i]) / h[i] - (y[i] - y[i-1]) / h[i-1] for the
/// interior knots (z is zero at both ends).
void add_difference_transpose(std::span<const double> x, const std::vector<double>& z, Eigen::Ref<Eigen::VectorXd> w) {
  for (std::size_t i = 1; i + 1 < x.size(); ++i) {
    const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
    const auto e = static_cast<Eigen::Index>(i);
    w[e - 1] += z[i] / h0;
    w[e] -= z[i] * (1.0 / h0 + 1.0 / h1);
    w[e + 1] += z[i] / h1;
  }
}

}  // namespace

void spline_moments(std::span<const double> x, const double* y, std::vector<double>& moments) {
  const std::size_t n = x.size();
  moments.assign(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i)
    moments[i] = (y[i + 1] - y[i]) / (x[i + 1] - x[i]) - (y[i] - y[i - 1]) / (x[i] - x[i - 1]);
  std::vector<double> scratch;
  solve_moment_system(x, moments.data(), scratch);
}

double spline_value(std::span<const double> x, const double* y, const double* m, double v, double* slope) {
  if (x.size() == 1) {
    if (slope) *slope = 0.0;
    return y[0];
  }
  const Interval in = interval_of(x, v);
  const std::size_t k = in.k;
  const double a = in.a, b = in.b, h = in.h;
  // s = a y_k + b y_k+1 + ((a^3 - a) M_k + (b^3 - b) M_k+1) h^2 / 6
  if (slope)
    *slope = in.inside ? (y[k + 1] - y[k]) / h + ((1.0 - 3.0 * a * a) * m[k] + (3.0 * b * b - 1.0) * m[k + 1]) * h / 6.0
                       : 0.0;
  return a * y[k] + b * y[k + 1] + ((a * a * a - a) * m[k] + (b * b * b - b) * m[k + 1]) * h * h / 6.0;
}

void spline_weights(std::span<const double> x, double v, Eigen::Ref<Eigen::VectorXd> w) {
  const std::size_t n = x.size();
  w.setZero();
  if (n == 1) {
    w[0] = 1.0;
    return;
  }
  const Interval in = interval_of(x, v);
  const auto k = static_cast<Eigen::Index>(in.k);
  const double a = in.a, b = in.b, h = in.h;
  // s = a y_k + b y_k+1 + c^T M with M = T^-1 D y and c_k = (a^3 - a) h^2 / 6,
  // c_k+1 = (b^3 - b) h^2 / 6; T is symmetric, so d s / d y = a e_k + b e_k+1 + D^T T^-1 c.
  w[k] += a;
  w[k + 1] += b;
  std::vector<double> z(n, 0.0), scratch;
  z[in.k] = (a * a * a - a) * h * h / 6.0;
  z[in.k + 1] = (b * b * b - b) * h * h / 6.0;
  solve_moment_system(x, z.data(), scratch);
  add_difference_transpose(x, z, w);
}

}  // namespace ccomp::model
