#include "progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace ccomp::cli {

bool stderr_is_terminal() {
  return isatty(STDERR_FILENO) == 1;
}

std::string progress_text(const std::string& label, double fraction, double elapsed, int width) {
  fraction = std::clamp(fraction, 0.0, 1.0);
  const int filled = static_cast<int>(std::lround(fraction * width));
  std::string bar =
      std::string(static_cast<std::size_t>(filled), '#') + std::string(static_cast<std::size_t>(width - filled), '.');
  std::string left = "";
  // The time left once there is a rate to tell it from.
  if (fraction > 0.02 && elapsed > 0.5) {
    const double seconds = elapsed * (1.0 - fraction) / fraction;
    left = seconds < 60
               ? fmt::format("  {:.0f} s left", std::ceil(seconds))
               : fmt::format("  {}:{:02} left", static_cast<int>(seconds) / 60, static_cast<int>(seconds) % 60);
  }
  return fmt::format("{} [{}] {:3}%{}", label, bar, static_cast<int>(std::floor(fraction * 100.0)), left);
}

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
  clear();
}

void ProgressBar::update(double fraction) {
  if (!enabled_) return;
  const std::lock_guard lock(mutex_);
  if (fraction <= shown_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100) && fraction < 1.0) return;
  last_draw_ = now;
  shown_ = fraction;
  draw(fraction);
}

void ProgressBar::draw(double fraction) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  fmt::print(stderr, "\r\033[K{}", progress_text(label_, fraction, elapsed, 30));
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::clear() {
  const std::lock_guard lock(mutex_);
  clear_locked();
}

void ProgressBar::clear_locked() {
  if (!enabled_ || !drawn_) return;
  fmt::print(stderr, "\r\033[K");
  std::fflush(stderr);
  drawn_ = false;
}

void ProgressBar::print_above(const std::string& text) {
  const std::lock_guard lock(mutex_);
  clear_locked();
  fmt::print(stderr, "{}", text);
  std::fflush(stderr);
  shown_ = -1.0;  // drawn again at the next update, whatever it says
}

void FilterProgress::update(double fraction) {
  const int percent = static_cast<int>(std::floor(std::clamp(fraction, 0.0, 1.0) * 100.0 + 1e-9));
  const std::lock_guard lock(mutex_);
  if (percent <= last_) return;
  last_ = percent;
  fmt::print(stderr, "{}FILTER_PROGRESS={}\n", prefix_, percent);
  std::fflush(stderr);
}

SharedProgress::SharedProgress(std::vector<std::uint64_t> sizes) : done_(sizes.size(), 0.0) {
  const double total = std::accumulate(sizes.begin(), sizes.end(), 0.0, [](double s, std::uint64_t n) {
    return s + static_cast<double>(std::max<std::uint64_t>(n, 1));
  });
  for (std::uint64_t n : sizes) weights_.push_back(static_cast<double>(std::max<std::uint64_t>(n, 1)) / total);
}

double SharedProgress::update(std::size_t i, double fraction) {
  const std::lock_guard lock(mutex_);
  done_[i] = std::max(done_[i], std::clamp(fraction, 0.0, 1.0));
  double whole = 0.0;
  for (std::size_t k = 0; k < done_.size(); ++k) whole += weights_[k] * done_[k];
  return whole;
}

}  // namespace ccomp::cli
