#pragma once
// PEGTL rules of grammar/gcode.peg, one struct per production and with the same name.
// tests/gcode/grammar_sync_test.cpp checks that the two name the same rules. The rules read
// the folded line (blanks removed, letters upper case; see the .peg file's lexical layer).
// `must<>` marks the points past which a failure is an error: the messages are in
// src/gcode/parser.cpp, keyed by the rule that failed.
#include <tao/pegtl.hpp>

#include "ccomp/gcode/dialect.hpp"

namespace ccomp::gcode::grammar {

namespace pegtl = tao::pegtl;

/// The state a custom rule may consult: which dialect is being read.
struct DialectView {
  const Dialect* dialect = nullptr;
};

struct real_value;
struct expression;

struct digits : pegtl::plus<pegtl::digit> {};
struct unsigned_real : pegtl::sor<pegtl::seq<digits, pegtl::opt<pegtl::one<'.'>, pegtl::opt<digits>>>,
                                  pegtl::seq<pegtl::one<'.'>, digits>> {};

struct parameter_name : pegtl::plus<pegtl::not_one<'>'>> {};
struct named_parameter : pegtl::seq<pegtl::one<'<'>, pegtl::must<parameter_name>, pegtl::must<pegtl::one<'>'>>> {};
struct parameter_value : pegtl::seq<pegtl::one<'#'>, pegtl::must<pegtl::sor<named_parameter, real_value>>> {};

struct operand : pegtl::seq<real_value> {};
struct binary_operator
    : pegtl::sor<TAO_PEGTL_STRING("**"), pegtl::one<'*'>, pegtl::one<'/'>, TAO_PEGTL_STRING("MOD"), pegtl::one<'+'>,
                 pegtl::one<'-'>, TAO_PEGTL_STRING("EQ"), TAO_PEGTL_STRING("NE"), TAO_PEGTL_STRING("GT"),
                 TAO_PEGTL_STRING("GE"), TAO_PEGTL_STRING("LT"), TAO_PEGTL_STRING("LE"), TAO_PEGTL_STRING("AND"),
                 TAO_PEGTL_STRING("OR"), TAO_PEGTL_STRING("XOR")> {};
struct expression : pegtl::seq<pegtl::one<'['>, pegtl::must<operand>,
                               pegtl::star<binary_operator, pegtl::must<operand>>, pegtl::must<pegtl::one<']'>>> {};

struct atan_call : pegtl::seq<TAO_PEGTL_STRING("ATAN"), pegtl::must<expression>, pegtl::must<pegtl::one<'/'>>,
                              pegtl::must<expression>> {};
struct exists_call : pegtl::seq<TAO_PEGTL_STRING("EXISTS"), pegtl::must<pegtl::one<'['>>, pegtl::must<pegtl::one<'#'>>,
                                pegtl::must<pegtl::sor<named_parameter, real_value>>, pegtl::must<pegtl::one<']'>>> {};
struct unary_function : pegtl::sor<TAO_PEGTL_STRING("ABS"), TAO_PEGTL_STRING("ACOS"), TAO_PEGTL_STRING("ASIN"),
                                   TAO_PEGTL_STRING("COS"), TAO_PEGTL_STRING("EXP"), TAO_PEGTL_STRING("FIX"),
                                   TAO_PEGTL_STRING("FUP"), TAO_PEGTL_STRING("LN"), TAO_PEGTL_STRING("ROUND"),
                                   TAO_PEGTL_STRING("SIN"), TAO_PEGTL_STRING("SQRT"), TAO_PEGTL_STRING("TAN")> {};
struct unary_call : pegtl::seq<unary_function, pegtl::must<expression>> {};
struct function_call : pegtl::seq<pegtl::at<pegtl::upper>, pegtl::sor<atan_call, exists_call, unary_call>> {};

struct unsigned_value : pegtl::sor<unsigned_real, expression, parameter_value, function_call> {};
struct signed_value : pegtl::seq<pegtl::one<'+', '-'>, pegtl::must<unsigned_value>> {};
struct real_value : pegtl::sor<unsigned_value, signed_value> {};

struct comment_text : pegtl::star<pegtl::not_one<')', '('>> {};

struct siemens_only;
struct comment : pegtl::seq<pegtl::not_at<siemens_only>, pegtl::one<'('>, comment_text, pegtl::must<pegtl::one<')'>>> {
};
struct eol_comment : pegtl::seq<pegtl::one<';'>, pegtl::star<pegtl::any>> {};

struct word_letter : pegtl::sor<pegtl::ranges<'A', 'M', 'P', 'Z'>, pegtl::one<'$'>> {};

/// A letter with no value, in the dialects that allow it (Haas `G82 R.1 Z-.1 P F15.`).
struct empty_value {
  using rule_t = empty_value;
  using subs_t = pegtl::empty_list;
  template <pegtl::apply_mode A, pegtl::rewind_mode M, template <typename...> class Action,
            template <typename...> class Control, typename ParseInput, typename State>
  static bool match(ParseInput& in, State& state) {
    if (!state.dialect->empty_word_values) return false;
    if (in.empty()) return true;
    const char c = in.peek_char();
    return (c >= 'A' && c <= 'Z' && c != 'N' && c != 'O') || c == '$' || c == '(' || c == ';';
  }
};

/// Matches nothing, only where the dialect is Siemens' (Dialect::named_commands).
struct siemens_only {
  using rule_t = siemens_only;
  using subs_t = pegtl::empty_list;
  template <pegtl::apply_mode A, pegtl::rewind_mode M, template <typename...> class Action,
            template <typename...> class Control, typename ParseInput, typename State>
  static bool match(ParseInput& /*in*/, State& state) {
    return state.dialect->named_commands;
  }
};

struct address_extension : pegtl::seq<siemens_only, pegtl::sor<pegtl::seq<digits, pegtl::one<'='>>, pegtl::one<'='>>> {
};
struct word
    : pegtl::seq<word_letter, pegtl::opt<address_extension>, pegtl::must<pegtl::sor<real_value, empty_value>>> {};

struct string_end : pegtl::one<'"'> {};
struct string : pegtl::seq<pegtl::one<'"'>, pegtl::star<pegtl::not_one<'"'>>, pegtl::must<string_end>> {};
struct command_name : pegtl::seq<pegtl::upper, pegtl::sor<pegtl::upper, pegtl::one<'_'>>,
                                 pegtl::star<pegtl::sor<pegtl::upper, pegtl::digit, pegtl::one<'_'>>>> {};
struct arguments_end : pegtl::one<')'> {};
struct command_arguments : pegtl::seq<pegtl::one<'('>, pegtl::star<pegtl::sor<string, command_arguments, pegtl::not_one<')'>>>,
                                      pegtl::must<arguments_end>> {};
struct command_value : pegtl::seq<pegtl::one<'='>, pegtl::must<real_value>> {};
struct command : pegtl::seq<siemens_only, command_name, pegtl::opt<pegtl::sor<command_arguments, command_value>>> {};

struct parameter_index : pegtl::sor<named_parameter, real_value> {};
struct parameter_setting
    : pegtl::seq<pegtl::one<'#'>, pegtl::must<parameter_index>, pegtl::must<pegtl::one<'='>>, pegtl::must<real_value>> {
};

struct separator : pegtl::one<' '> {};
struct segment : pegtl::sor<command, word, comment, parameter_setting, separator> {};

struct comment;
struct o_label : pegtl::sor<named_parameter, digits, parameter_value> {};
struct o_sub : TAO_PEGTL_STRING("SUB") {};
struct o_endsub : pegtl::seq<TAO_PEGTL_STRING("ENDSUB"), pegtl::opt<expression>> {};
struct o_call : pegtl::seq<TAO_PEGTL_STRING("CALL"), pegtl::star<pegtl::sor<expression, comment>>> {};
struct o_return : pegtl::seq<TAO_PEGTL_STRING("RETURN"), pegtl::opt<expression>> {};
struct o_if : pegtl::seq<TAO_PEGTL_STRING("IF"), pegtl::must<expression>> {};
struct o_elseif : pegtl::seq<TAO_PEGTL_STRING("ELSEIF"), pegtl::must<expression>> {};
struct o_else : TAO_PEGTL_STRING("ELSE") {};
struct o_endif : TAO_PEGTL_STRING("ENDIF") {};
struct o_while : pegtl::seq<TAO_PEGTL_STRING("WHILE"), pegtl::must<expression>> {};
struct o_endwhile : TAO_PEGTL_STRING("ENDWHILE") {};
struct o_do : TAO_PEGTL_STRING("DO") {};
struct o_break : TAO_PEGTL_STRING("BREAK") {};
struct o_continue : TAO_PEGTL_STRING("CONTINUE") {};
struct o_repeat : pegtl::seq<TAO_PEGTL_STRING("REPEAT"), pegtl::must<expression>> {};
struct o_endrepeat : TAO_PEGTL_STRING("ENDREPEAT") {};
struct o_keyword : pegtl::sor<o_sub, o_endsub, o_call, o_return, o_if, o_elseif, o_else, o_endif, o_while, o_endwhile,
                              o_do, o_break, o_continue, o_repeat, o_endrepeat> {};
struct o_statement
    : pegtl::seq<pegtl::not_at<command>, pegtl::one<'O'>, pegtl::must<o_label>, pegtl::opt<o_keyword>,
                 pegtl::star<segment>> {};

struct block_delete : pegtl::one<'/'> {};
struct line_number : pegtl::seq<pegtl::one<'N'>, pegtl::must<unsigned_real>> {};
struct end_of_block : pegtl::seq<pegtl::opt<eol_comment>, pegtl::eof> {};
struct block : pegtl::seq<pegtl::opt<block_delete>, pegtl::opt<line_number>,
                          pegtl::sor<o_statement, pegtl::star<segment>>, pegtl::must<end_of_block>> {};
struct program_delimiter : pegtl::seq<pegtl::one<'%'>, pegtl::star<pegtl::any>> {};
struct line : pegtl::sor<program_delimiter, block> {};

}  // namespace ccomp::gcode::grammar
