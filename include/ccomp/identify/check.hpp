#pragma once
// The model as it is against measurements: residuals overall and per source, and the
// noise floor the residuals cannot go below.
#include <string>
#include <vector>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify {

struct SourceResidual {
  std::string source;
  std::size_t observations = 0;
  double rms = 0.0, max = 0.0;  ///< mm
};

struct CheckReport {
  std::size_t observations = 0;
  double rms = 0.0, max = 0.0;  ///< mm
  std::uint32_t worst_row = 0;
  std::string worst_file;
  std::vector<SourceResidual> sources;
  /// mm: the reading noise. From repeated points (same position, approach and conditions)
  /// where there are any; otherwise from second differences of the residuals at evenly
  /// spaced points along lines, which a smooth model error nearly cancels and noise does not.
  double noise_floor = 0.0;
  std::string noise_method;  ///< "repeated points" or "second differences along lines"
  Eigen::VectorXd residual;  ///< mm, per reading: measured - predicted by the model as it is
};

/// The reading noise of `data` from the residuals of a model (mm): from repeated points
/// where there are any, else from second differences along evenly spaced lines. 0 and a
/// method that says so when the data have neither.
struct NoiseFloor {
  double value = 0.0;
  std::string method;
};
[[nodiscard]] NoiseFloor noise_floor(const MeasurementSet& data, const Eigen::VectorXd& residual);

[[nodiscard]] CheckReport check(const model::ForwardModel& model, const MeasurementSet& data);

}  // namespace ccomp::identify
