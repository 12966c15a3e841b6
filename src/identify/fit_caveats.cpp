// What a fit says of a polynomial fitted from about as many places as it has coefficients:
// it then passes through (nearly) every one and leaves "0.000 um" that proves nothing, and
// between and beyond them it is whatever the coefficients make it.
#include "ccomp/identify/fit_caveats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "ccomp/identify/fit.hpp"
#include "ccomp/model/term_span.hpp"

namespace ccomp::identify {

std::vector<std::string> thin_polynomials(const model::ForwardModel& model, const MeasurementSet& data) {
  std::vector<std::string> caveats;
  const model::MachineModel& machine = model.machine();
  const std::vector<std::size_t> free = free_parameters(model);
  const std::vector<std::optional<model::TermSpan>> spans = fitted_spans(machine, data);
  for (std::size_t t = 0; t < machine.terms.size(); ++t) {
    const model::ErrorTermSpec& term = machine.terms[t];
    if (term.shape.form != model::TermForm::polynomial || !spans[t]) continue;
    const std::size_t offset = model.parameter_offset(t), end = offset + static_cast<std::size_t>(term.parameters.size());
    const auto coefficients = static_cast<std::size_t>(
        std::count_if(free.begin(), free.end(), [&](std::size_t i) { return i >= offset && i < end; }));
    if (coefficients < 3) continue;  // a line: two places determine it, a third already checks it
    // The places its variable was read at, told apart to a millionth of the span (ISO 230-2's
    // repeated approaches to one target are one place).
    const double low = spans[t]->from, width = spans[t]->to - spans[t]->from;
    std::set<long long> places;
    for (const Observation& o : data.observations) {
      const std::optional<double> v = variable_value(term.primary, o);
      if (v) places.insert(std::llround((*v - low) / width * 1e6));
    }
    if (places.size() >= 2 * coefficients) continue;
    const std::string span = model::span_text(term, *spans[t]);
    caveats.push_back(fmt::format(
        "{}: a polynomial of {} fitted coefficients from {} places ({}): {}; what it leaves there proves little, "
        "between the places it is what the coefficients make it, and beyond {} its value at the end is held; measure "
        "at least {} places, or fit fewer coefficients",
        term.name, coefficients, places.size(), span,
        places.size() <= coefficients ? "as many coefficients as places, so it passes through every one"
                                      : fmt::format("{} degree(s) of freedom left", places.size() - coefficients),
        span, 2 * coefficients));
  }
  return caveats;
}

}  // namespace ccomp::identify
