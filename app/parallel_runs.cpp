#include "parallel_runs.h"

#include "parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <iomanip>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace predvs {
namespace {

class Progress {
 public:
  Progress(std::ostream& err, size_t total, bool bar, const char* label, double interval_s)
      : err_(err), total_(total), bar_(bar), label_(label), interval_s_(interval_s) {}
  void show(size_t done, double elapsed_s) {
    if (bar_) {
      constexpr int kWidth = 40;
      const int filled = total_ ? static_cast<int>(kWidth * done / total_) : kWidth;
      const double eta = done ? elapsed_s * static_cast<double>(total_ - done) / static_cast<double>(done) : 0.0;
      err_ << "\rpredvs " << label_ << " [" << std::string(static_cast<size_t>(filled), '#')
           << std::string(static_cast<size_t>(kWidth - filled), '.') << "] " << done << "/" << total_ << " runs, "
           << std::fixed << std::setprecision(0) << elapsed_s << " s, eta " << eta << " s   " << std::defaultfloat
           << std::flush;
      if (done == total_) err_ << "\n";
      return;
    }
    // Not a terminal: a line at every quarter, and after interval_s_ without one if runs ended since.
    const size_t quarter = total_ ? 4 * done / total_ : 4;
    const bool late = done > last_done_ && elapsed_s - last_line_s_ >= interval_s_;
    if (quarter > last_quarter_ || late || (done == total_ && !finished_)) {
      last_quarter_ = quarter;
      last_done_ = done;
      last_line_s_ = elapsed_s;
      finished_ = done == total_;
      err_ << "predvs: " << label_ << ": " << done << "/" << total_ << " runs (" << std::fixed << std::setprecision(1)
           << elapsed_s << " s)\n"
           << std::defaultfloat << std::flush;
    }
  }

 private:
  std::ostream& err_;
  size_t total_;
  bool bar_;
  const char* label_;
  double interval_s_;
  size_t last_quarter_ = 0;
  size_t last_done_ = 0;
  double last_line_s_ = 0.0;
  bool finished_ = false;
};

}  // namespace

void runParallel(size_t count, const std::function<void(size_t)>& run, const ParallelOptions& o, std::ostream& err) {
  std::atomic<size_t> done{0};
  WorkQueue queue(count);
  auto body = [&](size_t i) {
    run(i);
    ++done;
  };
  auto work = [&] { queue.work(body); };
  std::vector<std::thread> pool;
  for (int w = 0; w < std::max(1, o.workers); ++w) pool.emplace_back(work);
  Progress progress(err, count, o.progress_bar, o.label, o.progress_interval_s);
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - o.start).count(); };
  while (done < count && !queue.failed()) {
    progress.show(done, elapsed());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (auto& th : pool) th.join();
  queue.rethrow();
  progress.show(done, elapsed());
}

}  // namespace predvs
