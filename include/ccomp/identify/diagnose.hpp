#pragma once
// Diagnosis: which physical effect the model lacks. A library of candidate effects (a
// screw's periodic error, an axis' reversal, a squareness, a tilt growing with the tool
// length, a table's harmonics or worm wheel, a drift with a temperature or with time, a
// scale growing with heat, an error motion depending on another axis' position), each a
// term with a sentence of physics. Each is tried against the residual of the model refitted
// to the data (its free parameters and the candidate together, by projection), scored by
// the fall in the residual, the Bayesian information criterion and its significance
// against the noise floor, and ranked; only the significant are suggested.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ccomp/identify/fit.hpp"
#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/util/parallel.hpp"

namespace ccomp::identify {

struct Suggestion {
  int rank = 0;
  std::string effect;    ///< the physics, in words
  std::string error;     ///< ISO 230-1 name of the term, or "thermal"
  std::string term;      ///< the ISO name of the term added (also for thermal ones)
  std::string variable;  ///< "x", "b", "L", "t", "T_bed", "vx", "x,z"
  std::string form;      ///< polynomial, periodic, reversal, linear, exponential, harmonic, interaction
  double period = 0.0;   ///< periodic forms: in the variable's unit (mm, deg); warm-up: the time constant (s)
  double period_uncertainty = 0.0;
  double rms_before = 0.0, rms_after = 0.0;  ///< mm: the model refitted without, and with, the effect
  double bic_delta = 0.0;                    ///< negative: the effect is worth its parameters
  double significance = 0.0;                 ///< fall in chi-square against the noise floor
  /// Cross-validated: the fall in the sum of squares on readings each fit left out, as a
  /// share of the fall where it was fitted (1: it predicts what it was not fitted to as
  /// well as what it was). Only effects that predict beyond the noise are suggested.
  double held_out = 0.0;
  std::string held_out_by;  ///< "source" (a laser line, the grid left out in turn) or "block" (of one run's readings)
  /// The rms after comes from fitting the model with the spec (as `fit --add` does), not
  /// only from the linear projection (where the model has many free parameters for the data).
  bool refitted = false;
  /// Periodic forms whose readings are evenly spaced along the variable: the periods (in
  /// its unit) those readings cannot tell from `period`, and the sentence saying so with the
  /// run that settles it. Empty where the targets are irregular (ISO 230-2) or none alias.
  std::vector<double> aliases;
  std::string aliasing;
  std::string yaml;  ///< the term to add, with the values the data suggest
  std::string spec;  ///< the same, one line, for `ccomp fit --add`
  /// mm, per reading: the refitted residual with the effect added (the linear fit of the
  /// base's free parameters and the effect together; its rms is rms_after).
  Eigen::VectorXd residual;
};

struct Region {
  std::string variable;  ///< where the residual concentrates: "x", "b", "T_bed"...
  double from = 0.0, to = 0.0;
  double rms = 0.0;    ///< mm, of the residual there
  double ratio = 0.0;  ///< against the rms everywhere, or the median of the variable's bins where higher
};

/// Two suggestions the data cannot tell apart, and the measurement that would.
struct Tie {
  std::size_t first = 0, second = 0;  ///< into Diagnosis::suggestions
  double correlation = 0.0;           ///< of what each explains of the residual, on these data
  std::string measurement;            ///< in words: what to measure to separate them, and why
};

/// The readings fit the model better with their program zero moved: read with the wrong
/// work offset (a file's `# frame:` line, --work-offset, the model's work_offsets).
struct OriginMisfit {
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();  ///< mm: where program zero seems to be, less where it was taken
  double rms_before = 0.0, rms_after = 0.0;         ///< mm: the refit without, and with, the shift
  double bic_delta = 0.0;
  double significance = 0.0;  ///< fall in chi-square against the noise floor, less the shift's 3 parameters
};

struct DiagnoseOptions {
  double noise = 0.0;  ///< mm: the noise floor (check's estimate); 0 estimates it
  int max_suggestions = 5;
  /// Threads scoring the candidates (results do not depend on it).
  int threads = util::hardware_threads();
  /// How the model as it is gets refitted before the candidates are tried (--robust: the
  /// Huber loss, so that spikes do not pull the base the candidates are scored against).
  FitOptions fit;
  /// Called as the work goes on with its share done, 0 to 1 (from any scoring thread).
  std::function<void(double)> progress;
};

struct Diagnosis {
  double noise = 0.0;                   ///< mm
  double rms_refit = 0.0;               ///< mm: the model refitted to the data, without any new effect
  FitReport refit;                      ///< that refit: its parameters and identifiability
  Eigen::VectorXd residual;             ///< mm, per reading: the refitted model's (what the suggestions start from)
  std::vector<Suggestion> suggestions;  ///< best first, significant only
  std::vector<Region> regions;
  /// Set where moving the readings' program zero explains the residual, significantly and
  /// by more than kSmallestOriginShift (diagnose.cpp): said before any missing effect.
  std::optional<OriginMisfit> origin_misfit;
  /// The first suggestion and those the data cannot tell from it (next_measurement.hpp).
  std::vector<Tie> ties;
  std::size_t candidates_tried = 0;
  /// Significant where fitted but not predicting readings left out: not suggested.
  std::size_t unproven = 0;
  /// Significant, but only with values beyond 100 physical scales: not suggested.
  std::size_t implausible = 0;
  /// When the residual holds more than the noise and no candidate explains it: what is
  /// seen, in words ("unexplained structure along x and z, rms 0.41 um against a noise
  /// floor of 0.20 um, largest at x 100..150"). Empty otherwise.
  std::string unexplained;
  std::string skipped;  ///< why there was no refit and no diagnosis (too few readings); empty otherwise
};

[[nodiscard]] Diagnosis diagnose(const model::ForwardModel& model, const MeasurementSet& data,
                                 const DiagnoseOptions& options = {});

/// A suggestion's scanned value in words, with its unit: "period 9.99973 +- 0.0002 mm", "time
/// constant 2400 +- 52 s", "at 125.3 +- 0.41 mm" (a local defect's place); a harmonic's
/// fixed period without an uncertainty. Empty where it has none.
[[nodiscard]] std::string scanned_value_text(const Suggestion& s);

}  // namespace ccomp::identify
