#pragma once
// Candidates with a scanned parameter (a period, a time constant, a local defect's place):
// one scanner per spacing of the scan gives the values and a coarse pass over them, then
// the best value is refined and weighed exactly alike for all. A new spacing is one
// scanner: its values and its coarse pass, one row of the table in scanners.cpp.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "candidates.hpp"
#include "ccomp/identify/measurements.hpp"
#include "projector.hpp"

namespace ccomp::identify::detail {

/// A candidate is suggested when the chi-square falls by this much (five sigma) beyond
/// what noise and its scan would give.
inline constexpr double kSignificance = 25.0;

/// What a scan reads: the base, the probes with their rows, the data, the noise variance.
struct ScanContext {
  const Projector& base;
  const std::vector<Probe>& probes;
  const MeasurementSet& data;
  double sigma2 = 0.0;
};

/// A scanned candidate at its best value: the gain there (mm^2, the fall in the sum of
/// squares), its coefficients, the value's uncertainty (a chi-square rise of 1), and how
/// many values were tried (the look-elsewhere effect).
struct ScanOutcome {
  double value = 0.0;
  double gain = 0.0;
  Eigen::VectorXd coefficients;
  double uncertainty = 0.0;
  double trials = 1.0;
};

/// The candidate scanned, or nothing where its probe has no rows or it could not pass the
/// significance test even at twice its best coarse gain (such a one is not refined).
[[nodiscard]] std::optional<ScanOutcome> scan(const Candidate& c, const ScanContext& context);

}  // namespace ccomp::identify::detail
