// The machine model file at this stage: axes, limits, dialect; validate() names the entry.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <tuple>

#include "ccomp/error.hpp"
#include "ccomp/model/machine.hpp"
#include "ccomp/model/model_file.hpp"
#include "error_of.hpp"
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

TEST(MachineModel, DocumentMarkersAroundTheOneDocumentAreNoSecond) {
  for (const char* yaml :
       {"---\nname: a\naxes: {X: {}}\n", "name: a\naxes: {X: {}}\n...\n", "name: a\naxes: {X: {}}\n---\n",
        "%YAML 1.2\n---\nname: a\naxes: {X: {}}\n...\n", "{name: a, axes: {X: {}}}\n"}) {
    const MachineModel m = parse_machine_model(yaml, "a.yaml");
    EXPECT_EQ(m.name, "a") << yaml;
  }
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
    EXPECT_GT(e.where().line, 0U) << "no line: " << e.message();
  }
}

/// The smallest valid model: one axis moving one link, a tool.
constexpr const char* kOk =
    "name: m\naxes: {X: {min: -100, max: 100}}\nchain:\n  workpiece: [{link: X, axis: X}]\n"
    "  tool: [{link: tool, tool_length: [0, 0, -1]}]\n";

std::string ok(const std::string& more) {
  return std::string(kOk) + more;
}

// Every one of these was accepted, or ended as "a bug in ccomp" (exit 70), before the
// model file had a schema.
INSTANTIATE_TEST_SUITE_P(
    Files, BadModels,
    ::testing::Values(
        BadModel{"name: m\n", "axes"}, BadModel{"name: m\naxes: {Q: {}}\n", "Q"},
        BadModel{"name: m\naxes: {X: {min: 5, max: 1}}\n", "min 5"},
        BadModel{"name: m\naxes: {X: {min: .nan}}\n", "NaN"},
        BadModel{"name: m\naxes: {X: {max: fast}}\n", "must be a number"},
        BadModel{"name: m\naxes: {X: {type: spiral}}\n", "spiral"},
        // The type a program's words contradict: a U in millimetres cannot turn, an A in
        // degrees cannot slide.
        BadModel{"name: m\naxes: {U: {type: rotary}}\n", "axis U: type rotary, but programs give U in lengths"},
        BadModel{"name: m\naxes: {A: {type: linear}}\n", "axis A: type linear, but programs give A in degrees"},
        BadModel{"name: m\naxes: {X: {}}\ndialect: heidenhain\n", "heidenhain"}, BadModel{"name: m\naxes: [X\n", ""},
        // A misspelt safety bound is not silently dropped.
        BadModel{"name: m\nmax_corection: 0.001 mm\naxes: {X: {}}\n", "did you mean 'max_correction'"},
        BadModel{"name: m\naxes: {X: {mni: 3}}\n", "did you mean 'min'"}, BadModel{"axes: {X: {}}\n", "needs a 'name'"},
        BadModel{"name: m\nname: n\naxes: {X: {}}\n", "written twice"},
        BadModel{"name: m\naxes: {X: {}}\n---\nname: n\n", "one YAML document"},
        // A document may also start after the end marker of the one before, without '---',
        // at a directive, or after a root in flow style.
        BadModel{"name: m\naxes: {X: {}}\n...\nname: n\n", "one YAML document"},
        BadModel{"name: m\naxes: {X: {}}\n%YAML 1.2\nname: n\n", "one YAML document"},
        BadModel{"{name: m, axes: {X: {}}}\nname: n\n", "one YAML document"},
        // Fuzzing (tools/fuzz.sh model): yaml-cpp's LoadAll looped for ever on these.
        BadModel{",:\n", "a YAML mapping"},
        BadModel{",:\x01\xf6\xff\xff\xff\xff\xff\xff\x7f\xff\xff\xf8\xff", "a YAML mapping"},
        BadModel{"name: m\naxes: {X: [1, 2]}\n", "mapping"}, BadModel{"name: m\naxes: {X: {}, X: {}}\n", "twice"},
        BadModel{"name: [m]\naxes: {X: {}}\n", "single value"},
        BadModel{"name: m\nchain: 5\naxes: {X: {}}\n", "mapping"},
        BadModel{"name: m\naxes: {X: {}}\nmax_correction: -1 mm\n", "positive"},
        BadModel{"name: m\naxes: {X: {}}\nmax_correction: .inf\n", "not a number"},
        BadModel{"name: m\naxes: {X: {}, Y: {}}\nchain:\n  workpiece: [{link: X, axis: X}]\n  tool: [{link: tool, "
                 "tool_length: [0, 0, -1]}]\n",
                 "axis Y moves no link"},
        BadModel{"name: m\naxes: {X: {}}\nchain:\n  workpiece: [{link: X, axis: X}, {link: Q, axis: X}]\n  tool: "
                 "[{link: tool, tool_length: [0, 0, -1]}]\n",
                 "moves two links"},
        BadModel{"name: m\naxes: {X: {}}\nchain:\n  workpiece: [{link: X, axis: Y}]\n  tool: [{link: tool, "
                 "tool_length: [0, 0, -1]}]\n",
                 "not in 'axes'"},
        BadModel{"name: m\naxes: {X: {}}\nchain:\n  workpiece: [{link: X, axis: X, speed: 3}]\n  tool: [{link: tool, "
                 "tool_length: [0, 0, -1]}]\n",
                 "unknown key 'speed'"},
        BadModel{"name: m\naxes: {X: {}}\nchain:\n  workpiece: [{link: X, axis: X}]\n  tol: []\n",
                 "did you mean 'tool'"},
        BadModel{"name: m\naxes: {X: {}}\nchain:\n  workpiece: [{link: X, axis: X}]\n"
                 "  tool: [{link: t, tool_length: [0, 0, -1]}, {link: u, tool_length: [0, 0, -1]}]\n",
                 "more than one tool link"},
        BadModel{"name: m\naxes: {X: {}}\nchain:\n  workpiece: [{link: X, axis: X}]\n", "needs 'tool'"},
        // Linear axes the tool cannot reach every point with: the solve would have no answer.
        BadModel{"name: m\naxes: {X: {}, Y: {}}\nchain:\n  workpiece: [{link: X, axis: X}]\n  tool: [{link: Y, axis: Y, "
                 "direction: [-1, 0, 0]}, {link: tool, tool_length: [0, 0, -1]}]\n",
                 "axis Y moves the tool along the same line as axis X"},
        BadModel{"name: m\naxes: {X: {}, Y: {}, Z: {}}\nchain:\n  workpiece: [{link: X, axis: X}]\n  tool: [{link: Y, "
                 "axis: Y, direction: [0, 1, 0]}, {link: Z, axis: Z, direction: [1, 1, 0]}, {link: tool, "
                 "tool_length: [0, 0, -1]}]\n",
                 "move the tool in one plane"}),
    [](const auto& test) { return "case" + std::to_string(test.index); });

class BadTerms : public ::testing::TestWithParam<BadModel> {};

// Terms: every key known for the term's form, every value of the right kind.
TEST_P(BadTerms, AreRefusedAtTheirLine) {
  try {
    (void)parse_machine_model(ok(std::string("terms:\n  - ") + GetParam().yaml + "\n"), "m.yaml");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::model);
    EXPECT_NE(e.message().find(GetParam().words), std::string::npos) << e.message();
    EXPECT_EQ(e.where().line, 7U) << e.message();
  }
}

INSTANTIATE_TEST_SUITE_P(Files, BadTerms,
                         ::testing::Values(BadModel{"{name: EXX, value: 1, fit: ture}", "true or false"},
                                           BadModel{"{name: EXX, value: 1, unit: [um]}", "single value"},
                                           BadModel{"{name: EXX, vlaue: 1}", "did you mean 'value'"},
                                           BadModel{"{name: EXX, form: polynomial, coefficients: [0, 1], period: 3}",
                                                    "unknown key 'period'"},
                                           BadModel{"{name: EXX, value: .nan}", "not a number"},
                                           BadModel{"{name: EXX, value: 1e999}", "not a number"},
                                           BadModel{"{name: EXQ, value: 1}", "no chain has"},
                                           BadModel{"EXX", "mapping"},
                                           // An approach runs from -1 to +1 as the play is taken up.
                                           BadModel{"{name: EZX, variable: vx, form: polynomial, coefficients: [0, 0, 3]}",
                                                    "linear in it"},
                                           BadModel{"{name: EZX, variable: vx, form: table, at: [-1, 0, 1], "
                                                    "values: [0, 2, 0]}",
                                                    "linear in it"},
                                           BadModel{"{name: EZX, variable: vx, form: bump, at: 0, width: 0.5, "
                                                    "amplitude: 3}",
                                                    "linear in it"},
                                           BadModel{"{name: EZX, variable: vx, form: cross_axis, other: y, "
                                                    "coefficients: [[1]]}",
                                                    "variable is an axis"},
                                           // An axis the machine has not, read or approached.
                                           BadModel{"{name: EXX, variable: y, form: polynomial, "
                                                    "coefficients: [0, 1]}",
                                                    "no axis Y"},
                                           BadModel{"{name: EXX, variable: vc, form: reversal, reversal: 1}",
                                                    "no axis C"}),
                         [](const auto& test) { return "case" + std::to_string(test.index); });

TEST(MachineModel, EveryShippedModelPassesTheSchema) {
  int models = 0;
  for (const char* folder : {"/samples/machines", "/samples/test-piece"})
    for (const auto& e : std::filesystem::directory_iterator(test::source_dir() + folder))
      if (e.path().extension() == ".yaml") {
        EXPECT_NO_THROW((void)load_machine_model(e.path().string())) << e.path();
        ++models;
      }
  EXPECT_GE(models, 4);
}

// Fuzzing (tools/fuzz.sh model): a value of the wrong type where the reader converts it
// (a mapping for a name) let yaml-cpp's TypedBadConversion escape, an internal error (70).
TEST(MachineModel, AValueOfTheWrongTypeIsAModelErrorAtIt) {
  for (const auto& [yaml, line, column] :
       {std::tuple{"name: {a: 1}\naxes: {X: {}}\n", 1U, 7U},
        std::tuple{"name: m\naxes: {X: {}}\nsensors: [[1]]\n", 3U, 11U},
        std::tuple{"name: m\naxes: {X: {}}\nchain:\n  workpiece:\n    - {link: [X], axis: X}\n  tool: []\n", 5U,
                   14U}}) {
    const Error e = test::error_of([&] { (void)parse_machine_model(yaml, "m.yaml"); }, "accepted: ", yaml);
    EXPECT_EQ(e.kind(), ErrorKind::model) << yaml;
    EXPECT_NE(e.message().find("single value"), std::string::npos) << e.message();
    EXPECT_EQ(e.where().file, "m.yaml");
    EXPECT_EQ(e.where().line, line) << yaml;
    EXPECT_EQ(e.where().column, column) << yaml;
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
