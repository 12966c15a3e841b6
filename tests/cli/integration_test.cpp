// The hooks of docs/integration.md, run the way their hosts run them: LinuxCNC's [FILTER]
// entry, the shop-floor batch script, and the FreeCAD wrapper's compensate().
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

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

TEST(Integration, LinuxcncFilterEntryRunsAsLinuxcncRunsIt) {
  // Take the `ngc =` command from the shipped INI snippet, point it at our model, append the
  // program's path (what LinuxCNC does) and read stdout.
  std::string command;
  static const std::regex ngc(R"(^ngc\s*=\s*(.*)$)");
  for (const std::string& line : read_lines(source_dir() + "/integration/linuxcnc/ccomp-filter.ini")) {
    std::smatch m;
    if (std::regex_match(line, m, ngc)) command = m[1].str();
  }
  ASSERT_FALSE(command.empty()) << "no `ngc =` line in the INI snippet";
  ASSERT_EQ(command.rfind("ccomp ", 0), 0U);
  command.replace(0, 5, shell_quote(ccomp_binary()));
  command =
      std::regex_replace(command, std::regex("/etc/ccomp/machine.yaml"), source_dir() + "/samples/machines/zero.yaml");
  command = std::regex_replace(command, std::regex("/etc/ccomp/tool.tbl"), source_dir() + "/samples/tools.tbl");
  const std::string dir = temp_dir("filter");
  write_file(dir + "/part.ngc", kProgram);
  const CommandResult r = run_command(command + " " + dir + "/part.ngc");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(strip_header(r.out), kProgram);
  EXPECT_NE(r.err.find("FILTER_PROGRESS=100"), std::string::npos);

  write_file(dir + "/bad.ngc", "G0 X1\nG2 X5 F10\nM2\n");
  const CommandResult bad = run_command(command + " " + dir + "/bad.ngc");
  EXPECT_EQ(bad.exit_code, 3);
  EXPECT_NE(bad.err.find("bad.ngc:2"), std::string::npos) << bad.err;
}

TEST(Integration, BatchScriptCompensatesAFolder) {
  const std::string dir = temp_dir("batch_script");
  fs::create_directories(dir + "/in");
  write_file(dir + "/in/a.ngc", kProgram);
  write_file(dir + "/in/b.NC", kProgram);
  write_file(dir + "/in/notes.txt", "not a program");
  const std::string script = shell_quote(source_dir() + "/integration/batch/ccomp-batch.sh");
  const CommandResult r = run_command("CCOMP=" + shell_quote(ccomp_binary()) + " JOBS=2 bash " + script + " " + dir +
                                      "/in " + dir + "/out " + source_dir() + "/samples/machines/zero.yaml");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_EQ(strip_header(read_file(dir + "/out/a.ngc")), kProgram);
  EXPECT_EQ(strip_header(read_file(dir + "/out/b.NC")), kProgram);
  EXPECT_FALSE(fs::exists(dir + "/out/notes.txt"));
  EXPECT_NE(r.out.find("2 of 2 programs compensated"), std::string::npos) << r.out;

  write_file(dir + "/in/c.ngc", "G0 X1\nG12.3\nM2\n");
  const CommandResult failing = run_command("CCOMP=" + shell_quote(ccomp_binary()) + " bash " + script + " " + dir +
                                            "/in " + dir + "/out2 " + source_dir() + "/samples/machines/zero.yaml");
  EXPECT_EQ(failing.exit_code, 3);
  EXPECT_NE(failing.out.find("2 of 3 programs"), std::string::npos) << failing.out;
  EXPECT_NE(read_file(dir + "/out2/ccomp-batch.log").find("c.ngc:2"), std::string::npos);
}

TEST(Integration, FreecadWrapperCompensatesInPlace) {
  if (run_command("command -v python3").exit_code != 0) GTEST_SKIP() << "python3 not installed";
  const std::string dir = temp_dir("freecad");
  write_file(dir + "/part.nc", kProgram);
  const CommandResult r = run_command(
      "cd " + shell_quote(source_dir() + "/integration/freecad") + " && CCOMP=" + shell_quote(ccomp_binary()) +
      " CCOMP_MODEL=" + shell_quote(source_dir() + "/samples/machines/zero.yaml") +
      " python3 -c 'import ccomp_post, sys; ccomp_post.compensate(sys.argv[1])' " + dir + "/part.nc");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(strip_header(read_file(dir + "/part.nc")), kProgram);
  EXPECT_EQ(read_file(dir + "/part.nc.orig"), kProgram);
}

}  // namespace
}  // namespace ccomp::test
