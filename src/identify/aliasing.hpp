#pragma once
// Private to diagnose(): whether readings sample a variable on a regular lattice, which
// periods such sampling cannot tell apart (aliases), and ISO 230-2's irregular targets that
// break the lattice.
#include <string>
#include <vector>

namespace ccomp::identify::detail {

/// Whether most (9 in 10) of `positions` lie on a lattice of `step` (to 2% of it): targets
/// every `step`, where a period P and 1 / (k / step +- 1 / P) give the same readings.
[[nodiscard]] bool on_lattice(const std::vector<double>& positions, double step);

/// The periods, shortest last, that readings every `step` cannot tell from `period`:
/// 1 / (k / step +- 1 / period) for k = 1..3, those of at least `shortest` (below it no
/// mechanism of the kind has a period), at most four.
[[nodiscard]] std::vector<double> aliases_of(double period, double step, double shortest);

/// What a suggestion says of its period when the readings sample it on a lattice: the
/// periods it could be, and the run that settles it (`run`: "a laser line along X").
[[nodiscard]] std::string aliasing_text(double period, double step, const std::vector<double>& aliases,
                                        const std::string& unit, const std::string& run);

}  // namespace ccomp::identify::detail
