#include "origin_shift.hpp"

namespace ccomp::identify::detail {

Eigen::MatrixXd origin_shift_columns(const model::ForwardModel& model, const Eigen::VectorXd& parameters,
                                     const MeasurementSet& data) {
  // 50 um: far below any error feature (a screw's pitch, a bump's width), far above the
  // rounding of micrometre predictions.
  constexpr double kStep = 0.05;
  const auto n = static_cast<Eigen::Index>(data.observations.size());
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, 3);
  model::ForwardData d(model);
  d.set_parameters(parameters);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Observation& o = data.observations[static_cast<std::size_t>(i)];
    if (o.file < data.frames.size() && data.frames[o.file].frame.kind == FrameKind::machine) continue;
    for (Eigen::Index axis = 0; axis < 3; ++axis) {
      Observation moved = o;
      moved.q[axis] = o.q[axis] + kStep;
      const double up = predict(model, d, moved);
      moved.q[axis] = o.q[axis] - kStep;
      const double down = predict(model, d, moved);
      C(i, axis) = (up - down) / (2.0 * kStep);
    }
  }
  return C;
}

}  // namespace ccomp::identify::detail
