#include "ccomp/controller/table_checks.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace ccomp::controller {

std::optional<int> first_short_harmonic(double period, int order, double step) {
  if (!(step > 0) || !std::isfinite(period) || period == 0) return std::nullopt;
  // period / k < kStepsPerPeriod * step from this k on.
  const int first = static_cast<int>(std::floor(std::abs(period) / (kStepsPerPeriod * step))) + 1;
  if (first > order) return std::nullopt;
  return first;
}

double alias_period(double period, double step) {
  const double f = 1.0 / std::abs(period), fs = 1.0 / step;
  const double alias = std::abs(f - std::round(f / fs) * fs);
  return alias > 1e-12 * fs ? 1.0 / alias : std::numeric_limits<double>::infinity();
}

std::vector<ShortPeriod> short_periods(const model::MachineModel& model, std::size_t axis_index, double step) {
  std::vector<ShortPeriod> out;
  const char letter = kAxisLetters[axis_index];
  const model::AxisSpec* spec = model.axis(letter);
  // A rotary axis' period is held in radians; its table's step in degrees.
  const double per_unit = spec != nullptr && spec->type == model::AxisType::rotary ? std::numbers::pi / 180.0 : 1.0;
  for (std::size_t t = 0; t < model.terms.size(); ++t) {
    const model::ErrorTermSpec& term = model.terms[t];
    if (term.shape.form != model::TermForm::periodic || term.primary.kind != model::VariableKind::axis ||
        term.primary.index != axis_index || term.parameters.size() == 0)
      continue;
    const double period = std::abs(term.parameters[0]) / per_unit;
    const std::optional<int> k = first_short_harmonic(period, term.shape.order, step);
    if (!k) continue;
    ShortPeriod s{t, *k, period / *k, step, false, 0.0};
    s.aliased = s.period < 2 * step;
    if (s.aliased) s.alias = alias_period(s.period, step);
    out.push_back(s);
  }
  return out;
}

std::string describe(const model::MachineModel& model, const ShortPeriod& s, const char* unit) {
  const std::string what =
      s.aliased ? (std::isfinite(s.alias)
                       ? fmt::format("sampled every {:g} {} it aliases: the table holds a {:.4g} {} wave the machine "
                                     "does not have",
                                     s.step, unit, s.alias, unit)
                       : fmt::format("sampled every {:g} {} it falls on the same phase at every point: the table "
                                     "holds a constant the machine does not have",
                                     s.step, unit))
                : fmt::format("with {:.2g} points a period, interpolating between them holds it only in part",
                              s.period / s.step);
  return fmt::format(
      "term {}: its periodic error of period {:.4g} {} (harmonic {}) is shorter than {:g} of the table's {:g} {} "
      "steps; {}: give --step {:g} or less, or leave that error to ccomp's rewriting",
      model.terms[s.term].name, s.period, unit, s.harmonic, kStepsPerPeriod, s.step, unit, what,
      std::floor(s.period / kStepsPerPeriod * 1000) / 1000);
}

std::vector<std::string> worse_than_none(const Residual& r, const std::string& where, const char* unit) {
  // Below a thousandth of the unit the digits of the table decide, not the table.
  constexpr double kSlack = 1e-3;
  std::vector<std::string> out;
  if (r.max_after_um > r.max_before_um + kSlack || r.rms_after_um > r.rms_before_um + kSlack)
    out.push_back(fmt::format("the table makes the error worse than no table {}: max {:.3f} -> {:.3f} {}, rms {:.3f} "
                              "-> {:.3f} {}; do not load it as it is",
                              where, r.max_before_um, r.max_after_um, unit, r.rms_before_um, r.rms_after_um, unit));
  return out;
}

}  // namespace ccomp::controller
