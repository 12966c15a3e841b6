// The README's metrology walkthrough runs as written, and what it prints is what the
// README shows.
#include <gtest/gtest.h>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

TEST(Walkthrough, ReadmeShowsWhatTheLoopPrints) {
  const std::string readme = read_file(source_dir() + "/README.md");
  const std::string begin = "<!-- walkthrough:begin -->\n```\n", end = "```\n<!-- walkthrough:end -->";
  const auto from = readme.find(begin), to = readme.find(end);
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  const std::string shown = readme.substr(from + begin.size(), to - from - begin.size());
  const CommandResult r = run_command("CCOMP=" + shell_quote(ccomp_binary()) + " bash " +
                                      shell_quote(source_dir() + "/tools/walkthrough.sh"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, shown) << "rerun tools/walkthrough.sh and paste its output into the README";
  EXPECT_NE(r.out.find("missing effects: none"), std::string::npos) << "the loop ends with nothing missing";
}

}  // namespace
}  // namespace ccomp::test
