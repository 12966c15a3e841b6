// --json on every command: each command's output is checked against its documented
// schema (docs/schemas/<command>.schema.json) by tools/validate-json.py (Debian's
// python3-jsonschema), and its numbers are those of the text output, in the same units.
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

struct JsonCase {
  std::string schema;   ///< docs/schemas/<schema>.schema.json
  std::string command;  ///< after the binary; {out} is a temp folder, {s} the source folder
};

std::string expand(std::string text, const std::string& out) {
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"{out}", out}, {"{s}", source_dir()}})
    for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + value.size()))
      text.replace(at, key.size(), value);
  return text;
}

CommandResult validate(const std::string& schema, const std::string& document) {
  return run_command("/usr/bin/python3 " + shell_quote(source_dir() + "/tools/validate-json.py") + " " +
                     shell_quote(source_dir() + "/docs/schemas/" + schema + ".schema.json") + " " +
                     shell_quote(document));
}

class JsonOutput : public ::testing::TestWithParam<JsonCase> {};

TEST_P(JsonOutput, MatchesItsSchema) {
  const JsonCase& c = GetParam();
  const std::string out = temp_dir("json_" + c.schema);
  const CommandResult r = run_command(shell_quote(ccomp_binary()) + " " + expand(c.command, out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_FALSE(r.out.empty());
  write_file(out + "/out.json", r.out);
  const CommandResult v = validate(c.schema, out + "/out.json");
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err << "\n" << r.out.substr(0, 2000);
}

const std::string kGeometric = "-m {s}/samples/machines/hmc-xyzb-geometric.yaml";
const std::string kData = " {s}/samples/measurements/hmc-laser-grid-sphere.csv ";
const std::string kTools = " --tool-table {s}/samples/tools.tbl";

INSTANTIATE_TEST_SUITE_P(
    Commands, JsonOutput,
    ::testing::Values(
        JsonCase{"compensate", "{s}/samples/programs/pocket-xy.ngc " + kGeometric + kTools + " -o {out}/p.ngc --json"},
        JsonCase{"predict", "predict {s}/samples/programs/pocket-xy.ngc " + kGeometric + kTools + " --json"},
        JsonCase{"verify", "verify {s}/samples/programs/pocket-xy.ngc {s}/samples/programs/pocket-xy.ngc " +
                               kGeometric + kTools + " --tolerance 0.1 --json"},
        JsonCase{"trace", "trace {s}/samples/programs/pocket-xy.ngc" + kTools + " --json"},
        JsonCase{"flatten", "flatten {s}/samples/programs/pocket-xy.ngc" + kTools + " --json"},
        JsonCase{"fit", "fit" + kData + kGeometric + " -o {out}/fitted.yaml --json"},
        JsonCase{"check", "check" + kData + kGeometric + " --json"},
        JsonCase{"simulate", "simulate -m {s}/samples/machines/vmc-xyz.yaml -o {out}/nl.csv --json"},
        JsonCase{"positioning", "positioning" + kData + kGeometric + " --axis x --json"},
        JsonCase{"nine-line", "nine-line {s}/samples/measurements/hmc-laser-grid-sphere.csv " + kGeometric + " --json"},
        JsonCase{"export", "export " + kGeometric + " --control siemens --axis X -o {out}/x.spf --json"},
        JsonCase{"export-volume", "export " + kGeometric + " --control isg --step 100 -o {out}/v.csv --json"},
        JsonCase{"plan", "plan" + kData + kGeometric + kTools +
                             " --program {s}/samples/programs/pocket-xy.ngc --budget 200 -o {out}/plan.csv --json"}),
    [](const ::testing::TestParamInfo<JsonCase>& param) {
      std::string name = param.param.schema;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

// The validator can fail: a document missing a required field is refused.
TEST(JsonOutputValidator, RefusesADocumentThatBreaksTheSchema) {
  const std::string out = temp_dir("json_broken");
  write_file(out + "/broken.json", "{\"command\": \"simulate\", \"model\": \"m\", \"output\": \"x.csv\"}\n");
  const CommandResult v = validate("simulate", out + "/broken.json");
  EXPECT_NE(v.exit_code, 0);
  EXPECT_NE(v.err.find("observations"), std::string::npos) << v.err;
}

// Same figures as the text, same units: the main job's summary line against its JSON.
TEST(JsonOutputUnits, TheMainJobsFiguresAreTheTextsInMicrometres) {
  const std::string out = temp_dir("json_units");
  const std::string common = expand("{s}/samples/programs/pocket-xy.ngc " + kGeometric + kTools, out);
  const CommandResult text = run_command(shell_quote(ccomp_binary()) + " " + common + " -o " + out + "/a.ngc");
  const CommandResult json = run_command(shell_quote(ccomp_binary()) + " " + common + " -o " + out + "/b.ngc --json");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  ASSERT_EQ(json.exit_code, 0) << json.err;
  std::smatch t, j;
  ASSERT_TRUE(std::regex_search(text.err, t, std::regex("error before ([0-9.]+) um, after ([0-9.]+) um")));
  ASSERT_TRUE(
      std::regex_search(json.out, j, std::regex("\"error_before_um\": ([0-9.]+).*\"error_after_um\": ([0-9.]+)")));
  EXPECT_NEAR(std::stod(t[1]), std::stod(j[1]), 0.005);
  EXPECT_NEAR(std::stod(t[2]), std::stod(j[2]), 0.005);
  EXPECT_TRUE(json.err.empty()) << json.err;  // the summary line is the JSON's, not printed twice
}

TEST(JsonOutputUnits, StandardOutputCannotCarryBothTheProgramAndTheJson) {
  const CommandResult r =
      run_command(shell_quote(ccomp_binary()) + " " +
                  expand("{s}/samples/programs/pocket-xy.ngc " + kGeometric + kTools, "") + " -o - --json");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--json"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ccomp::test
