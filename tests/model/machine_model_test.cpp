// The machine model file at this stage: axes, limits, dialect; validate() names the entry.
#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>

#include "ccomp/error.hpp"
#include "ccomp/model/machine.hpp"
#include "trace_capture.hpp"

namespace ccomp::model {
namespace {

TEST(MachineModel, ZeroSampleAcceptsEveryAxis) {
  const MachineModel m = load_machine_model(test::source_dir() + "/samples/machines/zero.yaml");
  EXPECT_EQ(m.name, "zero");
  EXPECT_EQ(m.axes.size(), 9U);
  for (char c : std::string("XYZABCUVW")) EXPECT_NE(m.axis(c), nullptr) << c;
  EXPECT_EQ(m.sha256.size(), 64U);
}

TEST(MachineModel, HashNamesTheBytes) {
  const MachineModel a = parse_machine_model("name: a\naxes: {X: {}}\n", "a.yaml");
  const MachineModel b = parse_machine_model("name: a\naxes: {X: {}} \n", "b.yaml");
  EXPECT_NE(a.sha256, b.sha256);
}

struct BadModel {
  const char* yaml;
  const char* words;
};
void PrintTo(const BadModel& b, std::ostream* os) {
  *os << b.yaml;
}

class BadModels : public ::testing::TestWithParam<BadModel> {};

TEST_P(BadModels, AreRefusedNamingTheEntry) {
  try {
    (void)parse_machine_model(GetParam().yaml, "m.yaml");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::model);
    EXPECT_NE(e.message().find(GetParam().words), std::string::npos) << e.message();
    EXPECT_EQ(e.where().file, "m.yaml");
  }
}

INSTANTIATE_TEST_SUITE_P(Files, BadModels,
                         ::testing::Values(BadModel{"name: m\n", "axes"}, BadModel{"axes: {Q: {}}\n", "Q"},
                                           BadModel{"axes: {X: {min: 5, max: 1}}\n", "min 5"},
                                           BadModel{"axes: {X: {min: .nan}}\n", "NaN"},
                                           BadModel{"axes: {X: {max: fast}}\n", "must be a number"},
                                           BadModel{"axes: {X: {type: spiral}}\n", "spiral"},
                                           BadModel{"axes: {X: {}}\ndialect: heidenhain\n", "heidenhain"},
                                           BadModel{"axes: [X\n", ""}));

// Fuzzing (tools/fuzz.sh model): a value of the wrong type where the reader converts it
// (a mapping for a name) let yaml-cpp's TypedBadConversion escape, an internal error (70).
TEST(MachineModel, AValueOfTheWrongTypeIsAModelErrorAtIt) {
  for (const auto& [yaml, line, column] :
       {std::tuple{"name: {a: 1}\naxes: {X: {}}\n", 1U, 7U}, std::tuple{"axes: {X: {}}\nsensors: [[1]]\n", 2U, 11U},
        std::tuple{"axes: {X: {}}\nchain:\n  workpiece:\n    - {link: [X], axis: X}\n", 4U, 14U}}) {
    try {
      (void)parse_machine_model(yaml, "m.yaml");
      ADD_FAILURE() << "accepted: " << yaml;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::model) << yaml;
      EXPECT_NE(e.message().find("wrong type"), std::string::npos) << e.message();
      EXPECT_EQ(e.where().file, "m.yaml");
      EXPECT_EQ(e.where().line, line) << yaml;
      EXPECT_EQ(e.where().column, column) << yaml;
    }
  }
}

// What check suggests, added to a model in memory, is the term the file would have, with
// the sensor it needs; a spec that is not a term is refused as a model error.
TEST(MachineModel, WithTermsAddsTheSpecAndItsSensor) {
  const MachineModel base = load_machine_model(test::source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  const MachineModel with = with_terms(
      base, {"{name: EZS, variable: T_spindle, form: thermal, unit: um, coefficient: 1.5, fit: true}"}, "check");
  ASSERT_EQ(with.terms.size(), base.terms.size() + 1);
  EXPECT_EQ(with.terms.back().iso, "EZS");
  EXPECT_NE(std::find(with.sensors.begin(), with.sensors.end(), "spindle"), with.sensors.end());
  EXPECT_THROW((void)with_terms(base, {"[1, 2]"}, "check"), Error);
  EXPECT_THROW((void)with_terms(base, {"{name: EQQ, value: 1}"}, "check"), Error);
  EXPECT_THROW((void)with_terms(base, {"{name: [EXX], value: 1}"}, "check"), Error) << "not a YAML exception";
}

}  // namespace
}  // namespace ccomp::model
