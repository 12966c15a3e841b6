#pragma once
// Test support: one line of G-code parsed into a Block, the text kept with it (a Block views
// its text, so the pair stays where it was made: no copies, no moves).
#include <string>

#include "ccomp/gcode/block.hpp"
#include "ccomp/gcode/parser.hpp"

namespace ccomp::test {

struct ParsedBlock {
  explicit ParsedBlock(std::string line, std::uint32_t number = 1, gcode::Dialect dialect = {})
      : text(std::move(line)) {
    gcode::Parser(std::move(dialect)).parse(text, number, "test.ngc", block);
  }
  ParsedBlock(const ParsedBlock&) = delete;
  ParsedBlock& operator=(const ParsedBlock&) = delete;

  std::string text;
  gcode::Block block;
};

}  // namespace ccomp::test
