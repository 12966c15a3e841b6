#pragma once
// Private: the interpreter's state, shared by interpreter.cpp (the run loop and control
// flow) and execute.cpp (what one block does).
#include <array>
#include <bitset>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "ccomp/constants.hpp"
#include "ccomp/error.hpp"
#include "ccomp/gcode/interpreter.hpp"
#include "ccomp/gcode/parameters.hpp"
#include "ccomp/gcode/parser.hpp"
#include "cutter_compensation.hpp"

namespace ccomp::gcode {

/// The words of one block, evaluated: values by letter, G and M codes times ten.
struct Words {
  std::array<double, 26> value{};
  std::array<const Word*, 26> word{};  ///< for error positions; nullptr when absent
  std::uint32_t present = 0;           ///< bit (letter - 'A')
  std::array<int, 16> g{};
  std::array<const Word*, 16> g_word{};
  int g_count = 0;
  std::array<int, 8> m{};
  std::array<const Word*, 8> m_word{};
  int m_count = 0;
  bool has_spindle_selector = false;
  /// Siemens' direction vector under TRAORI (A3= B3= C3=): the components given.
  std::array<double, 3> vector{};
  std::array<const Word*, 3> vector_word{};
  /// The first of A3= B3= C3= the block gives, or nullptr.
  [[nodiscard]] const Word* first_vector_word() const {
    for (const Word* w : vector_word)
      if (w) return w;
    return nullptr;
  }
  std::bitset<1000> g_set;   ///< G codes (times ten) below G100 present, for has_g()
  std::uint32_t groups = 0;  ///< bit g: a G code of modal group g is present
  [[nodiscard]] bool has_group(int group) const { return (groups >> group) & 1U; }
  std::bitset<200> m_set;  ///< M codes below M200 present

  [[nodiscard]] bool has(char letter) const { return (present >> (letter - 'A')) & 1U; }
  [[nodiscard]] double operator[](char letter) const { return value[static_cast<std::size_t>(letter - 'A')]; }
  [[nodiscard]] bool has_g(int code) const {
    if (code < 1000) return g_set[static_cast<std::size_t>(code)];
    for (int i = 0; i < g_count; ++i)
      if (g[static_cast<std::size_t>(i)] == code) return true;
    return false;
  }
  [[nodiscard]] bool has_m(int code) const {
    if (code < 200) return m_set[static_cast<std::size_t>(code)];
    for (int i = 0; i < m_count; ++i)
      if (m[static_cast<std::size_t>(i)] == code) return true;
    return false;
  }
  [[nodiscard]] std::uint32_t axis_mask() const;
};

/// A subroutine call in progress.
struct CallFrame {
  std::string label;
  std::size_t source = 0;    ///< index into Impl::sources
  SourcePosition return_to;  ///< the line after the call
  std::size_t return_source = 0;
  SourcePosition body;  ///< the first line of the body (for Fanuc L repeats)
  std::size_t control_depth = 0;
  int repeats_left = 0;
  bool fanuc = false;
};

/// An if or loop in progress.
struct ControlFrame {
  OKeyword kind = OKeyword::if_;
  std::string label;
  SourcePosition start;  ///< while: the while line; do/repeat: the first line of the body
  double remaining = 0;  ///< repeat count left
};

struct SubDefinition {
  std::size_t source = 0;
  SourcePosition body;
  bool fanuc = false;
};

struct Interpreter::Impl {
  explicit Impl(InterpreterOptions o);

  InterpreterOptions options;
  Parser parser;
  Parameters params;
  NamedValues overrides;  ///< --param values
  ModalState modal;
  Offsets offsets;
  /// Bit s - 1: coordinate system s's origin is known (given, or set by the program).
  std::uint32_t known_systems = 0;
  bool warned_unknown_origin = false;
  /// Says once that a rotary axis moves in a coordinate system whose origin nobody gave.
  void check_origin_known(const Motion& m);
  Axes position{};                     ///< controlled point, machine frame, no tool length
  std::uint32_t position_unknown = 0;  ///< axes whose place only a probe knows
  ToolTable tools;

  // canned-cycle sticky values (mm, program frame of the cycle axis)
  double cycle_r = 0.0, cycle_bottom = 0.0, cycle_p = 0.0, cycle_q = 0.0;
  double cycle_r_increment = 0.0, cycle_bottom_increment = 0.0;
  bool cycle_values_set = false;
  double cycle_initial = 0.0;  ///< the initial level of a run of cycle blocks (program frame)
  bool cycle_initial_set = false;

  // control flow
  std::vector<std::unique_ptr<LineSource>> owned_sources;
  std::vector<LineSource*> sources;
  std::size_t current_source = 0;
  std::vector<CallFrame> calls;
  std::vector<ControlFrame> controls;
  std::unordered_map<std::string, SubDefinition> subs;
  bool program_started = false;  ///< an executable block was seen (O-number is a name before)
  bool percent_seen = false;
  bool ended = false;
  double value_returned = 0.0;
  bool has_value_returned = false;
  std::uint64_t blocks_executed = 0;
  std::uint64_t blocks_since_motion = 0;  ///< a loop that never moves is endless
  /// The program went back (a loop, a call, a return) since its last move: without that, a
  /// run of lines without a move is only a long file (a million blank lines), not a loop.
  bool jumped_since_motion = false;
  std::size_t last_source = 0;
  std::uint64_t last_offset = 0;
  /// Where each stretch skipped so far ended: a loop that skips the same false `if` on every
  /// pass reads it once (it rescanned it each time: quadratic in the file). Keyed by the
  /// source, the offset the skip started after, the label and the stopping keywords.
  struct SkipEnd {
    SourcePosition target;      ///< the line the skip stopped at (read again from here)
    std::uint64_t scanned = 0;  ///< lines passed over, the target included
  };
  std::unordered_map<std::string, SkipEnd> skip_ends;
  CutterCompensation comp;                ///< G41/G42's offset path and its waiting moves
  bool leaving_offset = false;            ///< G40 took an offset off: the next move leaves it
  CanonSink discard;                      ///< where output goes without a sink

  CanonSink* sink = nullptr;
  Block block;
  SourceLine line;
  Words words;
  std::vector<double> word_values;  ///< each word's value, for a sink that wants them

  // --- run loop and control flow (interpreter.cpp)
  void run(LineSource& source, CanonSink& out);
  bool next_block();
  /// Counts `n` blocks run or scanned against the limits (an endless loop; a loop without a
  /// move), refusing at the current block.
  void count_blocks(std::uint64_t n);
  void execute_o(const Block& b);
  void skip_to(const std::string& label, std::initializer_list<OKeyword> stops, bool fanuc_sub_end = false);
  void call_sub(const std::string& label, bool fanuc, const Block& b, const Word* where, int repeats);
  void return_from_sub(const Block& b);
  SubDefinition find_sub(const std::string& label, bool fanuc, const Block& b, const Word* where);
  void define_sub(const Block& b, bool fanuc);

  // --- values (interpreter.cpp)
  double evaluate(const Block& b, const Value& v);
  double read_numbered(const Block& b, double index);
  double read_named(const Block& b, std::string_view name);
  bool named_exists(std::string_view name);
  /// Where `<name>` (folded) stands in the original line, for error positions.
  [[nodiscard]] Span locate_name(const Block& b, std::string_view folded) const;
  void write_numbered(const Block& b, double index, double v);
  void write_named(const Block& b, std::string_view name, double v);

  // --- one block (execute.cpp)
  void execute(const Block& b);
  void decode(const Block& b);
  /// The G code (times ten) the dialect means by `code`: its alias, or a refusal at the word.
  [[nodiscard]] int dialect_g_code(const Block& b, const Word& w, int code) const;
  void check_unused_words(const Block& b, int motion_code, int non_modal);
  /// A dialect pass-through G code of the block that moves axes ccomp does not model, or -1.
  [[nodiscard]] int passthrough_code() const;
  void comment(const Block& b);
  void abort_comment(const Block& b);
  std::string substitute_parameters(const Block& b, std::string_view body);
  void set_units(Units u);
  void motion(const Block& b, int code, int non_modal);
  void straight(MotionKind kind, const Axes& target, MotionSource source);
  void arc(const Block& b, int code, const Axes& target);
  /// The centre and signed turns of the block's arc from `start` (interpreter frame).
  PlaneArc arc_centre(const Block& b, int code, const Axes& start, const Axes& target);
  /// A motion of the programmed point from here to `target`, in the interpreter's frame.
  [[nodiscard]] Motion motion_to(MotionKind kind, MotionSource source, const Axes& target) const;
  /// Moves the programmed point to `target` and reports `m` (interpreter frame): at once, or
  /// under G41/G42 through the offset's queue (the offset path, or `m` with it). `m` is
  /// turned into the machine frame in place (a motion is ~400 bytes, sent at every move).
  void send(Motion& m, const Axes& target);

  // --- cutter radius compensation (execute_cutter_comp.cpp)
  void cutter_compensation(const Block& b, int code);
  void refuse_under_compensation(const Block& b, const char* what) const;
  /// Runs a step of the offset path; its refusal becomes an error at the block.
  template <typename Step>
  void offset_path(Step&& step) {
    try {
      step();
    } catch (const CompensationError& e) {
      fail(block, nullptr, e.what());
    }
  }
  CanonSink& out() { return sink ? *sink : discard; }
  void canned_cycle(const Block& b, int code);
  void cycle_move(MotionKind kind, std::size_t first, std::size_t second, std::size_t normal, double a, double b,
                  double c);
  void reference_return(const Block& b, int code);
  void set_g92(const Block& b, int code);
  void g10(const Block& b);
  void tool_length(const Block& b, int code);
  /// TCP on or off by the block's M codes (M128/M129, M428/M429: TcpCodes::follow).
  void switch_tcp_by_m_codes(const Block& b);
  /// TCP by `code` (0: off), the position carried into the other coordinates where it
  /// switches (InterpreterOptions::tcp_switch).
  void set_tcp(int code);

  // --- the siemens dialect (execute_commands.cpp)
  /// The block's named commands (TRAORI, TRAFOOF, ORIAXES, ...): each followed, passed
  /// through or refused at its name.
  void named_commands(const Block& b);
  /// D as a cutting edge of the tool in the spindle, after a tool change (Dialect::
  /// d_selects_cutting_edge): its length offset in force, or none with D0.
  void cutting_edge(const Block& b, bool tool_changed);
  /// Under TRAORI, how the tool turns from block to block (ModalState::orientation_path):
  /// OrientationPath::other where the program's codes leave it to the machine data.
  [[nodiscard]] OrientationPath siemens_interpolation() const;
  /// Under TRAORI a feed move or an arc whose rotary axes turn is refused where ccomp does
  /// not follow its interpolation (an arc: along a great circle, too).
  void check_orientation_interpolation(const Block& b, const Axes& target, bool arc) const;
  /// Whether the block gives the tool's direction (G43.5's I J K, Siemens' A3= B3= C3=): a
  /// move, though it names no axis.
  [[nodiscard]] bool direction_given() const {
    return (modal.tcp == 435 && (words.has('I') || words.has('J') || words.has('K'))) ||
           words.first_vector_word() != nullptr;
  }
  /// Under G43.5 (the block's I J K) or TRAORI (its A3= B3= C3=): `target` with its rotary
  /// axes' angles where the control's kinematics put the direction the words give, a
  /// component left out 0 (InterpreterOptions::tcp_direction); as it is without them.
  Axes turned_to_direction(const Block& b, Axes target, const std::array<const Word*, 3>& given,
                           const std::array<double, 3>& values);
  void end_program(const Block& b);
  Axes target_of(const Block& b, bool machine_coordinates);

  // --- helpers
  [[noreturn]] void fail(const Block& b, const Word* where, const std::string& message) const;
  [[noreturn]] void fail_at(const Block& b, Span span, const std::string& message) const;
  /// Valid G-code ccomp does not handle (exit 4), at the span.
  [[noreturn]] void unsupported_at(const Block& b, Span span, const std::string& message) const;
  void warn(const std::string& message, std::uint32_t line_no) const;
  void emit(std::string_view name, std::string args);
  /// Tells the sink a block is about to run (or holds it behind moves the offset keeps).
  void announce(const Block& b, const SourceLine& l);
  /// For calls on hot paths: formats only when a sink reads canonical calls.
  template <typename MakeArguments>
  void emit_lazy(std::string_view name, MakeArguments&& make) {
    if (sink && sink->wants_calls()) emit(name, make());
  }
  /// mm per program unit (G20/G21) and per machine unit (parameters, tool table).
  [[nodiscard]] double unit() const { return modal.units == Units::inch ? kMmPerInch : 1.0; }
  [[nodiscard]] double machine_unit() const { return options.machine_units == Units::inch ? kMmPerInch : 1.0; }
  /// mm or deg per stored unit of a parameter for `axis` (machine units; degrees for A B C).
  [[nodiscard]] double stored_scale(std::size_t axis) const { return is_rotary(axis) ? 1.0 : machine_unit(); }
  [[nodiscard]] double program(std::size_t axis) const { return position[axis] - offsets.origin(axis); }
  [[nodiscard]] const std::string& file_name() const { return sources[current_source]->name(); }
  /// Changes offsets without moving the machine: the interpreter-frame point follows.
  template <typename Change>
  void change_offsets(Change&& change) {
    const Axes machine = offsets.to_machine(position);
    change();
    position = offsets.from_machine(machine);
  }
  void select_coordinate_system(int system);
};

}  // namespace ccomp::gcode
