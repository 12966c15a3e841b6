// The parallel helpers: every index handled exactly once whatever the thread count, and a
// failure on any thread reaches the caller.
#include "ccomp/util/parallel.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
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

}  // namespace
}  // namespace ccomp::util
