#pragma once
// What a fit knew of its own values, carried in the fitted model file (`fit_information:`,
// docs/machine-model.md) so that a program can be told how far the model may be trusted on
// it (compensate/trust.hpp): how uncertain the fitted parameters are, together (their
// covariance), what the fit left beyond the reading noise, and where the data were taken
// (how many readings of which runs in each stretch of each axis).
#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ccomp::model {

struct MachineModel;

/// One fitted parameter: the `index`-th parameter of term `term` (its place in the file's
/// `terms`), and its name ("EXX.a1") as a check that the file was not edited since.
struct FittedParameterRef {
  std::size_t term = 0;
  std::size_t index = 0;
  std::string label;
};

/// A stretch of an axis and the readings taken in it, per source (a laser line, `grid`).
struct CoverageBin {
  double from = 0.0, to = 0.0;  ///< mm or deg, as the file writes the axis
  std::vector<std::pair<std::string, std::size_t>> readings;
  std::size_t points = 0;  ///< distinct places of the linear axes (to 1 mm) read there
  [[nodiscard]] std::size_t total() const {
    std::size_t n = 0;
    for (const auto& [source, count] : readings) n += count;
    return n;
  }
};

/// Where the data lie along one chain variable (an axis, or `L` the tool length).
struct AxisCoverage {
  char axis = 'X';              ///< X Y Z A B C U V W, or 'L'
  double from = 0.0, to = 0.0;  ///< the data's range (mm, deg)
  bool rotary = false;          ///< bins over the turn: a program's angle is taken modulo 360
  std::vector<CoverageBin> bins;
};

/// A stretch of an axis is thinly measured where it holds fewer than this share of the
/// readings of its axis' fullest stretch, at fewer than kThinPoints places (two spheres
/// probed as a table turns; not a grid, not a laser line): a program running there relies
/// on extrapolation from elsewhere.
inline constexpr double kThinShare = 0.1;
inline constexpr std::size_t kThinPoints = 10;

[[nodiscard]] inline bool is_thin(const CoverageBin& bin, std::size_t fullest) {
  return static_cast<double>(bin.total()) < kThinShare * static_cast<double>(fullest) && bin.points < kThinPoints;
}

struct FitInformation {
  std::size_t observations = 0;
  double noise = 0.0;   ///< mm: the readings' noise floor the fit saw (0: unknown)
  double excess = 0.0;  ///< mm: rms of what the fit left beyond that noise (a missing effect)
  std::vector<FittedParameterRef> parameters;
  /// Rows u_k over `parameters` (internal units: mm, rad, s...): the covariance of the fitted
  /// values is the sum of u_k u_k^T (identify::FitReport::covariance_factor).
  Eigen::MatrixXd covariance_factor;
  std::vector<AxisCoverage> coverage;
};

/// The `fit_information:` of a model file's text (`model` read from the same text, whose
/// terms it names); none when the file has none. The model reader checks the section as it
/// reads the model (a bad one is refused with the model, exit 5); this gives its contents.
[[nodiscard]] std::optional<FitInformation> parse_fit_information(const std::string& text, const std::string& name,
                                                                  const MachineModel& model);
/// The same from the model's file (model.path).
[[nodiscard]] std::optional<FitInformation> load_fit_information(const MachineModel& model);

/// The model file's text with `info` as its `fit_information:` (replacing any). What
/// rewrite_parameters() (model_file.hpp) writes has none: new values make an earlier fit's
/// information stale.
[[nodiscard]] std::string with_fit_information(const std::string& text, const FitInformation& info);

}  // namespace ccomp::model
