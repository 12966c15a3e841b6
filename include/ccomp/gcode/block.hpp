#pragma once
// The lossless block model: one line of a program as parsed. The block keeps a view of
// the original text and the byte span of every word, so a writer can change one value and
// leave every other byte of the line as it was. Values that are expressions are kept as
// reverse-Polish programs, evaluated by the interpreter with the parameters of the moment.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ccomp::gcode {

/// Half-open byte range [begin, end) into Block::text.
struct Span {
  std::uint32_t begin = 0;
  std::uint32_t end = 0;
  [[nodiscard]] std::uint32_t size() const { return end - begin; }
  [[nodiscard]] bool empty() const { return end == begin; }
};

enum class ExprOp : std::uint8_t {
  number,           ///< push `number`
  name,             ///< a parameter name (only as operand of the three ops below)
  read_named,       ///< push the value of #<name>
  read_numbered,    ///< pop n, push #n
  exists,           ///< push 1 if #<name> exists, else 0
  exists_numbered,  ///< pop n, push 1 if #n is a valid parameter number
  negate,
  // binary, in rs274ngc's precedence order (see grammar/gcode.peg)
  power,
  times,
  divide,
  modulo,
  plus,
  minus,
  eq,
  ne,
  gt,
  ge,
  lt,
  le,
  logical_and,
  logical_or,
  logical_xor,
  // functions (angles in degrees, as in LinuxCNC)
  abs,
  acos,
  asin,
  cos,
  exp,
  fix,
  fup,
  ln,
  round,
  sin,
  sqrt,
  tan,
  atan2,
};

/// One node of a reverse-Polish expression. Names live in Block::names.
struct ExprNode {
  ExprOp op = ExprOp::number;
  double number = 0.0;
  std::uint32_t name_begin = 0;
  std::uint32_t name_size = 0;
};

/// A value: a literal number, or the reverse-Polish nodes [rpn_begin, rpn_end) of the block.
struct Value {
  double literal = 0.0;
  std::uint32_t rpn_begin = 0;
  std::uint32_t rpn_end = 0;
  [[nodiscard]] bool is_literal() const { return rpn_begin == rpn_end; }
};

/// A letter and its value, e.g. `X-1.5` or `Y[#1*2]`.
struct Word {
  char letter = 0;        ///< upper case; '$' is LinuxCNC's spindle selector
  bool has_value = true;  ///< false for a lone letter (fanuc dialect)
  /// How a plain number was written, for a writer to keep its style: the digits after its
  /// point (0 without one); -1 where the parser's fast path did not read it (an expression,
  /// a line the grammar read, more than 127 digits after the point).
  std::int8_t decimals = -1;
  bool point_first = false;  ///< written ".5": the point before any digit
  /// Siemens' extended address: the digits between the letter and `=` (`A3=0` is A, 3), 0
  /// where there are none. `X=10` has none: it is X.
  std::uint16_t extension = 0;
  Span span;                 ///< the whole word in the original text
  Span value_span;           ///< the value's bytes (what a writer replaces)
  Value value;
};

/// `#n = value` or `#<name> = value`; applied after every value of the block was read.
struct ParameterSetting {
  Span span;
  bool named = false;
  std::uint32_t name_begin = 0;  ///< into Block::names when named
  std::uint32_t name_size = 0;
  Value index;  ///< the parameter number when not named
  Value value;
};

struct Comment {
  Span span;                 ///< including the delimiters
  Span text;                 ///< inside the delimiters
  bool end_of_line = false;  ///< `;` comment
};

/// A named command of the siemens dialect (Dialect::named_commands): `TRAORI`, `ORIAXES`,
/// `CYCLE832(0.01,1)`, `MSG("ROUGHING")`, `CR=5`. Its arguments are kept as written.
struct Command {
  Span span;       ///< the whole command in the original text
  Span name;       ///< its name (letters, digits, '_')
  Span arguments;  ///< inside its parentheses; empty without them
  bool has_arguments = false;
  bool has_value = false;  ///< `NAME=value`
  Value value;
};

enum class OKeyword : std::uint8_t {
  none,  ///< a Fanuc program number: `O1000`
  sub,
  endsub,
  call,
  return_,
  if_,
  elseif,
  else_,
  endif,
  while_,
  endwhile,
  do_,
  break_,
  continue_,
  repeat,
  endrepeat,
};

/// An O-word statement. The label is `<name>` (folded) or a number.
struct OStatement {
  bool present = false;
  bool named = false;
  std::uint32_t number = 0;
  std::string name;
  bool computed = false;  ///< `o#<n> call`: the label is `label_value`, evaluated when run
  Value label_value;
  OKeyword keyword = OKeyword::none;
  std::vector<Value> arguments;  ///< call arguments, or the condition / count / return value
  Span span;
};

struct Block {
  std::string_view text;           ///< the original line, without its line terminator
  std::uint32_t line = 0;          ///< 1-based line number in the file
  bool program_delimiter = false;  ///< a `%` line
  bool block_delete = false;       ///< starts with `/`
  bool has_line_number = false;
  double line_number = 0.0;
  Span line_number_span;
  std::vector<Word> words;
  std::vector<ParameterSetting> settings;
  std::vector<Comment> comments;
  std::vector<Command> commands;
  OStatement o;
  std::vector<ExprNode> rpn;  ///< expression nodes of every non-literal value
  std::string names;          ///< arena of folded parameter names

  /// Empties the block but keeps its storage, so parsing line after line allocates nothing.
  void clear();

  [[nodiscard]] std::string_view name(std::uint32_t begin, std::uint32_t size) const {
    return std::string_view(names).substr(begin, size);
  }
  [[nodiscard]] std::string_view slice(Span s) const { return text.substr(s.begin, s.size()); }
  /// The first word with this letter and a value, or nullptr: a lone letter (where the
  /// dialect allows one) is ignored, as the interpreter ignores it.
  [[nodiscard]] const Word* find(char letter) const;
  /// True when the line holds nothing but blanks and comments.
  [[nodiscard]] bool is_empty() const {
    return words.empty() && settings.empty() && commands.empty() && !o.present && !program_delimiter;
  }
};

}  // namespace ccomp::gcode
