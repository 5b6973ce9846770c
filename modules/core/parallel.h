// volts::core — a parallel loop over independent items (std::thread). Callers write each item's
// result to its own slot and reduce serially afterwards, so results do not depend on the number
// of threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "core/log.h"

namespace volts::core {

/// Threads parallel_for uses: VOLTS_THREADS if set to a positive number, else the hardware's.
inline int thread_count() {
  if (const char* env = std::getenv("VOLTS_THREADS")) {
    const int n = std::atoi(env);
    if (n > 0) return n;
  }
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// Calls f(i) for every i in [0, n), on up to thread_count() threads taking chunks of `chunk`
/// items in turn (items cost unevenly: certification subdivides some elements). Fewer than two
/// chunks run on the calling thread. f must only write to state of item i and be safe to call
/// concurrently. The first exception thrown by f is rethrown here (the others are dropped).
template <class F>
void parallel_for(std::size_t n, F&& f, std::size_t chunk = 16) {
  chunk = std::max<std::size_t>(1, chunk);
  const std::size_t chunks = (n + chunk - 1) / chunk;
  const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(thread_count()), chunks);
  if (threads <= 1) {
    for (std::size_t i = 0; i < n; ++i) f(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(threads);
  auto run = [&](std::size_t t) {
    try {
      for (std::size_t c = next++; c < chunks; c = next++)
        for (std::size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) f(i);
    } catch (...) {
      errors[t] = std::current_exception();
      next = chunks;  // the others stop at their next chunk
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(run, t);
  run(0);
  for (auto& th : pool) th.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

/// parallel_for on threads started once: for loops called thousands of times on a few items
/// each (the optimization's per-node batches, ~64 elements), where starting threads per call
/// costs as much as the work. Same contract as parallel_for (each item writes its own slot; the
/// first exception is rethrown); for_each() must not be called concurrently or from inside an item.
class ThreadPool {
 public:
  explicit ThreadPool(int threads = thread_count()) {
    for (int t = 1; t < std::max(1, threads); ++t) workers_.emplace_back([this, t] { work(static_cast<std::size_t>(t)); });
    errors_.resize(workers_.size() + 1);
  }
  ~ThreadPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
  }
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  template <class F>
  void for_each(std::size_t n, F&& f, std::size_t chunk = 16) {
    chunk = std::max<std::size_t>(1, chunk);
    const std::size_t chunks = (n + chunk - 1) / chunk;
    if (workers_.empty() || chunks <= 1) {
      for (std::size_t i = 0; i < n; ++i) f(i);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      item_ = [&f](std::size_t i) { f(i); };
      n_ = n, chunk_ = chunk, chunks_ = chunks;
      next_ = 0;
      busy_ = workers_.size();
      ++generation_;
    }
    wake_.notify_all();
    run(0);
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return busy_ == 0; });
    item_ = nullptr;
    for (auto& e : errors_)
      if (e) {
        const std::exception_ptr x = e;
        for (auto& y : errors_) y = nullptr;
        std::rethrow_exception(x);
      }
  }

 private:
  void run(std::size_t t) {
    try {
      for (std::size_t c = next_++; c < chunks_; c = next_++)
        for (std::size_t i = c * chunk_; i < std::min(n_, (c + 1) * chunk_); ++i) item_(i);
    } catch (...) {
      errors_[t] = std::current_exception();
      next_ = chunks_;
    }
  }
  void work(std::size_t t) {
    std::size_t seen = 0;
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
      }
      run(t);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        --busy_;
      }
      done_.notify_one();
    }
  }

  std::vector<std::thread> workers_;
  std::vector<std::exception_ptr> errors_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::function<void(std::size_t)> item_;
  std::size_t n_ = 0, chunk_ = 1, chunks_ = 0, busy_ = 0, generation_ = 0;
  std::atomic<std::size_t> next_{0};
  bool stop_ = false;
};

/// Runs independent tasks on up to thread_count() threads (each task on one thread) and returns
/// when all are done. Each task's log is held back and printed in task order, so the log reads
/// as if they had run in turn. The exception of the first task (in order) that threw is rethrown.
inline void parallel_tasks(const std::vector<std::function<void()>>& tasks) {
  std::vector<std::exception_ptr> errors(tasks.size());
  std::vector<std::string> lines(tasks.size());
  std::atomic<std::size_t> next{0};
  auto run = [&] {
    for (std::size_t t = next++; t < tasks.size(); t = next++) {
      LogCapture capture;
      try {
        tasks[t]();
      } catch (...) {
        errors[t] = std::current_exception();
      }
      lines[t] = capture.release();
    }
  };
  const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(thread_count()), tasks.size());
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(run);
  run();
  for (auto& th : pool) th.join();
  for (const std::string& l : lines) log_lines(l);
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace volts::core
