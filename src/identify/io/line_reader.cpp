#include "line_reader.hpp"

#include <fmt/format.h>

#include <string_view>

#include "ccomp/error.hpp"

namespace ccomp::identify::io {

bool LineReader::next(std::string& line) {
  line.clear();
  std::streambuf* buffer = in_.rdbuf();
  if (!buffer) return false;
  using Traits = std::streambuf::traits_type;
  Traits::int_type c = buffer->sbumpc();
  if (Traits::eq_int_type(c, Traits::eof())) return false;
  ++number_;
  while (!Traits::eq_int_type(c, Traits::eof()) && Traits::to_char_type(c) != '\n') {
    if (line.size() == kMaxLineLength)
      throw Error(ErrorKind::data,
                  fmt::format("a line longer than {} characters: no measurement row is that long (a file "
                              "without line ends, or not a measurement file)",
                              kMaxLineLength),
                  SourceLocation{name_, number_, static_cast<std::uint32_t>(kMaxLineLength + 1)}, line.substr(0, 200));
    line.push_back(Traits::to_char_type(c));
    c = buffer->sbumpc();
  }
  // A spreadsheet's "CSV UTF-8" starts with a byte-order mark, which is no text of the line.
  constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
  if (number_ == 1 && std::string_view(line).starts_with(kByteOrderMark)) line.erase(0, kByteOrderMark.size());
  return true;
}

}  // namespace ccomp::identify::io
