#pragma once
// Which measurement next: when the data explain a missing effect as well by one candidate
// as by another (the spindle's temperature or the time since the start; a cross-axis term
// or a higher order), adding either is a guess. This names the pair and the measurement
// that would separate them (the nine-line method's placement sensitivity, docs/error-model.md Ref 4, carried to the loop).
#include <vector>

#include "ccomp/identify/diagnose.hpp"

namespace ccomp::identify {

/// The suggestions after the first that explain nearly the same part of `residual` (the
/// refitted residual the suggestions start from): what each explains correlates above 0.9
/// with what the first explains, and its rms after is within 10% of the first's gain.
[[nodiscard]] std::vector<Tie> find_ties(const std::vector<Suggestion>& suggestions, const Eigen::VectorXd& residual);

/// In words, the readings that would tell a term of variable(s) `a` from one of `b`
/// ("T_spindle" and "t", "x,z" and "x"...), and why.
[[nodiscard]] std::string separating_measurement(const std::string& a, const std::string& b);

/// A parameter of a model: its term, and its place among the term's parameters.
struct TermParameter {
  std::size_t term = 0, k = 0;
};
/// In words, what to measure to tell apart parameters `a` and `b` of `model` that a fit
/// could not separate (by the variables they change with, an angle from an offset), or
/// that no measurement can (constant offsets of the position: a work offset's business).
[[nodiscard]] std::string separating_parameters(const model::MachineModel& model, TermParameter a, TermParameter b);

}  // namespace ccomp::identify
