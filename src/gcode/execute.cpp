// What one block does, in RS-274/NGC's order of execution (LinuxCNC's convert_*).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "ccomp/constants.hpp"
#include "interpreter_impl.hpp"

namespace ccomp::gcode {

namespace {

/// More turns than any helix a program cuts: a runaway P (each turn is written out).
constexpr double kMaxArcTurns = 10000;

/// Modal group of a G code (times ten); -1 when unknown. Group numbers follow RS-274/NGC.
int g_group(int code) {
  switch (code) {
    case 0:
    case 10:
    case 20:
    case 30:
    case 330:
    case 331:
    case 382:
    case 383:
    case 384:
    case 385:
    case 730:
    case 760:
    case 800:
    case 810:
    case 820:
    case 830:
    case 840:
    case 850:
    case 860:
    case 870:
    case 880:
    case 890:
    case 50:
    case 51:
    case 52:
      return 1;
    case 170:
    case 171:
    case 180:
    case 181:
    case 190:
    case 191:
      return 2;
    case 900:
    case 910:
      return 3;
    case 901:
    case 911:
      return 4;
    case 930:
    case 940:
    case 950:
      return 5;
    case 200:
    case 210:
      return 6;
    case 400:
    case 410:
    case 411:
    case 420:
    case 421:
      return 7;
    case 430:
    case 431:
    case 432:
    case 490:
      return 8;
    case 980:
    case 990:
      return 10;
    case 540:
    case 550:
    case 560:
    case 570:
    case 580:
    case 590:
    case 591:
    case 592:
    case 593:
      return 12;
    case 610:
    case 611:
    case 640:
      return 13;
    case 960:
    case 970:
      return 14;
    case 70:
    case 80:
      return 15;
    case 40:
    case 100:
    case 280:
    case 281:
    case 300:
    case 301:
    case 520:
    case 530:
    case 920:
    case 921:
    case 922:
    case 923:
      return 0;
    default:
      return -1;
  }
}

/// Modal group of an M code; -1 for codes outside the standard set.
int m_group(int code) {
  switch (code) {
    case 0:
    case 1:
    case 2:
    case 30:
    case 60:
      return 4;
    case 6:
    case 61:
      return 6;
    case 3:
    case 4:
    case 5:
    case 19:
      return 7;
    case 7:
    case 8:
    case 9:
      return 8;
    case 48:
    case 49:
    case 50:
    case 51:
    case 52:
    case 53:
      return 9;
    case 62:
    case 63:
    case 64:
    case 65:
    case 66:
    case 67:
    case 68:
    case 70:
    case 71:
    case 72:
    case 73:
      return 5;
    case 98:
    case 99:
      return 10;
    default:
      return code >= 100 && code <= 199 ? 11 : -1;
  }
}

bool is_cycle(int code) {
  return code == 730 || (code >= 810 && code <= 890);
}

std::string g_name(int code) {
  return code % 10 == 0 ? fmt::format("G{}", code / 10) : fmt::format("G{}.{}", code / 10, code % 10);
}

std::string fixed4(double v) {
  return fmt::format("{:.4f}", v);
}

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
    if (w.letter == 'G') {
      const double scaled = v * 10.0;
      const auto code = static_cast<int>(std::lround(scaled));
      if (std::abs(scaled - code) > 1e-4 || code < 0) fail(b, &w, fmt::format("bad G code G{}", v));
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
    if (group < 0) {
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
  m.offsets = &offsets;
  m.line = block.line;
  return m;
}

void Interpreter::Impl::send(Motion m, const Axes& target) {
  const bool leaving = leaving_offset;
  position = target;
  blocks_since_motion = 0;
  leaving_compensation = false;
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
  if (through_queue) {
    comp.attach(m);
    return;
  }
  comp.flush(out());  // blocks held for the offset go first
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
  // 3. feed rate
  if (words.has('F')) {
    const double f = words['F'];
    if (f < 0) fail(b, words.word['F' - 'A'], fmt::format("negative F word: {}", f));
    modal.feed = modal.feed_mode == FeedMode::inverse_time ? f : f * u;
    emit_lazy("SET_FEED_RATE", [&] { return fixed4(f); });
  } else if (modal.feed_mode == FeedMode::inverse_time) {
    const int m = motion_code >= 0 ? motion_code : modal.motion;
    if ((m == 10 || m == 20 || m == 30) && words.axis_mask() != 0)
      fail(b, nullptr, fmt::format("F word missing with inverse time {} move", g_name(m)));
  }
  // 4. spindle speed
  if (words.has('S')) {
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
  // 6. tool change; 7. spindle (M codes are rare: skip them together)
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
    // 7. spindle
    if (words.has_m(3)) modal.spindle = 1, emit("START_SPINDLE_CLOCKWISE", "0");
    if (words.has_m(4)) modal.spindle = -1, emit("START_SPINDLE_COUNTERCLOCKWISE", "0");
    if (words.has_m(5)) modal.spindle = 0, emit("STOP_SPINDLE_TURNING", "0");
  }
  // 8. coolant: nothing that moves.  9. overrides: nothing that moves.
  // 10. dwell
  if (non_modal == 40) {
    if (!words.has('P')) fail(b, nullptr, "dwell time missing with G4");
    emit("DWELL", fixed4(words['P']));
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
    for (int code : {430, 431, 432, 490})
      if (words.has_g(code)) tool_length(b, code);
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
  if (motion_code >= 0 || (!axes_used_by_non_modal && words.axis_mask() != 0)) {
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
    comp.flush(out());  // rs274 issues the waiting moves before it stops
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
  if (!(arc || (cycle && motion_mode == 870) || g10 || words.has_g(50))) {
    unused('I', "G2, G3, G87, G10");
    unused('J', "G2, G3, G87, G10");
  }
  if (!(arc || (cycle && motion_mode == 870) || motion_mode == 331 || motion_mode == 330))
    unused('K', "G2, G3, G33, G87");
  if (!(cycle || g10 || words.has_m(98) || words.has_m(66) || motion_mode == 760))
    unused('L', "canned cycles, G10, M98, M66");
  if (!(cycle || words.has_m(61) || words.has_m(66) || words.has_m(67) || words.has_m(68) || words.has_m(19) ||
        words.has_g(640) || g10 || words.has_g(50)))
    unused('Q', "G73, G83, G64, M61, M66, M67, M68, G10");
  const bool p_user = non_modal == 40 || g10 || arc || cycle || words.has_g(640) || words.has_m(98) ||
                      words.has_m(66) || words.has_m(19) || words.has_m(62) || words.has_m(63) || words.has_m(64) ||
                      words.has_m(65) || words.has_g(50) || motion_mode == 760;
  if (!p_user) unused('P', "G4, G10, G64, G2/G3 turns, dwelling cycles, M98, M66");
  const bool d_user = words.has_g(410) || words.has_g(420) || words.has_g(411) || words.has_g(421) ||
                      words.has_g(960) || words.has_g(432);
  if (!d_user) unused('D', "G41, G42, G96");
  if (!(words.has_g(430) || words.has_g(432))) unused('H', "G43");
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
      if (words.axis_mask() == 0) {
        // An explicit G0/G1 without axis words moves nowhere, yet LinuxCNC still issues it.
        if (words.has_g(code))
          straight(code == 0 ? MotionKind::traverse : MotionKind::feed, position, MotionSource::program);
        return;
      }
      if (code == 10 && modal.feed == 0.0 && modal.feed_mode != FeedMode::inverse_time)
        fail(b, nullptr, "cannot do G1 with zero feed rate (no F word yet)");
      const Axes t = target_of(b, g53);
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
  if (leaving_compensation)
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

void Interpreter::Impl::cycle_move(MotionKind kind, std::size_t first, std::size_t second, std::size_t normal, double a,
                                   double b, double c) {
  Axes t = position;
  t[first] = a + offsets.origin(first);
  t[second] = b + offsets.origin(second);
  t[normal] = c + offsets.origin(normal);
  straight(kind, t, MotionSource::canned_cycle);
}

void Interpreter::Impl::canned_cycle(const Block& b, int code) {
  const PlaneAxes pa = plane_axes(modal.plane);
  const double u = unit();
  for (std::size_t i = 3; i < kAxisCount; ++i)
    if (words.has(kAxisLetters[i]))
      fail(b, words.word[static_cast<std::size_t>(kAxisLetters[i] - 'A')],
           fmt::format("cannot put an {} in canned cycle", static_cast<char>(std::tolower(kAxisLetters[i]))));
  if (modal.cutter_compensation != 400)
    fail(b, nullptr, "cannot use a canned cycle with cutter radius compensation on");
  if (modal.feed == 0.0 && modal.feed_mode != FeedMode::inverse_time)
    fail(b, nullptr, "cannot feed with zero feed rate: a canned cycle feeds (no F word yet)");
  const char first_letter = kAxisLetters[pa.first], second_letter = kAxisLetters[pa.second];
  const char depth_letter = kAxisLetters[pa.normal];
  // R, the depth, P and Q are sticky while the cycle stays in force.
  if (words.has('R'))
    cycle_r = words['R'] * u;
  else if (!cycle_values_set)
    fail(b, nullptr, "R word missing with canned cycle");
  if (words.has(depth_letter))
    cycle_bottom = words[depth_letter] * u;
  else if (!cycle_values_set)
    fail(b, nullptr, fmt::format("{} word missing with canned cycle", depth_letter));
  if (words.has('P')) cycle_p = words['P'];
  if (words.has('Q')) cycle_q = words['Q'] * u;
  cycle_values_set = true;
  // A bound on the moves one cycle block makes: L repeats and pecks (a Q far smaller than
  // the depth, or too small to change it at all) would otherwise run for hours or for ever.
  constexpr int kMaxCycleMoves = 100'000;
  int repeats = 1;
  if (words.has('L')) {
    const double l = words['L'];
    if (l < 0 || l != std::floor(l))
      fail(b, words.word['L' - 'A'], "L word for canned cycle repeats must be a non-negative integer");
    if (l > kMaxCycleMoves)
      fail(b, words.word['L' - 'A'], fmt::format("L{} canned cycle repeats: more than {}", l, kMaxCycleMoves));
    repeats = static_cast<int>(l);
  }
  // The initial level is where the first of a run of cycle blocks started (rs274's
  // cycle_il): a G91 R counts from it, and G98 returns to it, however the blocks come.
  if (!cycle_initial_set) cycle_initial = program(pa.normal), cycle_initial_set = true;
  double old_cc = cycle_initial;
  double aa = program(pa.first), bb = program(pa.second);
  double aa_step = 0.0, bb_step = 0.0, r = 0.0, cc = 0.0;
  if (modal.absolute) {
    if (words.has(first_letter)) aa = words[first_letter] * u;
    if (words.has(second_letter)) bb = words[second_letter] * u;
    r = cycle_r;
    cc = cycle_bottom;
  } else {
    if (words.has(first_letter)) aa_step = words[first_letter] * u;
    if (words.has(second_letter)) bb_step = words[second_letter] * u;
    r = cycle_r + old_cc;
    cc = r + cycle_bottom;
  }
  if (r < cc) {
    const std::string what =
        fmt::format("R value ({}) less than {} value ({}) in canned cycle", r / u, depth_letter, cc / u);
    // LinuxCNC refuses this; Fanuc-family controls feed "down" to a bottom above R.
    if (!options.dialect.cycles_own_modal_group) fail(b, nullptr, what);
    warn(what + ": the hole's bottom is above the R plane", b.line);
  }
  if ((code == 730 || code == 830) && cycle_q <= 0.0)
    fail(b, nullptr, fmt::format("Q word missing or not positive with {}", g_name(code)));
  if ((code == 840 || code == 860 || code == 880) && modal.spindle == 0 && options.dialect.cycles_need_spindle)
    fail(b, nullptr, fmt::format("spindle not turning in {}", g_name(code)));
  position_unknown &= ~((1U << pa.first) | (1U << pa.second) | (1U << pa.normal));
  int moves = 0;
  auto count_move = [&] {
    if (++moves > kMaxCycleMoves)
      fail(b, nullptr,
           fmt::format("{} makes more than {} moves (L repeats, and pecks of Q {} down to {} {}): a runaway cycle",
                       g_name(code), kMaxCycleMoves, cycle_q / u, depth_letter, cc / u));
  };
  auto traverse = [&](double a, double bv, double c) {
    count_move();
    cycle_move(MotionKind::traverse, pa.first, pa.second, pa.normal, a, bv, c);
  };
  auto feed = [&](double a, double bv, double c) {
    count_move();
    cycle_move(MotionKind::feed, pa.first, pa.second, pa.normal, a, bv, c);
  };
  double current_cc = program(pa.normal);  // the level the tool is at
  if (old_cc < r) {
    traverse(program(pa.first), program(pa.second), r);
    old_cc = current_cc = r;
  }
  const double clear = modal.retract_to_r ? r : old_cc;
  const double rapid_delta = 0.010 * kMmPerInch;  // rs274ngc: 0.010 inch, in mm
  for (int rep = 0; rep < repeats; ++rep) {
    aa += aa_step;
    bb += bb_step;
    // rs274: the first hole is reached at the level the tool is at (when above R), every
    // other at the clearance level; then down to R.
    if (rep == 0 && current_cc > r) {
      traverse(aa, bb, current_cc);
      traverse(aa, bb, r);
    } else {
      traverse(aa, bb, clear);
      if (clear > r) traverse(aa, bb, r);
    }
    switch (code) {
      case 810:
        feed(aa, bb, cc);
        traverse(aa, bb, clear);
        break;
      case 820:
        feed(aa, bb, cc);
        emit("DWELL", fixed4(cycle_p));
        traverse(aa, bb, clear);
        break;
      case 730:
      case 830:
        for (double depth = r - cycle_q; depth > cc; depth -= cycle_q) {
          feed(aa, bb, depth);
          if (code == 830) traverse(aa, bb, r);
          traverse(aa, bb, depth + rapid_delta);
        }
        feed(aa, bb, cc);
        traverse(aa, bb, clear);
        break;
      case 840:
        feed(aa, bb, cc);
        emit("DWELL", fixed4(0));
        feed(aa, bb, clear);
        break;
      case 850:
        feed(aa, bb, cc);
        feed(aa, bb, r);
        traverse(aa, bb, clear);
        break;
      case 860:
        feed(aa, bb, cc);
        emit("DWELL", fixed4(cycle_p));
        emit("STOP_SPINDLE_TURNING", "0");
        traverse(aa, bb, clear);
        emit("START_SPINDLE_CLOCKWISE", "0");
        break;
      case 880: {
        feed(aa, bb, cc);
        emit("DWELL", fixed4(cycle_p));
        emit("STOP_SPINDLE_TURNING", "0");
        emit("PROGRAM_STOP", "");
        // The operator retracts by hand: the program resumes at the clearance level.
        position[pa.normal] = clear + offsets.origin(pa.normal);
        warn("G88: the operator retracts by hand; ccomp continues from the clearance level", b.line);
        break;
      }
      case 890:
        feed(aa, bb, cc);
        emit("DWELL", fixed4(cycle_p));
        feed(aa, bb, clear);
        break;
      default:
        break;
    }
  }
}

void Interpreter::Impl::select_coordinate_system(int system) {
  const double u = unit();
  change_offsets([&] {
    offsets.coordinate_system = system;
    params.set_numbered(5220, system);
    const int base = 5221 + (system - 1) * 20;
    for (std::size_t i = 0; i < kAxisCount; ++i)
      offsets.g5x[i] = params.numbered(base + static_cast<int>(i)) * stored_scale(i);
    offsets.rotation = params.numbered(base + 9);
  });
  emit("SET_G5X_OFFSET",
       fmt::format("{}, {}, {}, {}, {}, {}, {}", system, fixed4(offsets.g5x[0] / u), fixed4(offsets.g5x[1] / u),
                   fixed4(offsets.g5x[2] / u), fixed4(offsets.g5x[3]), fixed4(offsets.g5x[4]), fixed4(offsets.g5x[5])));
  emit("SET_XY_ROTATION", fixed4(offsets.rotation));
}

void Interpreter::Impl::reference_return(const Block& b, int code) {
  const int base = code == 280 || code == 281 ? 5161 : 5181;
  if (code == 281 || code == 301) {  // store the current position
    const Axes machine = offsets.to_machine(position);
    for (std::size_t i = 0; i < kAxisCount; ++i)
      params.set_numbered(base + static_cast<int>(i), (machine[i] + offsets.tool[i]) / stored_scale(i));
    return;
  }
  if (modal.cutter_compensation != 400) fail(b, nullptr, "cannot use G28 or G30 with cutter radius compensation on");
  const std::uint32_t mask = words.axis_mask();
  const Axes intermediate = target_of(b, false);
  straight(MotionKind::traverse, intermediate, MotionSource::reference_return);
  Axes home = offsets.to_machine(position);  // home positions are machine axis positions
  for (std::size_t i = 0; i < kAxisCount; ++i) {
    if (mask != 0 && !((mask >> i) & 1U)) continue;
    home[i] = params.numbered(base + static_cast<int>(i)) * stored_scale(i) - offsets.tool[i];
  }
  straight(MotionKind::traverse, offsets.from_machine(home), MotionSource::reference_return);
}

void Interpreter::Impl::set_g92(const Block& b, int code) {
  if (code == 920 || code == 520) refuse_under_compensation(b, "change axis offsets (G92, G52)");
  const double u = unit();
  auto publish = [&]() {
    for (std::size_t i = 0; i < kAxisCount; ++i)
      params.set_numbered(5211 + static_cast<int>(i), offsets.g92[i] / stored_scale(i));
    emit("SET_G92_OFFSET", fmt::format("{}, {}, {}, {}, {}, {}", fixed4(offsets.g92[0] / u), fixed4(offsets.g92[1] / u),
                                       fixed4(offsets.g92[2] / u), fixed4(offsets.g92[3]), fixed4(offsets.g92[4]),
                                       fixed4(offsets.g92[5])));
  };
  switch (code) {
    case 920:
    case 520:
      if (words.axis_mask() == 0) fail(b, nullptr, "all axes missing with G92 or G52");
      for (std::size_t i = 0; i < kAxisCount; ++i) {
        const char letter = kAxisLetters[i];
        if (!words.has(letter)) continue;
        const double v = words[letter] * (is_rotary(i) ? 1.0 : u);
        // G92: make the current point read v. G52: shift the origin by v.
        offsets.g92[i] = code == 920 ? position[i] - offsets.g5x[i] - v : v;
      }
      params.set_numbered(5210, 1.0);
      publish();
      return;
    case 921:
      offsets.g92 = Axes{};
      params.set_numbered(5210, 0.0);
      publish();
      return;
    case 922:  // zero the offset, keep the stored values for G92.3
      offsets.g92 = Axes{};
      params.set_numbered(5210, 0.0);
      emit("SET_G92_OFFSET", "0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000");
      return;
    case 923:
      for (std::size_t i = 0; i < kAxisCount; ++i)
        offsets.g92[i] = params.numbered(5211 + static_cast<int>(i)) * stored_scale(i);
      params.set_numbered(5210, 1.0);
      publish();
      return;
    default:
      return;
  }
}

void Interpreter::Impl::g10(const Block& b) {
  const double u = unit();
  if (!words.has('L')) fail(b, nullptr, "G10 needs an L word");
  const int l = static_cast<int>(std::lround(words['L']));
  if (!words.has('P')) fail(b, nullptr, fmt::format("G10 L{} needs a P word", l));
  const int p = static_cast<int>(std::lround(words['P']));
  if (l == 2 || l == 20) {
    if (p < 0 || p > 9) fail(b, words.word['P' - 'A'], fmt::format("P value out of range with G10 L{}: {}", l, p));
    const int system = p == 0 ? offsets.coordinate_system : p;
    if (system == offsets.coordinate_system) refuse_under_compensation(b, "change the active coordinate system");
    const int base = 5221 + (system - 1) * 20;
    const double rotation = words.has('R') ? words['R'] : params.numbered(base + 9);
    // L20: the offset that makes the current point read the given value, in the new frame.
    const Axes machine = offsets.to_machine(position);
    const double a = rotation * std::numbers::pi / 180.0;
    // The point should read the given values, and keep reading what it reads on the axes
    // not given (with a rotation, X and Y offsets both change when either is given).
    Axes local{};  // value + G92, rotated into the machine frame
    for (std::size_t i = 0; i < kAxisCount; ++i)
      local[i] = (words.has(kAxisLetters[i]) ? words[kAxisLetters[i]] * (is_rotary(i) ? 1.0 : u) : program(i)) +
                 offsets.g92[i];
    const bool xy_given = words.has('X') || words.has('Y');
    const double lx = std::cos(a) * local[0] - std::sin(a) * local[1];
    const double ly = std::sin(a) * local[0] + std::cos(a) * local[1];
    local[0] = lx;
    local[1] = ly;
    for (std::size_t i = 0; i < kAxisCount; ++i) {
      const char letter = kAxisLetters[i];
      if (!words.has(letter) && !(l == 20 && i < 2 && xy_given)) continue;
      const double offset = l == 2 ? words[letter] * (is_rotary(i) ? 1.0 : u) : machine[i] - local[i];
      params.set_numbered(base + static_cast<int>(i), offset / stored_scale(i));
    }
    params.set_numbered(base + 9, rotation);
    if (system == offsets.coordinate_system) select_coordinate_system(system);
    return;
  }
  if (l == 1 || l == 10 || l == 11) {
    ToolEntry& e = tools.tools[p];
    e.tool = p;
    // L10: the offsets that make the current point read the given values in the current
    // system; L11 the same in G59.3 without G92 (a touch-off fixture). Axes not given keep
    // what the tool's table entry makes them read; with a rotation X and Y change together.
    Offsets frame = offsets;
    if (l == 11) {
      for (std::size_t i = 0; i < kAxisCount; ++i)
        frame.g5x[i] = params.numbered(5381 + static_cast<int>(i)) * stored_scale(i);
      frame.g92 = Axes{};
      frame.rotation = params.numbered(5390);
    }
    Axes spindle = offsets.to_machine(position);
    for (std::size_t i = 0; i < kAxisCount; ++i) spindle[i] += offsets.tool[i];
    Axes with_entry = spindle;
    for (std::size_t i = 0; i < kAxisCount; ++i) with_entry[i] -= e.offset[i];
    Axes wanted = frame.program_of(with_entry);
    for (std::size_t i = 0; i < kAxisCount; ++i) {
      if (words.has(kAxisLetters[i])) wanted[i] = words[kAxisLetters[i]] * (is_rotary(i) ? 1.0 : u);
      wanted[i] += frame.origin(i);
    }
    const Axes controlled = frame.to_machine(wanted);
    const bool xy_given = words.has('X') || words.has('Y');
    for (std::size_t i = 0; i < kAxisCount; ++i) {
      const char letter = kAxisLetters[i];
      if (!words.has(letter) && !(l != 1 && i < 2 && xy_given && frame.rotation != 0.0)) continue;
      e.offset[i] = l == 1 ? words[letter] * (is_rotary(i) ? 1.0 : u) : spindle[i] - controlled[i];
    }
    if (words.has('R')) e.diameter = 2.0 * words['R'] * u;
    emit("SET_TOOL_TABLE_ENTRY", fmt::format("{}", p));
    return;  // the active offset changes only with the next G43, as in LinuxCNC
  }
  fail(b, words.word['L' - 'A'], fmt::format("G10 L{} is not supported (L1, L2, L10, L11, L20 are)", l));
}

void Interpreter::Impl::tool_length(const Block& b, int code) {
  refuse_under_compensation(b, "change the tool length offset");
  const double u = unit();
  Axes next{};
  switch (code) {
    case 490:
      break;
    case 430:
    case 432: {
      const int tool = words.has('H') ? static_cast<int>(std::lround(words['H'])) : modal.tool;
      if (tool < 0) fail(b, nullptr, "negative H word");
      if (code == 432) next = offsets.tool;
      if (tool != 0) {
        const ToolEntry* e = tools.find(tool);
        if (!e)
          fail(b, words.has('H') ? words.word['H' - 'A'] : nullptr,
               fmt::format("tool {} is not in the tool table (give one with --tool-table)", tool));
        for (std::size_t i = 0; i < kAxisCount; ++i) next[i] += e->offset[i];
      }
      break;
    }
    case 431:  // the axes given; the others keep their offsets, as in LinuxCNC
      next = offsets.tool;
      for (std::size_t i = 0; i < kAxisCount; ++i)
        if (words.has(kAxisLetters[i])) next[i] = words[kAxisLetters[i]] * (is_rotary(i) ? 1.0 : u);
      break;
    default:
      break;
  }
  // The machine stays put: the controlled point moves by the change of offset (a vector in
  // the machine frame, so through to_machine when the coordinate system is rotated).
  Axes machine = offsets.to_machine(position);
  for (std::size_t i = 0; i < kAxisCount; ++i) machine[i] -= next[i] - offsets.tool[i];
  position = offsets.from_machine(machine);
  offsets.tool = next;
  modal.tool_length_mode = code;
  emit("USE_TOOL_LENGTH_OFFSET", fmt::format("{} {} {}, {} {} {}, {} {} {}", fixed4(next[0] / u), fixed4(next[1] / u),
                                             fixed4(next[2] / u), fixed4(next[3]), fixed4(next[4]), fixed4(next[5]),
                                             fixed4(next[6] / u), fixed4(next[7] / u), fixed4(next[8] / u)));
}

void Interpreter::Impl::end_program(const Block& /*b*/) {
  // LinuxCNC's program end resets: G54 offsets kept, G92 kept, plane XY, absolute, feed
  // per minute, cutter compensation off, motion G1, spindle off.
  modal.plane = Plane::xy;
  modal.absolute = true;
  modal.feed_mode = FeedMode::units_per_minute;
  comp.stop(out());
  modal.cutter_compensation = 400;
  modal.motion = 10;
  emit("PROGRAM_END", "");
  ended = true;
}

}  // namespace ccomp::gcode
