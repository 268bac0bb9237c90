#include "exoid/core/parallel_for.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace exoid::core {
namespace {

TEST(ParallelFor, EveryIndexOnceWhateverTheThreads) {
  for (int threads : {1, 2, 5, 0}) {
    std::vector<int> hits(1000, 0);
    parallelFor(hits.size(), threads, [&](std::size_t i) { hits[i] += 1; });
    for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i], 1) << i << " with " << threads << " threads";
  }
  parallelFor(0, 2, [](std::size_t) { FAIL() << "no index to run"; });
}

TEST(ParallelFor, TheLowestFailingIndexIsRethrownAfterAllStop) {
  for (int threads : {1, 2, 4}) {
    try {
      parallelFor(100, threads, [](std::size_t i) {
        if (i == 17 || i == 60) throw std::runtime_error("block " + std::to_string(i));
      });
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "block 17") << threads << " threads";
    }
  }
}

TEST(ParallelFor, ZeroThreadsMeansTheMachinesCores) {
  EXPECT_GE(resolveThreads(0), 1);
  EXPECT_EQ(resolveThreads(3), 3);
}

}  // namespace
}  // namespace exoid::core
