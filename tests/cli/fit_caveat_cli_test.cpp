// fit says when a polynomial has nearly as many coefficients as the places it was fitted
// from (issue 45: "on 5 targets a cubic leaves 0.000 um without a caveat"), naming the term
// and its span; with targets enough it says nothing.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "short_runs.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

struct CaveatCase {
  const char* name;
  int targets;             ///< evenly over [-20, 20] mm
  const char* cubic;       ///< the model's EXX coefficients (um per mm^k)
  const char* warning;     ///< on stderr; empty: no caveat
};

std::ostream& operator<<(std::ostream& os, const CaveatCase& c) { return os << c.name; }

class FitCaveat : public ::testing::TestWithParam<CaveatCase> {};

TEST_P(FitCaveat, NamesTheTermAndItsSpan) {
  const CaveatCase& c = GetParam();
  const std::string dir = temp_dir(std::string("fit_caveat_") + c.name);
  write_file(dir + "/m.yaml", one_axis_model(c.cubic));
  // An axis bending as a cubic (3 um at the ends), three runs each way, 0.05 um of scatter.
  std::string csv = "x,y,z,vx,nx,ny,nz,d\n";
  for (int run = 0; run < 3; ++run)
    for (const int v : {1, -1})
      for (int i = 0; i < c.targets; ++i) {
        const double x = -20.0 + 40.0 * i / (c.targets - 1), u = x / 20.0;
        const double d = 0.003 * (u * u * u - 0.4 * u) + 0.00005 * std::sin(7.0 * i + 3.0 * run + v);
        csv += fmt::format("{},0,0,{},1,0,0,{:.9f}\n", x, v, d);
      }
  write_file(dir + "/runs.csv", csv);
  const CommandResult r = run_command(shell_quote(ccomp_binary()) + " fit " + shell_quote(dir + "/runs.csv") + " -m " +
                                      shell_quote(dir + "/m.yaml") + " -o " + shell_quote(dir + "/fitted.yaml"));
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  if (*c.warning) {
    EXPECT_NE(r.err.find(c.warning), std::string::npos) << r.err;
  } else {
    EXPECT_EQ(r.err.find("warning: EXX: a polynomial"), std::string::npos) << r.err;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Issue45, FitCaveat,
    ::testing::Values(
        CaveatCase{"cubic_from_five_targets", 5, "[0, 0, 0, 0]",
                   "warning: EXX: a polynomial of 4 fitted coefficients from 5 places (x [-20, 20] mm): 1 degree(s) "
                   "of freedom left"},
        CaveatCase{"cubic_from_four_targets", 4, "[0, 0, 0, 0]",
                   "warning: EXX: a polynomial of 4 fitted coefficients from 4 places (x [-20, 20] mm): as many "
                   "coefficients as places"},
        CaveatCase{"cubic_from_nine_targets", 9, "[0, 0, 0, 0]", ""},
        CaveatCase{"slope_from_three_targets", 3, "[0, 0]", ""}),
    [](const ::testing::TestParamInfo<CaveatCase>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace ccomp::test
