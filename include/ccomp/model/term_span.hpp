#pragma once
// Where a model's terms were fitted, and saying so when they are used beyond it: a term
// with a span (model::TermSpan, written by `ccomp fit`) holds its value at the span's end
// beyond it (forward.hpp evaluates it so), and every use of the model there (the main job,
// predict, export) warns once per term, naming the term and its span.
#include <string>
#include <vector>

#include "ccomp/model/forward.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::model {

/// A span as a person reads it, in the variable's usual unit: "x [-20, 20] mm",
/// "b [0, 345] deg", "T_spindle [20.1, 27.4] degC".
[[nodiscard]] std::string span_text(const ErrorTermSpec& term, const TermSpan& span);

/// The terms with a span, and which of them were said to be used beyond it.
class SpanWatch {
 public:
  explicit SpanWatch(const MachineModel& machine);

  /// Whether no term has a span (nothing to watch).
  [[nodiscard]] bool empty() const { return watched_.empty(); }

  /// One warning for each term, the first time, whose variable leaves its span on the way
  /// from `low` to `high` (chain values, each no more than its `high`; mm and rad) or in
  /// the conditions (temperatures, time).
  [[nodiscard]] std::vector<std::string> beyond(const ChainQ& low, const ChainQ& high, const Conditions& conditions);

 private:
  const MachineModel& machine_;
  std::vector<std::size_t> watched_;  ///< terms with a span, not yet said
};

}  // namespace ccomp::model
