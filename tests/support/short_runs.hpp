#pragma once
// Measurements of one linear axis that support no fit above their noise: a short stroke,
// one run each way, few targets, one direction, one row (what real ISO 230-2 runs of small
// stages look like), and the one-axis model they are fitted with. Deterministic: the noise
// is a fixed pseudo-random sequence, the same on every platform.
#include <cstdint>
#include <string>
#include <vector>

namespace ccomp::test {

/// A one-axis machine (X on Y, Z carrying the tool) with one free term, EXX as a
/// polynomial of `coefficients` (um per mm^k), and the given max_correction (mm).
inline std::string one_axis_model(const std::string& coefficients = "[0, 0]", const std::string& max_correction = "1",
                                  double travel = 1000.0) {
  return "name: one-axis\nmax_correction: " + max_correction +
         " mm\naxes:\n  X: {type: linear, min: " + std::to_string(-travel) + ", max: " + std::to_string(travel) +
         "}\n  Y: {type: linear, min: -250, max: 250}\n  Z: {type: linear, min: -400, max: 400}\n"
         "chain:\n  workpiece:\n    - {link: Y, axis: Y, direction: [0, -1, 0]}\n"
         "    - {link: X, axis: X, direction: [-1, 0, 0]}\n  tool:\n    - {link: Z, axis: Z, direction: [0, 0, 1]}\n"
         "    - {link: tool, tool_length: [0, 0, -1]}\nterms:\n"
         "  - {name: EXX, form: polynomial, unit: um, coefficients: " +
         coefficients + ", fit: true}\n";
}

struct ShortRuns {
  const char* name;
  std::vector<double> targets;  ///< mm along X
  bool both_directions = true;
  int runs = 1;        ///< passes over the targets in each direction
  double noise = 0.0;  ///< mm, the half-width of the readings' uniform noise
};

/// The runs as a measurement CSV: deviations along X of pure noise, by direction of approach.
inline std::string short_runs_csv(const ShortRuns& s) {
  std::string csv = "x,y,z,vx,nx,ny,nz,d\n";
  std::uint32_t state = 12345;
  auto noise = [&] {
    state = state * 1664525U + 1013904223U;
    return s.noise * (2.0 * static_cast<double>(state >> 8) / static_cast<double>(1U << 24) - 1.0);
  };
  for (int run = 0; run < s.runs; ++run)
    for (const int v : s.both_directions ? std::vector<int>{1, -1} : std::vector<int>{1})
      for (std::size_t k = 0; k < s.targets.size(); ++k) {
        const double x = s.targets[v > 0 ? k : s.targets.size() - 1 - k];
        csv += std::to_string(x) + ",0,0," + std::to_string(v) + ",1,0,0," + std::to_string(noise()) + "\n";
      }
  return csv;
}

}  // namespace ccomp::test
