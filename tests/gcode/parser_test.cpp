// The lexer and parser: LinuxCNC's lexical rules, the lossless spans, and positioned errors.
#include "ccomp/gcode/parser.hpp"

#include <gtest/gtest.h>

#include "ccomp/error.hpp"

namespace ccomp::gcode {
namespace {

struct Parsed {
  std::string text;  // owns the bytes the block views
  Block block;
};

Parsed parse(const std::string& line, Dialect dialect = {}) {
  Parsed p{line, {}};
  Parser parser(std::move(dialect));
  parser.parse(p.text, 7, "t.ngc", p.block);
  return p;
}

TEST(Parser, WordsAreCaseInsensitiveAndToleratesBlanksInsideNumbers) {
  const Parsed p = parse("g 1 x 1 . 5 Y+2 z.5 a1.");
  ASSERT_EQ(p.block.words.size(), 5U);
  EXPECT_EQ(p.block.words[0].letter, 'G');
  EXPECT_DOUBLE_EQ(p.block.words[0].value.literal, 1.0);
  EXPECT_DOUBLE_EQ(p.block.words[1].value.literal, 1.5);
  EXPECT_DOUBLE_EQ(p.block.words[2].value.literal, 2.0);
  EXPECT_DOUBLE_EQ(p.block.words[3].value.literal, 0.5);
  EXPECT_DOUBLE_EQ(p.block.words[4].value.literal, 1.0);
}

TEST(Parser, SpansPointAtTheOriginalBytes) {
  const Parsed p = parse("N10  G01 x -1 . 25 (keep me) Y2");
  const Word& x = p.block.words[1];
  EXPECT_EQ(p.block.slice(x.span), "x -1 . 25");
  EXPECT_EQ(p.block.slice(x.value_span), "-1 . 25");
  EXPECT_DOUBLE_EQ(x.value.literal, -1.25);
  EXPECT_EQ(p.block.slice(p.block.line_number_span), "N10");
  ASSERT_EQ(p.block.comments.size(), 1U);
  EXPECT_EQ(p.block.slice(p.block.comments[0].text), "keep me");
}

TEST(Parser, LineNumbersBlockDeleteAndProgramDelimiter) {
  const Parsed a = parse("/N12.5 G0 X1");
  EXPECT_TRUE(a.block.block_delete);
  EXPECT_TRUE(a.block.has_line_number);
  EXPECT_DOUBLE_EQ(a.block.line_number, 12.5);
  EXPECT_TRUE(parse("  %").block.program_delimiter);
  EXPECT_TRUE(parse("").block.is_empty());
  EXPECT_TRUE(parse("(only a comment) ; and another").block.is_empty());
}

TEST(Parser, CommentsKeepTheirTextVerbatim) {
  const Parsed p = parse("G0 (MSG, Hello  World) X1 ; tail (not a paren comment");
  ASSERT_EQ(p.block.comments.size(), 2U);
  EXPECT_EQ(p.block.slice(p.block.comments[0].text), "MSG, Hello  World");
  EXPECT_TRUE(p.block.comments[1].end_of_line);
  EXPECT_EQ(p.block.slice(p.block.comments[1].text), " tail (not a paren comment");
}

TEST(Parser, ExpressionsAndParametersBecomeReversePolish) {
  const Parsed p = parse("X[1 + 2 * #3] Y#<_Global> Z-[#1] A sin[30] B ATAN[1]/[1] #<My Var> = 4 #5=[2**3]");
  const Block& b = p.block;
  ASSERT_EQ(b.words.size(), 5U);
  EXPECT_FALSE(b.words[0].value.is_literal());
  EXPECT_EQ(b.settings.size(), 2U);
  EXPECT_TRUE(b.settings[0].named);
  EXPECT_EQ(b.name(b.settings[0].name_begin, b.settings[0].name_size), "MYVAR");
  EXPECT_FALSE(b.settings[1].named);
  EXPECT_DOUBLE_EQ(b.settings[1].index.literal, 5.0);
  // [1 + 2 * #3] -> 1 2 3 read * +
  const Value& v = b.words[0].value;
  ASSERT_EQ(v.rpn_end - v.rpn_begin, 6U);
  EXPECT_EQ(b.rpn[v.rpn_begin + 3].op, ExprOp::read_numbered);
  EXPECT_EQ(b.rpn[v.rpn_begin + 4].op, ExprOp::times);
  EXPECT_EQ(b.rpn[v.rpn_begin + 5].op, ExprOp::plus);
}

TEST(Parser, OWordStatements) {
  const Parsed call = parse("o<Probe Me> call [1] (why not) [#2+1]");
  EXPECT_TRUE(call.block.o.present);
  EXPECT_TRUE(call.block.o.named);
  EXPECT_EQ(call.block.o.name, "PROBEME");
  EXPECT_EQ(call.block.o.keyword, OKeyword::call);
  EXPECT_EQ(call.block.o.arguments.size(), 2U);
  EXPECT_EQ(parse("O100 ELSEIF [1]").block.o.keyword, OKeyword::elseif);
  EXPECT_EQ(parse("O100 else").block.o.keyword, OKeyword::else_);
  EXPECT_EQ(parse("O1000 (program)").block.o.keyword, OKeyword::none);
  EXPECT_EQ(parse("O1000").block.o.number, 1000U);
  EXPECT_TRUE(parse("o#<sub> call").block.o.computed);
}

TEST(Parser, DialectWordsWithoutValues) {
  EXPECT_THROW(parse("G82 R0.1 P F15."), Error);
  const Parsed haas = parse("G82 R0.1 P F15.", *dialect_named("fanuc"));
  ASSERT_EQ(haas.block.words.size(), 4U);
  EXPECT_FALSE(haas.block.words[2].has_value);
}

TEST(Parser, WincncBracketsAreComments) {
  const Parsed p = parse(" G90 [ABSOLUTE MODE]", *dialect_named("wincnc"));
  ASSERT_EQ(p.block.words.size(), 1U);
  ASSERT_EQ(p.block.comments.size(), 1U);
  EXPECT_EQ(p.block.slice(p.block.comments[0].span), "[ABSOLUTE MODE]");
}

struct BadLine {
  const char* text;
  std::uint32_t column;
  const char* expected_words;
};

void PrintTo(const BadLine& b, std::ostream* os) {
  *os << '"' << b.text << '"';
}

class ParserErrors : public ::testing::TestWithParam<BadLine> {};

TEST_P(ParserErrors, NameFileLineColumnAndWhatWasExpected) {
  const BadLine& c = GetParam();
  try {
    (void)parse(c.text);
    FAIL() << "accepted: " << c.text;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::program);
    EXPECT_EQ(e.where().file, "t.ngc");
    EXPECT_EQ(e.where().line, 7U);
    EXPECT_EQ(e.where().column, c.column) << e.what();
    EXPECT_NE(e.message().find(c.expected_words), std::string::npos) << e.message();
    EXPECT_EQ(e.source_line(), c.text);
    EXPECT_NE(format_error(e).find("t.ngc:7:"), std::string::npos);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Lines, ParserErrors,
    ::testing::Values(BadLine{"G1 X1 (unclosed", 16, "unclosed comment"},
                      BadLine{"G1 (a (nested) one)", 7, "cannot nest"}, BadLine{"G1 X", 5, "expected a value"},
                      BadLine{"G1 X[1 + ]", 10, "expected a value"}, BadLine{"G1 X[1 + 2", 11, "expected ']'"},
                      BadLine{"#1 2", 5, "expected '='"} /* blanks vanish: #12 */,
                      BadLine{"G1 X#<abc", 10, "expected '>'"}, BadLine{"G1 X ATAN[1] 2", 14, "ATAN"},
                      BadLine{"G1 N10", 4, "unexpected text"}, BadLine{"G1 X1 @", 7, "unexpected text"}));

}  // namespace
}  // namespace ccomp::gcode
