#pragma once
// Identification: the free parameters of a model's terms from measurements, by weighted
// least squares on the forward model's exact parameter Jacobians (Gauss-Newton, so a
// period or a time constant is fitted too). What the data cannot determine is found from
// the singular values of the column-scaled design matrix and left at its prior value
// (truncated SVD), never fitted to noise; the report says which parameters, or which
// combinations of them, those are.
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify {

enum class Loss : std::uint8_t { least_squares, huber };

struct FitOptions {
  /// Weight of the observations of a source (by label); others weigh 1.
  std::vector<std::pair<std::string, double>> source_weights;
  Loss loss = Loss::least_squares;  ///< huber: rows beyond 1.345 robust sigmas count linearly
  int max_iterations = 30;
  /// A combination of parameters is determined when moving it by one physical scale
  /// (physical_scale.hpp) changes the predictions by more than 1 noise sigma (a parameter
  /// whose own effect is below 3 sigmas is held first; the change found along a determined
  /// combination is kept where it is beyond 3 sigmas); and, whatever
  /// the noise, when its singular value (columns in physical scales) is above this fraction
  /// of the largest (numerically zero below).
  double rank_tolerance = 1e-9;
  /// Called after each iteration with the share of the iterations allowed used (1 at the end).
  std::function<void(double)> progress;
};

struct FittedParameter {
  std::size_t index = 0;  ///< into the model's parameter vector
  std::size_t term = 0;
  std::string label;  ///< "EXX.a1", "EBB.period"
  double before = 0.0, after = 0.0;
  double uncertainty = 0.0;  ///< one standard deviation (internal units), 0 when not identified
  bool identified = true;
};

struct FitReport {
  std::vector<FittedParameter> parameters;  ///< the free ones
  Eigen::VectorXd all_parameters;           ///< the model's whole parameter vector after the fit
  Eigen::VectorXd singular_values;          ///< of the column-scaled weighted design matrix, descending
  double condition_number = 0.0;            ///< of the identified part
  std::size_t rank = 0;                     ///< combinations the data can determine
  std::size_t significant = 0;              ///< of those, how many moved by more than the noise (the rest stayed)
  std::vector<std::string> unidentifiable;  ///< in words, one per combination the data cannot determine
  double rms_before = 0.0, rms_after = 0.0, max_after = 0.0;  ///< mm
  double noise = 0.0;  ///< mm: the reading noise the data show (check's noise floor), 0 unknown
  /// Readings the fitted model leaves more than 5 robust sigmas off, where they are few
  /// (under 1% of the rows: spikes, a laser beam cut, not a missing effect), worst first.
  struct Outlier {
    std::uint32_t file = 0, row = 0;
    double residual = 0.0;  ///< mm
  };
  std::vector<Outlier> outliers;
  /// Why the fitted values must not be written: a change beyond 100 physical scales, a model
  /// that predicts more than its max_correction. Empty: the fit may be used.
  std::vector<std::string> refusals;
  std::vector<double> source_rms_before, source_rms_after;  ///< mm, per source
  int iterations = 0;
  bool converged = false;
  std::size_t observations = 0;
  /// How far each free parameter may be from the truth, as rows u_k (one per direction of the
  /// column-scaled design matrix, internal units, free parameters in `parameters` order) whose
  /// sum of outer products is the covariance: a direction the data determine with its least-
  /// squares variance (s^2 / sigma_k^2), one the fit left as it was with one physical scale
  /// (what it plausibly is on a machine: the data did not narrow it). What `predict` carries
  /// to a program's poses (model/fit_information.hpp).
  Eigen::MatrixXd covariance_factor;
};

/// Residuals (measured - predicted, mm) and the design matrix (d prediction / d free
/// parameter, one column per free parameter in free_parameters() order) at some parameters.
struct Linearization {
  Eigen::VectorXd residuals;
  Eigen::MatrixXd jacobian;
};

/// Fits the free parameters of `model` to `data`. `at_fit`, when given, receives the
/// residuals and the design matrix at the fitted parameters (the fit has them: a caller
/// saves a pass over the data).
[[nodiscard]] FitReport fit(const model::ForwardModel& model, const MeasurementSet& data,
                            const FitOptions& options = {}, Linearization* at_fit = nullptr);

/// "nothing identifiable above the noise floor: ..." when the fit had free parameters and
/// the data determine none of their combinations (a short stroke, few targets, one run
/// each way, one direction: no direction moves the predictions by more than 3 noise
/// sigmas); empty otherwise. A result, not a failure: `fit` refuses to write a model on it
/// (it is among the report's refusals), `check` reports it.
[[nodiscard]] std::string nothing_identifiable(const FitReport& report);

/// The model a fit works on: its free terms without the spans an earlier fit gave them (a
/// term held beyond its old span could not follow new data there; the new data say where
/// it holds).
[[nodiscard]] model::MachineModel without_free_spans(model::MachineModel machine);

/// Each fitted term's span (model::TermSpan): the range of its primary variable over the
/// data, for the free terms whose form grows without bound beyond it (polynomial, cross-axis
/// in its own axis, thermal, scale expansion); none for the others (a periodic term repeats
/// and a bump or a warm-up levels off by their nature; a table holds its ends already) and
/// where the data do not vary the variable. One entry per term of the model.
[[nodiscard]] std::vector<std::optional<model::TermSpan>> fitted_spans(const model::MachineModel& machine,
                                                                      const MeasurementSet& data);

/// The indices of the parameters a fit may change (free terms; a period only with
/// fit_period), and the model's whole parameter vector.
[[nodiscard]] std::vector<std::size_t> free_parameters(const model::ForwardModel& model);
[[nodiscard]] Eigen::VectorXd model_parameters(const model::ForwardModel& model);

/// Residuals at `parameters` and, when `J` is given, the design matrix: d prediction /
/// d parameters[free[j]] for every observation (n x free.size()).
void design_matrix(const model::ForwardModel& model, const Eigen::VectorXd& parameters, const MeasurementSet& data,
                   const std::vector<std::size_t>& free, Eigen::VectorXd& r, Eigen::MatrixXd* J);

/// A^T A (A^T diag(weights) A when given), summed over a fixed number of row blocks on
/// the cores: the same sums on any machine, whatever its core count.
[[nodiscard]] Eigen::MatrixXd normal_matrix(const Eigen::MatrixXd& A, const Eigen::VectorXd* weights = nullptr);
/// A^T B for tall A and B of the same rows (a design matrix and columns on its rows),
/// summed over the same fixed row blocks as normal_matrix().
[[nodiscard]] Eigen::MatrixXd transpose_product(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);

/// Residuals (measured - predicted, mm) of every observation with the given parameters.
[[nodiscard]] Eigen::VectorXd residuals(const model::ForwardModel& model, const Eigen::VectorXd& parameters,
                                        const MeasurementSet& data);

/// A parameter's name: the term's ISO name and the parameter's role ("EXX.a2", "EBB.b1").
[[nodiscard]] std::string parameter_label(const model::ErrorTermSpec& term, std::size_t k);

}  // namespace ccomp::identify
