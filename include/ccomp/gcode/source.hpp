#pragma once
// Reads a program line by line in constant memory. The source is seekable, so the
// interpreter can jump back for loops and forward to subroutine definitions; standard
// input is spooled to an unnamed temporary file first.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace ccomp::gcode {

/// The longest line of G-code read (bytes, without its line end): longer is no program. The
/// reader stops at it while reading, so a file without a newline (or /dev/zero) is refused
/// in bounded memory; the parser refuses it with its position too.
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

/// One physical line as it sits in the file.
struct SourceLine {
  std::string_view text;        ///< without the terminator
  std::string_view terminator;  ///< "\n", "\r\n" or "" (last line without one)
  std::uint64_t offset = 0;     ///< byte offset of the line's first byte
  std::uint32_t number = 0;     ///< 1-based
  std::string_view file;        ///< the name of the source it is in (a program calls others)
};

/// Where to resume reading: a byte offset and the line number found there.
struct SourcePosition {
  std::uint64_t offset = 0;
  std::uint32_t line = 1;
};

class LineSource {
 public:
  /// Opens a file; "-" reads standard input. Throws ccomp::Error (io) naming the path.
  static LineSource open(const std::string& path);
  /// A source over text in memory (tests, tools); the text is copied.
  static LineSource from_string(std::string text, std::string name = "<string>");
  /// A second, independent reader of the same bytes (the writer copies lines with it while
  /// the interpreter reads with the first).
  [[nodiscard]] LineSource another_reader() const;

  LineSource(LineSource&&) noexcept = default;
  LineSource& operator=(LineSource&&) noexcept = default;
  ~LineSource() = default;

  /// The next line, or false at the end. The views stay valid until the next call.
  bool next(SourceLine& line);
  /// Where the next call to next() reads from.
  [[nodiscard]] SourcePosition tell() const { return position_; }
  void seek(SourcePosition position);
  [[nodiscard]] const std::string& name() const { return name_; }
  /// Bytes in the source (for progress reports).
  [[nodiscard]] std::uint64_t size() const { return size_; }

 private:
  LineSource() = default;
  bool fill();

  std::string name_;
  std::shared_ptr<const int> fd_;              // shared by the readers of one file; closed with the last
  std::shared_ptr<const std::string> memory_;  // when reading from memory
  std::vector<char> buffer_;
  std::size_t begin_ = 0;            // first unread byte in buffer_
  std::size_t end_ = 0;              // one past the last valid byte in buffer_
  std::uint64_t buffer_offset_ = 0;  // file offset of buffer_[0]
  std::uint64_t read_offset_ = 0;    // file offset of the next read
  bool eof_ = false;
  SourcePosition position_;
  std::uint64_t size_ = 0;
};

}  // namespace ccomp::gcode
