// predvs app — a fork-join loop over independent items on a few threads, no progress output
// (parallel_runs.h is the one with progress, for long campaigns).
//
// body(i) is called once for every i in [0, count); item i is taken by the next free thread, in
// index order (so put the longest items first for the best balance). The calling thread is one of
// the `jobs` workers. What body computes must not depend on the thread or the order: results are
// then the same for any jobs. The first exception stops new items from starting and is rethrown
// once every thread has finished.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace predvs {

/// std::thread::hardware_concurrency(), at least 1: the default of --jobs.
inline int hardwareJobs() {
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

template <class Body>
void parallelFor(size_t count, int jobs, Body&& body) {
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    for (;;) {
      const size_t i = next.fetch_add(1);
      if (i >= count || failed) return;
      try {
        body(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        failed = true;
      }
    }
  };
  const size_t threads = std::min(count, static_cast<size_t>(jobs < 1 ? 1 : jobs));
  std::vector<std::thread> pool;
  for (size_t w = 1; w < threads; ++w) pool.emplace_back(work);
  work();
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace predvs
