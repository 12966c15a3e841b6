#pragma once
// Test support: the metrology loop as a script follows `ccomp check --json`: fit the model
// as it is, then add check's first suggestion and refit, again until nothing is suggested.
#include <string>
#include <vector>

#include "ccomp/identify/diagnose.hpp"
#include "ccomp/identify/fit.hpp"

namespace ccomp::test {

struct LoopResult {
  std::string text;                   ///< the model file it ends with
  std::vector<std::string> added;     ///< the specs it added, in order
  std::vector<std::string> ties;      ///< the measurements check asked for on the way
  identify::FitReport last;           ///< the last fit
  std::vector<std::string> refusals;  ///< any fit's refusals (none expected)
  bool ended = false;                 ///< check suggested nothing at the end
  std::string unexplained;            ///< what the last check said it sees and cannot name
};

/// Runs the loop from the model file `text` on `data` for at most `rounds` additions, each
/// fit with `options` (a script that saw `fit` name outliers reruns it with --robust).
[[nodiscard]] LoopResult follow_the_loop(std::string text, const identify::MeasurementSet& data, int rounds = 4,
                                         const identify::FitOptions& options = {});

}  // namespace ccomp::test
