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

/// The part every parallel loop here shares: hands out the indices 0..count-1 in order to the
/// threads that call work(), stops handing them out after the first exception and keeps that one
/// for rethrow(), to be called once the threads have joined.
class WorkQueue {
 public:
  explicit WorkQueue(size_t count) : count_(count) {}
  template <class Body>
  void work(Body& body) {
    for (;;) {
      const size_t i = next_.fetch_add(1);
      if (i >= count_ || failed_) return;
      try {
        body(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex_);
        if (!error_) error_ = std::current_exception();
        failed_ = true;
      }
    }
  }
  bool failed() const { return failed_; }
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  size_t count_;
  std::atomic<size_t> next_{0};
  std::atomic<bool> failed_{false};
  std::exception_ptr error_;
  std::mutex error_mutex_;
};

template <class Body>
void parallelFor(size_t count, int jobs, Body&& body) {
  WorkQueue queue(count);
  auto work = [&] { queue.work(body); };
  const size_t threads = std::min(count, static_cast<size_t>(jobs < 1 ? 1 : jobs));
  std::vector<std::thread> pool;
  for (size_t w = 1; w < threads; ++w) pool.emplace_back(work);
  work();
  for (auto& th : pool) th.join();
  queue.rethrow();
}

}  // namespace predvs
