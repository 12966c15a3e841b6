#pragma once
// What a fit says of where its model means little: a polynomial fitted from about as many
// places as it has coefficients (issue 45: "on 5 targets a cubic leaves 0.000 um without a
// caveat").
#include <optional>
#include <string>
#include <vector>

#include "ccomp/identify/measurements.hpp"
#include "ccomp/model/forward.hpp"

namespace ccomp::identify {

/// A reading's value of a term's variable (mm, rad, degC, s); none for an approach.
[[nodiscard]] std::optional<double> variable_value(const model::Variable& v, const Observation& o);

/// Each free polynomial of three free coefficients or more (a line is checked by a third
/// place) fitted from fewer than twice as many places (distinct values of its variable),
/// in words naming the term and its span: it then passes through (nearly) every place, and
/// its residual there proves little. Empty: none.
[[nodiscard]] std::vector<std::string> thin_polynomials(const model::ForwardModel& model, const MeasurementSet& data);

}  // namespace ccomp::identify
