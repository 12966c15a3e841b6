#include "ccomp/compensate/compensator.hpp"

#include <fmt/format.h>

#include "ccomp/error.hpp"

namespace ccomp::compensate {

using model::ChainQ;

Compensator::Compensator(const model::ForwardModel& model, CompensationOptions options)
    : model_(model), options_(std::move(options)), problem_(model), data_(model), check_(model) {}

ChainQ Compensator::point(const ChainQ& nominal, MoveReport& report) {
  const bool same_conditions = options_.conditions.directions == last_directions_;
  if (same_conditions && nominal == last_nominal_) return last_solution_;
  // Start from the last solution's correction: neighbouring points correct alike.
  const ChainQ guess = nominal + (last_solution_ - (last_nominal_.allFinite() ? last_nominal_ : last_solution_));
  const InverseResult r = solve_inverse(model_, problem_, data_, nominal, options_.conditions, {},
                                        last_nominal_.allFinite() ? &guess : nullptr);
  if (!r.converged)
    throw Error(ErrorKind::safety, fmt::format("the inverse did not converge in {} iterations (residual {:.3g} mm)",
                                               r.iterations, r.position_residual.norm()));
  report.max_correction = std::max(report.max_correction, (r.q - nominal).head<3>().cwiseAbs().maxCoeff());
  report.max_orientation_error = std::max(report.max_orientation_error, r.orientation_error.norm());
  last_nominal_ = nominal;
  last_solution_ = r.q;
  last_directions_ = options_.conditions.directions;
  return r.q;
}

double Compensator::error_at(const ChainQ& nominal) {
  model::forward(model_, check_, nominal, options_.conditions);
  return (check_.actual - check_.nominal).norm();
}

double Compensator::executed_deviation(const ChainQ& a_nominal, const ChainQ& b_nominal, const ChainQ& a_comp,
                                       const ChainQ& b_comp, double t) {
  // The machine interpolates the commanded axis values linearly; the program meant the
  // nominal tool tip at the same fraction of the nominal move.
  const ChainQ executed = a_comp + t * (b_comp - a_comp);
  const ChainQ meant = a_nominal + t * (b_nominal - a_nominal);
  model::forward(model_, check_, meant, options_.conditions, false, model::Evaluate::nominal);
  const Eigen::Vector3d target = check_.nominal;
  model::forward(model_, check_, executed, options_.conditions, false, model::Evaluate::actual);
  return (check_.actual - target).norm();
}

void Compensator::split(const ChainQ& a_nominal, const ChainQ& b_nominal, const ChainQ& a_comp, const ChainQ& b_comp,
                        double s0, double s1, int depth, double tolerance, std::vector<CompensatedPoint>& out,
                        MoveReport& report) {
  // At the quarters, or densely enough not to step over a short periodic error.
  double worst = 0.0;
  const int n = model_.check_points(a_nominal, b_nominal, 3, 64);
  for (int k = 1; k <= n; ++k)
    worst = std::max(worst, executed_deviation(a_nominal, b_nominal, a_comp, b_comp, static_cast<double>(k) / (n + 1)));
  if (worst <= tolerance || depth >= options_.max_depth) {
    report.max_deviation_after = std::max(report.max_deviation_after, worst);
    out.push_back({s1, b_comp});
    return;
  }
  const ChainQ m_nominal = 0.5 * (a_nominal + b_nominal);
  const ChainQ m_comp = point(m_nominal, report);
  const double sm = 0.5 * (s0 + s1);
  split(a_nominal, m_nominal, a_comp, m_comp, s0, sm, depth + 1, tolerance, out, report);
  split(m_nominal, b_nominal, m_comp, b_comp, sm, s1, depth + 1, tolerance, out, report);
}

void Compensator::straight(const ChainQ& start, const ChainQ& end, std::vector<CompensatedPoint>& out,
                           MoveReport& report, double tolerance) {
  out.clear();
  if (tolerance <= 0) tolerance = options_.tolerance;
  for (double t : {0.0, 0.5, 1.0}) report.max_deviation_before = std::max(report.max_deviation_before, error_at(start + t * (end - start)));
  const ChainQ a = point(start, report);
  const ChainQ b = point(end, report);
  split(start, end, a, b, 0.0, 1.0, 0, tolerance, out, report);
}

}  // namespace ccomp::compensate
