// A term's span (where `fit` fitted it): read strictly, held by the forward model beyond
// its ends (value and derivatives, on the fast path and the Jacobians' alike), and said
// once per term by whoever uses the model there.
#include "ccomp/model/term_span.hpp"

#include <gtest/gtest.h>

#include "ccomp/error.hpp"
#include "ccomp/model/forward.hpp"
#include "ccomp/model/model_file.hpp"
#include "error_of.hpp"
#include "short_runs.hpp"

namespace ccomp::model {
namespace {

/// The one-axis test machine with its EXX cubic held over x [-20, 20] mm (`span`).
MachineModel held_cubic(const std::string& span = "span: [-20, 20]") {
  std::string text = test::one_axis_model("[0, 0.1, 0.001, 0.0159]");
  text.replace(text.find("fit: true}"), 10, "fit: true, " + span + "}");
  return parse_machine_model(text, "held.yaml");
}

ChainQ at_x(double x) {
  ChainQ q = ChainQ::Zero();
  q[0] = x;
  q[static_cast<Eigen::Index>(kToolLengthIndex)] = 100.0;
  return q;
}

TEST(TermSpan, IsReadInTheVariablesUnit) {
  const MachineModel m = held_cubic("span: [-20, 20.5]");
  ASSERT_TRUE(m.terms[0].span.has_value());
  EXPECT_EQ(m.terms[0].span->from, -20.0);
  EXPECT_EQ(m.terms[0].span->to, 20.5);
  EXPECT_EQ(span_text(m.terms[0], *m.terms[0].span), "x [-20, 20.5] mm");
  EXPECT_FALSE(parse_machine_model(test::one_axis_model(), "m.yaml").terms[0].span.has_value());
}

TEST(TermSpan, BadSpansAreRefusedNamingTheTerm) {
  for (const char* span : {"span: [20, -20]", "span: [1, 1]", "span: [.nan, 1]", "span: [0, .inf]", "span: [1]",
                           "span: 5", "span: [a, 1]"}) {
    const Error e = test::error_of([&] { (void)held_cubic(span); }, span);
    EXPECT_EQ(e.kind(), ErrorKind::model) << span;
    EXPECT_NE(e.message().find("term EXX"), std::string::npos) << span << ": " << e.message();
  }
  // A reversal's variable is an approach: it has no range to fit over.
  std::string text = test::one_axis_model();
  text += "  - {name: EXX, variable: vx, form: reversal, unit: um, reversal: 2, span: [-1, 1]}\n";
  const Error e = test::error_of([&] { (void)parse_machine_model(text, "m.yaml"); }, "approach span");
  EXPECT_NE(e.message().find("span"), std::string::npos) << e.message();
}

TEST(TermSpan, TheForwardModelHoldsTheValueBeyondTheEnds) {
  const MachineModel held = held_cubic();
  const MachineModel free = parse_machine_model(test::one_axis_model("[0, 0.1, 0.001, 0.0159]"), "free.yaml");
  const ForwardModel h(held), f(free);
  ForwardData dh(h), df(f);
  auto error_x = [](const ForwardModel& m, ForwardData& d, double x, bool jacobians) {
    forward(m, d, at_x(x), Conditions{}, jacobians);
    return (d.actual - d.nominal).x();
  };
  for (const bool jacobians : {false, true}) {
    // Inside, the same as the term everywhere; beyond, its value at the nearer end.
    EXPECT_DOUBLE_EQ(error_x(h, dh, 7.5, jacobians), error_x(f, df, 7.5, jacobians));
    // (to the rounding of positions 1000 mm out)
    EXPECT_NEAR(error_x(h, dh, 1000.0, jacobians), error_x(f, df, 20.0, jacobians), 1e-12);
    EXPECT_NEAR(error_x(h, dh, -1000.0, jacobians), error_x(f, df, -20.0, jacobians), 1e-12);
    EXPECT_GT(std::abs(error_x(f, df, 1000.0, jacobians)), 1000.0) << "the cubic itself runs away (15.9 m)";
  }
  // Held: no slope beyond the span (the inverse's Newton sees the held value's).
  const ForwardModel z(parse_machine_model(test::one_axis_model("[0, 0]"), "zero.yaml"));
  ForwardData dz(z);
  (void)error_x(h, dh, 500.0, true);
  (void)error_x(z, dz, 500.0, true);
  EXPECT_DOUBLE_EQ(dh.J_q(0, 0), dz.J_q(0, 0)) << "X's nominal slope alone";
  (void)error_x(f, df, 500.0, true);
  EXPECT_NE(df.J_q(0, 0), dh.J_q(0, 0));
}

TEST(TermSpan, UseBeyondIsSaidOnceATerm) {
  const MachineModel m = held_cubic();
  SpanWatch watch(m);
  EXPECT_FALSE(watch.empty());
  EXPECT_TRUE(watch.beyond(at_x(-20), at_x(20), Conditions{}).empty()) << "within the span: nothing said";
  const std::vector<std::string> said = watch.beyond(at_x(0), at_x(300), Conditions{});
  ASSERT_EQ(said.size(), 1U);
  EXPECT_NE(said[0].find("term EXX was fitted over x [-20, 20] mm; at x 300 mm it holds its value at 20 mm"),
            std::string::npos)
      << said[0];
  EXPECT_TRUE(watch.beyond(at_x(-900), at_x(900), Conditions{}).empty()) << "once a term";
  EXPECT_TRUE(SpanWatch(parse_machine_model(test::one_axis_model(), "m.yaml")).empty());
}

}  // namespace
}  // namespace ccomp::model
