// The search window's queue: what it holds after any mix of appends and drops from the
// front is what a std::deque given the same calls holds, element for element, including
// across the drops that reclaim the vector's front.
#include "compensate/sliding_vector.hpp"

#include <gtest/gtest.h>

#include <deque>
#include <random>

namespace ccomp::compensate {
namespace {

TEST(SlidingVector, HoldsWhatADequeHoldsAcrossDropsAndReclaims) {
  std::mt19937 random(7);
  SlidingVector<int> window;
  std::deque<int> reference;
  int next = 0;
  for (int step = 0; step < 20000; ++step) {
    // Appends outrun drops (19.5 against 12 a step on average), so the front is reclaimed
    // many times over.
    const int appends = static_cast<int>(random() % 40);
    for (int k = 0; k < appends; ++k) window.push_back(next), reference.push_back(next), ++next;
    const auto drops = std::min<std::size_t>(random() % 25, reference.size());
    window.drop_front(drops);
    reference.erase(reference.begin(), reference.begin() + static_cast<std::ptrdiff_t>(drops));
    ASSERT_EQ(window.size(), reference.size()) << "step " << step;
    ASSERT_EQ(window.empty(), reference.empty());
    if (reference.empty()) continue;
    ASSERT_EQ(window.front(), reference.front()) << "step " << step;
    ASSERT_EQ(window.back(), reference.back()) << "step " << step;
    for (std::size_t i = 0; i < reference.size(); i += 1 + reference.size() / 7)
      ASSERT_EQ(window[i], reference[i]) << "step " << step << " element " << i;
  }
  EXPECT_GT(next, 100000);
}

TEST(SlidingVector, DroppingEverythingLeavesItEmptyForWhatComesNext) {
  SlidingVector<int> window;
  for (int k = 0; k < 300; ++k) window.push_back(k);
  window.drop_front(300);
  EXPECT_TRUE(window.empty());
  window.push_back(5);
  ASSERT_EQ(window.size(), 1U);
  EXPECT_EQ(window[0], 5);
  window.clear();
  EXPECT_TRUE(window.empty());
}

}  // namespace
}  // namespace ccomp::compensate
