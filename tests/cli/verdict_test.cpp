// One verdict: the main job's 'after' is its output measured as `ccomp verify` measures it
// (the same function), so the two agree on the same output; an output over the tolerance
// or worse than the program as written is still written, said so, and exits with 1; and
// --json carries every warning the text run prints.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <sstream>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;


/// A warm machine's readings for the full HMC's thermal and warm-up terms.
const std::string kWarm = " --sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600";

struct SampleRun {
  std::string machine;  ///< samples/machines/<machine>.yaml
  std::string program;  ///< samples/programs/<program>
  std::string extra;    ///< the main job's other options
};

CommandResult compensate(const SampleRun& r, const std::string& output, const std::string& more = "") {
  return run_command(shell_quote(ccomp_binary()) + " " + sample("programs/" + r.program) + " -m " +
                     sample("machines/" + r.machine + ".yaml") + " --tool-table " + sample("tools.tbl") + r.extra +
                     " -o " + shell_quote(output) + more);
}

/// verify of `output` with nothing but the model and the tool table: the tolerance and the
/// readings come from the output's header.
CommandResult verify(const SampleRun& r, const std::string& output) {
  return run_command(shell_quote(ccomp_binary()) + " verify " + sample("programs/" + r.program) + " " +
                     shell_quote(output) + " -m " + sample("machines/" + r.machine + ".yaml") + " --tool-table " +
                     sample("tools.tbl"));
}

double figure(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) {
    ADD_FAILURE() << "no '" << pattern << "' in:\n" << text;
    return -1;
  }
  return std::stod(m[1]);
}

/// The warnings a run printed, "file:line: message" each, in order.
std::vector<std::string> printed_warnings(const std::string& err) {
  std::vector<std::string> out;
  std::istringstream lines(err);
  const std::regex warning(R"(^(.*:\d+): warning: (.*)$)");
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, warning)) out.push_back(m[1].str() + ": " + m[2].str());
  }
  return out;
}

/// The warnings of --json's first program, "file:line: message" each, in order.
std::vector<std::string> json_warnings(const std::string& json) {
  std::vector<std::string> out;
  const std::regex warning(R"re(\{"file": "([^"]*)", "line": (\d+), "message": "((?:[^"\\]|\\.)*)"\})re");
  for (auto it = std::sregex_iterator(json.begin(), json.end(), warning); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1].str() + ":" + (*it)[2].str() + ": " + (*it)[3].str());
  return out;
}

class OneVerdict : public ::testing::TestWithParam<SampleRun> {};

// The summary's 'after' and verify's max on the same output agree to the printed rounding,
// and the job fails exactly where verify does.
TEST_P(OneVerdict, TheJobsAfterIsVerifysFigure) {
  const SampleRun& r = GetParam();
  const std::string out = temp_dir("verdict_" + r.machine) + "/" + r.program;
  const CommandResult job = compensate(r, out);
  ASSERT_TRUE(job.exit_code == 0 || job.exit_code == 1) << job.err;
  ASSERT_TRUE(fs::exists(out)) << "the output is written whatever the verdict";
  const CommandResult check = verify(r, out);
  ASSERT_TRUE(check.exit_code == 0 || check.exit_code == 7) << check.err;
  const double after = figure(job.err, R"(after ([0-9.]+) um)");
  const double measured = figure(check.out, R"(max ([0-9.]+) um)");
  EXPECT_NEAR(after, measured, 0.0051) << job.err << check.out;
  EXPECT_EQ(job.exit_code == 1, check.exit_code == 7) << job.err << check.out << check.err;
}

INSTANTIATE_TEST_SUITE_P(
    Samples, OneVerdict,
    ::testing::Values(SampleRun{"hmc-xyzb", "profile-g41.ngc", kWarm},  // the G41 profile: over the tolerance
                      SampleRun{"hmc-xyzb", "wrap-g93-xb.ngc", kWarm}, SampleRun{"hmc-xyzb-geometric", "pocket-xy.ngc", ""},
                      SampleRun{"vmc-xyz", "profile-g41.ngc", ""}, SampleRun{"vmc-xyzac-trunnion", "five-axis-xyzac.ngc", ""}),
    [](const ::testing::TestParamInfo<SampleRun>& p) {
      std::string name = p.param.machine + "_" + p.param.program;
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return name;
    });

// The G41 profile on the full HMC keeps more than 1 um where the control's own offset runs
// the corrections' pieces: written, said so, exit 1 (verify of it exits 7).
TEST(Verdict, AnOutputOverTheToleranceIsWrittenSaidSoAndExitsWithOne) {
  const SampleRun r{"hmc-xyzb", "profile-g41.ngc", kWarm};
  const std::string dir = temp_dir("verdict_over");
  const CommandResult job = compensate(r, dir + "/p.ngc");
  EXPECT_EQ(job.exit_code, 1) << job.err;
  EXPECT_NE(job.err.find("NOT PASSED"), std::string::npos) << job.err;
  EXPECT_NE(job.err.find("is more than the tolerance of 1.00 um; the output is written"), std::string::npos)
      << job.err;
  EXPECT_NE(read_file(dir + "/p.ngc").find("(ccomp "), std::string::npos);
  // The same through standard output (the output is judged before it is copied there).
  const CommandResult piped = compensate(r, "-");
  EXPECT_EQ(piped.exit_code, 1) << piped.err;
  EXPECT_EQ(piped.out, read_file(dir + "/p.ngc"));
  EXPECT_NE(piped.err.find("<stdout>"), std::string::npos) << piped.err;
}

// --tolerance 1mm (a bare 1 is refused as implausible): the arcs become chords far off the
// path, within that tolerance but far worse than the program as written. Written, said so,
// exit 1.
TEST(Verdict, AnOutputWorseThanTheProgramAsWrittenExitsWithOne) {
  const SampleRun r{"vmc-xyz", "pocket-xy.ngc", " --tolerance 1mm"};
  const std::string dir = temp_dir("verdict_worse");
  const CommandResult job = compensate(r, dir + "/p.ngc");
  EXPECT_EQ(job.exit_code, 1) << job.err;
  const double before = figure(job.err, R"(error before ([0-9.]+) um)");
  const double after = figure(job.err, R"(after ([0-9.]+) um)");
  EXPECT_GT(after, before + 100.0) << job.err;  // a tenth of the tolerance is 100 um
  EXPECT_NE(job.err.find("is worse than the program as written"), std::string::npos) << job.err;
  EXPECT_TRUE(fs::exists(dir + "/p.ngc"));
  // At the default tolerance the same program passes.
  const CommandResult fine = compensate(SampleRun{"vmc-xyz", "pocket-xy.ngc", ""}, dir + "/q.ngc");
  EXPECT_EQ(fine.exit_code, 0) << fine.err;
  EXPECT_EQ(fine.err.find("warning"), std::string::npos) << fine.err;
}

// Every warning the text run prints is in --json, in order, with its file and line; the
// verdict's included, with passed: false and the program's exit code 1.
TEST(Verdict, JsonCarriesEveryWarningPrinted) {
  const SampleRun r{"hmc-xyzb", "profile-g41.ngc", kWarm};
  const std::string dir = temp_dir("verdict_json");
  const CommandResult text = compensate(r, dir + "/a.ngc");
  const CommandResult json = compensate(r, dir + "/a.ngc", " --json");
  EXPECT_EQ(json.exit_code, 1) << json.err;
  const std::vector<std::string> printed = printed_warnings(text.err);
  ASSERT_FALSE(printed.empty()) << text.err;
  EXPECT_EQ(json_warnings(json.out), printed) << json.out;
  EXPECT_EQ(printed_warnings(json.err), printed) << "the JSON run prints the same warnings";
  EXPECT_NE(json.out.find("\"passed\": false"), std::string::npos) << json.out;
  EXPECT_NE(json.out.find("\"exit_code\": 1"), std::string::npos) << json.out;
}

}  // namespace
}  // namespace ccomp::test
