#pragma once
// What makes a control's table worse than it looks, for every export to say: a periodic
// error of the model that the table's spacing cannot hold (it aliases, or linear
// interpolation between too few points a period holds it only in part), and a table that
// leaves more error than no table at all.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "ccomp/controller/axis_table.hpp"
#include "ccomp/model/machine.hpp"

namespace ccomp::controller {

/// A table interpolates a harmonic well only over four or more points a period; at fewer
/// than two it aliases (Nyquist).
inline constexpr double kStepsPerPeriod = 4.0;

/// The first harmonic k (1..order) of a periodic error of `period` whose period / k is
/// shorter than kStepsPerPeriod steps of `step` (both in one unit), or none.
[[nodiscard]] std::optional<int> first_short_harmonic(double period, int order, double step);

/// The period (in the step's unit) a sinusoid of `period` shows when sampled every `step`:
/// the alias, infinite when it falls on the samples' own period.
[[nodiscard]] double alias_period(double period, double step);

/// A periodic term along a table's axis whose harmonics from `harmonic` on are shorter than
/// kStepsPerPeriod steps.
struct ShortPeriod {
  std::size_t term = 0;
  int harmonic = 1;     ///< the first too short
  double period = 0.0;  ///< of that harmonic, in the table's unit (mm, deg)
  double step = 0.0;    ///< the table's
  bool aliased = false;  ///< under two steps: sampled, it shows as another wave
  double alias = 0.0;    ///< the period it shows as, when aliased
};

/// The model's periodic terms of chain axis `axis_index` (0..8) that a table every `step`
/// (mm, or deg for a rotary axis) cannot hold.
[[nodiscard]] std::vector<ShortPeriod> short_periods(const model::MachineModel& model, std::size_t axis_index,
                                                     double step);
/// One sentence for a warning: the term, its period, the step, what follows, what to do.
[[nodiscard]] std::string describe(const model::MachineModel& model, const ShortPeriod& s, const char* unit);

/// The warnings of a residual a table leaves: one when it is worse, by its largest or its
/// rms, than no table (`where`: "along the line", "over the workspace").
[[nodiscard]] std::vector<std::string> worse_than_none(const Residual& r, const std::string& where,
                                                       const char* unit = "um");

}  // namespace ccomp::controller
