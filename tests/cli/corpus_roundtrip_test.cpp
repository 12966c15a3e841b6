// With the zero model, every real program in tests/data/corpus/programs comes back byte for
// byte, bar ccomp's header line. Each needs the options its control implies: the dialect,
// a tool table for G43, the controller values it reads.
#include <gtest/gtest.h>

#include <filesystem>

#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

namespace fs = std::filesystem;

struct CorpusProgram {
  const char* file;
  const char* options;
};
void PrintTo(const CorpusProgram& p, std::ostream* os) {
  *os << p.file;
}

const std::string kTools = "--tool-table " + shell_quote(CCOMP_SOURCE_DIR "/tests/data/corpus-tools.tbl");

const CorpusProgram kPrograms[] = {
    {"HAAS_sample.NCF", "--dialect fanuc"},
    {"boat-xyzbc.ngc", ""},
    {"camaster_sample.tap", "--dialect wincnc"},
    {"linuxcnc_sample.ngc", ""},
    {"mazak_sample.EIA", "--dialect mazak"},
    {"metric_pipe.ngc", "--param '_hal[plasmac.float-switch-travel]=1.5'"},
    {"stdbc.nc", "--dialect fanuc"},
    {"stellabee1.ngc", ""},
};

class CorpusRoundTrip : public ::testing::TestWithParam<CorpusProgram> {};

TEST_P(CorpusRoundTrip, ZeroModelGivesTheSameBytesBackWithAHeader) {
  const CorpusProgram& p = GetParam();
  const std::string in = corpus_dir() + "/programs/" + p.file;
  const std::string out = temp_dir(std::string("corpus_") + p.file) + "/" + p.file;
  const CommandResult r = run_command(shell_quote(ccomp_binary()) + " " + shell_quote(in) + " -m " +
                                      shell_quote(source_dir() + "/samples/machines/zero.yaml") + " -o " +
                                      shell_quote(out) + " " + kTools + " " + p.options);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string original = read_file(in);
  std::string result = read_file(out);
  const auto header = result.find("(ccomp ");
  ASSERT_NE(header, std::string::npos);
  const auto header_end = result.find('\n', header);
  EXPECT_TRUE(header == 0 || result.substr(0, header).find_first_not_of("% \r\n") == std::string::npos)
      << "the header goes first, or right after a leading %";
  result.erase(header, header_end - header + 1);
  EXPECT_EQ(result.size(), original.size());
  EXPECT_TRUE(result == original) << "output differs from " << p.file;
}

INSTANTIATE_TEST_SUITE_P(Programs, CorpusRoundTrip, ::testing::ValuesIn(kPrograms), [](const auto& test) {
  std::string name = test.param.file;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
});

TEST(CorpusRoundTrip, EveryCorpusProgramIsListed) {
  int listed = 0;
  for (const auto& e : fs::directory_iterator(corpus_dir() + "/programs")) {
    bool found = false;
    for (const auto& p : kPrograms) found = found || e.path().filename() == p.file;
    EXPECT_TRUE(found) << e.path().filename() << " is not in the round-trip list";
    ++listed;
  }
  EXPECT_EQ(listed, static_cast<int>(std::size(kPrograms)));
}

}  // namespace
}  // namespace ccomp::test
