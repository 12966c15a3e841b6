#include "ccomp/identify/nine_line.hpp"

#include <Eigen/Core>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>

#include "ccomp/identify/simulate.hpp"
#include "symmetric_eigen.hpp"

namespace ccomp::identify {
namespace {

/// The sensitivity of the fitted parameters to misplaced lines: for each line and each
/// direction across it, the change of the least-squares solution (within what the data
/// determine) when the line's readings really were taken 1 mm off.
struct Sensitivity {
  Eigen::MatrixXd per_line;  // (free parameters) x (lines x 2 directions), internal units per mm
  Eigen::VectorXd scale;     // column norms of the design: a parameter's effect on the readings
  std::vector<std::string> labels;
  std::vector<bool> identified;
};

Sensitivity sensitivity(const model::ForwardModel& model, const Eigen::VectorXd& parameters,
                        const MeasurementSet& data) {
  const std::vector<std::size_t> free = free_parameters(model);
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  design_matrix(model, parameters, data, free, r, &J);
  const auto m = J.cols();
  Sensitivity out;
  out.scale.resize(m);
  for (Eigen::Index j = 0; j < m; ++j) out.scale[j] = std::max(J.col(j).norm(), 1e-300);
  const Eigen::MatrixXd A = J * out.scale.cwiseInverse().asDiagonal();
  const SymmetricEigen eig = symmetric_eigen(normal_matrix(A));
  const double largest = eig.values.maxCoeff();
  Eigen::MatrixXd pinv = Eigen::MatrixXd::Zero(m, m);  // (A^T A)^+ on the identified directions
  Eigen::VectorXd unseen = Eigen::VectorXd::Zero(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::VectorXd v = eig.vectors.col(k);
    if (eig.values[k] > 1e-8 * largest)
      pinv += v * v.transpose() / eig.values[k];
    else
      unseen += v.cwiseProduct(v);
  }
  for (Eigen::Index j = 0; j < m; ++j) out.identified.push_back(unseen[j] <= 1e-4);
  // The predictions with every reading shifted 1 mm across its line.
  std::vector<std::vector<Eigen::Index>> rows(data.sources.size());
  for (std::size_t i = 0; i < data.observations.size(); ++i)
    rows[data.observations[i].source].push_back(static_cast<Eigen::Index>(i));
  out.per_line = Eigen::MatrixXd::Zero(m, static_cast<Eigen::Index>(2 * data.sources.size()));
  model::ForwardData d(model);
  d.set_parameters(parameters);
  for (std::size_t s = 0; s < data.sources.size(); ++s) {
    const std::string& name = data.sources[s];
    const auto axis = name.empty() ? std::string::npos : std::string_view("xyz").find(name[0]);
    if (axis == std::string::npos) continue;
    for (int side = 0; side < 2; ++side) {
      const auto across = static_cast<Eigen::Index>((axis + 1 + static_cast<std::size_t>(side)) % 3);
      Eigen::VectorXd shift = Eigen::VectorXd::Zero(A.rows());
      for (Eigen::Index i : rows[s]) {
        Observation o = data.observations[static_cast<std::size_t>(i)];
        const double at = predict(model, d, o);
        o.q[across] += 1.0;
        shift[i] = predict(model, d, o) - at;
      }
      out.per_line.col(static_cast<Eigen::Index>(2 * s) + side) =
          (pinv * (A.transpose() * shift)).cwiseQuotient(out.scale);
    }
  }
  const model::MachineModel& mm = model.machine();
  for (std::size_t index : free) {
    std::size_t t = 0;
    while (t + 1 < mm.terms.size() && model.parameter_offset(t + 1) <= index) ++t;
    out.labels.push_back(parameter_label(mm.terms[t], index - model.parameter_offset(t)));
  }
  return out;
}

/// One number for a placement: the root-sum-square, over lines and parameters, of each
/// parameter's change times its effect on the readings (so every unit weighs alike).
double overall(const Sensitivity& s) {
  double sum = 0;
  for (Eigen::Index j = 0; j < s.per_line.rows(); ++j)
    if (s.identified[static_cast<std::size_t>(j)]) sum += (s.per_line.row(j) * s.scale[j]).squaredNorm();
  return std::sqrt(sum);
}

/// The squareness of the nine-line method (docs/error-model.md Ref 4): the angle between the axes' lines as the model with
/// `p` draws them through the middle of the measured workspace (each line's least-squares slope over the measured
/// travel, in the two directions across it). With X's line along (1, a_xy, a_xz), Y's along (a_yx, 1, a_yz) and Z's
/// along (a_zx, a_zy, 1), the angles' cosines give EC0X = a_xy + a_yx, EB0X = -(a_xz + a_zx), EA0Y = a_yz + a_zy:
/// turning the whole machine rigidly changes none of them.
std::vector<LineSquareness> line_squareness(const model::ForwardModel& model, const Eigen::VectorXd& p,
                                            const MeasurementSet& data) {
  const model::MachineModel& mm = model.machine();
  if (!mm.axis('X') || !mm.axis('Y') || !mm.axis('Z') || data.observations.empty()) return {};
  model::ChainQ low = data.observations.front().q, high = low;
  for (const Observation& o : data.observations) low = low.cwiseMin(o.q), high = high.cwiseMax(o.q);
  const model::ChainQ middle = 0.5 * (low + high);
  model::ForwardData d(model);
  d.set_parameters(p);
  Eigen::Matrix3d slope = Eigen::Matrix3d::Zero();  // slope(i, j): deviation j per mm along axis i
  for (Eigen::Index axis = 0; axis < 3; ++axis) {
    if (!(high[axis] > low[axis])) continue;
    const int points = 41;
    Eigen::MatrixXd A(points, 2);
    Eigen::MatrixXd deviations(points, 3);
    for (int k = 0; k < points; ++k) {
      model::ChainQ q = middle;
      q[axis] = low[axis] + (high[axis] - low[axis]) * k / (points - 1);
      model::forward(model, d, q, model::Conditions{.temperatures = std::vector<double>(mm.sensors.size(), 20.0)});
      A(k, 0) = 1.0, A(k, 1) = q[axis];
      deviations.row(k) = model::deviation(d).transpose();
    }
    const Eigen::MatrixXd line = A.colPivHouseholderQr().solve(deviations);  // 2 x 3: offset, slope
    slope.row(axis) = line.row(1);
  }
  return {
      {"EC0X", "S_xy", slope(0, 1) + slope(1, 0), -1.0},
      {"EB0X", "S_xz", -(slope(0, 2) + slope(2, 0)), 1.0},
      {"EA0Y", "S_yz", slope(1, 2) + slope(2, 1), -1.0},
  };
}

}  // namespace

NineLineReport nine_line(const model::ForwardModel& model, const MeasurementSet& data) {
  NineLineReport report;
  report.fit = fit(model, data);
  report.squareness = line_squareness(model, report.fit.all_parameters, data);
  const Sensitivity s = sensitivity(model, report.fit.all_parameters, data);
  for (Eigen::Index j = 0; j < s.per_line.rows(); ++j) {
    if (!s.identified[static_cast<std::size_t>(j)]) continue;
    Eigen::Index worst = 0;
    const double per_mm = s.per_line.row(j).cwiseAbs().maxCoeff(&worst);
    const std::size_t source = static_cast<std::size_t>(worst / 2);
    const char* across[3][2] = {{"y", "z"}, {"z", "x"}, {"x", "y"}};
    const auto axis = std::string_view("xyz").find(data.sources[source].empty() ? ' ' : data.sources[source][0]);
    report.sensitivity.push_back(
        {s.labels[static_cast<std::size_t>(j)], per_mm,
         data.sources[source] + (axis < 3 ? std::string(" along ") + across[axis][worst % 2] : "")});
  }
  std::sort(report.sensitivity.begin(), report.sensitivity.end(),
            [&](const PlacementSensitivity& a, const PlacementSensitivity& b) { return a.per_mm > b.per_mm; });
  // The placement study: the fitted model measured with lines 1 and 3 at other places.
  model::MachineModel fitted = model.machine();
  for (std::size_t t = 0; t < fitted.terms.size(); ++t)
    fitted.terms[t].parameters = report.fit.all_parameters.segment(static_cast<Eigen::Index>(model.parameter_offset(t)),
                                                                   fitted.terms[t].parameters.size());
  const model::ForwardModel f(fitted);
  double best = std::numeric_limits<double>::infinity();
  for (double inset : {0.02, 0.05, 0.1, 0.2, 0.3, 0.4}) {
    SimulateOptions o;
    o.plans = {Plan::nine_lines};
    o.noise = 0.0;
    o.line_inset = inset;
    const double value = overall(sensitivity(f, report.fit.all_parameters, simulate(f, o)));
    report.placements.emplace_back(inset, value);
    if (value < best) best = value, report.recommended_inset = inset;
  }
  return report;
}

}  // namespace ccomp::identify
