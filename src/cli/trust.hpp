#pragma once
// The trust on a program (compensate/trust.hpp) for predict and the main job: gathered
// over one pass of predict, written as a line of text and as --json fields.
#include <optional>
#include <string>

#include "ccomp/compensate/trust.hpp"
#include "ccomp/compensate/verify.hpp"
#include "ccomp/util/json.hpp"

namespace ccomp::cli {

/// The trust on the program in file `input` (not "-": standard input is read once, by the
/// job), gathered by a pass of predict with `options`. Unknown (not `known`) without `info`
/// (a model no fit wrote); no pass is made then.
[[nodiscard]] compensate::ProgramTrust trust_on_file(const std::string& input, const model::ForwardModel& model,
                                                     const std::optional<model::FitInformation>& info,
                                                     compensate::CheckOptions options);

/// `expected_after_um`, `after_bound_um` (null when unknown; `added` mm on both: what the
/// job leaves against the model), `extrapolation` and `trust` (its sentence).
void trust_fields(util::JsonWriter& j, const std::optional<compensate::ProgramTrust>& trust, double added,
                  const std::string& why_none);

}  // namespace ccomp::cli
