#include "ccomp/gcode/trace.hpp"

#include <fmt/format.h>

#include <charconv>

#include "ccomp/constants.hpp"
#include "ccomp/util/json.hpp"

namespace ccomp::gcode {

void TracePrinter::block(const Block& block, const SourceLine& line) {
  source_line_ = line.number;
  if (block.has_line_number) {
    line_number_.clear();
    for (char c : block.slice(block.line_number_span))
      if (c != ' ' && c != '\t') line_number_.push_back(c == 'n' ? 'N' : c);
  } else {
    line_number_ = "N.....";
  }
}

void TracePrinter::print(const char* name, const std::string& arguments) {
  if (json_) return print_json(name, arguments);
  fmt::print(out_, "{:5} {:<6} {}({})\n", ++counter_, line_number_, name, arguments);
}

void TracePrinter::print_json(const std::string& name, const std::string& arguments) {
  util::JsonWriter j;
  j.begin_object()
      .field("n", ++counter_)
      .field("line", source_line_)
      .field("block", line_number_)
      .field("call", name)
      .key("arguments");
  j.begin_array();
  // rs274's arguments are ", "-separated: numbers stay numbers, the rest (CANON_PLANE_XY) strings.
  for (std::size_t at = 0; at < arguments.size();) {
    const std::size_t comma = std::min(arguments.find(", ", at), arguments.size());
    const std::string token = arguments.substr(at, comma - at);
    double v = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec == std::errc() && end == token.data() + token.size() && !token.empty())
      j.value(v);
    else
      j.value(token);
    at = comma + 2;
  }
  fmt::print(out_, "{}", j.end_array().end_object().text());
}

void TracePrinter::call(const CanonCall& call) {
  if (call.name.empty()) {  // (PRINT,...): rs274 writes the text as it is
    if (json_)
      fmt::print(out_, "{}", util::JsonWriter().begin_object().field("print", call.arguments).end_object().text());
    else
      fmt::print(out_, "{}\n", call.arguments);
    return;
  }
  if (json_) return print_json(std::string(call.name), call.arguments);
  fmt::print(out_, "{:5} {:<6} {}({})\n", ++counter_, line_number_, call.name, call.arguments);
}

void TracePrinter::warning(const std::string& message, std::uint32_t line) {
  if (warnings_) fmt::print(warnings_, "{}:{}: warning: {}\n", file_, line, message);
}

void TracePrinter::motion(const Motion& m) {
  const double u = m.units == Units::inch ? kMmPerInch : 1.0;
  // Canonical positions are in the program's units and the active coordinate system.
  const Axes e = m.offsets->program_of(m.end);
  auto p = [&](std::size_t axis, double v) { return is_rotary(axis) ? v : v / u; };
  switch (m.kind) {
    case MotionKind::traverse:
    case MotionKind::feed:
    case MotionKind::probe: {
      const std::string args = fmt::format("{:.4f}, {:.4f}, {:.4f}, {:.4f}, {:.4f}, {:.4f}", p(0, e[0]), p(1, e[1]),
                                           p(2, e[2]), p(3, e[3]), p(4, e[4]), p(5, e[5]));
      if (m.kind == MotionKind::probe) {
        print("TURN_PROBE_ON", "");
        print("STRAIGHT_PROBE", args);
        print("TURN_PROBE_OFF", "");
      } else {
        print(m.kind == MotionKind::traverse ? "STRAIGHT_TRAVERSE" : "STRAIGHT_FEED", args);
      }
      return;
    }
    case MotionKind::arc: {
      const PlaneAxes pa = plane_axes(m.arc.plane);
      Axes centre = m.end;
      centre[pa.first] = m.arc.center_first;
      centre[pa.second] = m.arc.center_second;
      centre = m.offsets->program_of(centre);
      print("ARC_FEED",
            fmt::format("{:.4f}, {:.4f}, {:.4f}, {:.4f}, {}, {:.4f}, {:.4f}, {:.4f}, {:.4f}", p(pa.first, e[pa.first]),
                        p(pa.second, e[pa.second]), p(pa.first, centre[pa.first]), p(pa.second, centre[pa.second]),
                        m.arc.turns, p(pa.normal, e[pa.normal]), p(3, e[3]), p(4, e[4]), p(5, e[5])));
      return;
    }
  }
}

}  // namespace ccomp::gcode
