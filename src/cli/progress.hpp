#pragma once
// Signs of life on stderr. A person at a terminal gets a bar with the percentage and the
// time left, redrawn in place at most ten times a second and cleared at the end; a pipe or
// a file gets nothing (a script reads only what it asked for). LinuxCNC's filter protocol
// is apart: FILTER_PROGRESS=N lines, whole percents that only grow.
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace ccomp::cli {

/// Whether standard error is a terminal (where a bar is drawn).
[[nodiscard]] bool stderr_is_terminal();

/// A bar for `label`; draws nothing when `enabled` is false. Thread-safe.
class ProgressBar {
 public:
  ProgressBar(std::string label, bool enabled);
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  ~ProgressBar();

  /// The work done, 0 to 1 (a smaller value than the last shown is ignored).
  void update(double fraction);
  /// Clears the bar's line (at the end).
  void clear();
  /// Writes `text` (a message ending in a newline) on stderr above the bar: the bar's line
  /// is cleared first and drawn again at the next update. One lock with the drawing, so a
  /// redraw from another thread cannot land inside the message.
  void print_above(const std::string& text);

 private:
  void draw(double fraction);
  void clear_locked();
  std::string label_;
  bool enabled_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_draw_{};
  double shown_ = -1.0;
  bool drawn_ = false;
};

/// The bar's text for `fraction` done after `elapsed` seconds: "label [#####.....]  45%  12 s left".
[[nodiscard]] std::string progress_text(const std::string& label, double fraction, double elapsed, int width);

/// FILTER_PROGRESS=N lines on stderr: whole percents, each printed once, never going back
/// (a loop that seeks back in the file does not move the bar back). With several programs
/// at once (-j), each line is prefixed by its program's name ("part.ngc: FILTER_PROGRESS=N"),
/// which LinuxCNC (one program per filter run) never sees. Thread-safe per instance.
class FilterProgress {
 public:
  explicit FilterProgress(std::string prefix) : prefix_(std::move(prefix)) {}
  void update(double fraction);

 private:
  std::string prefix_;
  std::mutex mutex_;
  int last_ = -1;
};

/// Several programs' progress as one fraction: each program's share weighted by its size.
class SharedProgress {
 public:
  explicit SharedProgress(std::vector<std::uint64_t> sizes);
  /// Program i is `fraction` done; returns the whole.
  double update(std::size_t i, double fraction);

 private:
  std::vector<double> weights_, done_;
  std::mutex mutex_;
};

}  // namespace ccomp::cli
