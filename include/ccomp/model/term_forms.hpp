#pragma once
// The error-term forms, one descriptor each: the names a model file gives it, the keys its
// parameters are written under, and its sentence of physics. The model file's schema check
// reads the keys from here; the parametrised Jacobian suite (tests/jacobian_suite_test.cpp)
// iterates the list and fails for a form it has no case of, so a new form cannot go
// untested. (Evaluation, reading, writing, scales and bounds are still one switch per
// concern over TermForm: docs/machine-model.md lists the forms.)
#include <string_view>
#include <vector>

#include "ccomp/model/error_term.hpp"

namespace ccomp::model {

struct TermFormInfo {
  TermForm form = TermForm::constant;
  std::vector<std::string_view> names;  ///< `form: <name>` in a model file, the first as written
  std::vector<std::string_view> keys;   ///< the keys of its parameters and shape
  std::string_view physics;             ///< what on a machine it describes
};

/// Every form, in TermForm's order.
[[nodiscard]] const std::vector<TermFormInfo>& term_forms();

/// The form a model file names, or null.
[[nodiscard]] const TermFormInfo* term_form(std::string_view name);

}  // namespace ccomp::model
