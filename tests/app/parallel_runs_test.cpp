// runParallel's progress outside a terminal (app/parallel_runs.h): a line at every quarter of the
// runs, and one more whenever progress_interval_s has passed since the last line and runs have
// ended since, so that a log of a long campaign (slow runs at the end) is never silent for minutes.
#include "parallel_runs.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <sstream>
#include <string>
#include <thread>

namespace predvs {
namespace {

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

/// The progress lines of 20 runs of run_ms each on one worker, with a line interval of interval_s.
std::string progressOf(int run_ms, double interval_s) {
  std::ostringstream err;
  ParallelOptions o;
  o.workers = 1;
  o.label = "test";
  o.progress_interval_s = interval_s;
  std::atomic<int> ran{0};
  runParallel(
      20,
      [&](size_t) {
        std::this_thread::sleep_for(std::chrono::milliseconds(run_ms));
        ++ran;
      },
      o, err);
  EXPECT_EQ(ran, 20);
  return err.str();
}

TEST(ParallelRuns, ALineAtEveryQuarterAndNoMoreWithinTheInterval) {
  // GIVEN 20 runs of 40 ms (0.8 s in all) and an interval longer than that
  const std::string out = progressOf(40, 60.0);
  // THEN a line per quarter at most (the loop looks every 0.1 s, so a line may come a run or two
  // late, and on a starved machine two quarters in one line), the last one at 20 of 20
  EXPECT_LE(lines(out), 4) << out;
  EXPECT_GE(lines(out), 2) << out;
  EXPECT_NE(out.find("predvs: test: 20/20 runs"), std::string::npos) << out;
}

TEST(ParallelRuns, ALineAfterEveryIntervalInWhichRunsEnded) {
  // GIVEN 20 runs of 100 ms (a quarter every 0.5 s) and an interval of 0.15 s
  const std::string out = progressOf(100, 0.15);
  // THEN lines between the quarters too: one each 0.2 s or so (the loop looks every 0.1 s), more
  // than the four quarters can give
  EXPECT_GE(lines(out), 6) << out;
  EXPECT_LE(lines(out), 14) << out;
  EXPECT_NE(out.find("predvs: test: 20/20 runs"), std::string::npos) << out;
}

}  // namespace
}  // namespace predvs
