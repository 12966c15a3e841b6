#pragma once
// Batches handed from a producer on a thread of its own to one consumer, in order, with at
// most `capacity` waiting: the consumer's memory stays bounded however far ahead the
// producer could run. The producer's failure reaches the consumer after every batch made
// before it; a consumer that gives up stops the producer at its next hand-over.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <utility>
#include <vector>

#include "ccomp/util/parallel.hpp"

namespace ccomp::util {

template <class T>
class Handoff {
 public:
  /// Thrown to the producer by push() once the consumer has cancelled.
  struct Cancelled {};

  explicit Handoff(std::size_t capacity) : capacity_(capacity) {}

  /// Producer: hands `batch` on (left empty), waiting while `capacity` batches wait.
  void push(std::vector<T>& batch) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return ready_.size() < capacity_ || cancelled_; });
    if (cancelled_) throw Cancelled{};
    ready_.push_back(std::move(batch));
    batch.clear();
    lock.unlock();
    changed_.notify_all();
  }
  /// Producer: there is no more; `error`, when set, is why.
  void close(std::exception_ptr error = nullptr) {
    {
      const std::lock_guard lock(mutex_);
      error_ = std::move(error);
      done_ = true;
    }
    changed_.notify_all();
  }
  /// Producer: runs make(*this), which pushes, then closes with what it threw (nothing
  /// for a cancellation).
  template <class Make>
  void produce(Make&& make) {
    try {
      make(*this);
      close();
    } catch (const Cancelled&) {
      close();
    } catch (...) {
      close(std::current_exception());
    }
  }

  /// Consumer: the next batch into `batch`; false at the end, where the producer's failure
  /// is rethrown.
  bool pop(std::vector<T>& batch) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return !ready_.empty() || done_; });
    if (ready_.empty()) {
      if (error_) std::rethrow_exception(error_);
      return false;
    }
    batch = std::move(ready_.front());
    ready_.pop_front();
    lock.unlock();
    changed_.notify_all();
    return true;
  }
  /// Consumer: the producer stops at its next push.
  void cancel() {
    {
      const std::lock_guard lock(mutex_);
      cancelled_ = true;
    }
    changed_.notify_all();
  }

 private:
  std::size_t capacity_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::vector<T>> ready_;
  bool done_ = false, cancelled_ = false;
  std::exception_ptr error_;
};

/// A producer on a thread of its own handing batches to its owner: the thread starts with
/// make(handoff) at construction; destruction stops it at its next hand-over and waits for it.
template <class T>
class BackgroundProducer {
 public:
  template <class Make>
  BackgroundProducer(std::size_t capacity, Make make) : handoff_(capacity) {
    thread_.run([this, make = std::move(make)]() mutable { handoff_.produce(make); });
  }
  BackgroundProducer(const BackgroundProducer&) = delete;
  BackgroundProducer& operator=(const BackgroundProducer&) = delete;
  ~BackgroundProducer() { handoff_.cancel(); }  // then thread_, declared last, is joined first

  /// The next batch; false at the end, where the producer's failure is rethrown.
  bool pop(std::vector<T>& batch) { return handoff_.pop(batch); }

 private:
  Handoff<T> handoff_;
  BackgroundThread thread_;
};

}  // namespace ccomp::util
