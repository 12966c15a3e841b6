#pragma once
// Data parallelism without shared state: work split over a few threads (the caller's among
// them), the first exception rethrown in the caller. Results never depend on the thread
// count as long as each index writes only its own outputs.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>
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

/// One thread that runs pieces of work, in the order they were queued, while its owner goes
/// on with others: the second stage of a pipeline. run() queues a piece and returns its
/// ticket (1, 2, ...); wait(ticket) returns once that piece and those before it are done,
/// wait() once all are, and both rethrow the first failure; done(ticket) asks without waiting.
class BackgroundThread {
 public:
  BackgroundThread() : thread_([this] { loop(); }) {}
  BackgroundThread(const BackgroundThread&) = delete;
  BackgroundThread& operator=(const BackgroundThread&) = delete;
  ~BackgroundThread() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }

  std::size_t run(std::function<void()> work) {
    std::size_t ticket = 0;
    {
      const std::lock_guard lock(mutex_);
      queue_.push_back(std::move(work));
      ticket = ++queued_;
    }
    wake_.notify_all();
    return ticket;
  }

  /// Whether the piece with that ticket, and those before it, are done (without waiting).
  [[nodiscard]] bool done(std::size_t ticket) {
    const std::lock_guard lock(mutex_);
    return done_count_ >= std::min(ticket, queued_);
  }

  void wait(std::size_t ticket) {
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return done_count_ >= std::min(ticket, queued_); });
    if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
  }
  void wait() { wait(static_cast<std::size_t>(-1)); }

 private:
  void loop() {
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return !queue_.empty() || stop_; });
      if (queue_.empty()) return;
      std::function<void()> work = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      std::exception_ptr failure;
      try {
        work();
      } catch (...) {
        failure = std::current_exception();
      }
      lock.lock();
      if (failure && !failure_) failure_ = failure;
      ++done_count_;
      done_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<std::function<void()>> queue_;
  std::size_t queued_ = 0, done_count_ = 0;
  std::exception_ptr failure_;
  bool stop_ = false;
  std::thread thread_;  // last: it starts once the rest is built
};

}  // namespace ccomp::util
