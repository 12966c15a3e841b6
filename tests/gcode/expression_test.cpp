// Expressions and parameters, with LinuxCNC's precedence, functions (degrees) and scoping.
#include <gtest/gtest.h>

#include <cmath>

#include "error_of.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

struct Case {
  const char* expression;
  double value;
};
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.expression;
}

class Expressions : public ::testing::TestWithParam<Case> {};

TEST_P(Expressions, EvaluateAsLinuxcncDoes) {
  EXPECT_NEAR(evaluate(GetParam().expression), GetParam().value, 1e-12) << GetParam().expression;
}

INSTANTIATE_TEST_SUITE_P(
    Table, Expressions,
    ::testing::Values(Case{"1 + 2 * 3", 7}, Case{"[1 + 2] * 3", 9}, Case{"2 ** 3 ** 2", 64},  // left to right
                      Case{"-2 ** 2", 4}, Case{"10 - 4 - 3", 3}, Case{"12 / 4 / 3", 1}, Case{"7 MOD 3", 1},
                      Case{"-7 MOD 3", 2}, Case{"1 + 2 EQ 3", 1}, Case{"3 GT 2 AND 2 GT 3", 0},
                      Case{"3 GT 2 OR 2 GT 3", 1}, Case{"1 XOR 1", 0}, Case{"2 LE 2", 1}, Case{"2 LT 2", 0},
                      Case{"1 NE 1.0000001", 0},  // rs274's 1e-6
                      Case{"SIN[30]", 0.5}, Case{"COS[60]", 0.5}, Case{"TAN[45]", 1.0}, Case{"ASIN[1]", 90},
                      Case{"ACOS[0]", 90}, Case{"ATAN[1]/[-1]", 135}, Case{"SQRT[16]", 4}, Case{"ABS[-2.5]", 2.5},
                      Case{"FIX[-2.5]", -3}, Case{"FUP[-2.5]", -2}, Case{"ROUND[2.5]", 3}, Case{"LN[EXP[2]]", 2},
                      Case{"EXISTS[#<nope>]", 0}, Case{"EXISTS[#5]", 1}, Case{"EXISTS[#99999]", 0},
                      Case{"sin [ 3 0 ]", 0.5}));

TEST(Expressions, DomainErrorsAreRefusedWithTheirLine) {
  for (const char* bad : {"SQRT[-1]", "LN[0]", "1/0", "ACOS[2]", "[-8]**0.5"}) {
    const Error e = test::error_of([&] { (void)evaluate(bad); }, bad, " was accepted");
    EXPECT_EQ(e.where().line, 1U) << bad;
  }
}

TEST(Parameters, SettingsTakeEffectAfterTheWholeBlockWasRead) {
  // #1 is read as 1 in the same block that sets it to 5, as RS-274/NGC says.
  const RunResult r = run_program("#1=1\n#1=5 G0 X#1\nG0 Y#1\nM2\n");
  ASSERT_FALSE(r.error) << r.error->what();
  ASSERT_EQ(r.motions.size(), 2U);
  EXPECT_DOUBLE_EQ(r.motions[0].motion.end[0], 1.0);
  EXPECT_DOUBLE_EQ(r.motions[1].motion.end[1], 5.0);
}

TEST(Parameters, NamedLocalsAreScopedToTheCallGlobalsAreNot) {
  const RunResult r = run_program(
      "o<s> sub\n#<loc> = 7\n#<_glob> = 8\n(debug,#1 #<loc>)\no<s> endsub\n"
      "#<loc> = 1\n#1 = 3\no<s> call [2]\n(debug,#1 #<loc> #<_glob>)\nM2\n");
  ASSERT_FALSE(r.error) << r.error->what();
  ASSERT_EQ(r.messages.size(), 2U);
  EXPECT_EQ(r.messages[0], "2.000000 7.000000");
  EXPECT_EQ(r.messages[1], "3.000000 1.000000 8.000000");  // #1 and #<loc> restored
}

TEST(Parameters, ControllerValuesAreRefusedUnlessGiven) {
  const RunResult refused = run_program("G0 X#<_hal[motion.probe]>\nM2\n");
  ASSERT_TRUE(refused.error);
  EXPECT_NE(std::string(refused.error->what()).find("--param"), std::string::npos);
  EXPECT_EQ(refused.error->where().column, 7U);
  EXPECT_TRUE(run_program("G0 X#5063\nM2\n").error) << "probe result";

  gcode::InterpreterOptions o;
  o.parameters = {{"_hal[motion.probe]", 2.5}, {"5063", 1.5}};
  const RunResult given = run_program("G0 X#<_hal[motion.probe]> Y#5063\nM2\n", o);
  ASSERT_FALSE(given.error) << given.error->what();
  EXPECT_DOUBLE_EQ(given.motions[0].motion.end[0], 2.5);
  EXPECT_DOUBLE_EQ(given.motions[0].motion.end[1], 1.5);
}

TEST(Parameters, UndefinedNamedParameterIsAnError) {
  const RunResult r = run_program("G0 X#<never_set>\nM2\n");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->message().find("never_set"), std::string::npos) << r.error->message();
}

TEST(Parameters, PredefinedNamedParametersFollowTheState) {
  const RunResult r = run_program("G20 G91 G0 X1\n(debug,#<_x> #<_imperial> #<_incremental> #<_motion_mode>)\nM2\n");
  ASSERT_FALSE(r.error) << r.error->what();
  ASSERT_EQ(r.messages.size(), 1U);
  EXPECT_EQ(r.messages[0], "1.000000 1.000000 1.000000 0.000000");
}

}  // namespace
}  // namespace ccomp::test
