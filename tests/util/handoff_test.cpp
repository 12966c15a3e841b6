// The hand-over between a reading thread and its consumer: batches in order, memory
// bounded, a failure after everything made before it, a consumer that gives up stopping
// the producer.
#include "ccomp/util/handoff.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>

namespace ccomp::util {
namespace {

TEST(Handoff, BatchesArriveInOrderAndAFailureAfterThem) {
  Handoff<int> handoff(2);
  std::atomic<int> most_waiting{0}, pushed{0}, popped{0};
  std::thread producer([&] {
    handoff.produce([&](Handoff<int>& out) {
      std::vector<int> batch;
      for (int k = 0; k < 100; ++k) {
        batch = {2 * k, 2 * k + 1};
        out.push(batch);
        EXPECT_TRUE(batch.empty()) << "handed over, not copied";
        most_waiting = std::max(most_waiting.load(), ++pushed - popped);
      }
      throw std::runtime_error("line 201: bad word");
    });
  });
  std::vector<int> batch, seen;
  try {
    while (handoff.pop(batch)) {
      ++popped;
      seen.insert(seen.end(), batch.begin(), batch.end());
    }
    ADD_FAILURE() << "the producer's failure was not rethrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "line 201: bad word");
  }
  producer.join();
  ASSERT_EQ(seen.size(), 200U) << "every batch made before the failure arrives first";
  for (int k = 0; k < 200; ++k) EXPECT_EQ(seen[static_cast<std::size_t>(k)], k);
  EXPECT_LE(most_waiting.load(), 3) << "at most the capacity waits (and one being handed over)";
}

TEST(Handoff, ACancelStopsTheProducerAtItsNextHandOver) {
  Handoff<int> handoff(1);
  std::atomic<int> pushes{0};
  std::thread producer([&] {
    handoff.produce([&](Handoff<int>& out) {
      std::vector<int> batch;
      for (;;) {  // would run for ever
        batch = {1};
        out.push(batch);
        ++pushes;
      }
    });
  });
  std::vector<int> batch;
  ASSERT_TRUE(handoff.pop(batch));
  handoff.cancel();
  producer.join();  // returns: the push after the cancel threw to the producer
  EXPECT_LE(pushes.load(), 3);
  while (handoff.pop(batch)) {
  }  // what was handed over before, then the end, without a failure
}

TEST(BackgroundProducer, HandsOverWhatItsThreadMakesAndStopsItWhenDestroyedEarly) {
  {
    BackgroundProducer<int> numbers(2, [](Handoff<int>& out) {
      std::vector<int> batch;
      for (int k = 0; k < 50; ++k) {
        batch = {k};
        out.push(batch);
      }
      throw std::runtime_error("out of numbers");
    });
    std::vector<int> batch, seen;
    EXPECT_THROW(
        {
          while (numbers.pop(batch)) seen.insert(seen.end(), batch.begin(), batch.end());
        },
        std::runtime_error);
    ASSERT_EQ(seen.size(), 50U);
    for (int k = 0; k < 50; ++k) EXPECT_EQ(seen[static_cast<std::size_t>(k)], k);
  }
  // A producer that would run for ever, its owner gone after one batch: the destructor
  // stops it at its next hand-over and returns.
  std::atomic<int> pushes{0};
  {
    BackgroundProducer<int> endless(1, [&pushes](Handoff<int>& out) {
      std::vector<int> batch;
      for (;;) {
        batch = {1};
        out.push(batch);
        ++pushes;
      }
    });
    std::vector<int> batch;
    ASSERT_TRUE(endless.pop(batch));
  }
  EXPECT_LE(pushes.load(), 3);
}

}  // namespace
}  // namespace ccomp::util
