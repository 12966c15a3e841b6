// The parallel helpers: every index handled exactly once whatever the thread count, a
// failure on any thread reaches the caller, and a background thread runs what it is given
// in order, each ticket done when its wait returns.
#include "ccomp/util/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace ccomp::util {
namespace {

TEST(Parallel, EveryIndexOnceWhateverTheThreadCount) {
  for (std::size_t n : {0UL, 1UL, 2UL, 7UL, 1000UL}) {
    for (int threads : {1, 2, 3, 16}) {
      std::vector<int> pieces(n, 0), indices(n, 0);
      for_each_piece(n, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) ++pieces[i];
      });
      for_each_index(n, threads, [&](std::size_t i) { ++indices[i]; });
      for (std::size_t i = 0; i < n; ++i) {
        ASSERT_EQ(pieces[i], 1) << "n " << n << " threads " << threads << " index " << i;
        ASSERT_EQ(indices[i], 1) << "n " << n << " threads " << threads << " index " << i;
      }
    }
  }
}

TEST(Parallel, AFailureOnAnyThreadReachesTheCaller) {
  EXPECT_THROW(for_each_index(100, 4,
                              [](std::size_t i) {
                                if (i == 97) throw std::runtime_error("index 97");
                              }),
               std::runtime_error);
  EXPECT_THROW(for_each_piece(100, 4,
                              [](std::size_t begin, std::size_t) {
                                if (begin > 0) throw std::runtime_error("a later piece");
                              }),
               std::runtime_error);
}

TEST(Parallel, BackgroundThreadRunsItsQueueInOrder) {
  BackgroundThread worker;
  std::vector<int> order;  // written by the worker only, read after a wait
  std::atomic<bool> release{false};
  // The first piece holds the thread while more are queued: run() must not wait for it.
  const std::size_t first = worker.run([&] {
    while (!release) std::this_thread::sleep_for(std::chrono::microseconds(50));
    order.push_back(1);
  });
  std::vector<std::size_t> tickets{first};
  for (int k = 2; k <= 5; ++k) tickets.push_back(worker.run([&order, k] { order.push_back(k); }));
  EXPECT_EQ(tickets, (std::vector<std::size_t>{1, 2, 3, 4, 5}));
  release = true;
  worker.wait(tickets[2]);
  ASSERT_GE(order.size(), 3U) << "wait(3) returned before the third piece was done";
  worker.wait();
  EXPECT_EQ(order, (std::vector<int>{1, 2, 3, 4, 5}));
  // A failure reaches the next wait, and the pieces after it still run.
  worker.run([] { throw std::runtime_error("a piece failed"); });
  const std::size_t after = worker.run([&order] { order.push_back(6); });
  EXPECT_THROW(worker.wait(after), std::runtime_error);
  EXPECT_EQ(order.back(), 6);
  EXPECT_NO_THROW(worker.wait());
}

}  // namespace
}  // namespace ccomp::util
