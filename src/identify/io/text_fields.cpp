#include "text_fields.hpp"

#include <cctype>
#include <charconv>
#include <cmath>

#include "ccomp/util/ascii.hpp"

namespace ccomp::identify::io {
namespace {

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

}  // namespace

std::vector<Field> split_fields(std::string_view line, char delimiter) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::vector<Field> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"') {
      quoted = !quoted;
    } else if (c == delimiter && !quoted) {
      fields.push_back({std::string(), static_cast<std::uint32_t>(i + 2)});
    } else if (fields.back().text.empty() && blank(c)) {
      ++fields.back().column;  // leading blanks
    } else {
      fields.back().text += c;
    }
  }
  for (Field& f : fields)
    while (!f.text.empty() && blank(f.text.back())) f.text.pop_back();
  return fields;
}

std::vector<Field> split_blanks(std::string_view line) {
  std::vector<Field> fields;
  for (std::size_t i = 0; i < line.size();) {
    if (blank(line[i])) {
      ++i;
      continue;
    }
    const std::size_t start = i;
    while (i < line.size() && !blank(line[i])) ++i;
    fields.push_back({std::string(line.substr(start, i - start)), static_cast<std::uint32_t>(start + 1)});
  }
  return fields;
}

std::optional<double> parse_number(std::string_view text, bool decimal_comma) {
  if (text.starts_with('+')) text.remove_prefix(1);
  if (text.empty()) return std::nullopt;
  std::string s(text);
  if (decimal_comma)
    for (char& c : s)
      if (c == ',') c = '.';
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string lower(std::string_view text) {
  return util::lower_ascii(text);
}

std::string fold(std::string_view text) {
  std::string s;
  for (const char c : text)
    if (c != ' ' && c != '\t' && c != '-' && c != '_' && c != '.' && c != ':')
      s += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::pair<std::string_view, std::string_view> name_and_unit(std::string_view text) {
  if (text.empty() || (text.back() != ']' && text.back() != ')')) return {text, {}};
  const char open = text.back() == ']' ? '[' : '(';
  const std::size_t at = text.rfind(open);
  if (at == std::string_view::npos) return {text, {}};
  std::string_view name = text.substr(0, at);
  while (!name.empty() && blank(name.back())) name.remove_suffix(1);
  return {name, text.substr(at + 1, text.size() - at - 2)};
}

std::optional<int> parse_direction(std::string_view text) {
  // Signs first: fold() drops '-'.
  if (text == "-" || text == "-1" || text == "-1.0") return -1;
  const std::string f = fold(text);
  if (f.empty()) return 0;
  for (const char* up : {"+", "+1", "1", "1.0", "up", "fwd", "forward", "pos", "positive", "increasing"})
    if (f == up) return 1;
  for (const char* down : {"down", "bwd", "back", "backward", "reverse", "neg", "negative", "decreasing"})
    if (f == down) return -1;
  return std::nullopt;
}

}  // namespace ccomp::identify::io
