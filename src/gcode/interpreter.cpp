#include "ccomp/gcode/interpreter.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "ccomp/constants.hpp"
#include "ccomp/util/ascii.hpp"
#include "interpreter_impl.hpp"

namespace ccomp::gcode {

namespace {

std::string label_of(const OStatement& o) {
  return o.named ? "<" + o.name + ">" : std::to_string(o.number);
}

std::string label_of_number(double v) {
  return std::to_string(static_cast<long long>(std::lround(v)));
}

// Parameters only a running controller can know: probe results, M66 inputs, tool-changer
// faults. Reading one without --param is refused rather than guessed.
bool controller_only(int n) {
  return (n >= 5061 && n <= 5070) || n == 5399 || n == 5600 || n == 5601;
}

}  // namespace

Interpreter::Impl::Impl(InterpreterOptions o)
    : options(std::move(o)), parser(options.dialect), tools(options.tools), comp(options.cutter_path) {
  // Hold the tool table in mm, like every other length inside the interpreter.
  for (auto& [number, entry] : tools.tools) {
    for (std::size_t i = 0; i < kAxisCount; ++i)
      if (!is_rotary(i)) entry.offset[i] *= machine_unit();
    entry.diameter *= machine_unit();
  }
  for (std::size_t s = 0; s < options.work_offsets.size(); ++s) {
    if (!options.work_offsets[s]) continue;
    known_systems |= 1U << s;
    for (std::size_t i = 0; i < kAxisCount; ++i)
      params.set_numbered(5221 + static_cast<int>(s) * 20 + static_cast<int>(i),
                          (*options.work_offsets[s])[i] / stored_scale(i));
  }
  for (const auto& [name, value] : options.parameters) {
    std::string folded;
    for (char c : name)
      if (c != ' ' && c != '\t') folded.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
    overrides[folded] = value;
    int n = 0;
    if (std::sscanf(folded.c_str(), "%d", &n) == 1 && std::to_string(n) == folded && n > 0 && n < kParameterCount) {
      params.set_numbered(n, value);
      if (n >= 5221 && n <= 5389 && (n - 5221) % 20 <= 9) known_systems |= 1U << ((n - 5221) / 20);
    }
  }
  params.set_numbered(5220, 1.0);
  // The control starts in G54 with its stored origin (rs274 reads it from its parameter
  // file): the machine stands where it stands, the program's point is relative to it.
  for (std::size_t i = 0; i < kAxisCount; ++i) offsets.g5x[i] = params.numbered(5221 + static_cast<int>(i)) * stored_scale(i);
  offsets.rotation = params.numbered(5230);
  modal.retract_to_r = options.dialect.starts_in_g99;
}

// ----------------------------------------------------------------------------------------
// Errors and warnings

void Interpreter::Impl::fail(const Block& b, const Word* where, const std::string& message) const {
  fail_at(b, where ? where->span : Span{}, message);
}

void Interpreter::Impl::unsupported_at(const Block& b, Span span, const std::string& message) const {
  throw Error(ErrorKind::unsupported, message, SourceLocation{file_name(), b.line, span.begin + 1},
              std::string(b.text));
}

void Interpreter::Impl::fail_at(const Block& b, Span span, const std::string& message) const {
  // Without a word to point at (an unknown subroutine, a radius that does not fit, a
  // division by zero), the block itself: where its text starts.
  std::uint32_t column = span.begin + 1;
  if (span.empty() && span.begin == 0) {
    const auto first = b.text.find_first_not_of(" \t");
    column = first == std::string_view::npos ? 1 : static_cast<std::uint32_t>(first + 1);
  }
  throw Error(ErrorKind::program, message, SourceLocation{file_name(), b.line, column}, std::string(b.text));
}

void Interpreter::Impl::warn(const std::string& message, std::uint32_t line_no) const {
  if (sink) sink->warning(message, line_no);
}

void Interpreter::Impl::announce(const Block& b, const SourceLine& l) {
  // A G41/G42 (or a G code an expression gives: it may be one) may make this block's move
  // wait: the block waits with it.
  const auto may_turn_on = [&] {
    for (const Word& w : b.words)
      if (w.letter == 'G' && (!w.value.is_literal() || (std::floor(w.value.literal) >= 41 && w.value.literal < 43)))
        return true;
    return false;
  };
  if (options.cutter_path == CutterPath::tool_centre || (!comp.on() && comp.idle() && !may_turn_on())) {
    sink->block(b, l);
    return;
  }
  if (!comp.offsetting() && !comp.move_waits()) comp.flush(*sink);  // what was held, for no move
  if (comp.holds_blocks(may_turn_on()))
    comp.hold(b, l);  // after the moves still waiting for the offset: each block before its own
  else
    sink->block(b, l);
}

void Interpreter::Impl::emit(std::string_view name, std::string args) {
  if (!sink || !sink->wants_calls()) return;
  CanonCall call{name, std::move(args), block.line};
  if (comp.holds(call))
    comp.hold(call);  // after the moves still waiting for the offset, as rs274 orders them
  else
    sink->call(call);
}

// ----------------------------------------------------------------------------------------
// Parameters and expressions

Span Interpreter::Impl::locate_name(const Block& b, std::string_view folded) const {
  // Find `<name>` in the original text, ignoring case and blanks as the lexer does.
  const std::string_view t = b.text;
  for (std::size_t at = t.find('<'); at != std::string_view::npos; at = t.find('<', at + 1)) {
    std::size_t i = at + 1, k = 0;
    while (i < t.size() && k < folded.size()) {
      const char c = t[i];
      if (c == ' ' || c == '\t') {
        ++i;
        continue;
      }
      if (std::toupper(static_cast<unsigned char>(c)) != folded[k]) break;
      ++i, ++k;
    }
    while (i < t.size() && (t[i] == ' ' || t[i] == '\t')) ++i;
    if (k == folded.size() && i < t.size() && t[i] == '>')
      return Span{static_cast<std::uint32_t>(at + 1), static_cast<std::uint32_t>(i)};
  }
  return Span{};
}

bool Interpreter::Impl::named_exists(std::string_view name) {
  if (overrides.contains(name)) return true;
  if (params.named(name)) return true;
  try {
    (void)read_named(block, name);
    return true;
  } catch (const Error&) {
    return false;
  }
}

double Interpreter::Impl::read_named(const Block& b, std::string_view name) {
  if (auto it = overrides.find(name); it != overrides.end()) return it->second;
  if (auto v = params.named(name)) return *v;
  if (name.starts_with("_HAL[") || name.starts_with("_INI[")) {
    const Span at = locate_name(b, name);
    const std::string spelled = at.empty() ? std::string(name) : std::string(b.slice(at));
    fail_at(b, at,
            fmt::format("#<{}> is a value only the controller has; give it with --param '{}=VALUE'", spelled, spelled));
  }
  const double u = unit();
  static constexpr std::string_view kAxisNames[] = {"X", "Y", "Z", "A", "B", "C", "U", "V", "W"};
  if (name.size() >= 2 && name[0] == '_') {
    const std::string_view rest = name.substr(1);
    for (std::size_t i = 0; i < kAxisCount; ++i) {
      if (rest == kAxisNames[i]) return program(i) / (is_rotary(i) ? 1.0 : u);
      if (rest.starts_with("ABS_") && rest.substr(4) == kAxisNames[i])
        return (offsets.to_machine(position)[i] + offsets.tool[i]) / (is_rotary(i) ? 1.0 : u);
    }
  }
  if (name == "_VALUE") return value_returned;
  if (name == "_VALUE_RETURNED") return has_value_returned ? 1.0 : 0.0;
  if (name == "_LINE") return block.line;  // the source line, as LinuxCNC counts it
  if (name == "_MOTION_MODE") return modal.motion;
  if (name == "_PLANE") return modal.plane == Plane::xy ? 170 : modal.plane == Plane::zx ? 180 : 190;
  if (name == "_CCOMP") return modal.cutter_compensation;
  if (name == "_METRIC") return modal.units == Units::mm;
  if (name == "_IMPERIAL") return modal.units == Units::inch;
  if (name == "_ABSOLUTE") return modal.absolute;
  if (name == "_INCREMENTAL") return !modal.absolute;
  if (name == "_INVERSE_TIME") return modal.feed_mode == FeedMode::inverse_time;
  if (name == "_UNITS_PER_MINUTE") return modal.feed_mode == FeedMode::units_per_minute;
  if (name == "_UNITS_PER_REV") return modal.feed_mode == FeedMode::units_per_rev;
  if (name == "_COORD_SYSTEM") {
    static constexpr int kCodes[] = {540, 550, 560, 570, 580, 590, 591, 592, 593};
    return kCodes[offsets.coordinate_system - 1];
  }
  if (name == "_TOOL_OFFSET") return modal.tool_length_mode != 490;
  if (name == "_RETRACT_R_PLANE") return modal.retract_to_r;
  if (name == "_RETRACT_OLD_Z") return !modal.retract_to_r;
  if (name == "_FEED") return modal.feed / u;
  if (name == "_RPM") return modal.speed;
  if (name == "_CURRENT_TOOL") return modal.tool;
  if (name == "_SELECTED_TOOL") return modal.selected_tool;
  if (name == "_CALL_LEVEL") return static_cast<double>(calls.size());
  if (name == "_REMAP_LEVEL") return 0.0;
  if (name == "_TASK") return 1.0;  // ccomp reads a program as the machine will run it
  const Span at = locate_name(b, name);
  fail_at(
      b, at,
      fmt::format("named parameter #<{}> is not defined", at.empty() ? std::string(name) : std::string(b.slice(at))));
}

double Interpreter::Impl::read_numbered(const Block& b, double index) {
  const double rounded = std::round(index);
  if (std::abs(index - rounded) > 1e-4 || rounded < 1 || rounded >= kParameterCount)
    fail(b, nullptr, fmt::format("parameter number out of range: #{}", index));
  const int n = static_cast<int>(rounded);
  const double u = unit();
  if (controller_only(n) && !overrides.contains(std::to_string(n)))
    fail(b, nullptr,
         fmt::format("#{} is a value only the controller has (a probe or input result); give it "
                     "with --param {}=VALUE",
                     n, n));
  // System parameters that mirror ccomp's own state, in the program's current units.
  auto length = [&](std::size_t axis, double mm) { return is_rotary(axis) ? mm : mm / u; };
  // #5161-#5389 are stored (in machine units) by G28.1, G92, G10 L2...; read as they are.
  if (n == 5220) return offsets.coordinate_system;
  if (n == 5400) return modal.tool;
  if (n >= 5401 && n <= 5409) {  // the loaded tool's table entry, in machine units
    const auto axis = static_cast<std::size_t>(n - 5401);
    const ToolEntry* e = tools.find(modal.tool);
    const double v = e ? e->offset[axis] : 0.0;
    return is_rotary(axis) ? v : v / machine_unit();
  }
  if (n >= 5420 && n <= 5428)
    return length(static_cast<std::size_t>(n - 5420), program(static_cast<std::size_t>(n - 5420)));
  if (n >= 5021 && n <= 5029) {  // machine axis positions: the controlled point plus the tool
    const auto axis = static_cast<std::size_t>(n - 5021);
    return length(axis, offsets.to_machine(position)[axis] + offsets.tool[axis]);
  }
  return params.numbered(n);
}

void Interpreter::Impl::write_numbered(const Block& b, double index, double v) {
  const double rounded = std::round(index);
  if (std::abs(index - rounded) > 1e-4 || rounded < 1 || rounded >= kParameterCount)
    fail(b, nullptr, fmt::format("parameter number out of range: #{}", index));
  const int n = static_cast<int>(rounded);
  params.set_numbered(n, v);
  const double u = machine_unit();
  if (n >= 5221 && n <= 5389) {
    const int system = (n - 5221) / 20 + 1;
    const auto field = static_cast<std::size_t>((n - 5221) % 20);
    if (field <= kAxisCount) known_systems |= 1U << (system - 1);
    if (system == offsets.coordinate_system && field <= kAxisCount)
      change_offsets([&] {
        if (field == kAxisCount)
          offsets.rotation = v;
        else
          offsets.g5x[field] = is_rotary(field) ? v : v * u;
      });
  }
}

void Interpreter::Impl::write_named(const Block& b, std::string_view name, double v) {
  if (name.starts_with("_HAL[") || name.starts_with("_INI["))
    fail(b, nullptr, fmt::format("cannot assign to read-only parameter #<{}>", name));
  params.set_named(name, v);
}

double Interpreter::Impl::evaluate(const Block& b, const Value& v) {
  if (v.is_literal()) return v.literal;
  std::array<double, 64> stack{};
  std::size_t top = 0;
  auto pop = [&]() { return stack[--top]; };
  auto push = [&](double x) {
    if (top == stack.size()) fail(b, nullptr, "expression too deeply nested");
    stack[top++] = x;
  };
  for (std::uint32_t i = v.rpn_begin; i < v.rpn_end; ++i) {
    const ExprNode& n = b.rpn[i];
    switch (n.op) {
      case ExprOp::number:
        push(n.number);
        break;
      case ExprOp::name:
        break;
      case ExprOp::read_named:
        push(read_named(b, b.name(n.name_begin, n.name_size)));
        break;
      case ExprOp::read_numbered:
        push(read_numbered(b, pop()));
        break;
      case ExprOp::exists:
        push(named_exists(b.name(n.name_begin, n.name_size)) ? 1.0 : 0.0);
        break;
      case ExprOp::exists_numbered: {
        const double index = pop();
        push(index >= 1 && index < kParameterCount && index == std::floor(index) ? 1.0 : 0.0);
        break;
      }
      case ExprOp::negate:
        push(-pop());
        break;
      case ExprOp::abs:
        push(std::abs(pop()));
        break;
      case ExprOp::acos: {
        const double x = pop();
        if (x < -1.0 || x > 1.0) fail(b, nullptr, fmt::format("argument to ACOS out of range: {}", x));
        push(std::acos(x) / kRadPerDeg);
        break;
      }
      case ExprOp::asin: {
        const double x = pop();
        if (x < -1.0 || x > 1.0) fail(b, nullptr, fmt::format("argument to ASIN out of range: {}", x));
        push(std::asin(x) / kRadPerDeg);
        break;
      }
      case ExprOp::cos:
        push(std::cos(pop() * kRadPerDeg));
        break;
      case ExprOp::exp:
        push(std::exp(pop()));
        break;
      case ExprOp::fix:
        push(std::floor(pop()));
        break;
      case ExprOp::fup:
        push(std::ceil(pop()));
        break;
      case ExprOp::ln: {
        const double x = pop();
        if (x <= 0.0) fail(b, nullptr, fmt::format("zero or negative argument to LN: {}", x));
        push(std::log(x));
        break;
      }
      case ExprOp::round:
        push(std::round(pop()));
        break;
      case ExprOp::sin:
        push(std::sin(pop() * kRadPerDeg));
        break;
      case ExprOp::sqrt: {
        const double x = pop();
        if (x < 0.0) fail(b, nullptr, fmt::format("negative argument to SQRT: {}", x));
        push(std::sqrt(x));
        break;
      }
      case ExprOp::tan:
        push(std::tan(pop() * kRadPerDeg));
        break;
      default: {  // binary
        const double rhs = pop();
        const double lhs = pop();
        double r = 0.0;
        switch (n.op) {
          case ExprOp::power:
            if (lhs < 0.0 && std::floor(rhs) != rhs)
              fail(b, nullptr, "attempt to raise a negative number to a non-integer power");
            r = std::pow(lhs, rhs);
            break;
          case ExprOp::times:
            r = lhs * rhs;
            break;
          case ExprOp::divide:
            if (rhs == 0.0) fail(b, nullptr, "attempt to divide by zero");
            r = lhs / rhs;
            break;
          case ExprOp::modulo:
            r = std::fmod(lhs, rhs);
            if (r < 0.0) r += std::abs(rhs);
            break;
          case ExprOp::plus:
            r = lhs + rhs;
            break;
          case ExprOp::minus:
            r = lhs - rhs;
            break;
          // Comparisons tolerate the same 1e-6 as rs274ngc (TOLERANCE_EQUAL).
          case ExprOp::eq:
            r = std::abs(lhs - rhs) < 1e-6;
            break;
          case ExprOp::ne:
            r = std::abs(lhs - rhs) >= 1e-6;
            break;
          case ExprOp::gt:
            r = lhs > rhs;
            break;
          case ExprOp::ge:
            r = lhs >= rhs;
            break;
          case ExprOp::lt:
            r = lhs < rhs;
            break;
          case ExprOp::le:
            r = lhs <= rhs;
            break;
          case ExprOp::logical_and:
            r = lhs != 0.0 && rhs != 0.0;
            break;
          case ExprOp::logical_or:
            r = lhs != 0.0 || rhs != 0.0;
            break;
          case ExprOp::logical_xor:
            r = (lhs != 0.0) != (rhs != 0.0);
            break;
          case ExprOp::atan2:
            r = std::atan2(lhs, rhs) / kRadPerDeg;
            break;
          default:
            fail(b, nullptr, "internal: bad expression node");
        }
        push(r);
      }
    }
  }
  if (top != 1) fail(b, nullptr, "internal: malformed expression");
  return stack[0];
}

// ----------------------------------------------------------------------------------------
// The run loop

bool Interpreter::Impl::next_block() {
  for (;;) {
    if (sources[current_source]->next(line)) {
      parser.parse(line.text, line.number, file_name(), block);
      return true;
    }
    // End of a subroutine file without endsub, or of the main file.
    if (!calls.empty() && calls.back().source == current_source && current_source != 0)
      fail(block, nullptr, "subroutine file ended without endsub");
    return false;
  }
}

void Interpreter::Impl::count_blocks(std::uint64_t n) {
  blocks_executed += n;
  blocks_since_motion += n;
  if (blocks_executed > options.max_blocks)
    fail(block, nullptr,
         fmt::format("more than {} blocks executed or skipped: an endless loop? (--max-blocks raises the limit)",
                     options.max_blocks));
  if (blocks_since_motion > options.max_blocks_without_motion && jumped_since_motion)
    fail(block, nullptr,
         fmt::format("{} blocks executed or skipped without a move: an endless loop (a while that never ends, a "
                     "subroutine that calls itself)?",
                     options.max_blocks_without_motion));
}

void Interpreter::Impl::run(LineSource& source, CanonSink& out) {
  sink = &out;
  sources.assign(1, &source);
  current_source = 0;
  emit("USE_LENGTH_UNITS", "CANON_UNITS_MM");
  emit("SET_G5X_OFFSET", "1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000");
  emit("SET_G92_OFFSET", "0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000");
  emit("SET_XY_ROTATION", "0.0000");
  emit("SET_FEED_REFERENCE", "CANON_XYZ");
  emit("ON_RESET", "");
  bool first_line = true;
  while (!ended && next_block()) {
    if (current_source != last_source || line.offset <= last_offset) jumped_since_motion = true;
    last_source = current_source, last_offset = line.offset;
    count_blocks(1);
    if (block.program_delimiter) {
      if (first_line || !percent_seen) {
        percent_seen = true;
        first_line = false;
        announce(block, line);
        continue;
      }
      announce(block, line);
      ended = true;
      // As rs274: the program ends here, and a move waiting for the offset's next is not run.
      if (comp.move_waits())
        warn(
            "the closing % ends the program under cutter radius compensation (G41/G42) with the last move "
            "waiting for the next to settle its corner: LinuxCNC does not run it (G40 and a move before % do)",
            block.line);
      comp.flush_held(out);
      break;  // the closing % ends the program
    }
    if (!block.text.empty()) first_line = false;
    if (block.block_delete && options.block_delete) continue;
    announce(block, line);
    if (block.o.present) {
      execute_o(block);
      continue;
    }
    execute(block);
  }
  if (ended) return;
  if (!controls.empty()) {
    const ControlFrame& open = controls.back();
    throw Error(ErrorKind::program,
                fmt::format("O{} {} is never closed: the file ends inside it", open.label,
                            open.kind == OKeyword::if_      ? "if"
                            : open.kind == OKeyword::repeat ? "repeat"
                                                            : "loop"),
                SourceLocation{file_name(), line.number, 0});
  }
  comp.flush(out);  // the file's end: what waits is issued as it stands
  if (!calls.empty()) warn("program ended inside a subroutine call", line.number);
  if (!percent_seen) warn("the program ends without M2, M30 or a closing %", line.number);
}

// ----------------------------------------------------------------------------------------
// Control flow: O-words and Fanuc subprograms

void Interpreter::Impl::define_sub(const Block& b, bool fanuc) {
  const std::string label = label_of(b.o);
  subs[label] = SubDefinition{current_source, sources[current_source]->tell(), fanuc};
  // Skip the body in normal flow.
  const std::uint32_t start_line = b.line;
  const std::string start_text(b.text);
  for (;;) {
    if (!sources[current_source]->next(line)) {
      throw Error(ErrorKind::program,
                  fanuc ? "Fanuc subprogram O" + label + " has no M99" : "subroutine O" + label + " has no endsub",
                  SourceLocation{file_name(), start_line, 1}, start_text);
    }
    parser.parse(line.text, line.number, file_name(), block);
    if (sink) announce(block, line);
    if (fanuc) {
      if (block.o.present && block.o.keyword == OKeyword::endsub)
        fail(block, nullptr, "Fanuc 'O....' subroutine definition must end with 'M99'");
      for (const Word& w : block.words)
        if (w.letter == 'M' && w.value.is_literal() && w.value.literal == 99) return;
      continue;
    }
    if (!block.o.present) continue;
    if (block.o.keyword == OKeyword::sub) fail(block, nullptr, "nested subroutine definition");
    if (block.o.keyword == OKeyword::endsub && label_of(block.o) == label) return;
  }
}

void Interpreter::Impl::skip_to(const std::string& label, std::initializer_list<OKeyword> stops,
                                bool /*fanuc_sub_end*/) {
  const std::uint32_t start_line = block.line;
  LineSource& src = *sources[current_source];
  std::string key = fmt::format("{}:{}:{}:", current_source, src.tell().offset, label);
  for (OKeyword k : stops) key += std::to_string(static_cast<int>(k)) + ",";
  // Skipped before from here: the same lines end it (the file does not change). The lines
  // between were announced the first time; the line it stops at is read again.
  if (const auto known = skip_ends.find(key); known != skip_ends.end()) {
    src.seek(known->second.target);
    if (!src.next(line)) throw Error(ErrorKind::internal, "a skipped stretch's end is no longer there");
    parser.parse(line.text, line.number, file_name(), block);
    count_blocks(known->second.scanned);
    if (sink) announce(block, line);
    return;
  }
  std::uint64_t scanned = 0;
  for (;;) {
    const SourcePosition before = src.tell();
    if (!src.next(line))
      throw Error(ErrorKind::program, "no matching end for O" + label, SourceLocation{file_name(), start_line, 0});
    parser.parse(line.text, line.number, file_name(), block);
    ++scanned;
    count_blocks(1);  // a skipped line is read as a run one is: it counts towards the limits
    if (sink) announce(block, line);
    if (!block.o.present || label_of(block.o) != label) continue;
    for (OKeyword k : stops)
      if (block.o.keyword == k) {
        skip_ends.emplace(std::move(key), SkipEnd{before, scanned});
        return;
      }
  }
}

SubDefinition Interpreter::Impl::find_sub(const std::string& label, bool fanuc, const Block& b, const Word* where) {
  if (auto it = subs.find(label); it != subs.end()) return it->second;
  // Defined later in the main file: scan ahead, then come back. (Not in a subroutine's own
  // file: LinuxCNC looks for those on the subroutine path only.)
  LineSource& src = *sources[current_source];
  const SourcePosition here = src.tell();
  Block scan;
  SourceLine l;
  Parser scanner(options.dialect);
  while (current_source == 0 && src.next(l)) {
    scanner.parse(l.text, l.number, file_name(), scan);
    if (!scan.o.present) continue;
    const bool is_def = fanuc ? scan.o.keyword == OKeyword::none : scan.o.keyword == OKeyword::sub;
    if (is_def && label_of(scan.o) == label) {
      SubDefinition d{current_source, src.tell(), fanuc};
      src.seek(here);
      subs[label] = d;
      return d;
    }
  }
  src.seek(here);
  // In a file of its own on the subroutine path.
  if (!fanuc && b.o.named) {
    const std::string lower = util::lower_ascii(b.o.name);
    for (const std::string& dir : options.subroutine_path) {
      for (const std::string& candidate : {lower, b.o.name}) {
        const std::filesystem::path p = std::filesystem::path(dir) / (candidate + ".ngc");
        // A folder the user cannot search, a file they cannot read: an I/O error (exit 6)
        // at the call that needed it, not an exception from deep in the library.
        const auto io_error_at_call = [&](const std::string& why) {
          try {
            fail(b, where, why);
          } catch (const Error& e) {
            throw Error(ErrorKind::io, e.message(), e.where(), e.source_line());
          }
        };
        std::error_code ec;
        if (!std::filesystem::exists(p, ec)) {
          if (ec) io_error_at_call(fmt::format("cannot look for '{}' (called as O<{}>): {}", p.string(), b.o.name,
                                               ec.message()));
          continue;
        }
        std::unique_ptr<LineSource> opened;
        try {
          opened = std::make_unique<LineSource>(LineSource::open(p.string()));
        } catch (const Error& e) {
          io_error_at_call(e.message() + fmt::format(" (called as O<{}>)", b.o.name));
        }
        owned_sources.push_back(std::move(opened));
        sources.push_back(owned_sources.back().get());
        const std::size_t index = sources.size() - 1;
        // The file starts with `O<name> sub`: the body follows it.
        LineSource& f = *sources[index];
        SourceLine first;
        Block head;
        bool headed = false;
        while (!headed && f.next(first)) {
          scanner.parse(first.text, first.number, f.name(), head);
          headed = head.o.present && head.o.keyword == OKeyword::sub;
        }
        // An empty file (or one without its `O<name> sub` line) is that file's error, shown
        // there, not the calling line's.
        if (!headed)
          throw Error(ErrorKind::program,
                      fmt::format("'{}' has no 'O<{}> sub' line: a subroutine file starts with it", f.name(),
                                  candidate),
                      SourceLocation{f.name(), f.tell().line > 1 ? f.tell().line - 1 : 1, 1});
        SubDefinition d{index, f.tell(), false};
        subs[label] = d;
        return d;
      }
    }
  }
  if (fanuc) fail(b, where, fmt::format("M98 calls O{}, which is not defined", label));
  fail(b, where, fmt::format("unknown subroutine O{}", label));
}

void Interpreter::Impl::call_sub(const std::string& label, bool fanuc, const Block& b, const Word* where, int repeats) {
  if (calls.size() >= 64) fail(b, where, "subroutines nested too deeply (64 levels)");
  const SubDefinition d = find_sub(label, fanuc, b, where);
  if (d.fanuc != fanuc)
    fail(b, where,
         fanuc ? "'O.... sub' subroutine must be called with 'O.... call'"
               : "Fanuc 'O....' subroutine must be called with 'M98'");
  CallFrame f;
  f.label = label;
  f.source = d.source;
  f.return_source = current_source;
  f.return_to = sources[current_source]->tell();
  f.body = d.body;
  f.control_depth = controls.size();
  f.repeats_left = repeats;
  f.fanuc = fanuc;
  if (!fanuc) {
    std::array<double, 30> args{};
    for (std::size_t i = 0; i < b.o.arguments.size() && i < args.size(); ++i) args[i] = evaluate(b, b.o.arguments[i]);
    params.push_scope();
    for (std::size_t i = 0; i < args.size(); ++i)
      params.set_numbered(static_cast<int>(i + 1), i < b.o.arguments.size() ? args[i] : 0.0);
  }
  calls.push_back(f);
  current_source = d.source;
  sources[current_source]->seek(d.body);
}

void Interpreter::Impl::return_from_sub(const Block& b) {
  if (calls.empty()) fail(b, nullptr, "return or endsub outside a subroutine");
  CallFrame& f = calls.back();
  if (f.fanuc && --f.repeats_left > 0) {
    sources[current_source]->seek(f.body);
    return;
  }
  controls.resize(f.control_depth);
  if (!f.fanuc) params.pop_scope();
  current_source = f.return_source;
  sources[current_source]->seek(f.return_to);
  calls.pop_back();
}

void Interpreter::Impl::execute_o(const Block& b) {
  const OStatement& o = b.o;
  const std::string label = o.computed ? label_of_number(evaluate(b, o.label_value)) : label_of(o);
  auto condition = [&]() { return o.arguments.empty() ? 0.0 : evaluate(b, o.arguments.front()); };
  for (const Word& w : b.words)
    if (o.keyword != OKeyword::none) fail(b, &w, "an O-word statement cannot carry other words");
  switch (o.keyword) {
    case OKeyword::none:
      // A Fanuc program number: the program's name at the start, a subprogram later.
      if (!program_started) {
        program_started = true;
        execute(b);
        return;
      }
      // Run into from the main program: it has not ended (M2, M30, %) before its
      // subprograms, and LinuxCNC refuses it (a control would run their lines as its own).
      if (calls.empty())
        fail(b, nullptr,
             "the main program runs into subprogram O" + label +
                 ": end it (M2, M30 or %) before its subprograms, or a control runs their lines as its own");
      define_sub(b, true);
      return;
    case OKeyword::sub:
      if (!calls.empty()) fail(b, nullptr, "nested subroutine definition: O" + label + " sub inside a subroutine");
      define_sub(b, false);
      return;
    case OKeyword::endsub:
    case OKeyword::return_:
      if (!o.arguments.empty()) {
        value_returned = evaluate(b, o.arguments.front());
        has_value_returned = true;
      }
      if (calls.empty() || calls.back().fanuc)
        fail(b, nullptr, "'O.... endsub' or 'O.... return' outside an 'O.... sub' subroutine");
      return_from_sub(b);
      return;
    case OKeyword::call:
      has_value_returned = false;
      value_returned = 0.0;
      call_sub(label, false, b, nullptr, 1);
      return;
    case OKeyword::if_:
      if (condition() != 0.0) {
        controls.push_back({OKeyword::if_, label, {}, 0});
        return;
      }
      for (;;) {
        skip_to(label, {OKeyword::elseif, OKeyword::else_, OKeyword::endif});
        if (block.o.keyword == OKeyword::endif) return;
        if (block.o.keyword == OKeyword::else_ || evaluate(block, block.o.arguments.front()) != 0.0) {
          controls.push_back({OKeyword::if_, label, {}, 0});
          return;
        }
      }
    case OKeyword::elseif:
    case OKeyword::else_:
      // Reached the end of the branch that ran: skip the rest of the if.
      if (controls.empty() || controls.back().label != label) fail(b, nullptr, "else or elseif without a matching if");
      controls.pop_back();
      skip_to(label, {OKeyword::endif});
      return;
    case OKeyword::endif:
      if (!controls.empty() && controls.back().label == label) controls.pop_back();
      return;
    case OKeyword::while_: {
      if (!controls.empty() && controls.back().label == label && controls.back().kind == OKeyword::do_) {
        if (condition() != 0.0)
          sources[current_source]->seek(controls.back().start);
        else
          controls.pop_back();
        return;
      }
      if (condition() == 0.0) {
        skip_to(label, {OKeyword::endwhile});
        return;
      }
      ControlFrame f{OKeyword::while_, label, {line.offset, line.number}, 0};
      controls.push_back(f);
      return;
    }
    case OKeyword::endwhile:
      if (controls.empty() || controls.back().label != label) fail(b, nullptr, "endwhile without a matching while");
      sources[current_source]->seek(controls.back().start);
      controls.pop_back();
      return;
    case OKeyword::do_:
      controls.push_back({OKeyword::do_, label, sources[current_source]->tell(), 0});
      return;
    case OKeyword::repeat: {
      const double count = condition();
      if (count < 1.0) {
        skip_to(label, {OKeyword::endrepeat});
        return;
      }
      controls.push_back({OKeyword::repeat, label, sources[current_source]->tell(), std::floor(count)});
      return;
    }
    case OKeyword::endrepeat:
      if (controls.empty() || controls.back().label != label) fail(b, nullptr, "endrepeat without a matching repeat");
      if (--controls.back().remaining > 0)
        sources[current_source]->seek(controls.back().start);
      else
        controls.pop_back();
      return;
    case OKeyword::break_:
    case OKeyword::continue_: {
      while (!controls.empty() && controls.back().label != label) controls.pop_back();
      if (controls.empty()) fail(b, nullptr, "break or continue outside a loop");
      const ControlFrame f = controls.back();
      controls.pop_back();
      const bool brk = o.keyword == OKeyword::break_;
      if (f.kind == OKeyword::while_) {
        if (brk)
          skip_to(label, {OKeyword::endwhile});
        else
          sources[current_source]->seek(f.start);
      } else if (f.kind == OKeyword::do_) {
        skip_to(label, {OKeyword::while_});
        if (!brk) {
          controls.push_back(f);
          execute_o(block);
        }
      } else if (f.kind == OKeyword::repeat) {
        if (brk) {
          skip_to(label, {OKeyword::endrepeat});
        } else if (f.remaining - 1 > 0) {
          ControlFrame g = f;
          g.remaining -= 1;
          controls.push_back(g);
          sources[current_source]->seek(f.start);
        } else {
          skip_to(label, {OKeyword::endrepeat});
        }
      } else {
        fail(b, nullptr, "break or continue outside a loop");
      }
      return;
    }
  }
}

// ----------------------------------------------------------------------------------------

Interpreter::Interpreter(InterpreterOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
Interpreter::~Interpreter() = default;
Interpreter::Interpreter(Interpreter&&) noexcept = default;
Interpreter& Interpreter::operator=(Interpreter&&) noexcept = default;

void Interpreter::run(LineSource& source, CanonSink& sink) {
  impl_->run(source, sink);
}
const ModalState& Interpreter::modal() const {
  return impl_->modal;
}
const Offsets& Interpreter::offsets() const {
  return impl_->offsets;
}
const Axes& Interpreter::position() const {
  return impl_->position;
}

}  // namespace ccomp::gcode
