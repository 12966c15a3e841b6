// The parser's fast path (hand-written, for blocks of literal words) must read every line
// exactly as the grammar does: same words, spans, values, comments, or a fall-back to the
// grammar. Checked on every line of every program in the shared corpus.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

#include "ccomp/error.hpp"
#include "ccomp/gcode/parser.hpp"
#include "trace_capture.hpp"

namespace ccomp::gcode {
namespace {

namespace fs = std::filesystem;

std::optional<std::string> differ(const Block& a, const Block& b) {
  if (a.program_delimiter != b.program_delimiter) return "program delimiter";
  if (a.block_delete != b.block_delete) return "block delete";
  if (a.has_line_number != b.has_line_number || a.line_number != b.line_number ||
      a.line_number_span.begin != b.line_number_span.begin || a.line_number_span.end != b.line_number_span.end)
    return "line number";
  if (a.words.size() != b.words.size()) return "word count";
  for (std::size_t i = 0; i < a.words.size(); ++i) {
    const Word& x = a.words[i];
    const Word& y = b.words[i];
    if (x.letter != y.letter || x.has_value != y.has_value || x.span.begin != y.span.begin ||
        x.span.end != y.span.end || x.value_span.begin != y.value_span.begin || x.value_span.end != y.value_span.end ||
        x.value.is_literal() != y.value.is_literal() || (x.value.is_literal() && x.value.literal != y.value.literal))
      return "word " + std::to_string(i);
  }
  if (a.comments.size() != b.comments.size()) return "comment count";
  for (std::size_t i = 0; i < a.comments.size(); ++i) {
    const Comment& x = a.comments[i];
    const Comment& y = b.comments[i];
    if (x.span.begin != y.span.begin || x.span.end != y.span.end || x.text.begin != y.text.begin ||
        x.text.end != y.text.end || x.end_of_line != y.end_of_line)
      return "comment " + std::to_string(i);
  }
  if (a.settings.size() != b.settings.size() || a.o.present != b.o.present) return "settings or O-word";
  return std::nullopt;
}

void compare_file(const fs::path& path, const Dialect& dialect, int& lines, int& fast) {
  Parser quick(dialect, true), grammar(dialect, false);
  Block a, b;
  std::uint32_t n = 0;
  for (const std::string& line : test::read_lines(path.string())) {
    ++n;
    std::string text = line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::optional<std::string> error_a, error_b;
    try {
      quick.parse(text, n, "f", a);
    } catch (const Error& e) {
      error_a = e.what();
    }
    try {
      grammar.parse(text, n, "f", b);
    } catch (const Error& e) {
      error_b = e.what();
    }
    ++lines;
    ASSERT_EQ(error_a, error_b) << path << ":" << n << ": " << text;
    if (error_a) continue;
    if (a.rpn.empty() && !b.rpn.empty()) ++fast;  // literals left nodes behind in the grammar's block
    if (auto d = differ(a, b)) FAIL() << path << ":" << n << ": " << *d << " differs: " << text;
  }
}

TEST(ParserFastPath, ReadsEveryCorpusLineAsTheGrammarDoes) {
  int lines = 0, fast = 0;
  for (const auto& e : fs::recursive_directory_iterator(test::corpus_dir())) {
    if (!e.is_regular_file()) continue;
    const std::string ext = e.path().extension().string();
    if (ext != ".ngc" && ext != ".nc" && ext != ".NCF" && ext != ".EIA" && ext != ".tap") continue;
    Dialect d = *dialect_named(ext == ".NCF" ? "fanuc" : ext == ".EIA" ? "mazak" : "linuxcnc");
    compare_file(e.path(), d, lines, fast);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(lines, 200000);
  EXPECT_GT(fast, lines / 2) << "the fast path should carry most real lines";
}

TEST(ParserFastPath, TrickyLinesFallBackOrAgree) {
  const char* tricky[] = {"G1 X 1 . 5",
                          "g1x-.5y+2.",
                          "N10 G0 X1 (a) ; b",
                          "/N5 M3 $1",
                          "  % tail",
                          "X1 5",
                          "X",
                          "X.",
                          "G1 X1 (open",
                          "G1 X1 (a (b) c)",
                          "N-1",
                          "N 1 0 G0",
                          "O100 sub",
                          "#1=2 G0 X#1",
                          "G0 X[1]",
                          "G0 X1.2345678901234567",
                          "G0 X000.000100",
                          "G0 x1e5",
                          "\tG0\tX1\t"};
  int lines = 0, fast = 0;
  const std::string dir = test::temp_dir("fast_path");
  std::string all;
  for (const char* t : tricky) all += std::string(t) + "\n";
  test::write_file(dir + "/tricky.ngc", all);
  compare_file(dir + "/tricky.ngc", Dialect{}, lines, fast);
  EXPECT_EQ(lines, static_cast<int>(std::size(tricky)));
}

}  // namespace
}  // namespace ccomp::gcode
