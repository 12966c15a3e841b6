// --hold: which rotary axes the compensation may turn, over the model's `hold:` keys.
#include <fmt/format.h>

#include <cctype>

#include "ccomp/error.hpp"
#include "command_line.hpp"
#include "commands.hpp"

namespace ccomp::cli {

void add_hold_option(CLI::App& cmd, std::vector<std::string>& holds) {
  cmd.add_option("--hold", holds,
                 "AXIS[=auto|clamped|free]: a rotary axis the compensation never turns (clamped, the default "
                 "for AXIS alone: an indexing or clamped table), turns only once the program does (auto, the "
                 "model's default) or always (free); over the model's hold (e.g. --hold B)");
}

model::MachineModel with_holds(model::MachineModel m, const std::vector<std::string>& specs) {
  for (const std::string& spec : specs) {
    const auto eq = spec.find('=');
    const std::string letters = spec.substr(0, eq);
    const std::string mode = eq == std::string::npos ? "clamped" : spec.substr(eq + 1);
    const std::optional<model::AxisHold> hold = model::axis_hold_named(mode);
    if (!hold)
      throw usage_error_at("--hold", spec,
                           fmt::format("--hold {}: '{}' is none of auto, clamped (or indexing), free", spec, mode));
    std::size_t named = 0;
    for (const char c : letters) {
      if (c == ',' || c == ' ') continue;
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      model::AxisSpec* axis = nullptr;
      for (model::AxisSpec& a : m.axes)
        if (a.letter == letter) axis = &a;
      if (axis == nullptr || axis->type != model::AxisType::rotary)
        throw usage_error_at("--hold", spec,
                             fmt::format("--hold {}: '{}' is not a rotary axis of the machine '{}'", spec, c, m.name));
      axis->hold = *hold;
      ++named;
    }
    if (named == 0) throw usage_error_at("--hold", spec, fmt::format("--hold {}: name a rotary axis (--hold B)", spec));
  }
  return m;
}

std::string held_axes_text(const model::MachineModel& m, AxisSet held) {
  std::string text;
  for (const model::AxisSpec& a : m.axes) {
    if (!held.contains(a.axis())) continue;
    text += fmt::format("{}{} held ({})", text.empty() ? "" : ", ", a.letter,
                        a.hold == model::AxisHold::clamped ? "hold: clamped" : "the program does not turn it");
  }
  return text;
}

}  // namespace ccomp::cli
