#include "random_terms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace ccomp::test {

std::string random_terms(const std::string& form, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  const char* motions[] = {"EXX", "EYX", "EZX", "EBX", "ECX", "EYY", "EXY", "EAY", "EZZ", "EXZ", "EBZ", "EBB", "EXB"};
  std::string out;
  char line[400];
  for (int k = 0; k < 4; ++k) {
    const std::string name = motions[std::uniform_int_distribution<int>(0, 12)(rng)];
    const bool rotary_axis = name.back() == 'B';
    if (form == "polynomial") {
      std::snprintf(line, sizeof line, "  - {name: %s, form: polynomial, coefficients: [%.3f, %.5f, %.3e]}\n",
                    name.c_str(), 10 * u(rng), 0.05 * u(rng), 1e-4 * u(rng));
    } else if (form == "table") {
      std::snprintf(line, sizeof line,
                    "  - {name: %s, form: table, interpolation: %s, at: [-500, -250, 0, 250, 500], values: [%.2f, "
                    "%.2f, 0, %.2f, %.2f]}\n",
                    rotary_axis ? "EXX" : name.c_str(), k % 2 ? "cubic" : "linear", 20 * u(rng), 20 * u(rng),
                    20 * u(rng), 20 * u(rng));
    } else if (form == "periodic") {
      std::snprintf(line, sizeof line, "  - {name: %s, form: periodic, period: %.3f %s, harmonics: [[%.2f, %.2f]]}\n",
                    name.c_str(), rotary_axis ? 20 + 60 * (u(rng) + 1) : 8 + 20 * (u(rng) + 1),
                    rotary_axis ? "deg" : "mm", 5 * u(rng), 5 * u(rng));
    } else if (form == "thermal") {
      std::snprintf(line, sizeof line, "  - {name: EZ0S, variable: T_spindle, form: thermal, coefficient: %.3f}\n",
                    3 * u(rng));
    } else if (form == "warmup") {
      std::snprintf(line, sizeof line,
                    "  - {name: EY0Y, variable: t, form: warmup, amplitude: %.2f, time_constant: %.0f s}\n",
                    20 * u(rng), 600 + 1200 * (u(rng) + 1));
    } else if (form == "scale_expansion") {
      std::snprintf(line, sizeof line,
                    "  - {name: EXX, form: scale_expansion, temperature: T_bed, coefficient: %.3e /degC}\n",
                    11.5e-6 * (1 + 0.2 * u(rng)));
    } else if (form == "cross_axis") {
      std::snprintf(line, sizeof line,
                    "  - {name: EBZ, form: cross_axis, other: x, unit: urad, coefficients: [[%.4f]]}\n",
                    (u(rng) > 0 ? 1 : -1) * (0.1 + 0.1 * std::abs(u(rng))));  // urad per mm: tens of um at the arms
    } else if (form == "reversal") {
      // Backlash on the axis' own positioning (negative: the axis lags its command) sets its
      // lost motion; another of the carriage's motions switches over the same travel, by
      // what such switches measure (tenths of a micrometre, a few urad: the carriage
      // shifting in its guideway clearance as the drive force turns round).
      const char* own[] = {"EXX, variable: vx", "EYY, variable: vy", "EZZ, variable: vz", "EBB, variable: vb"};
      const char* other[] = {"EYX, variable: vx", "EXY, variable: vy", "EBZ, variable: vz", "EXB, variable: vb"};
      const bool b = k == 3;
      std::snprintf(line, sizeof line,
                    "  - {name: %s, form: reversal, unit: %s, reversal: %.2f}\n"
                    "  - {name: %s, form: reversal, unit: %s, reversal: %.2f}\n",
                    own[k], b ? "urad" : "um", -(b ? 12 : 5) * (1.2 + u(rng)), other[k], k == 2 ? "urad" : "um",
                    (k == 2 ? 3 : 0.5) * u(rng));
    } else if (form == "location") {
      const char* location[] = {"EC0X", "EB0X", "EA0Y", "EA0B", "EC0B", "EX0B", "EZ0B"};
      std::snprintf(line, sizeof line, "  - {name: %s, value: %.2f}\n", location[k % 7], 30 * u(rng));
    } else {
      // A form misspelt in a test would give it no terms to test.
      ADD_FAILURE() << "random_terms: no form '" << form << "'";
      return out;
    }
    out += line;
  }
  return out;
}

}  // namespace ccomp::test
