// The README's metrology walkthrough runs as written, and what it prints is what the
// README shows.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

#include "ccomp/exit_codes.hpp"
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

/// The codes of a table's rows `| N |` (README) or of lines `  N  meaning` (--help).
std::set<int> codes_in(const std::string& text, const std::regex& row) {
  std::set<int> codes;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_search(line, m, row)) codes.insert(std::stoi(m[1].str()));
  }
  return codes;
}

TEST(Readme, ExitCodeTableListsEveryCodeTheCliReturns) {
  const std::string readme = read_file(source_dir() + "/README.md");
  const auto table = readme.find("| code | meaning |");
  ASSERT_NE(table, std::string::npos);
  const std::set<int> in_readme =
      codes_in(readme.substr(table, readme.find("\n\n", table) - table), std::regex(R"(^\| (\d+) \|)"));
  const CommandResult help = run_command(shell_quote(ccomp_binary()) + " --help");
  ASSERT_EQ(help.exit_code, 0);
  const std::set<int> in_help = codes_in(help.out.substr(help.out.find("Exit codes:")), std::regex(R"(^  (\d+)  )"));
  std::set<int> returned{0};  // success; every ErrorKind's code and the verdict's 1 besides (exit_codes.hpp)
  for (const int code : exit_codes()) returned.insert(code);
  EXPECT_EQ(in_readme, returned) << "the README's exit-code table";
  EXPECT_EQ(in_help, returned) << "ccomp --help's exit codes";
}

TEST(Readme, DocsAndSamplesPointOnlyInsideTheRepository) {
  // The source papers are cited by docs/error-model.md's references, never by a path or a name
  // (../shared/physics.md, "seed 003") a user who clones the project does not have.
  namespace fs = std::filesystem;
  static const std::regex outside(R"(\.\./shared/|shared/physics|[Ss]eeds? 00\d|the seed's)");
  std::vector<fs::path> files{source_dir() + "/README.md"};
  for (const char* folder : {"docs", "samples", "integration", "bench", "tools", "include", "src"})
    for (const auto& entry : fs::recursive_directory_iterator(source_dir() + "/" + folder))
      if (entry.is_regular_file() && entry.file_size() < (1U << 20)) files.push_back(entry.path());
  for (const fs::path& file : files) {
    std::istringstream in(read_file(file.string()));
    int n = 0;
    for (std::string line; std::getline(in, line);) {
      ++n;
      EXPECT_FALSE(std::regex_search(line, outside)) << file.string() << ":" << n << ": " << line;
    }
  }
}

}  // namespace
}  // namespace ccomp::test
