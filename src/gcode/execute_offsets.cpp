// What blocks that move the program's origin or the tool's do: G54-G59.3, G28/G30, G92 and
// G52, G10, G43/G49.
#include <fmt/format.h>

#include <cmath>

#include "ccomp/constants.hpp"
#include "g_codes.hpp"
#include "interpreter_impl.hpp"

namespace ccomp::gcode {

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
    known_systems |= 1U << (system - 1);
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
      // (Siemens' H is an auxiliary function: the length is the spindle's tool's, by its D.)
      const bool by_h = words.has('H') && !options.dialect.d_selects_cutting_edge;
      const int tool = by_h ? static_cast<int>(std::lround(words['H'])) : modal.tool;
      if (tool < 0) fail(b, nullptr, "negative H word");
      if (code == 432) next = offsets.tool;
      if (tool != 0) {
        const ToolEntry* e = tools.find(tool);
        if (!e)
          fail(b, by_h ? words.word['H' - 'A'] : nullptr,
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

}  // namespace ccomp::gcode
