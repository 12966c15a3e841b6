#include "ccomp/gcode/block.hpp"

namespace ccomp::gcode {

void Block::clear() {
  text = {};
  line = 0;
  program_delimiter = false;
  block_delete = false;
  has_line_number = false;
  line_number = 0.0;
  line_number_span = {};
  words.clear();
  settings.clear();
  comments.clear();
  commands.clear();
  o.present = false;
  o.named = false;
  o.number = 0;
  o.name.clear();
  o.computed = false;
  o.label_value = {};
  o.keyword = OKeyword::none;
  o.arguments.clear();
  o.span = {};
  rpn.clear();
  names.clear();
}

const Word* Block::find(char letter) const {
  for (const Word& w : words)
    if (w.letter == letter && w.has_value) return &w;
  return nullptr;
}

}  // namespace ccomp::gcode
