// What a block's G40, G41, G42, G41.1 and G42.1 do (the offset itself is computed in
// cutter_compensation.cpp).
#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "interpreter_impl.hpp"

namespace ccomp::gcode {

void Interpreter::Impl::cutter_compensation(const Block& b, int code) {
  const Word* g_word = nullptr;
  for (int i = 0; i < words.g_count; ++i)
    if (words.g[static_cast<std::size_t>(i)] == code) g_word = words.g_word[static_cast<std::size_t>(i)];
  if (code == 400) {
    emit("COMMENT", "\"interpreter: cutter radius compensation off\"");
    bool moved = false;
    offset_path([&] { moved = comp.turn_off(unit(), out()); });
    // The next move leaves from where the offset left the tool (and, in LinuxCNC, is no arc).
    leaving_offset = moved;
    modal.cutter_compensation = code;
    return;
  }
  if (modal.plane == Plane::yz)
    fail(b, g_word, "cutter radius compensation is allowed only in the XY and XZ planes (G17, G18)");
  if (modal.cutter_compensation != 400)
    fail(b, g_word, "cannot turn cutter radius compensation on when it is already on");
  const bool by_diameter = code == 411 || code == 421;
  const Word* d_word = words.word['D' - 'A'];
  double radius = 0.0;
  if (by_diameter) {
    if (!words.has('D')) fail(b, g_word, fmt::format("G{}.1 needs a D word: the tool's diameter", code / 10));
    radius = words['D'] * unit() / 2.0;
  } else {
    // D names a tool of the table; without it (or D0), the tool in the spindle.
    int tool = modal.tool;
    if (options.dialect.d_selects_cutting_edge) {
      // Siemens: the spindle's tool, by the edge in force (none under D0).
      if (modal.cutting_edge == 0) tool = -1;
    } else if (words.has('D')) {
      const double d = words['D'];
      if (std::abs(d - std::round(d)) >= 0.0001)
        fail(b, d_word, fmt::format("G{} needs D to be a whole number (a tool number), not {}", code / 10, d));
      if (d < 0) fail(b, d_word, fmt::format("negative D word: tool {}", d));
      if (d > std::numeric_limits<int>::max()) fail(b, d_word, fmt::format("bad tool number D{}", d));
      if (std::round(d) != 0) tool = static_cast<int>(std::round(d));
      if (tool != modal.tool && tools.find(tool) == nullptr)
        fail(b, d_word, fmt::format("tool {} is not in the tool table (D{})", tool, tool));
    }
    const ToolEntry* entry = tools.find(tool);
    radius = entry ? entry->diameter / 2.0 : 0.0;
  }
  // A negative radius (a worn tool below its nominal size) offsets to the other side.
  CompensationSide side = code / 10 == 41 ? CompensationSide::left : CompensationSide::right;
  if (radius < 0.0) {
    radius = -radius;
    side = side == CompensationSide::left ? CompensationSide::right : CompensationSide::left;
  }
  emit("COMMENT", fmt::format("\"interpreter: cutter radius compensation on {}\"",
                              side == CompensationSide::left ? "left" : "right"));
  comp.turn_on(side, radius, modal.plane, position);
  modal.cutter_compensation = code;
}

void Interpreter::Impl::refuse_under_compensation(const Block& b, const char* what) const {
  if (modal.cutter_compensation != 400)
    fail(b, nullptr, fmt::format("cannot {} with cutter radius compensation on", what));
}

}  // namespace ccomp::gcode
