// Issue 49: the files a run touches keep their protections, and running out of something
// (threads, memory for a line, a valid option value) is a documented exit, never a crash.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>
#include <filesystem>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

constexpr const char* kProgram = "G21 G90\nG0 X1 Y2\nG1 X3 F100\nM2\n";

std::string model() {
  return shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
}
/// Runs what follows as an ordinary user when the tests run as root, who is exempt from
/// `ulimit -u` and from file permissions: what they protect is then what is tested.
std::string as_user() {
  return ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
}
/// `dir` open to that user (the tests' folders are made by root, 0755).
void open_to_all(const std::string& dir) {
  ASSERT_EQ(::chmod(dir.c_str(), 0777), 0) << dir;
}
/// A folder that the user of as_user() can reach whatever the checkout's folders allow (a
/// clone made in `mktemp -d` is 0700): the binary and the model copied in, the test's own
/// files made there; removed at the end.
class UserSpace {
 public:
  explicit UserSpace(const std::string& name) {
    std::string pattern = (fs::temp_directory_path() / ("ccomp-" + name + "-XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp " + pattern);
    dir_ = pattern;
    fs::permissions(dir_, fs::perms::all);
    fs::copy_file(ccomp_binary(), dir_ + "/ccomp");
    fs::copy_file(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml", dir_ + "/model.yaml");
    fs::permissions(dir_ + "/model.yaml", fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  }
  UserSpace(const UserSpace&) = delete;
  UserSpace& operator=(const UserSpace&) = delete;
  ~UserSpace() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  [[nodiscard]] const std::string& dir() const { return dir_; }
  [[nodiscard]] std::string ccomp() const { return shell_quote(dir_ + "/ccomp"); }
  [[nodiscard]] std::string model() const { return shell_quote(dir_ + "/model.yaml"); }

 private:
  std::string dir_;
};
bool has_temporary(const std::string& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".ccomp-") != std::string::npos) return true;
  return false;
}
unsigned mode_of(const std::string& path) {
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
  return st.st_mode & 07777;
}

TEST(SafeFiles, ReadOnlyOutputIsRefusedNotRenamedOver) {
  const std::string dir = temp_dir("safe_read_only");
  write_file(dir + "/part.nc", kProgram);
  write_file(dir + "/out.nc", "kept\n");
  ASSERT_EQ(::chmod((dir + "/out.nc").c_str(), 0444), 0);
  const CommandResult r =
      run_command(ccomp() + " " + shell_quote(dir + "/part.nc") + " -m " + model() + " -o " + shell_quote(dir + "/out.nc"));
  EXPECT_EQ(r.exit_code, 6) << r.err;
  EXPECT_NE(r.err.find("read-only"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(dir + "/out.nc"), "kept\n");
  EXPECT_EQ(mode_of(dir + "/out.nc"), 0444u);
  EXPECT_FALSE(has_temporary(dir));
}

TEST(SafeFiles, InPlaceBackupKeepsTheInputsMode) {
  const std::string dir = temp_dir("safe_backup_mode");
  write_file(dir + "/part.nc", kProgram);
  ASSERT_EQ(::chmod((dir + "/part.nc").c_str(), 0640), 0);
  const CommandResult r = run_command(ccomp() + " -q --in-place " + shell_quote(dir + "/part.nc") + " -m " + model());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_file(dir + "/part.nc.orig"), kProgram);
  EXPECT_EQ(mode_of(dir + "/part.nc.orig"), 0640u);
  EXPECT_EQ(mode_of(dir + "/part.nc"), 0640u);
}

TEST(SafeFiles, StandardInputThatIsTheOutputIsRefused) {
  const std::string dir = temp_dir("safe_stdin_output");
  write_file(dir + "/p.ngc", kProgram);
  const CommandResult r = run_command(ccomp() + " - -m " + model() + " -o " + shell_quote(dir + "/p.ngc") + " < " +
                                      shell_quote(dir + "/p.ngc"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("which this run reads"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(dir + "/p.ngc"), kProgram);
}

TEST(SafeFiles, LineWithoutEndIsRefusedInBoundedMemory) {
  // /dev/zero never ends: without a check while reading, the line buffer grows until
  // bad_alloc (exit 70). The limit keeps memory under a few MiB: ulimit -v proves it.
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer reserves terabytes of address space for its shadow memory, which no
  // `ulimit -v` admits: under it, its own limit on resident memory proves the bound (a
  // process beyond it is stopped with a report, which fails tools/sanitize.sh too).
  const std::string limit = "ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:hard_rss_limit_mb=400\" ";
#else
  const std::string limit = "ulimit -v 400000; ";
#endif
  const CommandResult r = run_command(limit + ccomp() + " /dev/zero -m " + model() + " -o -");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("/dev/zero:1:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("without a line end"), std::string::npos) << r.err;
}

struct BadTime {
  const char* name;
  const char* value;
};
void PrintTo(const BadTime& b, std::ostream* os) {
  *os << b.name;
}
class TimeOption : public ::testing::TestWithParam<BadTime> {};

TEST_P(TimeOption, NegativeOrNotFiniteIsAUsageError) {
  const std::string dir = temp_dir(std::string("safe_time_") + GetParam().name);
  write_file(dir + "/part.nc", kProgram);
  for (const char* command : {" ", " predict "}) {
    const CommandResult r = run_command(ccomp() + command + shell_quote(dir + "/part.nc") + " -m " + model() +
                                        " -o - --time " + GetParam().value);
    EXPECT_EQ(r.exit_code, 2) << command << r.err;
    EXPECT_NE(r.err.find("--time"), std::string::npos) << command << r.err;
  }
}

INSTANTIATE_TEST_SUITE_P(Cli, TimeOption,
                         ::testing::Values(BadTime{"negative", "-100000"}, BadTime{"nan", "nan"},
                                           BadTime{"infinite", "inf"}),
                         [](const auto& test) { return std::string(test.param.name); });

TEST(SafeFiles, ThreadsTheSystemRefusesMeanFewerWorkersNotAnAbort) {
  // Under a process limit already reached, no thread can be made: the batch runs on the
  // main thread (before: `terminate called without an active exception`, exit 134).
  const UserSpace space("safe_threads");
  const std::string& dir = space.dir();
  std::string inputs;
  for (int i = 0; i < 4; ++i) {
    write_file(dir + "/p" + std::to_string(i) + ".nc", kProgram);
    inputs += " " + shell_quote(dir + "/p" + std::to_string(i) + ".nc");
  }
  fs::create_directories(dir + "/out");
  open_to_all(dir + "/out");
  const CommandResult r = run_command("ulimit -u 1; " + as_user() + space.ccomp() + " -q -j 200 --threads 1" +
                                      inputs + " -m " + space.model() + " --out-dir " + shell_quote(dir + "/out"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (int i = 0; i < 4; ++i) EXPECT_EQ(read_file(dir + "/out/p" + std::to_string(i) + ".nc").empty(), false) << i;
  EXPECT_FALSE(has_temporary(dir + "/out"));
}

TEST(SafeFiles, SubPathFolderThatCannotBeSearchedIsAPositionedIoError) {
  const UserSpace space("safe_sub_denied");
  const std::string& dir = space.dir();
  fs::create_directories(dir + "/subs");
  write_file(dir + "/part.ngc", "G21 G90\no<drill> call\nM2\n");
  write_file(dir + "/subs/drill.ngc", "o<drill> sub\nG1 X1 F100\no<drill> endsub\n");
  ASSERT_EQ(::chmod((dir + "/subs").c_str(), 0600), 0);  // readable, not searchable
  const CommandResult r = run_command(as_user() + space.ccomp() + " " + shell_quote(dir + "/part.ngc") + " -m " +
                                      space.model() + " --sub-path " + shell_quote(dir + "/subs") + " -o -");
  ::chmod((dir + "/subs").c_str(), 0755);
  EXPECT_EQ(r.exit_code, 6) << r.err;
  EXPECT_NE(r.err.find("part.ngc:2:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Permission denied"), std::string::npos) << r.err;
}

TEST(SafeFiles, FileSizeLimitIsAWriteErrorWithTheTemporaryRemoved) {
  // Past `ulimit -f` the kernel sends SIGXFSZ, whose default ends the run (exit 153) and
  // leaves the temporary; ignored, the write fails with EFBIG: exit 6, nothing left.
  const std::string dir = temp_dir("safe_file_size");
  std::string program = "G21 G90\n";
  for (int i = 0; i < 400; ++i) program += "G1 X" + std::to_string(i % 50) + " Y" + std::to_string(i % 7) + " F500\n";
  write_file(dir + "/part.nc", program + "M2\n");
  const CommandResult r = run_command("ulimit -f 2; " + ccomp() + " " + shell_quote(dir + "/part.nc") + " -m " +
                                      model() + " -o " + shell_quote(dir + "/out.nc"));
  EXPECT_EQ(r.exit_code, 6) << r.err;
  EXPECT_NE(r.err.find("out.nc"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/out.nc"));
  EXPECT_FALSE(has_temporary(dir));
}

TEST(SafeFiles, OutputNamedUpToNameMaxIsWritten) {
  // The temporary's name adds ".ccomp-<pid>-XXXXXX": for a name of 236-255 bytes it was
  // longer than NAME_MAX and the run failed.
  const std::string dir = temp_dir("safe_long_name");
  write_file(dir + "/part.nc", kProgram);
  for (const std::size_t length : {236u, 255u}) {
    const std::string name = std::string(length - 3, 'n') + ".nc";
    const CommandResult r = run_command(ccomp() + " -q " + shell_quote(dir + "/part.nc") + " -m " + model() +
                                        " -o " + shell_quote(dir + "/" + name));
    EXPECT_EQ(r.exit_code, 0) << length << r.err;
    EXPECT_TRUE(fs::exists(dir + "/" + name)) << length;
  }
  EXPECT_FALSE(has_temporary(dir));
}

TEST(SafeFiles, FolderAsToolTableIsRefused) {
  const std::string dir = temp_dir("safe_tool_folder");
  write_file(dir + "/part.nc", kProgram);
  const CommandResult r = run_command(ccomp() + " " + shell_quote(dir + "/part.nc") + " -m " + model() +
                                      " -o - --tool-table " + shell_quote(dir));
  EXPECT_EQ(r.exit_code, 6) << r.err;
  EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
}

TEST(SafeFiles, HelpToAFullDeviceIsAWriteError) {
  const CommandResult r = run_command(ccomp() + " --help > /dev/full");
  EXPECT_EQ(r.exit_code, 6) << r.err;
  EXPECT_NE(r.err.find("cannot write standard output"), std::string::npos) << r.err;
}

TEST(SafeFiles, OutputThatIsASubroutineFileOnTheSubPathIsRefused) {
  const std::string dir = temp_dir("safe_sub_output");
  fs::create_directories(dir + "/subs");
  write_file(dir + "/part.ngc", "G21 G90\no<drill> call\nM2\n");
  const std::string sub = "o<drill> sub\nG1 X1 F100\no<drill> endsub\n";
  write_file(dir + "/subs/drill.ngc", sub);
  const CommandResult r = run_command(ccomp() + " " + shell_quote(dir + "/part.ngc") + " -m " + model() +
                                      " --sub-path " + shell_quote(dir + "/subs") + " -o " +
                                      shell_quote(dir + "/subs/drill.ngc"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--sub-path"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(dir + "/subs/drill.ngc"), sub);
}

TEST(SafeFiles, EmptySubroutineFileIsThatFilesError) {
  const std::string dir = temp_dir("safe_sub_empty");
  fs::create_directories(dir + "/subs");
  write_file(dir + "/part.ngc", "G21 G90\no<drill> call\nM2\n");
  write_file(dir + "/subs/drill.ngc", "");
  const CommandResult r = run_command(ccomp() + " " + shell_quote(dir + "/part.ngc") + " -m " + model() +
                                      " --sub-path " + shell_quote(dir + "/subs") + " -o -");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("drill.ngc:1:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no 'O<drill> sub' line"), std::string::npos) << r.err;
}

TEST(SafeFiles, JsonShowsANonUtf8FileNameAsReplacementCharacters) {
  const std::string dir = temp_dir("safe_json_name");
  const std::string name = dir + "/caf\xe9.nc";
  write_file(name, kProgram);
  const CommandResult r = run_command(ccomp() + " --json " + shell_quote(name) + " -m " + model() + " --out-dir " +
                                      shell_quote(dir + "/out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("caf\\ufffd.nc"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("caf\\u00e9"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace ccomp::test
