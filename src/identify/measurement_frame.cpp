#include "ccomp/identify/measurement_frame.hpp"

#include <fmt/format.h>

#include <cctype>

#include "ccomp/error.hpp"

namespace ccomp::identify {
namespace {

constexpr std::string_view kFrameKey = "frame:";

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

/// The text after "# frame:", or nothing.
std::optional<std::string_view> frame_text(std::string_view line) {
  line = trimmed(line);
  if (!line.starts_with('#')) return std::nullopt;
  line = trimmed(line.substr(1));
  if (line.size() < kFrameKey.size()) return std::nullopt;
  for (std::size_t i = 0; i < kFrameKey.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(line[i])) != kFrameKey[i]) return std::nullopt;
  return trimmed(line.substr(kFrameKey.size()));
}

bool starts_with_word(std::string_view text, std::string_view word) {
  if (text.size() < word.size()) return false;
  for (std::size_t i = 0; i < word.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(text[i])) != word[i]) return false;
  return text.size() == word.size() || text[word.size()] == ' ' || text[word.size()] == '\t';
}

bool same_origin(const model::WorkOrigin& a, const model::WorkOrigin& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::abs(a[i] - b[i]) > 1e-6) return false;
  return true;
}

}  // namespace

bool is_frame_line(std::string_view line) {
  return frame_text(line).has_value();
}

MeasurementFrame parse_frame_line(std::string_view line, const std::string& file, std::uint32_t number) {
  const std::string_view text = *frame_text(line);
  auto fail = [&](const std::string& message) {
    throw Error(ErrorKind::data, message, SourceLocation{file, number, 1}, std::string(line.substr(0, 200)));
  };
  MeasurementFrame frame;
  if (starts_with_word(text, "machine")) {
    if (!trimmed(text.substr(7)).empty())
      fail("'# frame: machine' takes nothing after it: machine coordinates have no work offset");
    frame.kind = FrameKind::machine;
    return frame;
  }
  if (!starts_with_word(text, "program"))
    fail(fmt::format("'{}' is no frame: write '# frame: program G54 [X.. Y.. Z..]' or '# frame: machine'", text));
  const std::string_view system = trimmed(text.substr(7));
  if (system.empty()) fail("'# frame: program' needs its coordinate system: '# frame: program G54 [X.. Y.. Z..]'");
  // A system named alone leaves its origin to the user or the model.
  if (const std::optional<std::size_t> alone = model::coordinate_system_number(system)) {
    frame.system = *alone;
    return frame;
  }
  try {
    const model::WorkOffsetEntry e = model::parse_work_offset(system, "the frame");
    frame.system = e.system;
    frame.origin = e.origin;
  } catch (const Error& e) {
    fail(e.message());
  }
  return frame;
}

ResolvedFrame resolve_frame(const std::optional<MeasurementFrame>& in_file, const std::optional<MeasurementFrame>& given,
                            const model::MachineModel& model, const std::string& file) {
  ResolvedFrame r;
  if (in_file && given && in_file->kind != given->kind)
    throw Error(ErrorKind::data,
                fmt::format("{}: the file says its positions are in {} coordinates, and --frame says {}", file,
                            in_file->kind == FrameKind::machine ? "machine" : "program",
                            given->kind == FrameKind::machine ? "machine" : "program"),
                SourceLocation{file, 0, 0});
  r.frame = in_file ? *in_file : given ? *given : MeasurementFrame{};
  if (r.frame.kind == FrameKind::machine) return r;
  const std::size_t system = r.frame.system;
  const std::optional<model::WorkOrigin> from_user =
      given && given->kind == FrameKind::program && given->system == system ? given->origin : std::nullopt;
  if (in_file && in_file->origin) {
    if (from_user && !same_origin(*from_user, *in_file->origin))
      throw Error(ErrorKind::data,
                  fmt::format("{}: the file says {}, and --work-offset says {}: which is it?", file,
                              model::describe_work_offset(system, *in_file->origin),
                              model::describe_work_offset(system, *from_user)),
                  SourceLocation{file, 0, 0});
    r.origin = *in_file->origin;
  } else if (from_user) {
    r.origin = *from_user;
  } else if (model.work_offsets.of(system)) {
    r.origin = *model.work_offsets.of(system);
  } else {
    r.unknown = true;
  }
  r.frame.origin = r.origin;
  std::vector<char> axes;
  for (const model::AxisSpec& a : model.axes) axes.push_back(a.letter);
  const bool from_file = in_file && in_file->origin;
  model::check_on_machine(r.origin, system, axes, from_file ? ErrorKind::data : ErrorKind::usage,
                          from_file ? file + ": its frame" : "--work-offset");
  return r;
}

std::string frame_line(const ResolvedFrame& frame) {
  if (frame.frame.kind == FrameKind::machine) return "# frame: machine";
  return "# frame: program " + model::describe_work_offset(frame.frame.system, frame.origin);
}

}  // namespace ccomp::identify
