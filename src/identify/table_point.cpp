#include "table_point.hpp"

#include <Eigen/QR>
#include <string_view>

#include "ccomp/constants.hpp"

namespace ccomp::identify {

void reach_table_point(const model::ForwardModel& model, model::ForwardData& d, model::ChainQ& q,
                       const Eigen::Vector3d& target, const model::Conditions& conditions) {
  for (int iteration = 0; iteration < 2; ++iteration) {
    model::forward(model, d, q, conditions, false, model::Evaluate::nominal);
    const Eigen::Vector3d at = d.nominal;
    Eigen::Matrix3d J;
    for (int k = 0; k < 3; ++k) {
      model::ChainQ moved = q;
      moved[k] += 1.0;
      model::forward(model, d, moved, conditions, false, model::Evaluate::nominal);
      J.col(k) = d.nominal - at;
    }
    q.head<3>() += J.colPivHouseholderQr().solve(target - at);
  }
}

bool within_limits(const model::MachineModel& m, const model::ChainQ& q) {
  for (const model::AxisSpec& a : m.axes) {
    const auto j = static_cast<Eigen::Index>(a.index());
    const double v = a.type == model::AxisType::rotary ? q[j] / kRadPerDeg : q[j];
    if (v < a.min - 1e-9 || v > a.max + 1e-9) return false;
  }
  return true;
}

}  // namespace ccomp::identify
