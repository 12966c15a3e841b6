#pragma once
// A term's parameter as a person reads it: in the unit the model file writes it (um, urad,
// um/mm, urad/degC, a period in mm or deg), with an uncertainty printed to the digits it
// has. `ccomp fit`'s text and the HTML report print parameters this way.
#include <cstddef>
#include <string>

#include "ccomp/model/machine.hpp"
#include "ccomp/model/term_forms.hpp"  // MicroSign

namespace ccomp::model {

/// The unit of parameter `k` of term `t` as the model file writes it ("um", "urad/mm",
/// "mm" for a period, "s" for a time constant); "" where the unit has no common name.
[[nodiscard]] std::string parameter_unit_name(const ErrorTermSpec& t, std::size_t k,
                                              MicroSign micro = MicroSign::ascii);

/// An uncertainty to two significant digits (written out in full from 1e-4 to 1e6), in the
/// unit of `magnitude` (the parameter's value, or its largest); one below a billionth of
/// the magnitude, which is the arithmetic's rounding and no uncertainty, "0 (to rounding)":
/// no "+- 1.5e-14".
[[nodiscard]] std::string uncertainty_text(double uncertainty, double magnitude);
/// Whether an uncertainty is below the rounding of `magnitude` (or zero).
[[nodiscard]] bool within_rounding(double uncertainty, double magnitude);

}  // namespace ccomp::model
