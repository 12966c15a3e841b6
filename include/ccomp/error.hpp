#pragma once
// The one error root type of ccomp. Every failure a user can cause ends here, carrying
// where it happened (file:line:column), the offending text and what was expected, and
// an ErrorKind that maps to the process exit code.
#include <cstdint>
#include <stdexcept>
#include <string>

namespace ccomp {

/// What went wrong, coarse enough to be an exit code a batch script can act on.
enum class ErrorKind : std::uint8_t {
  usage = 2,        ///< bad command line
  program = 3,      ///< the G-code program is wrong (syntax or meaning)
  unsupported = 4,  ///< valid G-code that ccomp does not handle (yet)
  model = 5,        ///< the machine model file is wrong
  io = 6,           ///< a file could not be read or written
  safety = 7,       ///< refused: compensating would be unsafe
  data = 8,         ///< a measurement file is wrong
  internal = 70,    ///< a bug in ccomp
};

/// The process exit code for an error of this kind (0 is success; warnings do not change it).
[[nodiscard]] constexpr int exit_code(ErrorKind kind) {
  return static_cast<int>(kind);
}

/// A position in a source file; line and column count from 1, 0 means unknown.
struct SourceLocation {
  std::string file;
  std::uint32_t line = 0;
  std::uint32_t column = 0;
};

class Error : public std::runtime_error {
 public:
  /// `source_line` is the text the location points into, shown under the message.
  Error(ErrorKind kind, std::string message, SourceLocation where = {}, std::string source_line = {});

  [[nodiscard]] ErrorKind kind() const noexcept { return kind_; }
  [[nodiscard]] const std::string& message() const noexcept { return message_; }
  [[nodiscard]] const SourceLocation& where() const noexcept { return where_; }
  [[nodiscard]] const std::string& source_line() const noexcept { return source_line_; }

 private:
  ErrorKind kind_;
  std::string message_;
  SourceLocation where_;
  std::string source_line_;
};

/// "file:line:col: error: message", then the source line and a caret under the column.
[[nodiscard]] std::string format_error(const Error& error);

}  // namespace ccomp
