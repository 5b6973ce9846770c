// volts::core — a parallel loop over independent items (std::thread). Callers write each item's
// result to its own slot and reduce serially afterwards, so results do not depend on the number
// of threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <exception>
#include <thread>
#include <vector>

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

}  // namespace volts::core
