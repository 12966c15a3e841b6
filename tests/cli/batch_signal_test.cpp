// Issue 49: SIGTERM during a batch of more programs at once than the interrupt handler's
// table held (`-j 1100`) left up to 81 empty temporaries. The signal is now taken on a
// thread of its own that removes every temporary under the lock that making one takes, and
// ends the run by the signal (exit 143): every output is its old self or a whole new one.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "job_runner.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

TEST(BatchSignal, SigtermDuringAWideBatchLeavesNoTemporaryAndNothingHalfWritten) {
  const std::string dir = temp_dir("batch_sigterm");
  fs::create_directories(dir + "/in");
  fs::create_directories(dir + "/out");
  constexpr int kPrograms = 1100;
  const std::string program = random_program(7);
  for (int i = 0; i < kPrograms; ++i) {
    write_file(dir + "/in/p" + std::to_string(i) + ".ngc", program);
    write_file(dir + "/out/p" + std::to_string(i) + ".ngc", "old\n");
  }
  const std::string model = shell_quote(source_dir() + "/samples/machines/hmc-xyzb-geometric.yaml");
  // Killed once every program has its temporary (each is made before its program is read).
  const CommandResult r = run_command(shell_quote(ccomp_binary()) + " -q -j " + std::to_string(kPrograms) +
                                      " --threads 1 " + shell_quote(dir) + "/in/*.ngc -m " + model + " --out-dir " +
                                      shell_quote(dir + "/out") + " & pid=$!; sleep 2; kill -TERM $pid; wait $pid; " +
                                      "echo \"status $?\"");
  EXPECT_NE(r.out.find("status 143"), std::string::npos) << r.out << r.err;
  int temporaries = 0, replaced = 0;
  for (const auto& e : fs::directory_iterator(dir + "/out")) {
    const std::string name = e.path().filename().string();
    if (name.find(".ccomp-") != std::string::npos) {
      ++temporaries;
      continue;
    }
    const std::string text = read_file(e.path().string());
    if (text == "old\n") continue;
    ++replaced;
    EXPECT_NE(text.find("compensated for machine"), std::string::npos) << name;
    EXPECT_TRUE(text.ends_with(program.substr(program.rfind('\n', program.size() - 2) + 1))) << name << " is whole";
  }
  EXPECT_EQ(temporaries, 0);
  EXPECT_LT(replaced, kPrograms) << "the signal came while the batch ran";
  for (int i = 0; i < kPrograms; i += 97) EXPECT_EQ(read_file(dir + "/in/p" + std::to_string(i) + ".ngc"), program);
}

}  // namespace
}  // namespace ccomp::test
