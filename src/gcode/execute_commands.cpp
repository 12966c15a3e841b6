// What the siemens dialect's own syntax does: named commands, D as a cutting edge, and the
// orientation interpolation under TRAORI.
#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "ccomp/gcode/tcp_mode.hpp"
#include "interpreter_impl.hpp"
#include "siemens_commands.hpp"

namespace ccomp::gcode {

void Interpreter::Impl::named_commands(const Block& b) {
  const Command* tcp_switch = nullptr;
  for (const Command& c : b.commands) {
    const std::string_view name = b.slice(c.name);
    const CommandDescriptor* d = siemens_command(name);
    if (!d) unsupported_at(b, c.name, siemens_refusal(name));
    if (c.has_value) unsupported_at(b, c.span, fmt::format("{}= takes no value in the siemens dialect", name));
    switch (d->kind) {
      case CommandKind::tcp_on:
      case CommandKind::tcp_off: {
        if (tcp_switch) unsupported_at(b, c.span, "two tool-centre-point switches on one line");
        tcp_switch = &c;
        if (options.tcp == TcpCodes::pass) break;
        if (d->kind == CommandKind::tcp_on && options.tcp == TcpCodes::refuse)
          unsupported_at(b, c.name,
                         tcp_refusal(name, "Siemens' five-axis transformation (the tool tip in the part, the rotary "
                                           "axes given)"));
        if (d->kind == CommandKind::tcp_on && c.has_arguments && b.slice(c.arguments).find_first_not_of("0123456789") !=
                                                                      std::string_view::npos)
          unsupported_at(b, c.arguments,
                         "TRAORI's arguments beyond the transformation's number (a tool direction, offsets of the "
                         "rotary axes) are not followed");
        set_tcp(d->kind == CommandKind::tcp_on ? kTraoriTcp : 0);
        break;
      }
      case CommandKind::orientation_axes:
        modal.orientation_axes = true;
        break;
      case CommandKind::orientation_other:
        modal.orientation_axes = false;
        break;
      case CommandKind::setting:
        break;
    }
  }
}

void Interpreter::Impl::cutting_edge(const Block& b, bool tool_changed) {
  int edge = modal.cutting_edge;
  if (words.has('D')) {
    const double d = words['D'];
    if (d < 0 || d != std::floor(d) || d > 32000)
      fail(b, words.word['D' - 'A'], fmt::format("bad cutting edge D{}: a whole number from 0", d));
    edge = static_cast<int>(d);
  } else if (tool_changed) {
    edge = 1;  // the control's default edge after a tool change (MD20270 as shipped)
  }
  if (edge == modal.cutting_edge && !tool_changed) return;
  if (modal.tcp == kTraoriTcp)
    unsupported_at(b, words.has('D') ? words.word['D' - 'A']->span : Span{},
                   "a change of the tool's length offset under TRAORI (switch TRAFOOF first)");
  modal.cutting_edge = edge;
  tool_length(b, edge > 0 ? 430 : 490);
}

void Interpreter::Impl::check_orientation_interpolation(const Block& b, const Axes& target) const {
  if (modal.tcp != kTraoriTcp || modal.orientation_axes) return;
  for (std::size_t i = 0; i < kAxisCount; ++i) {
    if (!is_rotary(i) || target[i] == position[i]) continue;
    const Word* w = words.word[static_cast<std::size_t>(kAxisLetters[i] - 'A')];
    unsupported_at(b, w ? w->span : Span{},
                   fmt::format("{} turns under TRAORI without ORIAXES: the control interpolates the tool's direction "
                               "as ORIVECT or its machine data (MD21104) say, which ccomp does not follow; ccomp "
                               "follows a TRAORI program whose rotary axes move linearly (ORIAXES)",
                               kAxisLetters[i]));
  }
}

}  // namespace ccomp::gcode
