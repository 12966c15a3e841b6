#include "ccomp/gcode/parser.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>

#include "ccomp/error.hpp"
#include "ccomp/gcode/number.hpp"
#include "ccomp/gcode/source.hpp"
#include "grammar.hpp"

namespace ccomp::gcode {
namespace {

namespace pegtl = tao::pegtl;
namespace g = grammar;

// ---------------------------------------------------------------------------------------
// Error messages, keyed by the rule that a `must<>` found missing.
template <typename Rule>
inline constexpr const char* kMessage = nullptr;

template <>
inline constexpr const char* kMessage<g::end_of_block> =
    "unexpected text: expected a word (a letter and a value), a comment or the end of the line";
template <>
inline constexpr const char* kMessage<pegtl::sor<g::real_value, g::empty_value>> =
    "expected a value after the letter: a number, [expression], #parameter or function";
template <>
inline constexpr const char* kMessage<g::unsigned_real> = "expected a number";
template <>
inline constexpr const char* kMessage<g::unsigned_value> =
    "expected a number, [expression], #parameter or function after the sign";
template <>
inline constexpr const char* kMessage<g::operand> =
    "expected a value (number, [expression], #parameter or function) in the expression";
template <>
inline constexpr const char* kMessage<pegtl::one<']'>> = "expected ']' (or a binary operator) to close the bracket";
template <>
inline constexpr const char* kMessage<pegtl::one<')'>> =
    "unclosed comment: expected ')' before the end of the line (comments cannot nest)";
template <>
inline constexpr const char* kMessage<pegtl::one<'/'>> = "expected '/' between the two arguments of ATAN[y]/[x]";
template <>
inline constexpr const char* kMessage<pegtl::one<'['>> = "expected '[' after the function name";
template <>
inline constexpr const char* kMessage<pegtl::one<'#'>> = "expected '#' reading a parameter: EXISTS takes #<name>";
template <>
inline constexpr const char* kMessage<pegtl::one<'>'>> = "expected '>' to close the parameter name";
template <>
inline constexpr const char* kMessage<pegtl::one<'='>> = "expected '=' after the parameter in a parameter setting";
template <>
inline constexpr const char* kMessage<g::parameter_name> = "expected a parameter name between '<' and '>'";
template <>
inline constexpr const char* kMessage<pegtl::sor<g::named_parameter, g::real_value>> =
    "expected a parameter number or <name> after '#'";
template <>
inline constexpr const char* kMessage<g::parameter_index> = "expected a parameter number or <name> after '#'";
template <>
inline constexpr const char* kMessage<g::real_value> =
    "expected a value (number, [expression], #parameter or function)";
template <>
inline constexpr const char* kMessage<g::expression> = "expected a bracketed expression [ ... ]";
template <>
inline constexpr const char* kMessage<g::o_label> = "expected a number or <name> after O";
template <>
inline constexpr const char* kMessage<g::arguments_end> = "expected ')' to close the command's arguments";
template <>
inline constexpr const char* kMessage<g::string_end> = "unclosed string: expected '\"' before the end of the line";

struct Errors {
  template <typename Rule>
  static constexpr const char* message = kMessage<Rule>;
  // Only `must<>` raises; a rule that fails while alternatives are tried is no error.
  template <typename Rule>
  static constexpr bool raise_on_failure = false;
};

// ---------------------------------------------------------------------------------------
struct State {
  const Dialect* dialect = nullptr;  // read by the dialect-dependent custom rules
  Block* block = nullptr;
  const char* base = nullptr;              // the folded line
  const std::uint32_t* offsets = nullptr;  // folded index -> original index (+ sentinel)
  std::vector<std::uint32_t>& marks;       // rpn size when a marked rule started
  std::vector<std::uint8_t>& operators;    // shunting-yard stack; kMarker opens a bracket
  std::uint32_t expression_depth = 0;
  bool collecting_o_arguments = false;
  std::uint32_t index_end = 0;  // rpn size after a parameter_setting's index
  bool index_named = false;
  std::uint32_t index_name_begin = 0;
  std::uint32_t index_name_size = 0;
  // The word being read: its extended address (Siemens `A3=`) and where its value starts.
  std::uint16_t extension = 0;
  const char* value_begin = nullptr;
  Command command{};  // the command being read

  [[nodiscard]] std::uint32_t original(const char* p) const { return offsets[static_cast<std::size_t>(p - base)]; }
  [[nodiscard]] Span span(const char* begin, const char* end) const {
    if (end == begin) return {original(begin), original(begin)};
    return {original(begin), offsets[static_cast<std::size_t>(end - base) - 1] + 1};
  }
  [[nodiscard]] auto rpn_size() const { return static_cast<std::uint32_t>(block->rpn.size()); }
  [[nodiscard]] Value value(std::uint32_t begin, std::uint32_t end) const {
    if (end - begin == 1 && block->rpn[begin].op == ExprOp::number) return Value{block->rpn[begin].number, 0, 0};
    return Value{0.0, begin, end};
  }
};

constexpr std::uint8_t kMarker = 0xff;

int precedence(ExprOp op) {
  switch (op) {
    case ExprOp::power:
      return 6;
    case ExprOp::times:
    case ExprOp::divide:
    case ExprOp::modulo:
      return 5;
    case ExprOp::plus:
    case ExprOp::minus:
      return 4;
    case ExprOp::eq:
    case ExprOp::ne:
    case ExprOp::gt:
    case ExprOp::ge:
    case ExprOp::lt:
    case ExprOp::le:
      return 3;
    default:
      return 2;  // and, or, xor
  }
}

// Rules whose start is remembered, so their action knows where their values begin.
template <typename Rule>
inline constexpr bool kMarked =
    std::is_same_v<Rule, g::word> || std::is_same_v<Rule, g::signed_value> ||
    std::is_same_v<Rule, g::parameter_value> || std::is_same_v<Rule, g::parameter_setting> ||
    std::is_same_v<Rule, g::expression> || std::is_same_v<Rule, g::exists_call> || std::is_same_v<Rule, g::o_label> ||
    std::is_same_v<Rule, g::command>;

template <typename Rule>
struct Control : pegtl::must_if<Errors>::control<Rule> {
  using Base = typename pegtl::must_if<Errors>::template control<Rule>;

  template <typename Input>
  static void start(const Input& in, State& st) {
    Base::start(in, st);
    if constexpr (kMarked<Rule>) st.marks.push_back(st.rpn_size());
    if constexpr (std::is_same_v<Rule, g::expression>) {
      st.operators.push_back(kMarker);
      ++st.expression_depth;
    }
    if constexpr (std::is_same_v<Rule, g::o_keyword>) st.collecting_o_arguments = true;
  }
  template <typename Input>
  static void success(const Input& in, State& st) {
    finish(st);
    Base::success(in, st);
  }
  template <typename Input>
  static void failure(const Input& in, State& st) {
    finish(st);
    if constexpr (std::is_same_v<Rule, g::expression>) {
      while (!st.operators.empty() && st.operators.back() != kMarker) st.operators.pop_back();
      if (!st.operators.empty()) st.operators.pop_back();
    }
    Base::failure(in, st);
  }
  static void finish(State& st) {
    if constexpr (kMarked<Rule>) st.marks.pop_back();
    if constexpr (std::is_same_v<Rule, g::expression>) --st.expression_depth;
    if constexpr (std::is_same_v<Rule, g::o_keyword>) st.collecting_o_arguments = false;
  }
};

// ---------------------------------------------------------------------------------------
template <typename Rule>
struct Action : pegtl::nothing<Rule> {};

/// Decimal text to the nearest double. Up to 15 significant digits (every coordinate a
/// control prints) the digits make an exact integer m and the value is m / 10^k with both
/// exact, so one division rounds correctly (Clinger's fast path); longer numbers go to
/// std::from_chars.
double decimal_value(const char* first, const char* last) {
  std::uint64_t mantissa = 0;
  int digits = 0, fraction = 0;
  bool point = false;
  for (const char* p = first; p != last; ++p) {
    if (*p == '.') {
      point = true;
      continue;
    }
    if (mantissa == 0 && *p == '0') {  // leading zeros carry no precision
      fraction += point;
      continue;
    }
    mantissa = mantissa * 10 + static_cast<std::uint64_t>(*p - '0');
    ++digits;
    fraction += point;
  }
  if (digits <= 15 && fraction <= 22) return static_cast<double>(mantissa) / kPowersOfTen[fraction];
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(first, last, v);
  // Out of range: zero below the smallest double; beyond the largest, infinity, which the
  // action refuses (not a number a program can mean, and not one to drop).
  if (ec == std::errc::result_out_of_range) return read_long_decimal(std::string_view(first, last - first));
  return v;
}

template <>
struct Action<g::unsigned_real> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    const double v = decimal_value(in.begin(), in.end());
    if (!std::isfinite(v))
      throw pegtl::parse_error(fmt::format("the number {}... is beyond any machine's range (1.8e308 at most)",
                                           std::string_view(in.begin(), std::min<std::size_t>(in.size(), 12))),
                               in);
    st.block->rpn.push_back(ExprNode{ExprOp::number, v, 0, 0});
  }
};

template <>
struct Action<g::named_parameter> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    Block& b = *st.block;
    const auto begin = static_cast<std::uint32_t>(b.names.size());
    b.names.append(in.begin() + 1, in.end() - 1);
    b.rpn.push_back(ExprNode{ExprOp::name, 0.0, begin, static_cast<std::uint32_t>(in.size() - 2)});
  }
};

template <>
struct Action<g::parameter_value> {
  template <typename Input>
  static void apply(const Input& /*in*/, State& st) {
    auto& rpn = st.block->rpn;
    if (st.rpn_size() - st.marks.back() == 1 && rpn.back().op == ExprOp::name)
      rpn.back().op = ExprOp::read_named;
    else
      rpn.push_back(ExprNode{ExprOp::read_numbered});
  }
};

template <>
struct Action<g::exists_call> {
  template <typename Input>
  static void apply(const Input& /*in*/, State& st) {
    auto& rpn = st.block->rpn;
    if (st.rpn_size() - st.marks.back() == 1 && rpn.back().op == ExprOp::name)
      rpn.back().op = ExprOp::exists;
    else
      rpn.push_back(ExprNode{ExprOp::exists_numbered});
  }
};

template <>
struct Action<g::signed_value> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    if (in.peek_char() != '-') return;
    auto& rpn = st.block->rpn;
    if (st.rpn_size() - st.marks.back() == 1 && rpn.back().op == ExprOp::number)
      rpn.back().number = -rpn.back().number;
    else
      rpn.push_back(ExprNode{ExprOp::negate});
  }
};

ExprOp function_named(std::string_view s) {
  if (s.starts_with("ABS")) return ExprOp::abs;
  if (s.starts_with("ACOS")) return ExprOp::acos;
  if (s.starts_with("ASIN")) return ExprOp::asin;
  if (s.starts_with("COS")) return ExprOp::cos;
  if (s.starts_with("EXP")) return ExprOp::exp;
  if (s.starts_with("FIX")) return ExprOp::fix;
  if (s.starts_with("FUP")) return ExprOp::fup;
  if (s.starts_with("LN")) return ExprOp::ln;
  if (s.starts_with("ROUND")) return ExprOp::round;
  if (s.starts_with("SIN")) return ExprOp::sin;
  if (s.starts_with("SQRT")) return ExprOp::sqrt;
  return ExprOp::tan;
}

template <>
struct Action<g::unary_call> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    st.block->rpn.push_back(ExprNode{function_named(in.string_view())});
  }
};

template <>
struct Action<g::atan_call> {
  template <typename Input>
  static void apply(const Input& /*in*/, State& st) {
    st.block->rpn.push_back(ExprNode{ExprOp::atan2});
  }
};

ExprOp operator_named(std::string_view s) {
  if (s == "**") return ExprOp::power;
  if (s == "*") return ExprOp::times;
  if (s == "/") return ExprOp::divide;
  if (s == "MOD") return ExprOp::modulo;
  if (s == "+") return ExprOp::plus;
  if (s == "-") return ExprOp::minus;
  if (s == "EQ") return ExprOp::eq;
  if (s == "NE") return ExprOp::ne;
  if (s == "GT") return ExprOp::gt;
  if (s == "GE") return ExprOp::ge;
  if (s == "LT") return ExprOp::lt;
  if (s == "LE") return ExprOp::le;
  if (s == "AND") return ExprOp::logical_and;
  if (s == "OR") return ExprOp::logical_or;
  return ExprOp::logical_xor;
}

template <>
struct Action<g::binary_operator> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    const ExprOp op = operator_named(in.string_view());
    auto& ops = st.operators;
    // Left to right within a level, as rs274ngc does (also for **).
    while (ops.back() != kMarker && precedence(static_cast<ExprOp>(ops.back())) >= precedence(op)) {
      st.block->rpn.push_back(ExprNode{static_cast<ExprOp>(ops.back())});
      ops.pop_back();
    }
    ops.push_back(static_cast<std::uint8_t>(op));
  }
};

template <>
struct Action<g::expression> {
  template <typename Input>
  static void apply(const Input& /*in*/, State& st) {
    auto& ops = st.operators;
    while (ops.back() != kMarker) {
      st.block->rpn.push_back(ExprNode{static_cast<ExprOp>(ops.back())});
      ops.pop_back();
    }
    ops.pop_back();
    if (st.collecting_o_arguments && st.expression_depth == 1)
      st.block->o.arguments.push_back(Value{0.0, st.marks.back(), st.rpn_size()});
  }
};

template <>
struct Action<g::address_extension> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    std::uint32_t digits = 0;
    if (in.size() > 1) {
      const auto [ptr, ec] = std::from_chars(in.begin(), in.end() - 1, digits);
      if (ec != std::errc() || digits == 0 || digits > 99)
        throw pegtl::parse_error("an extended address has 1 to 99 after its letter (A3=, C7=)", in);
    }
    st.extension = static_cast<std::uint16_t>(digits);
    st.value_begin = in.end();
  }
};

template <>
struct Action<g::word> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    Word w;
    const char* value_begin = st.value_begin ? st.value_begin : in.begin() + 1;
    w.letter = in.peek_char();
    w.extension = st.extension;
    w.span = st.span(in.begin(), in.end());
    w.value_span = st.span(value_begin, in.end());
    w.has_value = value_begin < in.end();
    w.value = st.value(st.marks.back(), st.rpn_size());
    st.block->words.push_back(w);
    st.extension = 0;
    st.value_begin = nullptr;
  }
};

template <>
struct Action<g::command_name> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    st.command = Command{};
    st.command.name = st.span(in.begin(), in.end());
  }
};

template <>
struct Action<g::command_arguments> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    st.command.has_arguments = true;
    st.command.arguments = st.span(in.begin() + 1, in.end() - 1);
  }
};

template <>
struct Action<g::command> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    Command c = st.command;
    c.span = st.span(in.begin(), in.end());
    c.has_value = st.rpn_size() > st.marks.back();
    if (c.has_value) c.value = st.value(st.marks.back(), st.rpn_size());
    st.block->commands.push_back(c);
  }
};

template <>
struct Action<g::parameter_index> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    st.index_end = st.rpn_size();
    st.index_named = in.peek_char() == '<';
    if (st.index_named) {
      st.index_name_begin = st.block->rpn.back().name_begin;
      st.index_name_size = st.block->rpn.back().name_size;
    }
  }
};

template <>
struct Action<g::parameter_setting> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    ParameterSetting s;
    s.span = st.span(in.begin(), in.end());
    s.named = st.index_named;
    s.name_begin = st.index_name_begin;
    s.name_size = st.index_name_size;
    if (!s.named) s.index = st.value(st.marks.back(), st.index_end);
    s.value = st.value(st.index_end, st.rpn_size());
    st.block->settings.push_back(s);
  }
};

template <>
struct Action<g::comment> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    Comment c;
    c.span = st.span(in.begin(), in.end());
    c.text = Span{c.span.begin + 1, c.span.end - 1};
    st.block->comments.push_back(c);
  }
};

template <>
struct Action<g::eol_comment> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    Comment c;
    c.span = st.span(in.begin(), in.end());
    c.text = Span{c.span.begin + 1, c.span.end};
    c.end_of_line = true;
    st.block->comments.push_back(c);
  }
};

template <>
struct Action<g::block_delete> {
  template <typename Input>
  static void apply(const Input& /*in*/, State& st) {
    st.block->block_delete = true;
  }
};

template <>
struct Action<g::line_number> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    Block& b = *st.block;
    b.has_line_number = true;
    b.line_number = b.rpn.back().number;
    b.rpn.pop_back();
    b.line_number_span = st.span(in.begin(), in.end());
  }
};

template <>
struct Action<g::program_delimiter> {
  template <typename Input>
  static void apply(const Input& /*in*/, State& st) {
    st.block->program_delimiter = true;
  }
};

template <>
struct Action<g::o_label> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    OStatement& o = st.block->o;
    if (in.peek_char() == '#') {
      o.computed = true;
      o.label_value = st.value(st.marks.back(), st.rpn_size());
      return;
    }
    if (in.peek_char() == '<') {
      const ExprNode n = st.block->rpn.back();
      st.block->rpn.pop_back();
      o.named = true;
      o.name.assign(st.block->name(n.name_begin, n.name_size));
      return;
    }
    std::uint32_t number = 0;
    const auto [ptr, ec] = std::from_chars(in.begin(), in.end(), number);
    if (ec != std::errc()) throw pegtl::parse_error("O number out of range", in);
    o.number = number;
  }
};

template <>
struct Action<g::o_statement> {
  template <typename Input>
  static void apply(const Input& in, State& st) {
    st.block->o.present = true;
    st.block->o.span = st.span(in.begin(), in.end());
  }
};

template <OKeyword K>
struct KeywordAction {
  template <typename Input>
  static void apply(const Input& /*in*/, State& st) {
    st.block->o.keyword = K;
  }
};
template <>
struct Action<g::o_sub> : KeywordAction<OKeyword::sub> {};
template <>
struct Action<g::o_endsub> : KeywordAction<OKeyword::endsub> {};
template <>
struct Action<g::o_call> : KeywordAction<OKeyword::call> {};
template <>
struct Action<g::o_return> : KeywordAction<OKeyword::return_> {};
template <>
struct Action<g::o_if> : KeywordAction<OKeyword::if_> {};
template <>
struct Action<g::o_elseif> : KeywordAction<OKeyword::elseif> {};
template <>
struct Action<g::o_else> : KeywordAction<OKeyword::else_> {};
template <>
struct Action<g::o_endif> : KeywordAction<OKeyword::endif> {};
template <>
struct Action<g::o_while> : KeywordAction<OKeyword::while_> {};
template <>
struct Action<g::o_endwhile> : KeywordAction<OKeyword::endwhile> {};
template <>
struct Action<g::o_do> : KeywordAction<OKeyword::do_> {};
template <>
struct Action<g::o_break> : KeywordAction<OKeyword::break_> {};
template <>
struct Action<g::o_continue> : KeywordAction<OKeyword::continue_> {};
template <>
struct Action<g::o_repeat> : KeywordAction<OKeyword::repeat> {};
template <>
struct Action<g::o_endrepeat> : KeywordAction<OKeyword::endrepeat> {};

// How the lexical layer treats each byte: copied (folded to upper case), dropped (blank),
// or the start of a comment.
enum : std::uint8_t { kCopy = 0, kBlank = 1, kComment = 2 };

struct ByteClasses {
  std::array<std::uint8_t, 256> kind{};
  std::array<char, 256> upper{};
  constexpr ByteClasses() {
    for (int c = 0; c < 256; ++c)
      upper[static_cast<std::size_t>(c)] = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
    kind[' '] = kind['\t'] = kBlank;
    kind['('] = kind[';'] = kind['['] = kComment;
  }
};
constexpr ByteClasses kBytes;

bool is_name_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

/// Whether the folded text before `k` ends in a command's name: two letters after anything
/// but a letter (`N60ORIMKS`, `CYCLE832`), then letters, digits and '_' to `k`.
bool ends_a_name(const char* folded, std::size_t k) {
  auto letter = [](char c) { return c >= 'A' && c <= 'Z'; };
  std::size_t start = k;
  while (start > 0 && is_name_char(folded[start - 1])) --start;
  for (std::size_t p = start; p + 1 < k; ++p)
    if (letter(folded[p]) && letter(folded[p + 1]) && (p == start || !letter(folded[p - 1]))) return true;
  return false;
}

// The lexical layer: blanks out, letters up, comments verbatim; remember where each kept
// byte came from.
constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";

void fold(std::string_view line, const Dialect& dialect, std::string& folded, std::vector<std::uint32_t>& offsets) {
  const std::size_t n = line.size();
  folded.resize(n);
  offsets.resize(n + 1);
  char* f = folded.data();
  std::uint32_t* o = offsets.data();
  std::size_t k = 0;  // bytes kept
  // A UTF-8 byte-order mark (editors on Windows write one) is not text of the program.
  std::size_t i = line.starts_with(kByteOrderMark) ? kByteOrderMark.size() : 0;
  auto keep = [&](std::size_t at) {
    f[k] = line[at];
    o[k++] = static_cast<std::uint32_t>(at);
  };
  while (i < n) {
    const char c = line[i];
    const std::uint8_t kind = kBytes.kind[static_cast<unsigned char>(c)];
    if (c == '"' && !dialect.parenthesis_comments) {
      // A Siemens string: verbatim, blanks, case and ';' included.
      keep(i++);
      while (i < n && line[i] != '"') keep(i++);
      if (i < n) keep(i++);
      continue;
    }
    if (kind == kCopy || (c == '[' && !dialect.bracket_comments) || (c == '(' && !dialect.parenthesis_comments)) {
      f[k] = kBytes.upper[static_cast<unsigned char>(c)];
      o[k++] = static_cast<std::uint32_t>(i++);
    } else if (kind == kBlank) {
      // Siemens: a blank ends a command's name (`TRAORI G0`): one is kept after a name, for
      // the grammar's separator (after a word's letter it goes, as `X 10` is X10).
      if (dialect.named_commands && ends_a_name(f, k)) {
        std::size_t next = i;
        while (next < n && kBytes.kind[static_cast<unsigned char>(line[next])] == kBlank) ++next;
        if (next < n && is_name_char(kBytes.upper[static_cast<unsigned char>(line[next])])) {
          f[k] = ' ';
          o[k++] = static_cast<std::uint32_t>(i);
        }
        i = next;
        continue;
      }
      ++i;
    } else if (c == '(' || c == '[') {
      // WinCNC's `[ ... ]` reads as `( ... )`; the offsets still point at the brackets.
      const char close = c == '(' ? ')' : ']';
      keep(i++);
      if (c == '[') f[k - 1] = '(';
      while (i < n && line[i] != close) keep(i++);
      if (i < n) {
        keep(i++);
        if (c == '[') f[k - 1] = ')';
      }
    } else {  // ';' to the end of the line
      while (i < n) keep(i++);
    }
  }
  o[k] = static_cast<std::uint32_t>(n);
  folded.resize(k);
  offsets.resize(k + 1);
}

template <typename Rule>
struct NameCollector {
  static void visit(std::vector<std::string>& names) {
    const std::string_view full = pegtl::demangle<Rule>();
    constexpr std::string_view prefix = "ccomp::gcode::grammar::";
    if (!full.starts_with(prefix)) return;
    const std::string_view name = full.substr(prefix.size());
    if (name.find_first_of("<:") != std::string_view::npos) return;
    names.emplace_back(name);
  }
};

}  // namespace

Parser::Parser(Dialect dialect, bool fast_path) : dialect_(std::move(dialect)), fast_path_(fast_path) {}

// The fast path: `[/][N<number>] (<letter><number> | (comment))* [;comment]` and `%` lines,
// with blanks between tokens, upper or lower case. Anything else (parameters, expressions,
// O-words, blanks inside a number, a letter without a number, anything malformed) returns
// false and the grammar reads the line, so errors always come from the grammar.
bool Parser::parse_simple(std::string_view t, Block& out) const {
  const std::size_t n = t.size();
  std::size_t i = 0;
  auto skip_blanks = [&] {
    while (i < n && (t[i] == ' ' || t[i] == '\t')) ++i;
  };
  // A number at i: sets `value`, advances i.
  double value = 0.0;
  DecimalForm form;
  auto number = [&] { return read_decimal(t, i, value, &form); };
  auto is_letter = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); };
  auto upper = [](char c) { return c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c; };

  if (t.starts_with(kByteOrderMark)) i = kByteOrderMark.size();
  skip_blanks();
  if (i < n && t[i] == '%') {
    out.program_delimiter = true;
    return true;
  }
  if (i < n && t[i] == '/') {
    out.block_delete = true;
    ++i;
    skip_blanks();
  }
  if (i < n && (t[i] == 'N' || t[i] == 'n')) {
    const std::size_t start = i++;
    skip_blanks();
    if (i == n || t[i] == '+' || t[i] == '-' || !number()) return false;
    out.has_line_number = true;
    out.line_number = value;
    out.line_number_span = Span{static_cast<std::uint32_t>(start), static_cast<std::uint32_t>(i)};
  }
  for (;;) {
    skip_blanks();
    if (i == n) return true;
    const char c = t[i];
    if (c == '(') {
      if (!dialect_.parenthesis_comments) return false;
      const std::size_t close = t.find(')', i + 1);
      if (close == std::string_view::npos) return false;
      if (t.substr(i + 1, close - i - 1).find('(') != std::string_view::npos) return false;
      out.comments.push_back(Comment{Span{static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(close + 1)},
                                     Span{static_cast<std::uint32_t>(i + 1), static_cast<std::uint32_t>(close)},
                                     false});
      i = close + 1;
      continue;
    }
    if (c == ';') {
      out.comments.push_back(Comment{Span{static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(n)},
                                     Span{static_cast<std::uint32_t>(i + 1), static_cast<std::uint32_t>(n)}, true});
      return true;
    }
    const char letter = upper(c);
    if (!(is_letter(c) || c == '$') || letter == 'N' || letter == 'O') return false;
    const std::size_t start = i++;
    skip_blanks();
    const std::size_t value_start = i;
    if (i == n || !number() || !std::isfinite(value)) return false;  // the grammar says why
    // A digit right after the number (a blank inside it, `X1 5`) is the grammar's to read.
    // (i is left after the blanks: the next token starts there.)
    const std::size_t after = i;
    skip_blanks();
    if (i < n && ((t[i] >= '0' && t[i] <= '9') || t[i] == '.')) return false;
    Word w;
    w.letter = letter;
    w.span = Span{static_cast<std::uint32_t>(start), static_cast<std::uint32_t>(after)};
    w.value_span = Span{static_cast<std::uint32_t>(value_start), static_cast<std::uint32_t>(after)};
    w.value = Value{value, 0, 0};
    w.decimals = form.fraction_digits <= 127 ? static_cast<std::int8_t>(form.fraction_digits) : std::int8_t{-1};
    w.point_first = form.point_first;
    out.words.push_back(w);
  }
}

constexpr std::size_t kMaxNesting = 256;

/// Refuses what would exhaust the parser rather than be read: a line longer than any
/// program has (kMaxLineBytes), brackets and `#` nested deeper than kMaxNesting (the grammar
/// recurses once for each; LinuxCNC's own limit on expressions is far below), and a
/// carriage return inside the line (a file of CR-only line ends read as one line).
void check_size(std::string_view text, std::uint32_t line, std::string_view file) {
  auto refuse = [&](std::size_t at, const std::string& message) {
    throw Error(ErrorKind::program, message,
                SourceLocation{std::string(file), line, static_cast<std::uint32_t>(at + 1)},
                std::string(text.substr(0, std::min<std::size_t>(text.size(), 200))));
  };
  auto refuse_cr = [&](std::size_t at) {
    refuse(at,
           "a carriage return inside the line: line ends of CR alone (classic Mac files) are not read; "
           "convert them to LF or CRLF");
  };
  if (text.size() > kMaxLineBytes) {
    if (const auto cr = text.find('\r'); cr != std::string_view::npos) refuse_cr(cr);
    refuse(kMaxLineBytes,
           fmt::format("a line of {} bytes: more than {}, not a line of G-code", text.size(), kMaxLineBytes));
  }
  std::size_t depth = 0, hashes = 0;  // brackets open; '#' in a row (each nests a parameter)
  bool in_comment = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == ';' && !in_comment) break;
    if (c == '(') in_comment = true;
    if (c == ')') in_comment = false;
    if (in_comment) continue;
    if (c == '\r') refuse_cr(i);
    if (c == '#')
      ++hashes;
    else if (c != '+' && c != '-' && c != ' ' && c != '\t' && c != '[')
      hashes = 0;
    if (c == '[') ++depth;
    if (c == ']' && depth > 0) --depth;
    if (depth + hashes > kMaxNesting)
      refuse(i, fmt::format("brackets and parameters nested more than {} deep", kMaxNesting));
  }
}

void Parser::parse(std::string_view text, std::uint32_t line, std::string_view file, Block& out) {
  out.clear();
  out.text = text;
  out.line = line;
  if (text.size() > kMaxLineBytes) check_size(text, line, file);
  if (fast_path_ && !dialect_.bracket_comments) {
    if (parse_simple(text, out)) return;
    out.clear();
    out.text = text;
    out.line = line;
  }
  check_size(text, line, file);
  fold(text, dialect_, folded_, offsets_);
  marks_.clear();
  operators_.clear();
  State st{&dialect_, &out, nullptr, nullptr, marks_, operators_};
  st.base = folded_.data();
  st.offsets = offsets_.data();
  pegtl::memory_input<pegtl::tracking_mode::lazy, pegtl::eol::lf_crlf> in(folded_.data(), folded_.size(), "");
  try {
    pegtl::parse<g::line, Action, Control>(in, st);
  } catch (const pegtl::parse_error& e) {
    const auto& pos = e.positions().front();
    const std::uint32_t column = offsets_[std::min(pos.byte, folded_.size())] + 1;
    throw Error(ErrorKind::program, std::string(e.message()), SourceLocation{std::string(file), line, column},
                std::string(text));
  }
}

std::vector<std::string> grammar_rule_names() {
  std::vector<std::string> names;
  pegtl::visit<g::line, NameCollector>(names);
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace ccomp::gcode
