#pragma once
// How far a model may be trusted on the program at hand: the error the compensation is
// expected to leave there and a 95% bound on it, from the fitted parameters' covariance
// carried to the program's poses, and the stretches of the axes where the program runs
// but the data were thin (extrapolation), named. Needs the fit's information in the model
// (model/fit_information.hpp); without it the bound is unknown, and said so.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ccomp/model/fit_information.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::compensate {

struct ProgramTrust {
  bool known = false;          ///< the model carries its fit's information
  double expected_after = 0;   ///< mm: the largest error along the program the model's uncertainty leaves, on average
  double after_bound = 0;      ///< mm: 95% of the model's possible errors leave less than this anywhere on the program
  double excess = 0;           ///< mm: what the fit left beyond the noise, in both (a missing effect)
  std::uint32_t worst_line = 0;  ///< where the uncertainty is largest
  std::uint64_t points = 0;      ///< points of the program looked at
  /// Stretches of the axes the program runs in where the data were thin: "B 90-270: only
  /// sphere (48 readings) measured there", "X 300-480: beyond the measured -250..250".
  std::vector<std::string> extrapolation;
};

/// Gathers a program's poses (predict's, compensate/verify.hpp) and weighs the model's
/// uncertainty on them. The poses are kept at most kKeptPoses, spread over the program
/// (every second dropped, and then every second one taken, when full); the coverage sees every one.
class TrustGauge {
 public:
  static constexpr std::size_t kKeptPoses = 2048;
  static constexpr int kSamples = 400;  ///< draws of the parameters' error for the 95% bound

  /// `info`: the model's fit information (model::load_fit_information), none: unknown.
  TrustGauge(const model::ForwardModel& model, std::optional<model::FitInformation> info);
  void add(const model::ChainQ& q, const model::Conditions& conditions, std::uint32_t line);
  [[nodiscard]] ProgramTrust result() const;

 private:
  struct Kept {
    model::ChainQ q;
    model::Conditions conditions;
    std::uint32_t line = 0;
  };
  const model::ForwardModel& model_;
  std::optional<model::FitInformation> info_;
  std::vector<Kept> kept_;
  std::uint64_t seen_ = 0, stride_ = 1;
  std::vector<std::vector<bool>> visited_;  ///< per coverage axis, per bin
  std::vector<double> low_, high_;          ///< per coverage axis: the program's range (mm, deg)
};

/// The trust as one line of text: "expected after 0.42 um, 95% bound 1.10 um (worst at line
/// 31); extrapolation: ..." or "no fit information: bound unknown".
[[nodiscard]] std::string trust_text(const ProgramTrust& trust);

}  // namespace ccomp::compensate
