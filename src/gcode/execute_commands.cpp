// Tool-centre-point syntax beyond RS-274: the siemens dialect's named commands, D as a
// cutting edge and the orientation interpolation under TRAORI, and G43.5's tool direction.
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
    if (c.has_value && d->kind != CommandKind::setting)
      unsupported_at(b, c.span, fmt::format("{}= takes no value in the siemens dialect", name));
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
        // TRAORI(1) is the first transformation, the model's; another is other kinematics.
        if (d->kind == CommandKind::tcp_on && c.has_arguments && b.slice(c.arguments) != "1")
          unsupported_at(b, c.arguments,
                         "TRAORI with arguments other than (1): another transformation, a tool direction or offsets of "
                         "the rotary axes, which ccomp does not follow (the model is the first transformation)");
        set_tcp(d->kind == CommandKind::tcp_on ? kTraoriTcp : 0);
        break;
      }
      case CommandKind::orientation_vector:
        modal.orientation_path = OrientationPath::vector;
        break;
      case CommandKind::orientation_axes:
        modal.orientation_path = OrientationPath::axes;
        break;
      case CommandKind::orientation_other:
        modal.orientation_path = OrientationPath::other;
        break;
      case CommandKind::orientation_workpiece:
        modal.orientation_in_machine = false;
        break;
      case CommandKind::orientation_machine:
        modal.orientation_in_machine = true;
        break;
      case CommandKind::setting:
        break;
    }
  }
}

OrientationPath Interpreter::Impl::siemens_interpolation() const {
  if (modal.orientation_path == OrientationPath::vector && !modal.orientation_in_machine) return OrientationPath::vector;
  if (modal.orientation_path == OrientationPath::axes && modal.orientation_in_machine) return OrientationPath::axes;
  return OrientationPath::other;  // a pair that disagrees, or a path ccomp does not follow
}

void Interpreter::Impl::cutting_edge(const Block& b, bool tool_changed) {
  int edge = modal.cutting_edge;
  if (words.has('D')) {
    const double d = words['D'];
    if (d < 0 || d != std::floor(d) || d > 32000)
      fail(b, words.word['D' - 'A'], fmt::format("bad cutting edge D{}: a whole number from 0", d));
    edge = static_cast<int>(d);
    // A LinuxCNC tool table holds one length and one radius a tool: edge 1's.
    if (edge > 1)
      unsupported_at(b, words.word['D' - 'A']->span,
                     fmt::format("D{}: a cutting edge other than the first, whose offsets a tool table (--tool-table) "
                                 "does not hold",
                                 edge));
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

void Interpreter::Impl::check_orientation_interpolation(const Block& b, const Axes& target, bool arc) const {
  if (modal.tcp != kTraoriTcp) return;
  // A turn this small goes the same way under every interpolation (they part by its square
  // over 8: 4e-9 rad), as the rotary axes' corrections in a compensated program do.
  constexpr double kTurnTooSmallToDiffer = 0.01;  // deg
  const Word* turning = nullptr;
  for (std::size_t i = 0; i < kAxisCount && !turning; ++i)
    if (is_rotary(i) && std::abs(target[i] - position[i]) > kTurnTooSmallToDiffer)
      turning = words.word[static_cast<std::size_t>(kAxisLetters[i] - 'A')];
  if (!turning) return;
  const OrientationPath path = siemens_interpolation();
  if (path == OrientationPath::axes || (path == OrientationPath::vector && !arc)) return;
  const std::string why =
      path == OrientationPath::vector
          ? std::string("an arc whose rotary axes turn with the tool's direction on a great circle (ORIWKS, ORIVECT) is "
                        "not followed; with ORIMKS and ORIAXES the rotary axes move linearly, which is")
      : modal.orientation_path == OrientationPath::other
          ? std::string("the tool's direction goes along a cone, a curve or the path (G group 51), which ccomp does "
                        "not follow")
          : fmt::format("{} and {} disagree, and which decides is the control's machine data (MD21104): state ORIWKS "
                        "with ORIVECT (a great circle) or ORIMKS with ORIAXES (the axes linearly)",
                        modal.orientation_in_machine ? "ORIMKS" : "ORIWKS",
                        modal.orientation_path == OrientationPath::axes ? "ORIAXES" : "ORIVECT");
  unsupported_at(b, turning ? turning->span : Span{}, fmt::format("a rotary axis turns under TRAORI: {}", why));
}

Axes Interpreter::Impl::turned_to_direction(const Block& b, Axes target, const std::array<const Word*, 3>& given,
                                            const std::array<double, 3>& values) {
  const bool fanuc = modal.tcp == 435;
  for (std::size_t i = 0; i < kAxisCount; ++i)
    if (is_rotary(i) && words.has(kAxisLetters[i]))
      unsupported_at(b, words.word[static_cast<std::size_t>(kAxisLetters[i] - 'A')]->span,
                     fanuc ? "under G43.5 the rotary axes follow the tool's direction (I J K): an A B C word is not read"
                           : "a block that gives both the rotary axes' angles and the tool's direction (A3= B3= C3=)");
  const Word* first = given[0] ? given[0] : given[1] ? given[1] : given[2];
  if (!first) return target;  // the direction stays, and so do the angles
  if (offsets.rotation != 0.0)
    unsupported_at(b, first->span, "a tool direction in a rotated coordinate system (G10 L2 R) is not followed");
  // (A component not given is 0, on Fanuc and Siemens controls alike.)
  const std::array<double, 3> direction{given[0] ? values[0] : 0.0, given[1] ? values[1] : 0.0,
                                        given[2] ? values[2] : 0.0};
  std::optional<Axes> turned;
  try {
    turned = options.tcp_direction ? options.tcp_direction(direction, target, offsets) : std::nullopt;
  } catch (const Error& e) {
    if (!e.where().file.empty()) throw;
    unsupported_at(b, first->span, e.message());
  }
  if (!options.tcp_direction)
    unsupported_at(b, first->span, "the tool's direction given: this command does not follow it (the main job, "
                                   "verify and predict do)");
  if (!turned)
    fail(b, first,
         fmt::format("the tool's direction ({:g}, {:g}, {:g}) is none the machine's rotary axes can turn the tool to",
                     direction[0], direction[1], direction[2]));
  for (std::size_t i = 0; i < kAxisCount; ++i)
    if (is_rotary(i)) target[i] = (*turned)[i];
  return target;
}

}  // namespace ccomp::gcode
