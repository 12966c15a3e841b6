#pragma once
// Prints what the interpreter does in the canonical format of LinuxCNC's `rs274 -g`, so
// LinuxCNC's own interpreter test suite and rs274 itself can check ccomp's reading.
#include <cstdint>
#include <cstdio>
#include <string>

#include "ccomp/gcode/canon.hpp"

namespace ccomp::gcode {

class TracePrinter : public CanonSink {
 public:
  explicit TracePrinter(std::FILE* out) : out_(out) {}

  void block(const Block& block, const SourceLine& line) override;
  void motion(const Motion& motion) override;
  void call(const CanonCall& call) override;
  [[nodiscard]] bool wants_calls() const override { return true; }
  void warning(const std::string& message, std::uint32_t line) override;

  /// Where warnings go (stderr by default, nullptr to drop them).
  void set_warning_stream(std::FILE* stream) { warnings_ = stream; }
  void set_file_name(std::string name) { file_ = std::move(name); }
  /// JSON Lines instead of rs274's text: one object per call, {"n", "line" (in the
  /// file), "block" (its N word, rs274's N.....), "call", "arguments"} (numbers as numbers, names as strings),
  /// {"print": text} for (PRINT,...).
  void set_json(bool json) { json_ = json; }

 private:
  void print(const char* name, const std::string& arguments);
  void print_json(const std::string& name, const std::string& arguments);
  bool json_ = false;
  std::uint32_t source_line_ = 0;  ///< of the block being run (for JSON)

  std::FILE* out_;
  std::FILE* warnings_ = stderr;
  std::string file_;
  std::string line_number_ = "N.....";
  unsigned counter_ = 0;
};

}  // namespace ccomp::gcode
