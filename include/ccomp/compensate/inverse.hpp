#pragma once
// The inverse of the machine's error: the axis values whose actual tool tip lands on the
// point the program means. Newton's method on the exact forward model, with its analytic
// Jacobian: three position equations, plus one per rotary axis (the table's rotation about
// that axis, which the rotary axis itself can correct). The orientation the machine cannot
// correct is reported.
#include <Eigen/Core>

#include "ccomp/model/forward.hpp"

namespace ccomp::compensate {

struct InverseOptions {
  double position_tolerance = 1e-6;  ///< mm: converged below 1 nm
  double angle_tolerance = 1e-9;     ///< rad, for the rotary axes' own equations
  int max_iterations = 20;
};

struct InverseResult {
  model::ChainQ q;                 ///< the commanded axis values (mm, rad; L unchanged)
  Eigen::Vector3d position_residual = Eigen::Vector3d::Zero();  ///< actual - target, mm
  Eigen::Vector3d orientation_error = Eigen::Vector3d::Zero();  ///< rotation left, rad (table frame)
  int iterations = 0;
  bool converged = false;
};

/// The axes the solve may move: the chain's linear and rotary axes (not the tool length).
struct InverseProblem {
  explicit InverseProblem(const model::ForwardModel& model);
  std::vector<int> unknowns;          ///< chain variable indices moved by the solve
  std::vector<Eigen::Vector3d> rotary_directions;  ///< for each rotary unknown: its axis in the table frame at q=0
  std::vector<int> rotary_unknowns;   ///< their indices into q
};

/// Solves for q' with actual(q') = nominal(q_nominal). `data` is scratch. `guess`, when
/// given, is where Newton starts (a neighbouring point's solution shifted here).
[[nodiscard]] InverseResult solve_inverse(const model::ForwardModel& model, const InverseProblem& problem,
                                          model::ForwardData& data, const model::ChainQ& q_nominal,
                                          const model::Conditions& conditions, const InverseOptions& options = {},
                                          const model::ChainQ* guess = nullptr);

}  // namespace ccomp::compensate
