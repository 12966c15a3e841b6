// The hooks of docs/integration.md, run the way their hosts run them: LinuxCNC's [FILTER]
// entry as AXIS runs it, the shop-floor batch script, the FreeCAD post wrapper as FreeCAD
// calls a post processor, and the Fusion 360 hook as Fusion calls onTerminate().
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <sstream>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

const char* kProgram = "G21 G90\nG0 X1 Y2\nG1 X3 F100\nM2\n";

std::string strip_header(std::string text) {
  const auto at = text.find("(ccomp ");
  if (at != std::string::npos) text.erase(at, text.find('\n', at) - at + 1);
  return text;
}

/// The `ngc =` command of the shipped INI snippet, pointed at this build and a sample model.
std::string filter_entry(const std::string& model) {
  std::string command;
  static const std::regex ngc(R"(^ngc\s*=\s*(.*)$)");
  for (const std::string& line : read_lines(source_dir() + "/integration/linuxcnc/ccomp-filter.ini")) {
    std::smatch m;
    if (std::regex_match(line, m, ngc)) command = m[1].str();
  }
  EXPECT_FALSE(command.empty()) << "no `ngc =` line in the INI snippet";
  EXPECT_EQ(command.rfind("ccomp ", 0), 0U);
  if (command.rfind("ccomp ", 0) != 0) return "false";
  command.replace(0, 5, shell_quote(ccomp_binary()));
  command = std::regex_replace(command, std::regex("/etc/ccomp/machine.yaml"), model);
  return std::regex_replace(command, std::regex("/etc/ccomp/tool.tbl"), source_dir() + "/samples/tools.tbl");
}

struct FilterRun {
  int exit_code = -1;
  std::string loaded;         ///< stdout: the program AXIS loads
  std::vector<int> progress;  ///< the FILTER_PROGRESS=N values, in order
  std::string shown;          ///< the other stderr lines: AXIS's "Filter failed" dialog text
};

/// Runs a [FILTER] command as AXIS's filter_program() does (axis.py; QtVCP and GladeVCP
/// copy it): `sh -c "<command> '<path>'"` with the path single-quoted ('\'' for a quote in
/// it), AXIS_PROGRESS_BAR=1 added to the environment, standard input at end of file,
/// standard output to the file it then loads, and each stderr line matching
/// ^FILTER_PROGRESS=(\d*)$ taken for the progress bar while the rest is shown to the user
/// when the exit code is not 0.
FilterRun run_as_axis(const std::string& filter, const std::string& path) {
  std::string quoted;
  for (char c : path) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  const CommandResult r =
      run_command("AXIS_PROGRESS_BAR=1 sh -c " + shell_quote(filter + " '" + quoted + "'"), /*stdin_text=*/"");
  FilterRun run;
  run.exit_code = r.exit_code;
  run.loaded = r.out;
  static const std::regex progress(R"(^FILTER_PROGRESS=(\d*)$)");
  std::istringstream err(r.err);
  for (std::string line; std::getline(err, line);) {
    std::smatch m;
    if (std::regex_match(line, m, progress))
      run.progress.push_back(m[1].str().empty() ? 0 : std::stoi(m[1].str()));
    else
      run.shown += line + "\n";
  }
  return run;
}

TEST(Integration, LinuxcncFilterEntryRunsAsAxisRunsIt) {
  const std::string filter = filter_entry(source_dir() + "/samples/machines/zero.yaml");
  const std::string dir = temp_dir("filter");
  // A quote and a blank in the folder's name: AXIS quotes the path for sh itself.
  fs::create_directories(dir + "/it's here");
  write_file(dir + "/it's here/part.ngc", kProgram);
  const FilterRun r = run_as_axis(filter, dir + "/it's here/part.ngc");
  ASSERT_EQ(r.exit_code, 0) << r.shown;
  EXPECT_EQ(strip_header(r.loaded), kProgram);
  ASSERT_FALSE(r.progress.empty()) << "no FILTER_PROGRESS lines for the progress bar";
  for (int p : r.progress) {
    EXPECT_GE(p, 0);
    EXPECT_LE(p, 100);
  }

  write_file(dir + "/bad.ngc", "G0 X1\nG2 X5 F10\nM2\n");
  const FilterRun bad = run_as_axis(filter, dir + "/bad.ngc");
  EXPECT_EQ(bad.exit_code, 3);
  EXPECT_NE(bad.shown.find("bad.ngc:2"), std::string::npos) << bad.shown;
}

TEST(Integration, LinuxcncFilterTakesTheAppendedPathAfterAnyOption) {
  // A [FILTER] line may end with any option; LinuxCNC appends the path after it. Options that
  // repeat (--sensor, --param, --sub-path) must not take the path as one more value: the
  // filter's output must be what the same options give with the path first.
  const std::string dir = temp_dir("filter_last");
  fs::create_directories(dir + "/subs");
  write_file(dir + "/subs/square.ngc", "O<square> sub\nG1 X[#1] F100\nG1 Y[#1]\nO<square> endsub\nM2\n");
  write_file(dir + "/part.ngc", kProgram);
  write_file(dir + "/calls.ngc", "G21 G90\nG0 X0 Y0\nO<square> call [4]\nM2\n");
  write_file(dir + "/reads.ngc", "G21 G90\nG0 X[#5063] Y2\nM2\n");
  const std::string hmc = source_dir() + "/samples/machines/hmc-xyzb.yaml";
  const std::string zero = source_dir() + "/samples/machines/zero.yaml";
  struct Case {
    std::string model, program, options;
  };
  for (const Case& c :
       {Case{hmc, "part.ngc", "--sensor bed=24 --sensor column=23 --sensor spindle=31"},
        Case{zero, "reads.ngc", "--param 5063=1.5"}, Case{zero, "reads.ngc", "--param 5064=2 --param 5063=1.5"},
        Case{zero, "calls.ngc", "--sub-path " + shell_quote(dir + "/subs")}}) {
    SCOPED_TRACE(c.options);
    const std::string program = dir + "/" + c.program;
    const CommandResult direct =
        run_command(shell_quote(ccomp_binary()) + " " + shell_quote(program) + " -m " + shell_quote(c.model) +
                    " --tool-table " + shell_quote(source_dir() + "/samples/tools.tbl") + " -o - " + c.options);
    ASSERT_EQ(direct.exit_code, 0) << direct.err;
    const FilterRun r = run_as_axis(filter_entry(c.model) + " " + c.options, program);
    ASSERT_EQ(r.exit_code, 0) << r.shown;
    EXPECT_EQ(r.loaded, direct.out);
    EXPECT_FALSE(r.progress.empty());
  }
  // Without the option, the programs that need it are refused: the option was used.
  EXPECT_EQ(run_as_axis(filter_entry(zero), dir + "/calls.ngc").exit_code, 3);
}

TEST(Integration, BatchScriptCountsWhatCcompCompensated) {
  const std::string dir = temp_dir("batch_script");
  fs::create_directories(dir + "/in");
  // A small machine: X within +-100, so a program can be refused as unsafe (exit 7).
  write_file(dir + "/m.yaml", "name: small\naxes: {X: {min: -100, max: 100}, Y: {min: -100, max: 100}}\n");
  write_file(dir + "/in/a.ngc", kProgram);
  write_file(dir + "/in/b.NC", kProgram);
  write_file(dir + "/in/c.tap", kProgram);
  write_file(dir + "/in/notes.txt", "not a program");
  const std::string batch = "CCOMP=" + shell_quote(ccomp_binary()) + " JOBS=2 bash " +
                            shell_quote(source_dir() + "/integration/batch/ccomp-batch.sh") + " " + dir + "/in " + dir +
                            "/out " + dir + "/m.yaml";
  const CommandResult r = run_command(batch);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_EQ(strip_header(read_file(dir + "/out/a.ngc")), kProgram);
  EXPECT_EQ(strip_header(read_file(dir + "/out/b.NC")), kProgram);
  EXPECT_FALSE(fs::exists(dir + "/out/notes.txt"));
  EXPECT_NE(r.out.find("3 of 3 programs compensated"), std::string::npos) << r.out;

  // The programs change: b now has a G-code error (3), c goes beyond X's limit (7). Their
  // outputs of the first run are still in the folder; they must not be counted.
  write_file(dir + "/in/b.NC", "G0 X1\nG12.3\nM2\n");
  write_file(dir + "/in/c.tap", "G21 G90\nG0 X150\nM2\n");
  const CommandResult failing = run_command(batch);
  EXPECT_EQ(failing.exit_code, 7) << "the highest of the programs' codes";
  EXPECT_NE(failing.out.find("1 of 3 programs compensated"), std::string::npos) << failing.out;
  EXPECT_NE(failing.out.find("b.NC not compensated (exit 3)"), std::string::npos) << failing.out;
  EXPECT_NE(failing.out.find("c.tap not compensated (exit 7) (" + dir + "/out/c.tap is an earlier run's output"),
            std::string::npos)
      << failing.out;
  EXPECT_EQ(failing.out.find("a.ngc not compensated"), std::string::npos) << failing.out;
  const std::string log = read_file(dir + "/out/ccomp-batch.log");
  EXPECT_NE(log.find("b.NC:2"), std::string::npos) << log;
  EXPECT_NE(log.find("c.tap:2:1: refused: axis X would go to 150"), std::string::npos) << log;

  // Only the program error: its code, 3.
  write_file(dir + "/in/c.tap", kProgram);
  const CommandResult one = run_command(batch);
  EXPECT_EQ(one.exit_code, 3);
  EXPECT_NE(one.out.find("2 of 3 programs compensated"), std::string::npos) << one.out;
}

TEST(Integration, BatchScriptSaysAnOutputThatFailedItsVerdict) {
  // The G41 profile on the full sample HMC keeps more than 1 um: ccomp writes it and exits 1.
  // The batch must say it was written but not passed, not that it was not compensated.
  const std::string dir = temp_dir("batch_verdict");
  fs::create_directories(dir + "/in");
  fs::copy_file(source_dir() + "/samples/programs/profile-g41.ngc", dir + "/in/profile-g41.ngc");
  write_file(dir + "/in/a.ngc", kProgram);
  const std::string script =
      "CCOMP=" + shell_quote(ccomp_binary()) + " JOBS=2 bash " +
      shell_quote(source_dir() + "/integration/batch/ccomp-batch.sh") + " " + dir + "/in " + dir + "/out " +
      shell_quote(source_dir() + "/samples/machines/hmc-xyzb.yaml") + " " +
      shell_quote(source_dir() + "/samples/tools.tbl") + " --sensor bed=20 --sensor column=20 --sensor spindle=20";
  const CommandResult r = run_command(script);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("profile-g41.ngc compensated but NOT PASSED (exit 1)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("not compensated"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 of 2 programs compensated and passed"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir + "/out/profile-g41.ngc")) << "the output is written all the same";
}

TEST(Integration, BatchScriptPassesAnyCcompOption) {
  // The full sample HMC has thermal terms: without its sensors every program is refused; the
  // options after the model (with or without `--`, after the tool table or in its place)
  // reach every ccomp, and each output is what ccomp gives with them by hand.
  const std::string dir = temp_dir("batch_options");
  fs::create_directories(dir + "/in");
  const std::string hmc = source_dir() + "/samples/machines/hmc-xyzb.yaml";
  const std::string tools = source_dir() + "/samples/tools.tbl";
  const std::string tool_program = "G21 G90 G54\nT1 M6\nG43 H1\nG0 X10 Y20 Z50\nG1 X60 F300\nG1 Y80\nM2\n";
  for (const char* name : {"a.ngc", "b.ngc", "c.nc", "d.tap"}) write_file(dir + "/in/" + name, kProgram);
  write_file(dir + "/in/tool.ngc", tool_program);  // G43 H1: needs the tool table
  const std::string script = "CCOMP=" + shell_quote(ccomp_binary()) + " JOBS=2 bash " +
                             shell_quote(source_dir() + "/integration/batch/ccomp-batch.sh") + " " + dir + "/in " +
                             dir + "/out " + shell_quote(hmc);
  const std::string sensors = "--sensor bed=24 --sensor column=23 --sensor spindle=31 --time 3600";

  const CommandResult bare = run_command(script);
  EXPECT_NE(bare.exit_code, 0) << bare.out << bare.err;
  EXPECT_NE(bare.out.find("0 of 5 programs compensated"), std::string::npos) << bare.out;
  EXPECT_NE(read_file(dir + "/out/ccomp-batch.log").find("bed"), std::string::npos) << "the missing sensor named";

  for (const std::string& options : {" -- " + sensors + " --tool-table " + shell_quote(tools),
                                     " " + shell_quote(tools) + " " + sensors + " --dialect linuxcnc",
                                     " " + shell_quote(tools) + " -- " + sensors}) {
    SCOPED_TRACE(options);
    fs::remove_all(dir + "/out");
    const CommandResult r = run_command(script + options);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("5 of 5 programs compensated"), std::string::npos) << r.out;
    for (const char* name : {"a.ngc", "tool.ngc"}) {
      const CommandResult direct =
          run_command(shell_quote(ccomp_binary()) + " " + shell_quote(dir + "/in/" + name) + " -m " + shell_quote(hmc) +
                      " --tool-table " + shell_quote(tools) + " " + sensors + " -o -");
      ASSERT_EQ(direct.exit_code, 0) << direct.err;
      EXPECT_EQ(read_file(dir + "/out/" + name), direct.out) << name;
    }
  }
  // The thermal terms moved the points: the options were not dropped on the way.
  EXPECT_NE(strip_header(read_file(dir + "/out/tool.ngc")), tool_program);

  // A bad option reaches every ccomp, which refuses it as usage (exit 2).
  const CommandResult bad = run_command(script + " -- --dialect klingon");
  EXPECT_EQ(bad.exit_code, 2) << bad.out;
  EXPECT_NE(bad.out.find("0 of 5 programs compensated"), std::string::npos) << bad.out;
}

TEST(Integration, FreecadPostRunsAsFreecadRunsIt) {
  // tests/cli/freecad/freecad_post_test.py imports the wrapper by name with stubs of the
  // FreeCAD modules a post imports, and calls export(objects, filename, argstring) as FreeCAD
  // 0.21 (a file name) and 1.0 ("-") do. python3 is a test dependency: no python, a failure.
  ASSERT_EQ(run_command("command -v python3").exit_code, 0) << "python3 is needed to run the FreeCAD post's test";
  const CommandResult r = run_command("CCOMP=" + shell_quote(ccomp_binary()) + " python3 " +
                                      shell_quote(source_dir() + "/tests/cli/freecad/freecad_post_test.py"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("Ran 0 tests"), std::string::npos) << r.err;
  EXPECT_NE(r.err.rfind("\nOK"), std::string::npos) << r.err;
}

TEST(Integration, Fusion360HookRunsAsFusionRunsIt) {
  // tests/cli/fusion360/fusion_hook_test.js runs the hook's onTerminate() under node with stubs
  // of Fusion's post functions; its execute() stands for wsl.exe (Windows command line taken
  // apart, /mnt/c/ mapped to a folder) and runs this build's ccomp.
  ASSERT_EQ(run_command("command -v node").exit_code, 0) << "node is needed to run the Fusion 360 hook's test";
  const CommandResult r = run_command("CCOMP=" + shell_quote(ccomp_binary()) + " node " +
                                      shell_quote(source_dir() + "/tests/cli/fusion360/fusion_hook_test.js"));
  EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("all checks passed"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace ccomp::test
