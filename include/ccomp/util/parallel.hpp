#pragma once
// Data parallelism without shared state: work split over a few threads (the caller's among
// them), the first exception rethrown in the caller. Results never depend on the thread
// count as long as each index writes only its own outputs.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace ccomp::util {

/// The threads worth using here: the machine's cores.
[[nodiscard]] inline int hardware_threads() {
  return static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
}

namespace detail {
template <class Work>
void run_on_threads(int threads, Work&& work) {
  std::vector<std::exception_ptr> failures(static_cast<std::size_t>(std::max(threads, 1)));
  auto guarded = [&](std::size_t id) {
    try {
      work(id);
    } catch (...) {
      failures[id] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < failures.size(); ++t) pool.emplace_back(guarded, t);
  guarded(0);
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : failures)
    if (e) std::rethrow_exception(e);
}
}  // namespace detail

/// fn(begin, end) on [0, n) cut into one contiguous piece per thread: for uniform work
/// that wants scratch of its own per piece.
template <class Fn>
void for_each_piece(std::size_t n, int threads, Fn&& fn) {
  const auto pieces = static_cast<std::size_t>(
      std::clamp<std::ptrdiff_t>(threads, 1, std::max<std::ptrdiff_t>(1, static_cast<std::ptrdiff_t>(n))));
  detail::run_on_threads(static_cast<int>(pieces), [&](std::size_t id) {
    const std::size_t begin = n * id / pieces, end = n * (id + 1) / pieces;
    if (begin < end) fn(begin, end);
  });
}

/// fn(i) for every i in [0, n), handed out one at a time: for work of uneven size.
template <class Fn>
void for_each_index(std::size_t n, int threads, Fn&& fn) {
  std::atomic<std::size_t> next{0};
  detail::run_on_threads(std::clamp(threads, 1, static_cast<int>(std::max<std::size_t>(n, 1))), [&](std::size_t) {
    for (std::size_t i = next++; i < n; i = next++) fn(i);
  });
}

}  // namespace ccomp::util
