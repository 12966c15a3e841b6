#pragma once
// Parses one line of G-code into a Block. The parser owns scratch buffers and reuses them,
// so a program of any length is parsed line by line without allocating.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ccomp/gcode/block.hpp"
#include "ccomp/gcode/dialect.hpp"

namespace ccomp::gcode {

class Parser {
 public:
  /// `fast_path`: read blocks of literal words, comments and line numbers (nearly every
  /// line CAM posts) with a hand-written scanner, and everything else with the PEGTL
  /// grammar. Both give the same Block (tests/gcode/parser_fast_path_test.cpp).
  explicit Parser(Dialect dialect = {}, bool fast_path = true);

  /// Parses `text` (one line, without its terminator) into `out`. `out.text` views `text`,
  /// which must outlive the block. Throws ccomp::Error (ErrorKind::program) with
  /// file:line:column, the line, and what was expected.
  void parse(std::string_view text, std::uint32_t line, std::string_view file, Block& out);

  [[nodiscard]] const Dialect& dialect() const { return dialect_; }

 private:
  bool parse_simple(std::string_view text, Block& out) const;

  Dialect dialect_;
  bool fast_path_ = true;
  std::string folded_;
  std::vector<std::uint32_t> offsets_;
  std::vector<std::uint32_t> marks_;  // parse scratch, kept between lines
  std::vector<std::uint8_t> operators_;
};

/// The names of the grammar's rules, as the parser declares them (for the sync test).
[[nodiscard]] std::vector<std::string> grammar_rule_names();

}  // namespace ccomp::gcode
