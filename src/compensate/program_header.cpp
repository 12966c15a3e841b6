#include "ccomp/compensate/program_header.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <string>
#include <system_error>

#include "ccomp/error.hpp"
#include "ccomp/version.hpp"

namespace ccomp::compensate {
namespace {

constexpr std::string_view kHeaderPrefix = "(ccomp ";
constexpr std::string_view kWorkOffsets = "work offsets ";

/// "G54 X0 Y0 Z-400, G55 X100 Y0 Z0" (or "none") as header_line() writes it.
std::optional<model::WorkOffsets> read_work_offsets(std::string_view text) {
  model::WorkOffsets offsets;
  if (text == "none") return offsets;
  while (!text.empty()) {
    const auto comma = text.find(',');
    const std::string_view one = text.substr(0, comma);
    try {
      const model::WorkOffsetEntry e = model::parse_work_offset(one, "the header");
      offsets.set(e.system, e.origin);
    } catch (const Error&) {
      return std::nullopt;
    }
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  return offsets;
}

/// The model's name inside a comment: no parenthesis or line end may close it early.
std::string sanitize(std::string_view s) {
  std::string out;
  for (char c : s) out.push_back(c == '(' || c == ')' || c == '\n' || c == '\r' ? '_' : c);
  return out;
}

}  // namespace

std::string header_line(const model::MachineModel& model, double tolerance, const model::WorkOffsets& work_offsets) {
  return fmt::format("{}{} compensated for machine '{}' model sha256:{} at {:g} um; {}{})", kHeaderPrefix, kVersion,
                     sanitize(model.name), model.sha256, tolerance * 1000.0, kWorkOffsets,
                     model::describe_work_offsets(work_offsets));
}

std::optional<HeaderFacts> read_header(std::string_view line) {
  if (!is_header_line(line)) return std::nullopt;
  HeaderFacts facts;
  constexpr std::string_view kSha = "model sha256:", kAt = " at ";
  // (The hash and the tolerance read in any case: an upper-cased header is still ours.)
  std::string lower(line);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::string_view original = line;
  line = lower;
  if (const auto sha = line.rfind(kSha); sha != std::string_view::npos) {
    const auto begin = sha + kSha.size();
    const auto end = line.find_first_not_of("0123456789abcdef", begin);
    facts.model_sha256 = std::string(line.substr(begin, end == std::string_view::npos ? end : end - begin));
    if (end != std::string_view::npos && line.substr(end).starts_with(kAt)) {
      double um = 0.0;
      const std::string_view number = line.substr(end + kAt.size());
      if (const auto [p, ec] = std::from_chars(number.data(), number.data() + number.size(), um);
          ec == std::errc() && (std::string_view(p, number.data() + number.size()).starts_with(" um)") ||
                                std::string_view(p, number.data() + number.size()).starts_with(" um;")))
        facts.tolerance = um / 1000.0;
    }
  }
  if (const auto at = line.find(kWorkOffsets); at != std::string_view::npos) {
    const auto begin = at + kWorkOffsets.size();
    const auto end = line.find(')', begin);
    if (end != std::string_view::npos) facts.work_offsets = read_work_offsets(original.substr(begin, end - begin));
  }
  return facts;
}

/// A line that is one comment, `( ... )` or `; ...`: its text lower-cased with every blank
/// taken out (a Fanuc control or a DNC transfer stores comments upper-cased, an editor may
/// respace them); empty for any other line.
std::string comment_letters(std::string_view line) {
  if (line.starts_with("\xEF\xBB\xBF")) line.remove_prefix(3);  // a byte-order mark before it
  const auto first = line.find_first_not_of(" \t");
  if (first == std::string_view::npos || (line[first] != '(' && line[first] != ';')) return {};
  std::string letters;
  for (const char c : line.substr(first + 1))
    if (c != ' ' && c != '\t' && c != '\r') letters.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  return letters;
}

bool is_header_line(std::string_view line) {
  const std::string letters = comment_letters(line);
  return letters.starts_with("ccomp") && letters.find("compensatedformachine") != std::string::npos;
}

}  // namespace ccomp::compensate
