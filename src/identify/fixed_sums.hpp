#pragma once
// What scoring the candidates without a scan needs of the readings, summed a block of rows at
// a time: the n x F matrix of all their columns is never formed (it was much of check's
// memory on a large file: bench/check-memory.sh).
#include <Eigen/Core>
#include <vector>

#include "candidates.hpp"
#include "ccomp/identify/measurements.hpp"

namespace ccomp::identify::detail {

struct FixedSums {
  Eigen::MatrixXd AtC;               ///< m x F: the base's columns against the candidates'
  Eigen::VectorXd Ctr;               ///< F: the candidates' columns against the residual
  std::vector<Eigen::MatrixXd> CtC;  ///< per candidate, its columns' Gram matrix (empty without fixed columns)
};

/// `column[i]`: candidate i's first column among the F (-1: scanned, or no rows). `A` the
/// base's columns (n x m), `r` the residual. The sums are taken over eight fixed row chunks
/// added in order: the same on any machine, whatever its core count.
[[nodiscard]] FixedSums fixed_sums(const std::vector<Candidate>& candidates, const std::vector<Probe>& probes,
                                   const std::vector<Eigen::Index>& column, Eigen::Index F, const MeasurementSet& data,
                                   const Eigen::MatrixXd& A, const Eigen::VectorXd& r, int threads);

}  // namespace ccomp::identify::detail
