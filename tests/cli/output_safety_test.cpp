// Nothing of the user's is lost: no output replaces what the run reads, or a link, a
// device or a FIFO; --in-place never replaces a backup; every write error is exit 6; an
// interrupted or killed run leaves the previous output and, by the next run, no temporary.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "trace_capture.hpp"

extern char** environ;

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

constexpr const char* kProgram = "G21 G90\nG0 X1 Y2\nG1 X3 F100\nM2\n";

std::string sample_model() {
  return source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml";
}

/// The files in `dir` whose names hold ".ccomp-" (temporary outputs).
std::vector<std::string> temporaries(const std::string& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".ccomp-") != std::string::npos) found.push_back(e.path().string());
  return found;
}

struct Clobber {
  const char* name;
  const char* output;  ///< relative to the test's folder
};
void PrintTo(const Clobber& c, std::ostream* os) {
  *os << c.name;
}

class OutputThatIsAnInput : public ::testing::TestWithParam<Clobber> {};

TEST_P(OutputThatIsAnInput, IsRefusedAndLeftAsItWas) {
  const std::string dir = temp_dir(std::string("clobber_") + GetParam().name);
  write_file(dir + "/part.nc", kProgram);
  write_file(dir + "/other.nc", kProgram);
  write_file(dir + "/tools.tbl", "T1 P1 Z50 D10 ;\n");
  fs::copy_file(sample_model(), dir + "/machine.yaml");
  const std::string model_before = read_file(dir + "/machine.yaml");
  const CommandResult r = run_command("cd " + shell_quote(dir) + " && " + ccomp() +
                                      " part.nc -m machine.yaml --tool-table tools.tbl -o " + GetParam().output);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("which this run reads"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(dir + "/part.nc"), kProgram);
  EXPECT_EQ(read_file(dir + "/machine.yaml"), model_before);
  EXPECT_EQ(read_file(dir + "/tools.tbl"), "T1 P1 Z50 D10 ;\n");
  EXPECT_TRUE(temporaries(dir).empty());
}

INSTANTIATE_TEST_SUITE_P(Cli, OutputThatIsAnInput,
                         ::testing::Values(Clobber{"program", "part.nc"},
                                           Clobber{"program_by_another_path", "./part.nc"},
                                           Clobber{"model", "machine.yaml"}, Clobber{"tool_table", "tools.tbl"}),
                         [](const auto& test) { return std::string(test.param.name); });

TEST(OutputSafety, LinksDevicesFifosAndFoldersAreNotWrittenOver) {
  const std::string dir = temp_dir("not_regular");
  write_file(dir + "/part.nc", kProgram);
  write_file(dir + "/target.nc", "kept\n");
  fs::create_symlink(dir + "/target.nc", dir + "/link.nc");
  ASSERT_EQ(::mkfifo((dir + "/fifo.nc").c_str(), 0600), 0);
  fs::create_directory(dir + "/folder.nc");
  for (const std::string& out : {dir + "/link.nc", dir + "/fifo.nc", dir + "/folder.nc", std::string("/dev/null")}) {
    const CommandResult r = run_command(ccomp() + " " + shell_quote(dir + "/part.nc") + " -m " +
                                        shell_quote(sample_model()) + " -o " + shell_quote(out));
    EXPECT_EQ(r.exit_code, 2) << out << ": " << r.err;
  }
  EXPECT_TRUE(fs::is_symlink(dir + "/link.nc"));
  EXPECT_EQ(read_file(dir + "/target.nc"), "kept\n");
  EXPECT_TRUE(fs::is_fifo(dir + "/fifo.nc"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

TEST(OutputSafety, TwoInputsThatWouldWriteOneOutputAreRefused) {
  const std::string dir = temp_dir("same_output");
  fs::create_directories(dir + "/a");
  fs::create_directories(dir + "/b");
  write_file(dir + "/a/part.nc", kProgram);
  write_file(dir + "/b/part.nc", "G21 G90\nG0 X5\nM2\n");
  const CommandResult r =
      run_command(ccomp() + " " + shell_quote(dir + "/a/part.nc") + " " + shell_quote(dir + "/b/part.nc") + " -m " +
                  shell_quote(sample_model()) + " --out-dir " + shell_quote(dir + "/out"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("would both be written"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/out/part.nc"));
}

TEST(OutputSafety, InPlaceNeverReplacesABackupNorCompensatesOne) {
  const std::string dir = temp_dir("backups");
  const std::string part = dir + "/part.nc";
  write_file(part, kProgram);
  const std::string run = ccomp() + " -m " + shell_quote(sample_model()) + " -q --in-place ";
  ASSERT_EQ(run_command(run + shell_quote(part)).exit_code, 0);
  const std::string once = read_file(part);
  // Again, forced: the original stays in .orig, the compensated text goes to .orig.1.
  ASSERT_EQ(run_command(run + "--force " + shell_quote(part)).exit_code, 0);
  EXPECT_EQ(read_file(part + ".orig"), kProgram);
  EXPECT_EQ(read_file(part + ".orig.1"), once);
  for (const std::string& backup : {part + ".orig", part + ".orig.1"}) {
    const CommandResult r = run_command(run + shell_quote(backup));
    EXPECT_EQ(r.exit_code, 2) << backup;
    EXPECT_NE(r.err.find("is an --in-place backup"), std::string::npos) << r.err;
  }
  EXPECT_EQ(read_file(part + ".orig"), kProgram);
}

TEST(OutputSafety, WriteErrorsOnStandardOutputAreExit6) {
  const std::string dir = temp_dir("full");
  write_file(dir + "/part.nc", kProgram);
  const std::string part = shell_quote(dir + "/part.nc"), model = shell_quote(sample_model());
  const std::string data = shell_quote(source_dir() + "/samples/measurements/hmc-laser-grid-sphere.csv");
  for (const std::string& command :
       {ccomp() + " trace " + part, ccomp() + " flatten " + part, ccomp() + " " + part + " -m " + model + " -o -",
        ccomp() + " check " + data + " -m " + model + " --json"}) {
    const CommandResult r = run_command(command + " > /dev/full");
    EXPECT_EQ(r.exit_code, 6) << command << ": " << r.err;
    EXPECT_NE(r.err.find("cannot write"), std::string::npos) << r.err;
  }
}

/// Starts ccomp with `args` (no shell), its output and errors to /dev/null.
pid_t spawn(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  std::vector<std::string> copy = args;
  for (std::string& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int failed = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return failed ? -1 : pid;
}

/// Waits until a temporary output exists in `dir` (the job is writing): true, or false
/// after 20 s.
bool writing(const std::string& dir) {
  for (int i = 0; i < 2000; ++i) {
    if (!temporaries(dir).empty()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

/// A program long enough to be caught in the middle of its compensation (`moves` G1 blocks).
std::string long_program(int moves = 400000) {
  std::string text = "G21 G90 G0 X0 Y0 Z0\nF1000\n";
  for (int i = 0; i < moves; ++i) text += "G1 X" + std::to_string(i % 400) + ".5 Y" + std::to_string(i % 300) + "\n";
  return text + "M2\n";
}

/// Compensates `dir`/part.nc into `dir`/out.nc and sends `signal` while the output is being
/// written; the job's wait status.
int signalled_while_writing(const std::string& dir, int signal) {
  const pid_t pid = spawn({ccomp_binary(), dir + "/part.nc", "-m", sample_model(), "-o", dir + "/out.nc", "-q"});
  if (pid <= 0) {  // never kill(0 or -1): that would signal the test itself, or everything
    ADD_FAILURE() << "cannot start ccomp";
    return 0;
  }
  EXPECT_TRUE(writing(dir)) << "no temporary output appeared";
  ::kill(pid, signal);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

TEST(OutputSafety, AnInterruptedRunLeavesThePreviousOutputAndNoTemporary) {
  const std::string dir = temp_dir("interrupted");
  write_file(dir + "/part.nc", long_program());
  for (const int signal : {SIGINT, SIGTERM}) {
    write_file(dir + "/out.nc", "previous\n");
    const int status = signalled_while_writing(dir, signal);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the job ended before the signal: make the program longer";
    EXPECT_EQ(WTERMSIG(status), signal);
    EXPECT_EQ(read_file(dir + "/out.nc"), "previous\n");
    EXPECT_TRUE(temporaries(dir).empty()) << ::testing::PrintToString(temporaries(dir));
  }
}

TEST(OutputSafety, AKilledRunsTemporaryIsRemovedByTheNextRun) {
  const std::string dir = temp_dir("killed");
  write_file(dir + "/part.nc", long_program());
  write_file(dir + "/small.nc", kProgram);
  write_file(dir + "/out.nc", "previous\n");
  (void)signalled_while_writing(dir, SIGKILL);
  EXPECT_EQ(read_file(dir + "/out.nc"), "previous\n");
  ASSERT_EQ(temporaries(dir).size(), 1U) << "SIGKILL cannot be caught: its temporary stays";
  const CommandResult r = run_command(ccomp() + " " + shell_quote(dir + "/small.nc") + " -m " +
                                      shell_quote(sample_model()) + " -q -o " + shell_quote(dir + "/out.nc"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(temporaries(dir).empty()) << ::testing::PrintToString(temporaries(dir));
  EXPECT_NE(read_file(dir + "/out.nc").find("G1 X"), std::string::npos);
}

TEST(OutputSafety, AnIgnoredHangupStaysIgnoredAsUnderNohup) {
  const std::string dir = temp_dir("nohup");
  // Long enough to be caught writing, short enough to run to its end quickly under ASan.
  write_file(dir + "/part.nc", long_program(40000));
  // The shell ignores SIGHUP and starts ccomp, which must keep it ignored; the signal is sent
  // while ccomp writes. (A ccomp that ends before it writes fails the test, not hangs it.)
  const CommandResult r = run_command(
      "cd " + shell_quote(dir) + " && trap '' HUP && (" + ccomp() + " part.nc -m " + shell_quote(sample_model()) +
      " -q -o out.nc & pid=$!; while kill -0 $pid 2>/dev/null && ! ls out.nc.ccomp-* >/dev/null 2>&1; do sleep 0.01; "
      "done; kill -HUP $pid && echo signalled; wait $pid; echo status=$?)");
  EXPECT_NE(r.out.find("signalled"), std::string::npos) << "ccomp ended before it was caught writing: " << r.out;
  EXPECT_NE(r.out.find("status=0"), std::string::npos) << r.out << r.err;
  EXPECT_NE(read_file(dir + "/out.nc").find("(ccomp "), std::string::npos);
}

TEST(OutputSafety, OutputsTakeTheModeAPlainWriteWouldGive) {
  const std::string dir = temp_dir("modes");
  const CommandResult r = run_command("cd " + shell_quote(dir) + " && umask 022 && " + ccomp() + " simulate -m " +
                                      shell_quote(sample_model()) + " --plan grid -o data.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(fs::status(dir + "/data.csv").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read | fs::perms::others_read);
}

TEST(OutputSafety, AClosedPipeIsAWriteErrorNotASignal) {
  const std::string dir = temp_dir("pipe");
  write_file(dir + "/part.nc", long_program());
  const CommandResult r =
      run_command("bash -c " + shell_quote(ccomp() + " trace " + shell_quote(dir + "/part.nc") +
                                           " | head -c 1 > /dev/null; echo status=${PIPESTATUS[0]}"));
  EXPECT_NE(r.out.find("status=6"), std::string::npos) << r.out << r.err;
}

}  // namespace
}  // namespace ccomp::test
