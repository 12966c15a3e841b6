#include "aliasing.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace ccomp::identify::detail {

bool on_lattice(const std::vector<double>& positions, double step) {
  if (positions.size() < 3 || !(step > 0)) return false;
  const double origin = *std::min_element(positions.begin(), positions.end());
  const auto on = std::count_if(positions.begin(), positions.end(), [&](double x) {
    const double f = (x - origin) / step;
    return std::abs(f - std::round(f)) <= 0.02;
  });
  return static_cast<double>(on) >= 0.9 * static_cast<double>(positions.size());
}

std::vector<double> aliases_of(double period, double step, double shortest) {
  std::vector<double> out;
  for (int k = 1; k <= 3; ++k)
    for (const double sign : {-1.0, 1.0}) {
      const double frequency = k / step + sign / period;
      if (!(frequency > 0)) continue;
      const double alias = 1.0 / frequency;
      // (The period itself, at two steps its own mirror image, is no alias of itself; two
      // orders may give one alias.)
      if (alias < shortest || std::abs(alias - period) <= 0.02 * period) continue;
      if (std::none_of(out.begin(), out.end(), [alias](double a) { return std::abs(a - alias) <= 0.01 * alias; }))
        out.push_back(alias);
    }
  std::sort(out.begin(), out.end(), std::greater<>());
  if (out.size() > 4) out.resize(4);
  return out;
}

std::string aliasing_text(double period, double step, const std::vector<double>& aliases, const std::string& unit,
                          const std::string& run) {
  std::string list;
  for (const double a : aliases) list += fmt::format("{}{:.4g}", list.empty() ? "" : ", ", a);
  return fmt::format(
      "possibly aliased: the readings are evenly spaced every {:.4g} {}, where a period of {} {} gives the same "
      "readings as {:.4g} {}; {} at ISO 230-2's irregular targets (simulate's plans space them so), or with targets "
      "under {:.3g} {} apart, settles it",
      step, unit, list, unit, period, unit, run, aliases.empty() ? step : aliases.back() / 2.5, unit);
}

}  // namespace ccomp::identify::detail
