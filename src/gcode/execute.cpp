// What one block does, in RS-274/NGC's order of execution (LinuxCNC's convert_*).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "ccomp/constants.hpp"
#include "ccomp/gcode/tcp_mode.hpp"
#include "g_codes.hpp"
#include "interpreter_impl.hpp"
#include "siemens_commands.hpp"

namespace ccomp::gcode {

namespace {

/// More turns than any helix a program cuts: a runaway P (each turn is written out).
constexpr double kMaxArcTurns = 10000;

std::string axis_letters(std::uint32_t mask) {
  std::string s;
  for (std::size_t i = 0; i < kAxisCount; ++i)
    if ((mask >> i) & 1U) s.push_back(kAxisLetters[i]);
  return s;
}

}  // namespace

std::uint32_t Words::axis_mask() const {
  std::uint32_t mask = 0;
  for (std::size_t i = 0; i < kAxisCount; ++i)
    if (has(kAxisLetters[i])) mask |= 1U << i;
  return mask;
}

int Interpreter::Impl::dialect_g_code(const Block& b, const Word& w, int code) const {
  for (const auto& [refused, why] : options.dialect.unsupported_g_codes)
    if (code == refused) unsupported_at(b, w.span, why);
  for (const auto& [alias, meant] : options.dialect.g_code_aliases)
    if (code == alias) return meant;
  return code;
}

void Interpreter::Impl::decode(const Block& b) {
  words = Words{};
  const bool report = sink && sink->wants_values();
  if (report) word_values.clear();
  for (const Word& w : b.words) {
    if (!w.has_value) {  // a lone letter, where the dialect allows it
      if (report) word_values.push_back(std::nan(""));
      continue;
    }
    const double v = w.value.is_literal() ? w.value.literal : evaluate(b, w.value);
    if (!std::isfinite(v)) fail(b, &w, fmt::format("{} word evaluates to {}", w.letter, v));
    if (report) word_values.push_back(v);
    if (w.extension != 0) {
      // Siemens' direction vector (A3= B3= C3=), read where TRAORI is (motion()).
      if (w.extension == 3 && w.letter >= 'A' && w.letter <= 'C' && options.dialect.named_commands) {
        const auto k = static_cast<std::size_t>(w.letter - 'A');
        if (words.vector_word[k]) fail(b, &w, fmt::format("multiple {}3= words on one line", w.letter));
        words.vector[k] = v, words.vector_word[k] = &w;
        continue;
      }
      unsupported_at(b, w.span, extended_address_refusal(w.letter, w.extension));
    }
    if (w.letter == 'G') {
      const double scaled = v * 10.0;
      auto code = static_cast<int>(std::lround(scaled));
      if (std::abs(scaled - code) > 1e-4 || code < 0) fail(b, &w, fmt::format("bad G code G{}", v));
      code = dialect_g_code(b, w, code);
      if (words.g_count == static_cast<int>(words.g.size())) fail(b, &w, "too many G codes on one line");
      words.g[static_cast<std::size_t>(words.g_count)] = code;
      if (code < 1000) words.g_set.set(static_cast<std::size_t>(code));
      words.g_word[static_cast<std::size_t>(words.g_count++)] = &w;
    } else if (w.letter == 'M') {
      const auto code = static_cast<int>(std::lround(v));
      if (std::abs(v - code) > 1e-4 || code < 0) fail(b, &w, fmt::format("bad M code M{}", v));
      if (words.m_count == static_cast<int>(words.m.size())) fail(b, &w, "too many M codes on one line");
      words.m[static_cast<std::size_t>(words.m_count)] = code;
      if (code < 200) words.m_set.set(static_cast<std::size_t>(code));
      words.m_word[static_cast<std::size_t>(words.m_count++)] = &w;
    } else if (w.letter == '$') {
      words.has_spindle_selector = true;
    } else {
      const auto i = static_cast<std::size_t>(w.letter - 'A');
      if (words.has(w.letter)) fail(b, &w, fmt::format("multiple {} words on one line", w.letter));
      words.present |= 1U << i;
      words.value[i] = v;
      words.word[i] = &w;
    }
  }
  // Modal groups: at most one code of each in a block.
  std::array<int, 16> seen_g;
  seen_g.fill(-1);
  for (int i = 0; i < words.g_count; ++i) {
    const int code = words.g[static_cast<std::size_t>(i)];
    const Word* w = words.g_word[static_cast<std::size_t>(i)];
    int group = g_group(code);
    // G43.4 and G43.5: G43's group
    if (group < 0 && options.tcp == TcpCodes::follow && (code == 434 || (code == 435 && options.tcp_direction)))
      group = g_group(430);
    if (group < 0) {
      if (code == 435 && options.tcp == TcpCodes::follow)
        unsupported_at(b, w->span,
                       "G43.5 gives the tool's direction as I J K, which this command does not follow (the main "
                       "job, verify and predict do)");
      if (const auto mode = tcp_g_code(code)) unsupported_at(b, w->span, tcp_refusal(g_name(code), *mode));
      const auto& pass = options.dialect.passthrough_g_codes;
      const auto& moving = options.dialect.passthrough_moving_g_codes;
      if (std::find(pass.begin(), pass.end(), code) != pass.end() ||
          std::find(moving.begin(), moving.end(), code) != moving.end())
        continue;
      fail(b, w, fmt::format("unknown G code {}", g_name(code)));
    }
    words.groups |= 1U << group;
    if (group == 0) continue;  // checked below: only one of G10/G28/G30/G52/G53/G92 uses axes
    if (group == 1 && options.dialect.cycles_own_modal_group && (code == 800 || is_cycle(code)))
      group = 9;  // Fanuc's canned-cycle group
    int& s = seen_g[static_cast<std::size_t>(group)];
    if (s >= 0 && !(s == code && options.dialect.repeated_modal_codes))
      fail(b, w, fmt::format("two G codes used from the same modal group: {} and {}", g_name(s), g_name(code)));
    s = code;
  }
  std::array<int, 16> seen_m;
  seen_m.fill(-1);
  for (int i = 0; i < words.m_count; ++i) {
    const int code = words.m[static_cast<std::size_t>(i)];
    const Word* w = words.m_word[static_cast<std::size_t>(i)];
    if (options.tcp != TcpCodes::pass) {
      const auto mode = tcp_m_code(options.dialect, code);
      if (mode && (options.tcp == TcpCodes::refuse || (options.dialect.name == "linuxcnc" && code == 430)))
        unsupported_at(b, w->span, tcp_refusal(fmt::format("M{}", code), *mode));
      if (options.tcp == TcpCodes::follow && (mode || tcp_off_m_code(options.dialect, code))) continue;
    }
    const int group = m_group(code);
    if (group < 0) {
      if (options.dialect.strict_m_codes) fail(b, w, fmt::format("unknown M code M{}", code));
      continue;
    }
    int& s = seen_m[static_cast<std::size_t>(group)];
    if (s >= 0 && !(s == code && options.dialect.repeated_modal_codes))
      fail(b, w, fmt::format("two M codes used from the same modal group: M{} and M{}", s, code));
    s = code;
  }
  if (report) sink->values(b, line, file_name(), word_values);
  // Parameter settings take effect after every value of the block was read.
  if (!b.settings.empty()) {
    std::array<double, 32> values{};
    std::size_t n = 0;
    for (const ParameterSetting& s : b.settings) {
      if (n == values.size()) fail_at(b, s.span, "too many parameter settings on one line");
      values[n++] = evaluate(b, s.value);
    }
    n = 0;
    for (const ParameterSetting& s : b.settings) {
      if (s.named)
        write_named(b, b.name(s.name_begin, s.name_size), values[n++]);
      else
        write_numbered(b, evaluate(b, s.index), values[n++]);
    }
  }
}

void Interpreter::Impl::abort_comment(const Block& b) {
  for (const Comment& c : b.comments) {
    if (c.end_of_line) continue;
    const std::string_view text = b.slice(c.text);
    if (text.size() < 6) continue;
    std::string upper;
    for (char ch : text.substr(0, 6)) upper.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
    // The machine stops here; ccomp's run goes on, with a warning: the condition around an
    // abort usually reads the machine's state (the tool in the spindle, a probe result),
    // which ccomp only simulates, so stopping would refuse programs that run.
    if (upper == "ABORT,")
      warn(fmt::format("(ABORT, {}) reached as ccomp runs the program: on the machine it stops here unless the "
                       "machine's state (tool, parameters) differs from ccomp's",
                       substitute_parameters(b, text.substr(6))),
           b.line);
  }
}

void Interpreter::Impl::comment(const Block& b) {
  for (const Comment& c : b.comments) {
    if (c.end_of_line) continue;
    const std::string_view text = b.slice(c.text);
    std::string upper;
    for (char ch : text.substr(0, 6)) upper.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
    if (upper.starts_with("ABORT,")) {
      fail_at(b, c.span, fmt::format("(ABORT) {}", substitute_parameters(b, text.substr(6))));
    } else if (upper.starts_with("MSG,")) {
      emit("MESSAGE", fmt::format("\"{}\"", text.substr(4)));
    } else if (upper.starts_with("DEBUG,") || upper.starts_with("PRINT,")) {
      const std::string out = substitute_parameters(b, text.substr(6));
      if (upper.starts_with("DEBUG,"))
        emit("MESSAGE", fmt::format("\"{}\"", out));
      else
        emit("", out);
    } else {
      emit("COMMENT", fmt::format("\"{}\"", text));
    }
  }
}

std::string Interpreter::Impl::substitute_parameters(const Block& b, std::string_view body) {
  // #n and #<name> become their values, printed with %f as LinuxCNC does.
  {
    {
      std::string out;
      for (std::size_t i = 0; i < body.size(); ++i) {
        if (body[i] != '#') {
          out.push_back(body[i]);
          continue;
        }
        std::size_t j = i + 1;
        if (j < body.size() && body[j] == '<') {
          const std::size_t close = body.find('>', j);
          if (close == std::string_view::npos) {
            out.push_back('#');
            continue;
          }
          std::string name;
          for (char ch : body.substr(j + 1, close - j - 1))
            if (ch != ' ') name.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
          if (named_exists(name))
            out += fmt::format("{:f}", read_named(b, name));
          else
            out += "######";
          i = close;
        } else {
          while (j < body.size() && std::isdigit(static_cast<unsigned char>(body[j]))) ++j;
          if (j == i + 1) {
            out.push_back('#');
            continue;
          }
          out += fmt::format("{:f}", read_numbered(b, std::stod(std::string(body.substr(i + 1, j - i - 1)))));
          i = j - 1;
        }
      }
      return out;
    }
  }
}

void Interpreter::Impl::set_units(Units u) {
  modal.units = u;
  comp.print_in(u);
  emit("USE_LENGTH_UNITS", u == Units::mm ? "CANON_UNITS_MM" : "CANON_UNITS_INCHES");
}

Axes Interpreter::Impl::target_of(const Block& /*b*/, bool machine_coordinates) {
  Axes t = machine_coordinates ? offsets.to_machine(position) : position;
  const double u = unit();
  for (std::size_t i = 0; i < kAxisCount; ++i) {
    const char letter = kAxisLetters[i];
    if (!words.has(letter)) continue;
    const double v = words[letter] * (is_rotary(i) ? 1.0 : u);
    if (machine_coordinates)
      t[i] = v - offsets.tool[i];  // G53 places the machine axis; the tool tip is below it
    else if (modal.absolute)
      t[i] = v + offsets.origin(i);
    else
      t[i] = position[i] + v;
    position_unknown &= ~(1U << i);
  }
  return machine_coordinates ? offsets.from_machine(t) : t;
}

void Interpreter::Impl::switch_tcp_by_m_codes(const Block& b) {
  const Word* seen = nullptr;
  for (int i = 0; i < words.m_count; ++i) {
    const int code = words.m[static_cast<std::size_t>(i)];
    const bool on = tcp_m_code(options.dialect, code).has_value(), off = tcp_off_m_code(options.dialect, code);
    if (!on && !off) continue;
    if (seen) fail(b, words.m_word[static_cast<std::size_t>(i)], "two tool-centre-point switches on one line");
    seen = words.m_word[static_cast<std::size_t>(i)];
    if (on) set_tcp(code);
    if (off && modal.tcp == code - 1) set_tcp(0);  // M129 of M128, M429 of M428
  }
}

void Interpreter::Impl::set_tcp(int code) {
  const bool was = modal.tcp != 0;
  modal.tcp = code;
  if (was != (code != 0) && options.tcp_switch) position = options.tcp_switch(position, offsets, code != 0);
}

Motion Interpreter::Impl::motion_to(MotionKind kind, MotionSource source, const Axes& target) const {
  Motion m;
  m.kind = kind;
  m.source = source;
  m.start = position;
  m.end = target;
  m.feed_mode = modal.feed_mode;
  m.feed = modal.feed;
  m.units = modal.units;
  m.incremental = !modal.absolute;
  m.absolute_centre = modal.arc_absolute;
  m.radius_compensation = modal.cutter_compensation != 400;
  m.tcp = modal.tcp != 0;
  m.tcp_great_circle = modal.tcp == 435 || (modal.tcp == kTraoriTcp && siemens_interpolation() == OrientationPath::vector);
  m.direction_words = modal.tcp == 435                                ? DirectionWords::ijk
                      : modal.tcp == kTraoriTcp && modal.siemens_vectors ? DirectionWords::siemens_vector
                                                                         : DirectionWords::none;
  m.offsets = &offsets;
  m.line = block.line;
  return m;
}

void Interpreter::Impl::check_origin_known(const Motion& m) {
  if (!options.origin_matters || warned_unknown_origin || (known_systems >> (offsets.coordinate_system - 1) & 1U))
    return;
  bool turns = false;
  for (std::size_t i = 0; i < kAxisCount; ++i) turns = turns || (is_rotary(i) && m.start[i] != m.end[i]);
  if (!turns) return;
  warned_unknown_origin = true;
  const char* names[] = {"G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"};
  const char* name = names[offsets.coordinate_system - 1];
  warn(fmt::format("a rotary axis turns in {0}, whose origin nobody gave (no work_offsets in the model, no "
                   "--work-offset or --param, no G10 L2 before): program zero is taken at machine zero, and every "
                   "rotary error's lever with it; give it with --work-offset {0}=X..,Y..,Z.. or the model's "
                   "work_offsets (docs/machine-model.md)",
                   name),
       m.line);
}

void Interpreter::Impl::send(Motion& m, const Axes& target) {
  const bool leaving = leaving_offset;
  position = target;
  blocks_since_motion = 0;
  jumped_since_motion = false;
  leaving_offset = false;
  // Under G41/G42 the offset path went out through the offset's queue, or the programmed
  // move goes with it, once the next move settles where the tool centre ends.
  const bool through_queue = comp.offsetting();
  if (through_queue && options.cutter_path != CutterPath::programmed) return;
  if (m.kind == MotionKind::arc) {
    const PlaneAxes pa = plane_axes(m.arc.plane);
    Axes centre = m.end;
    centre[pa.first] = m.arc.center_first;
    centre[pa.second] = m.arc.center_second;
    centre = offsets.to_machine(centre);
    m.arc.center_first = centre[pa.first];
    m.arc.center_second = centre[pa.second];
  }
  if (leaving) {  // the move after G40 leaves from where the offset left the tool
    m.offset = true;
    m.tool_start = comp.tool();
    m.tool_end = m.end;
    if (options.cutter_path != CutterPath::programmed) m.start = comp.tool();
    m.tool_start = offsets.to_machine(m.tool_start);
    m.tool_end = offsets.to_machine(m.tool_end);
  }
  m.start = offsets.to_machine(m.start);
  m.end = offsets.to_machine(m.end);
  check_origin_known(m);
  if (through_queue) {
    comp.attach(m);
    return;
  }
  if (!comp.idle()) comp.flush(out());  // blocks held for the offset go first
  if (sink) sink->motion(m);
}

void Interpreter::Impl::straight(MotionKind kind, const Axes& target, MotionSource source) {
  Motion m = motion_to(kind, source, target);
  if (comp.offsetting()) {
    if (source == MotionSource::machine_coordinates)
      fail(block, nullptr, "cannot use G53 with cutter radius compensation on");
    if (kind == MotionKind::probe) fail(block, nullptr, "cannot probe with cutter radius compensation on");
    const Axes from = position;
    offset_path([&] { comp.straight(m, from, unit(), out()); });
  }
  send(m, target);
}

// ----------------------------------------------------------------------------------------

void Interpreter::Impl::execute(const Block& b) {
  if (!b.words.empty() || !b.settings.empty()) program_started = true;
  decode(b);
  const double u = unit();

  int motion_code = -1;  // an explicit group 1 code in this block
  int non_modal = -1;    // group 0
  for (int i = 0; i < words.g_count; ++i) {
    const int code = words.g[static_cast<std::size_t>(i)];
    const int group = g_group(code);
    if (group == 1 && code == 800 && options.dialect.cycles_own_modal_group) {
      // Fanuc: `G00 G80` cancels the cycle and keeps G00; G80 alone returns to the G0-G3 mode.
      modal.motion = modal.basic_motion;
      if (motion_code < 0) motion_code = -2;
      continue;
    }
    if (group == 1) motion_code = motion_code == -2 ? code : code;
    if (group == 0 && code != 530) {
      if (non_modal >= 0 && non_modal != 40)
        fail(b, words.g_word[static_cast<std::size_t>(i)],
             fmt::format("two G codes used from the same modal group: {} and {}", g_name(non_modal), g_name(code)));
      if (non_modal != 40 || code == 40)
        non_modal = code;
      else
        non_modal = code;
    }
  }
  if (motion_code == -2) motion_code = words.axis_mask() != 0 ? modal.motion : -1;
  const bool g53 = words.has_g(530);
  const int passthrough = passthrough_code();
  const bool axes_used_by_non_modal = non_modal == 100 || non_modal == 280 || non_modal == 300 || non_modal == 520 ||
                                      non_modal == 920 || passthrough >= 0 ||
                                      words.has_g(431);  // G43.1 takes its offsets as axis words
  if (g53 && motion_code < 0 && options.dialect.g53_alone_is_rapid) motion_code = 0;
  if (motion_code >= 0 && axes_used_by_non_modal && words.axis_mask() != 0)
    fail(b, nullptr,
         fmt::format("cannot use two G codes that both use axis values: {} and {}", g_name(motion_code),
                     g_name(passthrough >= 0 ? passthrough : non_modal)));
  check_unused_words(b, motion_code, non_modal);

  // 1. comments
  if (!b.comments.empty()) {
    if (sink && sink->wants_calls())
      comment(b);
    else
      abort_comment(b);  // an (ABORT, ...) is said in every run, not only a trace
  }
  // 2. feed rate mode
  if (words.has_group(5)) {
    if (words.has_g(930)) modal.feed_mode = FeedMode::inverse_time, emit("SET_FEED_MODE", "0, 1");
    if (words.has_g(940)) modal.feed_mode = FeedMode::units_per_minute, emit("SET_FEED_MODE", "0, 0");
    if (words.has_g(950)) modal.feed_mode = FeedMode::units_per_rev, emit("SET_FEED_MODE", "0, 2");
  }
  // 3. feed rate (a Siemens dwell's F is its time)
  const bool dwell_words = non_modal == 40 && options.dialect.dwell_in_f_or_s;
  if (words.has('F') && !dwell_words) {
    const double f = words['F'];
    if (f < 0) fail(b, words.word['F' - 'A'], fmt::format("negative F word: {}", f));
    modal.feed = modal.feed_mode == FeedMode::inverse_time ? f : f * u;
    emit_lazy("SET_FEED_RATE", [&] { return fixed4(f); });
  } else if (modal.feed_mode == FeedMode::inverse_time) {
    const int m = motion_code >= 0 ? motion_code : modal.motion;
    // (an explicit G1 without axis words moves too, to where it is)
    if ((m == 10 || m == 20 || m == 30) && (words.axis_mask() != 0 || (m == 10 && motion_code == 10)))
      fail(b, nullptr, fmt::format("F word missing with inverse time {} move", g_name(m)));
  }
  // 4. spindle speed
  if (words.has('S') && !dwell_words) {
    if (words['S'] < 0) fail(b, words.word['S' - 'A'], "negative spindle speed");
    modal.speed = words['S'];
    emit_lazy("SET_SPINDLE_SPEED", [&] { return "0, " + fixed4(modal.speed); });
  }
  // 5. select tool
  if (words.has('T')) {
    const double t = words['T'];
    // Beyond int it is no tool either, and its conversion would be undefined.
    if (t < 0 || t != std::floor(t) || t > std::numeric_limits<int>::max())
      fail(b, words.word['T' - 'A'], fmt::format("bad tool number T{}", t));
    modal.selected_tool = static_cast<int>(t);
    emit_lazy("SELECT_TOOL", [&] { return fmt::format("{}", modal.selected_tool); });
  }
  // 6. tool change; 7. spindle (M codes are rare: skip them together); a Siemens D after both
  const bool tool_changed = words.m_count > 0 && words.has_m(6);
  if (words.m_count > 0) {
    if (words.has_m(6)) {
      refuse_under_compensation(b, "change tools");
      if (modal.selected_tool >= 0) modal.tool = modal.selected_tool;
      modal.spindle = 0;  // a tool change stops the spindle
      emit("STOP_SPINDLE_TURNING", "0");
      emit("CHANGE_TOOL", "");
    }
    if (words.has_m(61)) {
      if (!words.has('Q')) fail(b, nullptr, "M61 needs a Q word (the tool number)");
      const double q = words['Q'];
      if (q < 0 || q != std::floor(q) || q > std::numeric_limits<int>::max())
        fail(b, words.word['Q' - 'A'], fmt::format("bad tool number Q{} with M61", q));
      modal.tool = static_cast<int>(q);
    }
    if (options.tcp == TcpCodes::follow) switch_tcp_by_m_codes(b);
    // 7. spindle
    if (words.has_m(3)) modal.spindle = 1, emit("START_SPINDLE_CLOCKWISE", "0");
    if (words.has_m(4)) modal.spindle = -1, emit("START_SPINDLE_COUNTERCLOCKWISE", "0");
    if (words.has_m(5)) modal.spindle = 0, emit("STOP_SPINDLE_TURNING", "0");
  }
  if (options.dialect.d_selects_cutting_edge) cutting_edge(b, tool_changed);
  // 8. coolant: nothing that moves.  9. overrides: nothing that moves.
  // 10. dwell
  if (non_modal == 40) {
    if (dwell_words) {
      if (!words.has('F') && !words.has('S')) fail(b, nullptr, "dwell time missing with G4: F (seconds) or S (turns)");
      if (!words.has('F') && !(modal.speed > 0.0))
        fail(b, words.word['S' - 'A'], "G4 S (spindle turns) with no spindle speed in force (S before it)");
      emit("DWELL", fixed4(words.has('F') ? words['F'] : words['S'] * 60.0 / modal.speed));
    } else {
      if (!words.has('P')) fail(b, nullptr, "dwell time missing with G4");
      emit("DWELL", fixed4(words['P']));
    }
  }
  // 11.-18. modal settings, only when the block has a G code of those groups
  constexpr std::uint32_t kSettingGroups =
      (1U << 2) | (1U << 3) | (1U << 4) | (1U << 6) | (1U << 7) | (1U << 8) | (1U << 10) | (1U << 12) | (1U << 13);
  if (words.groups & kSettingGroups) {
    // 11. plane
    const Plane plane_before = modal.plane;
    if (words.has_g(170)) modal.plane = Plane::xy, emit("SELECT_PLANE", "CANON_PLANE_XY");
    if (words.has_g(180)) modal.plane = Plane::zx, emit("SELECT_PLANE", "CANON_PLANE_XZ");
    if (words.has_g(190)) modal.plane = Plane::yz, emit("SELECT_PLANE", "CANON_PLANE_YZ");
    if (modal.plane != plane_before) refuse_under_compensation(b, "change planes");
    // 12. units
    if (words.has_g(200)) set_units(Units::inch);
    if (words.has_g(210)) set_units(Units::mm);
    // 13. cutter radius compensation
    for (int code : {400, 410, 411, 420, 421})
      if (words.has_g(code)) cutter_compensation(b, code);
    // 14. tool length offset
    // Off under the offset it was on with, on under the offset it takes.
    for (int code : {430, 431, 432, 490})
      if (words.has_g(code)) {
        if (modal.tcp == 434 || modal.tcp == 435) set_tcp(0);
        tool_length(b, code);
      }
    for (int code : {434, 435})  // G43.4, G43.5: G43's offset, and TCP
      if (words.has_g(code)) tool_length(b, 430), set_tcp(code);
    // 15. coordinate system
    static constexpr int kSystems[] = {540, 550, 560, 570, 580, 590, 591, 592, 593};
    for (int s = 0; s < 9; ++s) {
      if (!words.has_g(kSystems[s])) continue;
      if (modal.cutter_compensation != 400)
        fail(b, nullptr, "cannot change coordinate systems with cutter radius compensation on");
      select_coordinate_system(s + 1);
    }
    // 16. path control
    if (words.has_g(610)) modal.path_mode = 610;
    if (words.has_g(611)) modal.path_mode = 611;
    if (words.has_g(640)) modal.path_mode = 640;
    // 17. distance modes
    if (words.has_g(900)) modal.absolute = true;
    if (words.has_g(910)) modal.absolute = false;
    if (words.has_g(901)) modal.arc_absolute = true;
    if (words.has_g(911)) modal.arc_absolute = false;
    // 18. retract mode
    if (words.has_g(980)) modal.retract_to_r = false;
    if (words.has_g(990)) modal.retract_to_r = true;
  }
  if (!b.commands.empty()) named_commands(b);
  // 19. reference return, coordinate data, axis offsets
  if (non_modal == 100) g10(b);
  if (non_modal == 280 || non_modal == 300 || non_modal == 281 || non_modal == 301) reference_return(b, non_modal);
  if (non_modal == 520 || (non_modal >= 920 && non_modal <= 923)) set_g92(b, non_modal);
  if (passthrough >= 0 && words.axis_mask() != 0) {
    // The controller moves these axes in a way ccomp does not model.
    position_unknown |= words.axis_mask();
    warn(fmt::format("{} is passed through unmodelled: ccomp does not know where it moves {}", g_name(passthrough),
                     axis_letters(words.axis_mask())),
         b.line);
  }
  // 20. motion
  if (motion_code >= 0 || (!axes_used_by_non_modal && (words.axis_mask() != 0 || direction_given()))) {
    if (g53 && motion_code != 0 && motion_code != 10 && !(motion_code < 0 && (modal.motion == 0 || modal.motion == 10)))
      fail(b, nullptr, "must use G0 or G1 with G53");
    if (g53 && !modal.absolute) fail(b, nullptr, "cannot use G53 incremental");
    motion(b, motion_code >= 0 ? motion_code : modal.motion, non_modal);
  }
  // 21. stop
  if (words.has_m(98)) {
    if (!words.has('P')) fail(b, words.m_word[0], "M98 needs a P word: the subprogram number");
    const double p = words['P'];
    const int repeats = words.has('L') ? static_cast<int>(std::lround(words['L'])) : 1;
    if (repeats > 0) call_sub(std::to_string(static_cast<std::uint32_t>(std::lround(p))), true, b, nullptr, repeats);
    return;
  }
  if (words.has_m(99)) {
    if (calls.empty()) {
      warn("M99 in the main program: read as the end of the program (a controller would restart it)", b.line);
      end_program(b);
    } else if (!calls.back().fanuc) {
      fail(b, nullptr, "an 'O.... sub' subroutine must end with 'O.... endsub', not M99");
    } else {
      return_from_sub(b);
    }
    return;
  }
  if (words.has_m(0) || words.has_m(1) || words.has_m(60)) {
    // rs274 settles the waiting moves where the tool is, as G40 does, before it stops.
    offset_path([&] { comp.settle(unit(), out()); });
    emit("PROGRAM_STOP", "");
  }
  if (words.has_m(2) || words.has_m(30)) end_program(b);
}

int Interpreter::Impl::passthrough_code() const {
  const auto& moving = options.dialect.passthrough_moving_g_codes;
  for (int i = 0; i < words.g_count; ++i)
    if (std::find(moving.begin(), moving.end(), words.g[static_cast<std::size_t>(i)]) != moving.end())
      return words.g[static_cast<std::size_t>(i)];
  return -1;
}

void Interpreter::Impl::check_unused_words(const Block& b, int motion_code, int non_modal) {
  constexpr auto bit = [](char c) { return 1U << (c - 'A'); };
  constexpr std::uint32_t kChecked =
      bit('R') | bit('I') | bit('J') | bit('K') | bit('L') | bit('Q') | bit('P') | bit('D') | bit('H') | bit('E');
  if ((words.present & kChecked) == 0) return;  // the common block: nothing to check
  const int motion_mode = motion_code >= 0 ? motion_code : modal.motion;
  const bool arc = motion_mode == 20 || motion_mode == 30;
  const bool cycle = is_cycle(motion_mode);
  const bool g10 = non_modal == 100;
  auto unused = [&](char letter, const char* users) {
    if (!words.has(letter)) return;
    const std::string what = fmt::format("{} word with no G code that uses it ({})", letter, users);
    if (options.dialect.unused_words_are_errors) fail(b, words.word[static_cast<std::size_t>(letter - 'A')], what);
    warn(what + ": passed through", b.line);
  };
  if (!(arc || cycle || g10 || words.has_m(19) || words.has_g(640)))
    unused('R', "G2, G3, canned cycles, G10, G64, M19");
  const bool direction = modal.tcp == 435 || words.has_g(435);  // G43.5's I J K: the tool's direction
  if (!(arc || (cycle && motion_mode == 870) || g10 || words.has_g(50) || direction)) {
    unused('I', "G2, G3, G87, G10, G43.5");
    unused('J', "G2, G3, G87, G10, G43.5");
  }
  if (!(arc || (cycle && motion_mode == 870) || motion_mode == 331 || motion_mode == 330 || direction))
    unused('K', "G2, G3, G33, G87, G43.5");
  if (!(cycle || g10 || words.has_m(98) || words.has_m(66) || motion_mode == 760))
    unused('L', "canned cycles, G10, M98, M66");
  if (!(cycle || words.has_m(61) || words.has_m(66) || words.has_m(67) || words.has_m(68) || words.has_m(19) ||
        words.has_g(640) || g10 || words.has_g(50)))
    unused('Q', "G73, G83, G64, M61, M66, M67, M68, G10");
  const bool p_user = non_modal == 40 || g10 || arc || cycle || words.has_g(640) || words.has_m(98) ||
                      words.has_m(66) || words.has_m(19) || words.has_m(62) || words.has_m(63) || words.has_m(64) ||
                      words.has_m(65) || words.has_g(50) || motion_mode == 760;
  if (!p_user) unused('P', "G4, G10, G64, G2/G3 turns, dwelling cycles, M98, M66");
  const bool d_user = options.dialect.d_selects_cutting_edge || words.has_g(410) || words.has_g(420) || words.has_g(411) || words.has_g(421) ||
                      words.has_g(960) || words.has_g(432);
  if (!d_user) unused('D', "G41, G42, G96");
  if (!(words.has_g(430) || words.has_g(432) || words.has_g(434) || words.has_g(435))) unused('H', "G43");
  // LinuxCNC's E is G70/G76's taper and M66-M68's analog channel ("X1e999" is X1 and E999).
  if (!(motion_mode == 760 || words.has_g(700) || words.has_m(66) || words.has_m(67) || words.has_m(68)))
    unused('E', "G70, G76, M66, M67, M68");
}

void Interpreter::Impl::motion(const Block& b, int code, int non_modal) {
  (void)non_modal;
  if (!is_cycle(code)) cycle_initial_set = false;  // a run of cycle blocks ends
  const bool g53_rapid = code == 0 && words.has_g(530) && options.dialect.g53_alone_is_rapid;
  if (g_group(code) == 1 && code != 800 && !g53_rapid) modal.motion = code;
  if (code <= 30 && !g53_rapid) modal.basic_motion = code;
  const bool g53 = words.has_g(530);
  switch (code) {
    case 0:
    case 10: {
      if (code == 10 && modal.feed == 0.0 && modal.feed_mode != FeedMode::inverse_time && words.has_g(code))
        fail(b, nullptr, "cannot do G1 with zero feed rate (no F word yet)");
      if (words.axis_mask() == 0 && !direction_given()) {
        // An explicit G0/G1 without axis words moves nowhere, yet LinuxCNC still issues it.
        if (words.has_g(code))
          straight(code == 0 ? MotionKind::traverse : MotionKind::feed, position, MotionSource::program);
        return;
      }
      if (code == 10 && modal.feed == 0.0 && modal.feed_mode != FeedMode::inverse_time)
        fail(b, nullptr, "cannot do G1 with zero feed rate (no F word yet)");
      Axes t = target_of(b, g53);
      if (modal.tcp == 435) {
        t = turned_to_direction(b, t, {words.word['I' - 'A'], words.word['J' - 'A'], words.word['K' - 'A']},
                                {words['I'], words['J'], words['K']});
      } else if (const Word* first = words.first_vector_word()) {
        if (modal.tcp != kTraoriTcp)
          unsupported_at(b, first->span, "A3= B3= C3= give the tool's direction under TRAORI only");
        t = turned_to_direction(b, t, words.vector_word, words.vector);
        modal.siemens_vectors = true;
      } else if (modal.tcp == kTraoriTcp && (words.has('A') || words.has('B') || words.has('C'))) {
        modal.siemens_vectors = false;
      }
      if (code == 10) check_orientation_interpolation(b, t, false);
      straight(code == 0 ? MotionKind::traverse : MotionKind::feed, t,
               g53 ? MotionSource::machine_coordinates : MotionSource::program);
      return;
    }
    case 20:
    case 30: {
      const PlaneAxes pa = plane_axes(modal.plane);
      const std::uint32_t in_plane = (1U << pa.first) | (1U << pa.second);
      const bool has_center = words.has('I') || words.has('J') || words.has('K') || words.has('R');
      if (words.axis_mask() == 0 && !has_center) return;
      if (modal.tcp == 435)
        unsupported_at(b, Span{}, "an arc under G43.5, whose I J K are the tool's direction: ccomp follows arcs under "
                                  "G43.4");
      check_orientation_interpolation(b, target_of(b, false), true);
      if (!has_center) fail(b, nullptr, "R, I, J and K words all missing for arc");
      if (modal.feed == 0.0 && modal.feed_mode != FeedMode::inverse_time)
        fail(b, nullptr, "cannot make an arc with zero feed rate (no F word yet)");
      (void)in_plane;
      arc(b, code, target_of(b, false));
      return;
    }
    case 800:
      modal.motion = options.dialect.cycles_own_modal_group ? modal.basic_motion : 800;
      if (words.axis_mask() != 0) {
        if (modal.motion == 800) fail(b, nullptr, "cannot use axis values with G80");
        motion(b, modal.motion, non_modal);  // Fanuc: G80 X1 moves in the G0/G1 mode
      }
      return;
    case 382:
    case 383:
    case 384:
    case 385: {
      if (words.axis_mask() == 0) fail(b, nullptr, "all axes missing with motion code G38.x");
      if (modal.feed == 0.0) fail(b, nullptr, "cannot probe with zero feed rate");
      const Axes t = target_of(b, false);
      straight(MotionKind::probe, t, MotionSource::program);
      warn(
          "probe move (G38.x): ccomp takes the probe to reach its target; the controller stops it "
          "on contact",
          b.line);
      return;
    }
    case 330:
    case 331:
    case 760:
    case 50:
    case 51:
    case 52:
    case 870:
    case 880:
      if (code == 880 || is_cycle(code)) {
        if (code == 870)
          throw Error(ErrorKind::unsupported, "G87 back boring is not supported",
                      SourceLocation{file_name(), b.line, 0}, std::string(b.text));
        break;
      }
      throw Error(ErrorKind::unsupported,
                  fmt::format("{} is not supported (spindle-synchronised, lathe or spline motion)", g_name(code)),
                  SourceLocation{file_name(), b.line, 0}, std::string(b.text));
    default:
      break;
  }
  if (is_cycle(code)) canned_cycle(b, code);
}

PlaneArc Interpreter::Impl::arc_centre(const Block& b, int code, const Axes& start, const Axes& target) {
  const PlaneAxes pa = plane_axes(modal.plane);
  const double u = unit();
  const double s1 = start[pa.first], s2 = start[pa.second];
  const double e1 = target[pa.first], e2 = target[pa.second];
  double c1 = 0.0, c2 = 0.0;
  const bool cw = code == 20;
  int turns = 1;
  if (words.has('P')) {
    const double p = words['P'];
    if (p < 1 || p != std::floor(p) || p > std::numeric_limits<int>::max())
      fail(b, words.word['P' - 'A'], fmt::format("P value for arc turns must be a positive integer, not {}", p));
    if (p > kMaxArcTurns)
      fail(
          b, words.word['P' - 'A'],
          fmt::format("an arc of {} turns: more than {}, a runaway value rather than a helix to cut", p, kMaxArcTurns));
    turns = static_cast<int>(p);
  }
  if (words.has('R')) {
    const double radius = words['R'] * u;
    const double abs_radius = std::abs(radius);
    if (s1 == e1 && s2 == e2)
      fail(b, words.word['R' - 'A'], "start point and end point of an R-format arc are the same");
    const double mid1 = (s1 + e1) / 2.0, mid2 = (s2 + e2) / 2.0;
    double half = std::hypot(mid1 - e1, mid2 - e2);
    if (half / abs_radius > 1.0 + 1e-12)
      fail(b, words.word['R' - 'A'],
           fmt::format("arc radius {} too small to reach the end point (half chord {})", words['R'], half / u));
    if (half / abs_radius > 1.0 - 1e-12) half = abs_radius;  // a semicircle within rounding
    const double theta =
        std::atan2(e2 - s2, e1 - s1) + ((cw == (radius > 0)) ? -std::numbers::pi / 2 : std::numbers::pi / 2);
    const double offset = abs_radius * std::cos(std::asin(half / abs_radius));
    c1 = mid1 + offset * std::cos(theta);
    c2 = mid2 + offset * std::sin(theta);
  } else {
    // I J K by plane: XY -> I J, ZX -> K I, YZ -> J K.
    auto offset_word = [&](std::size_t axis) {
      const char letter = "IJK"[axis];
      return words.has(letter) ? words[letter] * u : 0.0;
    };
    const double o1 = offset_word(pa.first), o2 = offset_word(pa.second);
    if (modal.arc_absolute) {
      c1 = o1 + offsets.origin(pa.first);
      c2 = o2 + offsets.origin(pa.second);
    } else {
      c1 = s1 + o1;
      c2 = s2 + o2;
    }
    const double r1 = std::hypot(s1 - c1, s2 - c2) / u;
    const double r2 = std::hypot(e1 - c1, e2 - c2) / u;
    const double zero = modal.units == Units::inch ? 0.0001 : 0.001;
    if (r1 < zero || r2 < zero) fail(b, nullptr, "zero-radius arc");
    // rs274ngc's tolerance: absolute error in program units, relative to the larger radius.
    const double abs_tolerance = (modal.units == Units::inch ? 0.001 : 0.01) * 2.0 * std::sqrt(2.0);
    const double abs_err = std::abs(r1 - r2);
    const double rel_err = abs_err / std::max(r1, r2);
    if (abs_err > 100.0 * abs_tolerance || (abs_err > abs_tolerance && rel_err > 0.001)) {
      const char* l1 = modal.plane == Plane::xy ? "X" : modal.plane == Plane::zx ? "Z" : "Y";
      const char* l2 = modal.plane == Plane::xy ? "Y" : modal.plane == Plane::zx ? "X" : "Z";
      const double o1p = offsets.origin(pa.first), o2p = offsets.origin(pa.second);
      fail(b, nullptr,
           fmt::format("radius to end of arc differs from radius to start: start=({0}{2:.4f},{1}{3:.4f}) "
                       "center=({0}{4:.4f},{1}{5:.4f}) end=({0}{6:.4f},{1}{7:.4f}) r1={8:.4f} r2={9:.4f} "
                       "abs_err={10:.4g} rel_err={11:.4f}%",
                       l1, l2, (s1 - o1p) / u, (s2 - o2p) / u, (c1 - o1p) / u, (c2 - o2p) / u, (e1 - o1p) / u,
                       (e2 - o2p) / u, r1, r2, abs_err, rel_err * 100.0));
    }
  }
  return PlaneArc{c1, c2, cw ? -turns : turns};
}

void Interpreter::Impl::arc(const Block& b, int code, const Axes& target) {
  // As LinuxCNC: the exit move of cutter compensation is where the offset is taken off.
  // (LinuxCNC's rule; other dialects' controls take an arc there)
  if (leaving_offset && options.dialect.name == "linuxcnc")
    fail(b, nullptr, "the move just after exiting cutter compensation mode (G40) must be straight, not an arc");
  // rs274 measures the entry arc's I and J from where the tool centre is.
  const bool entry = comp.offsetting() && comp.first_move();
  if (entry) offset_path([&] { comp.check_entry_arc(target); });
  const PlaneArc centre_of = arc_centre(b, code, entry ? comp.tool() : position, target);
  if (offsets.rotation != 0.0 && modal.plane != Plane::xy)
    throw Error(ErrorKind::unsupported, "arcs outside the XY plane with a rotated coordinate system are not supported",
                SourceLocation{file_name(), b.line, 0}, std::string(b.text));
  Motion m = motion_to(MotionKind::arc, MotionSource::program, target);
  m.arc = Arc{modal.plane, centre_of.center_first, centre_of.center_second, centre_of.turns};
  if (comp.offsetting()) {
    const Axes from = position;
    offset_path([&] { comp.arc(m, from, centre_of, unit(), out()); });
  }
  send(m, target);
}

void Interpreter::Impl::end_program(const Block& /*b*/) {
  // LinuxCNC's program end resets: G54 offsets kept, G92 kept, plane XY, absolute, feed
  // per minute, cutter compensation off, motion G1, spindle off.
  modal.plane = Plane::xy;
  modal.absolute = true;
  modal.feed_mode = FeedMode::units_per_minute;
  offset_path([&] { comp.stop(unit(), out()); });
  modal.cutter_compensation = 400;
  modal.motion = 10;
  emit("PROGRAM_END", "");
  ended = true;
}

}  // namespace ccomp::gcode
