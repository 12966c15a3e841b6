// Ref 3's split of an axis' mean positional deviation (docs/error-model.md): a cumulative
// cubic, a periodic part scanned over its period, and the reversal (the report's B_mean).
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include "ccomp/identify/positioning.hpp"

namespace ccomp::identify {

void split_mean_deviation(PositioningReport& report) {
  // docs/error-model.md Ref 3: the mean deviation is cumulative (a smooth curve: a cubic here) plus periodic
  // (the pitch); the reversal is B_mean. The period is the best of a scan from 2.5 target
  // spacings to a quarter of the travel (four cycles seen, as `check` asks: fewer are a
  // cubic's wiggle, not a pitch), kept when it takes a third of what the cubic leaves.
  // The bidirectional means where the runs give them; else the one direction's.
  const bool bidirectional = report.M.has_value();
  std::vector<std::pair<double, double>> points;
  for (const PositioningTarget& t : report.targets) {
    const std::optional<double> m = bidirectional ? t.mean : t.mean_up ? t.mean_up : t.mean_down;
    if (m) points.emplace_back(t.position, *m);
  }
  report.cumulative.assign(4, 0.0);
  const auto n = static_cast<Eigen::Index>(points.size());
  if (n == 0) return;
  Eigen::VectorXd x(n), y(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = points[static_cast<std::size_t>(i)].first, y[i] = points[static_cast<std::size_t>(i)].second;
  const double centre = 0.5 * (x.maxCoeff() + x.minCoeff()), half = std::max(0.5 * (x.maxCoeff() - x.minCoeff()), 1e-9);
  auto design = [&](double period) {
    Eigen::MatrixXd D(n, period > 0 ? 6 : 4);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double u = (x[i] - centre) / half;
      D(i, 0) = 1, D(i, 1) = u, D(i, 2) = u * u, D(i, 3) = u * u * u;
      if (period > 0)
        D(i, 4) = std::cos(2 * std::numbers::pi * x[i] / period),
             D(i, 5) = std::sin(2 * std::numbers::pi * x[i] / period);
    }
    return D;
  };
  // The sum of squares left by the fit (no fit: fewer targets than coefficients, infinite).
  auto solve = [&](double period, Eigen::VectorXd& c) {
    const Eigen::MatrixXd D = design(period);
    if (n <= D.cols()) return std::numeric_limits<double>::infinity();
    c = D.colPivHouseholderQr().solve(y);
    return (y - D * c).squaredNorm();
  };
  if (n < 5) {  // too few targets for a cubic: the mean deviation is the cumulative part
    report.split_caveat = fmt::format("{} targets: too few for a cubic (4 coefficients), the cumulative part is their mean", n);
    report.cumulative[0] = y.mean();
    report.rms_left = std::sqrt((y.array() - y.mean()).square().mean());
    return;
  }
  // A cubic through 5 to 7 targets keeps 1 to 3 degrees of freedom: what it leaves is small
  // because it has nearly as many coefficients as targets, not because the axis is smooth.
  if (n < 8)
    report.split_caveat = fmt::format(
        "a cubic (4 coefficients) from {} targets leaves {} degree(s) of freedom: what it leaves proves little", n,
        n - 4);
  Eigen::VectorXd cubic, with_period;
  const double sse_cubic = solve(0.0, cubic);
  double best_sse = sse_cubic, best_period = 0.0;
  const double spacing = (x.maxCoeff() - x.minCoeff()) / std::max<double>(1.0, static_cast<double>(n - 1));
  const double from = 2.5 * spacing, to = 0.5 * half;
  if (n > 8 && to > from) {
    // Each period's fit is the cubic's plus what its cosine and sine explain of the cubic's
    // residual once the cubic's part of them is taken out: an n x 2 projection per period
    // instead of a QR of the n x 6 design (the same sum of squares; 4000 periods of 4000
    // targets took seconds).
    const Eigen::MatrixXd D0 = design(0.0);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(D0);
    const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(n, 4);
    const Eigen::VectorXd r0 = y - D0 * cubic;
    Eigen::MatrixXd C(n, 2);
    const int frequencies = static_cast<int>(std::clamp(4.0 * (2 * half) / from, 20.0, 4000.0));
    const double f0 = 1.0 / from, df = (1.0 / to - 1.0 / from) / (frequencies - 1);
    // Each target's cos and sin over the frequencies by rotation (one complex product per
    // step, not two calls to the trigonometric functions), set afresh every 64 steps.
    std::vector<std::complex<double>> phase(static_cast<std::size_t>(n)), turn(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i)
      turn[static_cast<std::size_t>(i)] = std::polar(1.0, 2 * std::numbers::pi * x[i] * df);
    Eigen::MatrixXd QtC(4, 2);
    for (int k = 0; k < frequencies; ++k) {
      const double f = f0 + df * k;
      for (Eigen::Index i = 0; i < n; ++i) {
        std::complex<double>& z = phase[static_cast<std::size_t>(i)];
        if (k % 64 == 0) {
          z = std::polar(1.0, 2 * std::numbers::pi * x[i] * f);
        } else {  // by hand: the library's product checks for infinities at every call
          const std::complex<double> w = turn[static_cast<std::size_t>(i)];
          z = {z.real() * w.real() - z.imag() * w.imag(), z.real() * w.imag() + z.imag() * w.real()};
        }
        C(i, 0) = z.real(), C(i, 1) = z.imag();
      }
      QtC.noalias() = Q.transpose() * C;
      C.noalias() -= Q * QtC;
      const Eigen::Matrix2d gram = C.transpose() * C;
      const Eigen::Vector2d b = C.transpose() * r0;
      const Eigen::LDLT<Eigen::Matrix2d> ldlt(gram);
      if (ldlt.info() != Eigen::Success || !(gram.determinant() > 1e-12 * gram.trace() * gram.trace())) continue;
      const double sse = sse_cubic - b.dot(ldlt.solve(b));
      if (sse < best_sse) best_sse = sse, best_period = 1.0 / f;
    }
  }
  if (best_period > 0 && best_sse < sse_cubic / 3.0) {
    solve(best_period, with_period);
    report.period = best_period;
    report.periodic_amplitude = std::hypot(with_period[4], with_period[5]);
    cubic = with_period.head(4);
  } else {
    best_sse = sse_cubic;
  }
  // The cubic back in units per unit^k of the position (from the centred, scaled one).
  for (int k = 0; k < 4; ++k) {
    // sum_k c_k ((x - centre) / half)^k, expanded in powers of x
    for (int j = 0; j <= k; ++j) {
      const double binomial = k == 3 ? (j == 0 || j == 3 ? 1 : 3) : k == 2 ? (j == 1 ? 2 : 1) : 1;
      report.cumulative[static_cast<std::size_t>(j)] +=
          cubic[k] * binomial * std::pow(-centre, k - j) / std::pow(half, k);
    }
  }
  report.rms_left = std::sqrt(best_sse / static_cast<double>(n));
}

}  // namespace ccomp::identify
