// README's exit-code table, `ccomp --help`'s list and the ErrorKinds in code name the same
// codes: a script reading either acts on what the tool really returns.
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <set>
#include <sstream>

#include "ccomp/exit_codes.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

/// The codes in README's table "| code | meaning |" (128+N, the signals, left out).
std::set<int> readme_codes() {
  std::istringstream readme(read_file(source_dir() + "/README.md"));
  std::set<int> codes;
  std::string line;
  bool in_table = false;
  const std::regex row(R"(^\| (\d+) \|)");
  while (std::getline(readme, line)) {
    if (line == "| code | meaning |") {
      in_table = true;
      continue;
    }
    if (!in_table) continue;
    if (!line.starts_with("|")) break;
    std::smatch m;
    if (std::regex_search(line, m, row)) codes.insert(std::stoi(m[1]));
  }
  return codes;
}

/// The codes `ccomp --help` lists under "Exit codes:".
std::set<int> help_codes() {
  const CommandResult help = run_command(shell_quote(ccomp_binary()) + " --help");
  EXPECT_EQ(help.exit_code, 0) << help.err;
  const auto at = help.out.find("Exit codes:");
  EXPECT_NE(at, std::string::npos) << help.out;
  std::istringstream list(help.out.substr(at == std::string::npos ? 0 : at));
  std::set<int> codes;
  std::string line;
  const std::regex row(R"(^  (\d+) )");
  while (std::getline(list, line)) {
    std::smatch m;
    if (std::regex_search(line, m, row)) codes.insert(std::stoi(m[1]));
  }
  return codes;
}

std::set<int> codes_in_code() {
  std::set<int> codes{0};
  for (const int code : exit_codes()) codes.insert(code);
  return codes;
}

TEST(ExitCodes, ReadmesTableNamesEveryCodeAndNoOther) {
  const std::set<int> readme = readme_codes();
  ASSERT_GE(readme.size(), 5U) << "README's table was not found or not read";
  EXPECT_EQ(readme, codes_in_code());
}

TEST(ExitCodes, HelpListsTheSameCodes) {
  EXPECT_EQ(help_codes(), codes_in_code());
}

// The codes are distinct, each a valid exit status below the signals' 128+N.
TEST(ExitCodes, EachIsItsOwnCode) {
  std::set<int> seen;
  for (const int code : exit_codes()) {
    EXPECT_GT(code, 0);
    EXPECT_LT(code, 128);
    EXPECT_TRUE(seen.insert(code).second) << code;
  }
}

}  // namespace
}  // namespace ccomp::test
