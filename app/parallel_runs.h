// predvs app — independent runs on a pool of threads, with progress on stderr.
//
// Work item i is taken by the next free thread; what it computes must not depend on which thread
// or in which order (each run builds its own predictor, noise and loop), so that results do not
// depend on the number of threads. The first exception a run throws stops the pool (no new run
// starts) and is rethrown once every thread has finished.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <ostream>

namespace predvs {

struct ParallelOptions {
  int workers = 1;              ///< threads (>= 1)
  bool progress_bar = false;    ///< redraw a bar on `err` (a terminal); else a line at every quarter
  /// Without the bar, also a line when this long has passed since the last one and runs have ended
  /// since (a log of a long campaign is never silent for minutes).
  double progress_interval_s = 30.0;
  const char* label = "compare";  ///< names the command in the progress lines
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();  ///< elapsed time origin
};

/// Calls run(i) for every i in [0, count) on options.workers threads, reporting progress on `err`.
void runParallel(size_t count, const std::function<void(size_t)>& run, const ParallelOptions& options,
                 std::ostream& err);

}  // namespace predvs
