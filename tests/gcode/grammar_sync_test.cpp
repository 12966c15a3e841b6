// grammar/gcode.peg is normative and src/gcode/grammar.hpp mirrors it rule for rule: the
// two must name the same productions, so neither can change without the other.
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <set>

#include "ccomp/gcode/parser.hpp"
#include "trace_capture.hpp"

namespace ccomp::test {
namespace {

std::set<std::string> rules_in_grammar_file() {
  std::set<std::string> names;
  static const std::regex rule(R"(^([a-z_]+)\s+<-)");
  for (const std::string& line : read_lines(source_dir() + "/grammar/gcode.peg")) {
    std::smatch m;
    if (std::regex_search(line, m, rule)) names.insert(m[1].str());
  }
  return names;
}

TEST(GrammarSync, ParserDeclaresExactlyTheRulesOfTheGrammarFile) {
  const std::set<std::string> file = rules_in_grammar_file();
  const std::vector<std::string> parser_list = gcode::grammar_rule_names();
  const std::set<std::string> parser(parser_list.begin(), parser_list.end());
  ASSERT_GT(file.size(), 30U) << "the grammar file should hold the whole dialect";
  for (const std::string& name : file)
    EXPECT_TRUE(parser.count(name)) << "grammar rule '" << name << "' has no parser rule";
  for (const std::string& name : parser)
    EXPECT_TRUE(file.count(name)) << "parser rule '" << name << "' is not in grammar/gcode.peg";
}

TEST(GrammarSync, EveryRuleOfTheFileIsDefinedOnce) {
  std::vector<std::string> names;
  static const std::regex rule(R"(^([a-z_]+)\s+<-)");
  for (const std::string& line : read_lines(source_dir() + "/grammar/gcode.peg")) {
    std::smatch m;
    if (std::regex_search(line, m, rule)) names.push_back(m[1].str());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end());
}

}  // namespace
}  // namespace ccomp::test
