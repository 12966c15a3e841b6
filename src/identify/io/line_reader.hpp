#pragma once
// Reads a measurement file a line at a time, with the cap on a line's length checked while
// reading: a line of 100 MB is refused at its 65,537th character, never held whole.
#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>

namespace ccomp::identify::io {

/// The longest line a measurement file may have (characters, its end excluded). A contract
/// row with every column and a long source label is a few hundred.
inline constexpr std::size_t kMaxLineLength = 65536;

class LineReader {
 public:
  LineReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}
  /// The next line (without its LF; a CR before it is kept for the caller's check), false at
  /// the end. A UTF-8 byte-order mark before the first line is read past. Throws
  /// ccomp::Error (data) at a line longer than kMaxLineLength, with what was read of it.
  bool next(std::string& line);
  /// The line last read, counted from 1.
  [[nodiscard]] std::uint32_t number() const { return number_; }
  [[nodiscard]] const std::string& name() const { return name_; }

 private:
  std::istream& in_;
  std::string name_;
  std::uint32_t number_ = 0;
};

}  // namespace ccomp::identify::io
