#pragma once
// Test support: a location term's fitted value (mm or rad) from a fit's report, by its ISO
// 230-7 name, for the tests that fit a reference machine's lines back.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "ccomp/identify/fit.hpp"

namespace ccomp::test {

inline double fitted_location(const model::ForwardModel& m, const identify::FitReport& r, const std::string& iso) {
  for (std::size_t t = 0; t < m.machine().terms.size(); ++t)
    if (m.machine().terms[t].iso == iso && m.machine().terms[t].placement == model::ErrorPlacement::location)
      return r.all_parameters[static_cast<Eigen::Index>(m.parameter_offset(t))];
  ADD_FAILURE() << "no location term " << iso;
  return std::nan("");
}

}  // namespace ccomp::test
