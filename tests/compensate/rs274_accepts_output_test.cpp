// What the job writes must run on the control. LinuxCNC's own interpreter, rs274, reads
// every program of its suite that it accepts as written, compensated (--flatten) for three
// sample machines, and with --expand-cycles: it must accept the output too. This caught
// chords and split moves under cutter radius compensation, which it refuses. A sample
// machine may refuse a program for what the machine is (an axis it lacks, its limits) or
// what ccomp does not compensate yet (exit 7 or 4); nothing else. The machine without error
// and with every axis (samples/machines/zero.yaml) takes every program rs274 takes, flattened
// (a program LinuxCNC's own tests expect rejected, or out of ccomp's scope, may be refused
// there too, as a program error): a program no machine with error terms compensates is
// skipped with their reasons.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>
#include <tuple>
#include <utility>

#include "ccomp/error.hpp"
#include "ccomp/exit_codes.hpp"
#include "linuxcnc_suite.hpp"
#include "rs274_oracle.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

class Rs274AcceptsOutput : public ::testing::TestWithParam<SuiteProgram> {};

TEST_P(Rs274AcceptsOutput, OnTheSampleMachinesAndWithCyclesExpanded) {
  CCOMP_REQUIRE_RS274();
  const fs::path path = fs::path(corpus_dir()) / "linuxcnc" / GetParam().path;
  // What LinuxCNC's own tests expect ccomp to refuse, or what is out of ccomp's scope, may
  // be refused even by the machine that takes every program (the suite test holds ccomp to
  // a refusal it expects).
  if (GetParam().path.find("endless-loop") != std::string::npos)
    GTEST_SKIP() << "rs274 loops for ever on it (what the suite tests)";
  if (GetParam().path.find("12-M99-endless-main-program") != std::string::npos)
    GTEST_SKIP() << "M99 in a main program restarts it for ever on a controller; ccomp ends there (out of scope, "
                    "tests/gcode/linuxcnc_suite_test.cpp)";
  const SuiteCase* c = suite_case(GetParam().path);
  const std::string may_refuse = !c                                  ? ""
                                 : c->expect == Expect::out_of_scope ? std::string("out of scope: ") + c->reason
                                 : c->expect == Expect::rejected
                                     ? "LinuxCNC's test expects it rejected (tests/gcode/linuxcnc_suite_test.cpp)"
                                     : "";
  const std::string dir = temp_dir("rs274_accepts");
  std::string tools = (path.parent_path() / "test.tbl").string();
  if (!fs::exists(tools)) write_file(tools = dir + "/tools.tbl", "T1 P1 Z1 D0.25 ;\n");
  if (const TraceResult original = rs274_trace(path.string(), tools); original.error)
    GTEST_SKIP() << "rs274 refuses the original: " << original.error->what();
  // The VMC's model without its travel limits too: LinuxCNC's tests run inch programs metres
  // long, which every sample machine refuses for its limits.
  std::string unlimited = read_file(source_dir() + "/samples/machines/vmc-xyz.yaml");
  unlimited = std::regex_replace(unlimited, std::regex(", min: -?[0-9.]+, max: -?[0-9.]+"), "");
  write_file(dir + "/vmc-xyz-unlimited.yaml", unlimited);
  auto sample = [](const char* name) { return source_dir() + "/samples/machines/" + name + ".yaml"; };
  const std::tuple<std::string, std::string, const char*> runs[] = {
      {"zero", sample("zero"), ""},
      {"vmc-xyz", sample("vmc-xyz"), ""},
      {"hmc-xyzb-geometric", sample("hmc-xyzb-geometric"), ""},
      // (the full HMC: backlash, and thermal terms at the bench's readings)
      {"hmc-xyzb", sample("hmc-xyzb"), " --sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600"},
      {"vmc-xyz", sample("vmc-xyz"), " --expand-cycles"},
      {"vmc-xyz-unlimited", dir + "/vmc-xyz-unlimited.yaml", " --expand-cycles"}};
  int compensated = 0;  // outputs of a machine with error terms that rs274 read
  std::string refusals;
  for (const auto& [machine, model, options] : runs) {
    const std::string out = dir + "/" + machine + ".ngc";
    const CommandResult job =
        run_command("cd " + shell_quote(path.parent_path().string()) + " && " + shell_quote(ccomp_binary()) + " " +
                    shell_quote(path.filename().string()) + " -m " + shell_quote(model) + " --tool-table " +
                    shell_quote(tools) + " --machine-units inch --flatten" + options + " -q -o " + shell_quote(out));
    const bool zero = machine == "zero";
    const bool refused_for_a_reason = job.exit_code == exit_code(ErrorKind::safety) ||
                                      job.exit_code == exit_code(ErrorKind::unsupported) ||
                                      (zero && job.exit_code == exit_code(ErrorKind::program));
    if (job.exit_code != 0 && refused_for_a_reason && (!zero || !may_refuse.empty())) {
      if (zero) GTEST_SKIP() << may_refuse << "\n" << job.err;
      refusals += machine + options + ": " + job.err.substr(0, job.err.find('\n')) + "\n";
      continue;  // what the machine is, or what ccomp does not do: nothing written
    }
    // Exit 1: written, its verdict failed (over the tolerance under the control's G41/G42,
    // say); what is written must still be what rs274 accepts.
    ASSERT_TRUE(job.exit_code == 0 || job.exit_code == kVerdictExitCode)
        << machine << options << " refuses what rs274 accepts:\n" << job.err;
    const TraceResult theirs = rs274_trace(out, tools);
    EXPECT_FALSE(theirs.error) << machine << options << ": " << theirs.error->what() << "\n" << read_file(out);
    compensated += zero ? 0 : 1;
  }
  // Only the machine without error wrote it (its output is the program, flattened): said.
  if (compensated == 0) GTEST_SKIP() << "no machine with error terms compensates it:\n" << refusals;
}

INSTANTIATE_TEST_SUITE_P(Corpus, Rs274AcceptsOutput, ::testing::ValuesIn(suite_programs()), suite_test_name);

}  // namespace
}  // namespace ccomp::test
