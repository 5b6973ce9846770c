// core::parallel_for, core::ThreadPool and core::parallel_tasks: every item once, on any number of
// threads; errors reach the caller; tasks' logs read in task order.
#include <gtest/gtest.h>

#include <cstdlib>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
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

// Each task logs three lines with pauses between them, the later tasks faster, so on several
// threads the lines interleave unless they are held back: the log must be task 0's lines, then
// task 1's, ... for any thread count; every task runs even when one throws, and the first
// failing task's exception (in task order) is the one the caller gets.
TEST(ParallelTasks, LogsInTaskOrderAndTheFirstFailureWins) {
  for (const char* threads : {"1", "2", "4"}) {
    setenv("VOLTS_THREADS", threads, 1);
    std::vector<int> ran(4, 0);
    std::vector<std::function<void()>> tasks;
    for (int t = 0; t < 4; ++t)
      tasks.push_back([&ran, t] {
        for (int line = 0; line < 3; ++line) {
          std::this_thread::sleep_for(std::chrono::milliseconds(2 * (4 - t)));
          log("task " + std::to_string(t) + " line " + std::to_string(line));
        }
        ++ran[static_cast<std::size_t>(t)];
        if (t == 1 || t == 3) throw std::runtime_error("task " + std::to_string(t));
      });
    testing::internal::CaptureStderr();
    std::string what;
    try {
      parallel_tasks(tasks);
    } catch (const std::runtime_error& e) {
      what = e.what();
    }
    const std::string log = testing::internal::GetCapturedStderr();
    EXPECT_EQ(what, "task 1") << threads << " threads";
    EXPECT_EQ(ran, std::vector<int>(4, 1)) << threads << " threads";
    std::string expected;
    for (int t = 0; t < 4; ++t)
      for (int line = 0; line < 3; ++line) expected += "[volts] task " + std::to_string(t) + " line " + std::to_string(line) + "\n";
    EXPECT_EQ(log, expected) << threads << " threads";
  }
  unsetenv("VOLTS_THREADS");
}

// A capture inside a capture hands its lines to the outer one, which prints them in place.
TEST(LogCapture, NestsAndReleases) {
  testing::internal::CaptureStderr();
  std::string outer_lines;
  {
    LogCapture outer;
    log("a");
    {
      LogCapture inner;
      log("b");
    }
    log("c");
    outer_lines = outer.release();
    log("d");
  }
  EXPECT_EQ(outer_lines, "[volts] a\n[volts] b\n[volts] c\n");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "[volts] d\n");
}

}  // namespace
}  // namespace volts::core
