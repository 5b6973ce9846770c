// core::parallel_for and core::ThreadPool: every item once, on any number of threads; errors reach the caller.
#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "core/parallel.h"

namespace volts::core {
namespace {

TEST(ParallelFor, EveryItemOnceForAnyThreadCount) {
  for (const char* threads : {"1", "2", "3", "8"}) {
    setenv("VOLTS_THREADS", threads, 1);
    EXPECT_EQ(thread_count(), std::atoi(threads));
    for (const std::size_t n : {0, 1, 15, 16, 17, 1000}) {
      std::vector<int> hits(n, 0);
      parallel_for(n, [&](std::size_t i) { ++hits[i]; }, 4);
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(hits[i], 1) << "item " << i << " of " << n << " on " << threads << " threads";
    }
  }
  unsetenv("VOLTS_THREADS");
  EXPECT_GE(thread_count(), 1);
}

TEST(ParallelFor, RethrowsAnItemsException) {
  setenv("VOLTS_THREADS", "2", 1);
  EXPECT_THROW(parallel_for(100, [](std::size_t i) {
    if (i == 57) throw std::runtime_error("item 57");
  }), std::runtime_error);
  unsetenv("VOLTS_THREADS");
}

TEST(ThreadPool, EveryItemOnceOverManyCallsForAnyThreadCount) {
  for (const int threads : {1, 2, 3, 8}) {
    ThreadPool pool(threads);
    for (int round = 0; round < 200; ++round)
      for (const std::size_t n : {0, 1, 3, 4, 5, 64, 1000}) {
        std::vector<int> hits(n, 0);
        pool.for_each(n, [&](std::size_t i) { ++hits[i]; }, 4);
        for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i], 1) << "item " << i << " of " << n << " on " << threads << " threads";
      }
  }
}

TEST(ThreadPool, RethrowsAnItemsExceptionAndStaysUsable) {
  ThreadPool pool(2);
  EXPECT_THROW(pool.for_each(100, [](std::size_t i) {
    if (i == 57) throw std::runtime_error("item 57");
  }, 1), std::runtime_error);
  std::vector<int> hits(100, 0);
  pool.for_each(100, [&](std::size_t i) { ++hits[i]; }, 1);
  for (const int h : hits) EXPECT_EQ(h, 1);
}

}  // namespace
}  // namespace volts::core
