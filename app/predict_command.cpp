#include "predict_command.h"

#include "predictor_choice.h"
#include "number_text.h"

#include "cache_line.h"
#include "general_number.h"
#include "gnuplot.h"
#include "large_buffer.h"
#include "output_dir.h"
#include "plots.h"
#include "streaming_file.h"

#include "predvs/predictors/predictor.h"
#include "predvs/servo/sampled_signal.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <algorithm>
#include <iomanip>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

nlohmann::json errorsJson(const PredictionErrors& e) {
  nlohmann::json j;
  j["rmse_px"] = e.n > 0 ? e.rmse_px : kNaN;
  j["rmse_u_px"] = e.n > 0 ? e.rmse_u_px : kNaN;
  j["rmse_v_px"] = e.n > 0 ? e.rmse_v_px : kNaN;
  j["n"] = e.n;
  return j;
}

/// The double a number's text stands for (what gnuplot reads from it): from_chars, strtod when
/// from_chars refuses (a subnormal).
double textValue(const char* begin, char* end) {
  double value = 0.0;
  const auto r = std::from_chars(begin, end, value);
  if (r.ec == std::errc() && r.ptr == end) return value;
  *end = '\0';
  return std::strtod(begin, nullptr);
}

/// Writes `text` to `path` in one call; throws std::runtime_error naming the file on failure.
void writeWhole(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!f) throw std::runtime_error(path + ": write failed");
}

}  // namespace

namespace {

/// The RMSEs of n (u, v) errors from their sums of squares (NaN when n == 0).
PredictionErrors fromSquareSums(double su, double sv, int n) {
  PredictionErrors e;
  e.n = n;
  if (n == 0) {
    e.rmse_px = e.rmse_u_px = e.rmse_v_px = kNaN;
    return e;
  }
  e.rmse_u_px = std::sqrt(su / n);
  e.rmse_v_px = std::sqrt(sv / n);
  e.rmse_px = std::sqrt((su + sv) / n);
  return e;
}

/// Sums of squared (u, v) errors over the rows where the prediction and the reference are both
/// finite, added in row order: predictionErrors over a whole track, and ErrorSums block by block
/// (the same additions, so the same bits).
struct SquareSums {
  double su = 0.0, sv = 0.0;
  int n = 0;
  /// Adds rows [begin, end) of predictions (u, v) against references (ur, vr) at t + horizon.
  void add(const double* u, const double* v, const double* ur, const double* vr, size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      if (!std::isfinite(u[i]) || !std::isfinite(v[i])) continue;
      if (!std::isfinite(ur[i]) || !std::isfinite(vr[i])) continue;
      su += (u[i] - ur[i]) * (u[i] - ur[i]);
      sv += (v[i] - vr[i]) * (v[i] - vr[i]);
      ++n;
    }
  }
  /// Adds another's sums (a point's into a run's overall): pooled exactly, so one point's pool is
  /// that point's figures, bit for bit.
  void add(const SquareSums& other) {
    su += other.su;
    sv += other.sv;
    n += other.n;
  }
  PredictionErrors errors() const { return fromSquareSums(su, sv, n); }
};

}  // namespace

PredictionErrors predictionErrors(const std::vector<double>& t_s, const std::vector<double>& u_pred,
                                  const std::vector<double>& v_pred, double horizon_s,
                                  const std::vector<double>& u_ref, const std::vector<double>& v_ref) {
  SquareSums sums;
  sums.add(u_pred.data(), v_pred.data(), interpolateShifted(t_s, u_ref, horizon_s).data(),
           interpolateShifted(t_s, v_ref, horizon_s).data(), 0, u_pred.size());
  return sums.errors();
}

namespace {

/// Runs one channel of a predictor over `count` rows: out[i] is the position at t_s[i] + horizon of
/// a 1-channel instance after its update with z[i] (NaN: predict-only). The channels of a predictor
/// are independent (predictor.h), so this is channel c of the instance that runs every channel, bit
/// for bit (PredictorProperty.EachChannelIsThatOfAOneChannelPredictor,
/// tests/predictors/property_test.cpp). Called block after block of rows on the same instance.
/// The measurement is viewed in place in the track's column, which no thread writes. (A copy in a
/// 1-element VectorXd, allocated per block, was written on every row: the allocator could place it
/// on a cache line beside the state of a predictor that the other thread updates on every row, and
/// both threads' updates then ran up to five times slower; docs/PERFORMANCE.md, "Fifteenth pass".)
void runChannel(Predictor& predictor, const double* t_s, const double* z, double horizon_s, size_t count,
                double* out) {
  for (size_t i = 0; i < count; ++i) {
    predictor.update(t_s[i], Eigen::Map<const Eigen::VectorXd>(z + i, 1));
    out[i] = predictor.predictPosition(0, t_s[i] + horizon_s);
  }
}

/// Each predictor's cost per channel, to share the channels among the threads: its wall time on the
/// first kTrialRows rows of the first point's u, measured on a throw-away 1-channel instance; 1 for
/// every predictor on one thread or a short track. Only the speed depends on it, never the results.
std::vector<double> predictorCosts(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors,
                                   double horizon_s, size_t threads) {
  std::vector<double> cost(predictors.size(), 1.0);
  constexpr size_t kTrialRows = 2000;
  if (threads < 2 || predictors.size() < 2 || track.size() < 10 * kTrialRows) return cost;
  std::vector<double> trial(kTrialRows);
  for (size_t k = 0; k < predictors.size(); ++k) {
    auto predictor = makePredictor(predictors[k].name, 1, predictors[k].params);
    const auto t0 = std::chrono::steady_clock::now();
    try {
      runChannel(*predictor, track.t_s.data(), track.u_px[0].data(), horizon_s, kTrialRows, trial.data());
    } catch (...) {
      // The real run reports it.
    }
    cost[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return cost;
}

/// One block of rows of a streamed run (streamPredictions): every predictor's predictions and the
/// references at t + horizon for rows [i0, i1) of the track.
struct PredictionBlock {
  size_t index = 0;      ///< 0, 1, ... in row order
  size_t full_rows = 0;  ///< rows of every block but the last
  size_t i0 = 0, i1 = 0;
  size_t channels = 0;  ///< 2 per point: u, v
  size_t stride = 0;    ///< doubles from one column to the next
  const double* predictions = nullptr;  ///< column k * channels + c: predictor k's channel c
  const double* references = nullptr;   ///< column 4 p + r: point p's u, v measured, u, v true (r = 0..3)
  const double* prediction(size_t k, size_t c) const { return predictions + (k * channels + c) * stride; }
  const double* reference(size_t p, size_t r) const { return references + (4 * p + r) * stride; }
};

/// What a streamed run does with each block (streamPredictions): items(block) pieces of work, each
/// run once, on any thread, alongside the others and alongside the predictors on the next block.
/// Every item of a block ends before any item of the next one begins.
class BlockConsumer {
 public:
  virtual ~BlockConsumer() = default;
  virtual size_t items(const PredictionBlock& block) const = 0;
  virtual void run(const PredictionBlock& block, size_t item) = 0;
};

/// The threads' meeting point at the end of each round; the last to arrive runs `completion` before
/// any of them goes on (std::barrier's rule, which C++17 lacks).
class RoundBarrier {
 public:
  explicit RoundBarrier(size_t threads) : threads_(threads) {}
  template <class Completion>
  void arriveAndWait(Completion&& completion) {
    std::unique_lock<std::mutex> lock(mutex_);
    const size_t round = round_;
    if (++arrived_ == threads_) {
      completion();
      arrived_ = 0;
      ++round_;
      changed_.notify_all();
      return;
    }
    changed_.wait(lock, [&] { return round_ != round; });
  }

 private:
  size_t threads_;
  size_t arrived_ = 0, round_ = 0;
  std::mutex mutex_;
  std::condition_variable changed_;
};

/// Adds each of `from`'s counts to the count of the same name in `to` (appended when new).
void addTallies(NamedValues& to, const NamedValues& from) {
  for (const auto& kv : from) {
    auto it = std::find_if(to.begin(), to.end(), [&](const auto& t) { return t.first == kv.first; });
    if (it == to.end())
      to.push_back(kv);
    else
      it->second += kv.second;
  }
}

/// Runs every predictor along the track in blocks of `block_rows` rows and hands each block to the
/// consumers; nothing of a whole track's size is allocated (docs/PERFORMANCE.md, "Ninth pass").
///
/// The work items are the channels (u or v of a point) of the predictors, each a 1-channel instance
/// (runChannel). They are shared among `jobs` threads once, the costliest first to the least loaded
/// thread (with two channels per point and equal costs, every thread gets the same share), and
/// each thread builds its own instances, on its own heap, and keeps them to the end: no two threads
/// ever write to one predictor's state. Round r: each thread runs its channels over block r, then
/// takes, from a queue shared by all, the consumers' items of block r - 1 and the interpolation of
/// block r's references; then all wait for each other. The block buffers alternate between two
/// sets. So what is computed is the same, bit for bit, for any jobs and block_rows, and the same as
/// one pass over the whole track (interpolateShifted's range form; the consumers keep their sums in
/// row order).
///
/// Errors, as a serial run over the predictors would report them: a channel that throws stops, the
/// channels after it in (predictor, channel) order stop too, the ones before it run to the end, and
/// the first exception in that order is rethrown (the consumers get no more blocks once one has
/// thrown); else a consumer's first exception is rethrown after the round it happened in.
/// report.runs[k].tallies (one run per predictor, in order): Predictor::tallies() of predictor k
/// summed over its channels' instances.
void streamPredictions(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors, double horizon_s,
                       int jobs, size_t block_rows, const std::vector<BlockConsumer*>& consumers,
                       PredictionReport& report) {
  if (!(horizon_s >= 0.0) || !std::isfinite(horizon_s))
    throw std::invalid_argument("the prediction horizon must be a finite number >= 0 s");
  const size_t np = static_cast<size_t>(track.points()), nc = 2 * np, rows = track.size();
  for (const auto& spec : predictors) makePredictor(spec.name, 2 * track.points(), spec.params);  // throws as before
  const size_t channel_items = predictors.size() * nc;
  const size_t threads = std::max<size_t>(1, std::min(channel_items, static_cast<size_t>(std::max(jobs, 1))));
  // The channels per thread: longest processing time first, each to the least loaded thread.
  const std::vector<double> cost = predictorCosts(track, predictors, horizon_s, threads);
  std::vector<size_t> by_cost(channel_items);
  std::iota(by_cost.begin(), by_cost.end(), size_t{0});
  std::stable_sort(by_cost.begin(), by_cost.end(), [&](size_t a, size_t b) { return cost[a / nc] > cost[b / nc]; });
  std::vector<std::vector<size_t>> mine(threads);
  std::vector<double> load(threads, 0.0);
  for (size_t item : by_cost) {
    const size_t t = static_cast<size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    mine[t].push_back(item);
    load[t] += cost[item / nc];
  }
  // Two sets of block buffers (round r fills set r % 2 while the consumers read set (r - 1) % 2);
  // columns a few cache lines apart.
  block_rows = std::max<size_t>(1, std::min(block_rows, rows));
  const size_t stride = (block_rows + 7) / 8 * 8 + 8;
  const size_t blocks = (rows + block_rows - 1) / block_rows;
  std::vector<double> pred_buf(2 * channel_items * stride), ref_buf(2 * 4 * np * stride);
  auto blockAt = [&](size_t b) {
    PredictionBlock blk;
    blk.index = b;
    blk.full_rows = block_rows;
    blk.i0 = b * block_rows;
    blk.i1 = std::min(rows, blk.i0 + block_rows);
    blk.channels = nc;
    blk.stride = stride;
    blk.predictions = pred_buf.data() + (b % 2) * channel_items * stride;
    blk.references = ref_buf.data() + (b % 2) * 4 * np * stride;
    return blk;
  };
  const size_t refs_per_point = track.hasTruth() ? 4 : 2;
  auto interpolateReference = [&](const PredictionBlock& blk, size_t item) {
    const size_t p = item / refs_per_point, r = item % refs_per_point;
    const std::vector<double>& y = r == 0 ? track.u_px[p] : r == 1 ? track.v_px[p] : r == 2 ? track.u_true_px[p] : track.v_true_px[p];
    interpolateShifted(track.t_s, y, horizon_s, blk.i0, blk.i1, const_cast<double*>(blk.reference(p, r)));
  };
  std::vector<std::exception_ptr> channel_errors(channel_items);
  std::atomic<size_t> first_failed{channel_items};  // the first channel in order that threw
  std::exception_ptr consumer_error;
  std::mutex consumer_error_mutex;
  std::atomic<bool> consumer_failed{false};
  bool feed_consumers = true;  // decided for each round by the barrier's completion
  bool stop = false;
  std::vector<std::atomic<size_t>> next(blocks + 1);  // the shared queue's cursor, one per round
  for (auto& n : next) n.store(0);
  RoundBarrier barrier(threads);
  std::mutex tallies_mutex;
  auto channelFailed = [&](size_t item) {
    channel_errors[item] = std::current_exception();
    size_t seen = first_failed.load();
    while (item < seen && !first_failed.compare_exchange_weak(seen, item)) {
    }
  };
  auto worker = [&](size_t t) {
    // Every exception is caught and kept: a thread must reach the barrier of every round.
    std::vector<std::unique_ptr<Predictor>> instances;  // built here: on this thread's heap
    for (size_t item : mine[t]) {
      instances.emplace_back();
      try {
        instances.back() = makePredictor(predictors[item / nc].name, 1, predictors[item / nc].params);
      } catch (...) {
        channelFailed(item);
      }
    }
    for (size_t r = 0; r <= blocks; ++r) {
      if (r < blocks) {
        const PredictionBlock blk = blockAt(r);
        for (size_t j = 0; j < mine[t].size(); ++j) {
          const size_t item = mine[t][j];
          if (!instances[j] || item > first_failed.load()) continue;
          const size_t k = item / nc, c = item % nc;
          const std::vector<double>& z = c % 2 == 0 ? track.u_px[c / 2] : track.v_px[c / 2];
          try {
            runChannel(*instances[j], track.t_s.data() + blk.i0, z.data() + blk.i0, horizon_s, blk.i1 - blk.i0,
                       const_cast<double*>(blk.prediction(k, c)));
          } catch (...) {
            channelFailed(item);
            instances[j].reset();
          }
        }
      }
      // The shared queue: the consumers' items of block r - 1, then block r's references.
      std::vector<size_t> ends;
      PredictionBlock last;
      if (r >= 1 && feed_consumers) {
        last = blockAt(r - 1);
        for (BlockConsumer* consumer : consumers) ends.push_back((ends.empty() ? 0 : ends.back()) + consumer->items(last));
      }
      const size_t consumer_items = ends.empty() ? 0 : ends.back();
      const size_t ref_items = r < blocks ? np * refs_per_point : 0;
      for (size_t i = next[r].fetch_add(1); i < consumer_items + ref_items; i = next[r].fetch_add(1)) {
        if (i >= consumer_items) {
          interpolateReference(blockAt(r), i - consumer_items);
          continue;
        }
        const size_t which = static_cast<size_t>(std::upper_bound(ends.begin(), ends.end(), i) - ends.begin());
        try {
          consumers[which]->run(last, i - (which == 0 ? 0 : ends[which - 1]));
        } catch (...) {
          std::lock_guard<std::mutex> lock(consumer_error_mutex);
          if (!consumer_error) consumer_error = std::current_exception();
          consumer_failed = true;
        }
      }
      barrier.arriveAndWait([&] {
        feed_consumers = first_failed.load() == channel_items && !consumer_failed;
        stop = consumer_failed;
      });
      if (stop) break;
    }
    {  // each instance's counts into its predictor's sums (integers: any order, the same sums)
      std::lock_guard<std::mutex> lock(tallies_mutex);
      for (size_t j = 0; j < mine[t].size(); ++j)
        if (instances[j]) addTallies(report.runs[mine[t][j] / nc].tallies, instances[j]->tallies());
    }
  };
  for (PredictionRun& run : report.runs) run.tallies.clear();
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (auto& th : pool) th.join();
  for (const auto& e : channel_errors)
    if (e) std::rethrow_exception(e);
  if (consumer_error) std::rethrow_exception(consumer_error);
}

/// The errors of every predictor and point (a BlockConsumer): SquareSums kept in
/// row order over the blocks, so the figures are the same bits as one pass; rows before score_from
/// are not scored (--fit-split).
class ErrorSums : public BlockConsumer {
 public:
  ErrorSums(PredictionReport& report, bool truth, size_t score_from)
      : report_(report), truth_(truth), score_from_(score_from), sums_(report.runs.size() * pointsOf(report)) {}
  size_t items(const PredictionBlock&) const override { return report_.runs.size(); }
  void run(const PredictionBlock& blk, size_t k) override {
    const size_t np = blk.channels / 2;
    const size_t begin = std::max(blk.i0, std::min(score_from_, blk.i1)) - blk.i0, end = blk.i1 - blk.i0;
    for (size_t p = 0; p < np; ++p) {
      Sums& s = sums_[k * np + p];
      const double* u = blk.prediction(k, 2 * p);
      const double* v = blk.prediction(k, 2 * p + 1);
      s.meas.add(u, v, blk.reference(p, 0), blk.reference(p, 1), begin, end);
      if (truth_) s.truth.add(u, v, blk.reference(p, 2), blk.reference(p, 3), begin, end);
    }
  }
  /// Fills the report's errors (after the last block).
  void finish() {
    for (size_t k = 0; k < report_.runs.size(); ++k) {
      PredictionRun& run = report_.runs[k];
      SquareSums meas, truth;  // overall: every (frame, point) pair
      for (size_t p = 0; p < run.points.size(); ++p) {
        const Sums& s = sums_[k * run.points.size() + p];
        PointPrediction& pt = run.points[p];
        pt.vs_measurement = s.meas.errors();
        meas.add(s.meas);
        if (truth_) {
          pt.vs_truth = s.truth.errors();
          truth.add(s.truth);
        }
      }
      run.vs_measurement = meas.errors();
      if (truth_) run.vs_truth = truth.errors();
    }
  }

 private:
  struct alignas(64) Sums {  // a cache line of its own: items of different predictors run at once
    SquareSums meas, truth;
  };
  static size_t pointsOf(const PredictionReport& report) { return report.runs.empty() ? 0 : report.runs[0].points.size(); }
  PredictionReport& report_;
  bool truth_;
  size_t score_from_;
  std::vector<Sums> sums_;
};

/// The third panel of predictions.png (a BlockConsumer, one item per predictor): each predictor's
/// RMS error per equal time slice of the track, pooled over every point and both coordinates, against
/// the truth when the track has it and else against the measurement (the table's error, slice by
/// slice), over the rows the table scores. About kErrorSliceFrames frames per slice, at most
/// kMaxErrorSlices slices. Each predictor's sums are added in row order, so the panel is the same
/// for any jobs and block size.
class ErrorSlices : public BlockConsumer {
 public:
  ErrorSlices(const FeatureTrack& track, const PredictionReport& report, size_t score_from)
      : track_(track), truth_(track.hasTruth()), score_from_(score_from) {
    const size_t rows = track.size();
    slices_ = std::max<size_t>(1, std::min(kMaxErrorSlices, rows / kErrorSliceFrames));
    t0_ = track.t_s.front();
    span_ = track.t_s.back() - t0_;
    if (!(span_ > 0.0)) slices_ = 1;
    sums_.resize(report.runs.size());
    for (auto& s : sums_) s = std::make_unique<Sums>(slices_);
  }
  size_t items(const PredictionBlock&) const override { return sums_.size(); }
  void run(const PredictionBlock& blk, size_t k) override {
    const size_t np = blk.channels / 2, r0 = truth_ ? 2 : 0;
    const size_t begin = std::max(blk.i0, std::min(score_from_, blk.i1)) - blk.i0, end = blk.i1 - blk.i0;
    Sums& s = *sums_[k];
    for (size_t i = begin; i < end; ++i) {
      const size_t slice = sliceOf(track_.t_s[blk.i0 + i]);
      for (size_t p = 0; p < np; ++p) {
        const double du = blk.prediction(k, 2 * p)[i] - blk.reference(p, r0)[i];
        const double dv = blk.prediction(k, 2 * p + 1)[i] - blk.reference(p, r0 + 1)[i];
        if (!std::isfinite(du) || !std::isfinite(dv)) continue;
        s.sq[slice] += du * du + dv * dv;
        ++s.n[slice];
      }
    }
  }
  size_t slices() const { return slices_; }
  /// The time the forecasts of slice j are made for: the slice's middle plus the horizon.
  double targetTime(size_t j, double horizon_s) const {
    return t0_ + span_ * (static_cast<double>(j) + 0.5) / static_cast<double>(slices_) + horizon_s;
  }
  /// Predictor k's RMS error over slice j (NaN: no scored pair in it).
  double rms(size_t k, size_t j) const {
    const Sums& s = *sums_[k];
    return s.n[j] ? std::sqrt(s.sq[j] / static_cast<double>(s.n[j])) : kNaN;
  }
  /// The first row scored, when the track has a row there (else 0: every row).
  size_t scoredFrom() const { return score_from_ < track_.size() ? score_from_ : 0; }
  /// Rows per slice, and a slice's length (for the panel's title).
  double framesPerSlice() const { return static_cast<double>(track_.size()) / static_cast<double>(slices_); }
  double sliceSeconds() const { return span_ / static_cast<double>(slices_); }
  /// The time axis every panel shares: the first row's time to the last row's target time.
  double firstTime() const { return t0_; }
  double lastTime() const { return t0_ + span_; }

 private:
  static constexpr size_t kErrorSliceFrames = 8;
  static constexpr size_t kMaxErrorSlices = 200;
  struct alignas(64) Sums {  // on cache lines of its own: items of different predictors run at once
    explicit Sums(size_t slices) : sq(slices, 0.0), n(slices, 0) {}
    std::vector<double> sq;
    std::vector<size_t> n;
  };
  size_t sliceOf(double t) const {
    if (slices_ == 1) return 0;
    const double x = (t - t0_) / span_ * static_cast<double>(slices_);
    return x <= 0.0 ? 0 : std::min(slices_ - 1, static_cast<size_t>(x));
  }
  const FeatureTrack& track_;
  bool truth_;
  size_t score_from_;
  size_t slices_ = 1;
  double t0_ = 0.0, span_ = 0.0;
  std::vector<std::unique_ptr<Sums>> sums_;
};

/// The report's prediction columns, block after block (a BlockConsumer; predictTrack). Reserved on
/// the first block, in huge pages where the kernel offers them, and filled without zeroing first
/// (large_buffer.h).
class ColumnKeeper : public BlockConsumer {
 public:
  ColumnKeeper(PredictionReport& report, size_t rows) : report_(report), rows_(rows) {}
  size_t items(const PredictionBlock& blk) const override { return report_.runs.size() * blk.channels; }
  void run(const PredictionBlock& blk, size_t item) override {
    const size_t k = item / blk.channels, c = item % blk.channels;
    PointPrediction& pt = report_.runs[k].points[c / 2];
    std::vector<double>& column = c % 2 == 0 ? pt.u_pred_px : pt.v_pred_px;
    if (blk.index == 0) reserveLarge(column, rows_);
    const double* values = blk.prediction(k, c);
    column.insert(column.end(), values, values + (blk.i1 - blk.i0));
  }

 private:
  PredictionReport& report_;
  size_t rows_;
};

/// A report with every predictor's spec and a PointPrediction per point (columns and errors empty).
PredictionReport emptyReport(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors, double horizon_s) {
  PredictionReport report;
  report.horizon_s = horizon_s;
  report.runs.resize(predictors.size());
  for (size_t k = 0; k < predictors.size(); ++k) {
    report.runs[k].spec = predictors[k];
    report.runs[k].points.resize(static_cast<size_t>(track.points()));
  }
  return report;
}

}  // namespace

void requirePredictor(const std::string& option, const std::string& name) {
  if (isPredictor(name)) return;
  std::string known;
  for (const auto& p : predictorRegistry()) known += (known.empty() ? "" : ", ") + p.name;
  throw std::invalid_argument(option + ": unknown predictor '" + name + "' (known: " + known + ")");
}

void setGlitchSigmas(std::vector<PredictorSpec>& specs, double g) {
  if (!(g >= 0.0 && std::isfinite(g))) throw std::invalid_argument("--glitch-sigmas: expected a number of sigmas >= 0 (0 = no gate)");
  for (PredictorSpec& s : specs)
    s.params.setUnlessGiven("glitch_sigmas", g);
}

void setHorizonFrames(std::vector<PredictorSpec>& specs, double frames) {
  for (PredictorSpec& s : specs)
    s.params.setUnlessGiven("horizon_frames", frames);
}

std::vector<PredictorSpec> parsePredictorSpecs(const std::string& option, const std::vector<std::string>& items) {
  std::vector<PredictorSpec> specs;
  if (items.size() == 1 && items[0] == "all") {
    for (const auto& p : predictorRegistry()) specs.push_back({p.name, {}, {}});
    return specs;
  }
  if (items.empty()) throw std::invalid_argument(option + ": expected NAME, a comma list NAME,NAME,... or 'all'");
  for (const auto& item : items) {
    if (item == "all") throw std::invalid_argument(option + ": 'all' stands alone, not in a list");
    const PredictorChoice c = parsePredictorChoice(item, option);
    requirePredictor(option, c.type);  // a bare word: a registry name (no scenario labels here)
    PredictorSpec spec{c.type, c.params, c.labelled ? c.label : std::string()};
    for (const auto& s : specs)
      if (s.shownName() == spec.shownName())
        throw std::invalid_argument(option + ": '" + spec.shownName() +
                                    "' is listed twice (give each its own LABEL=TYPE[:KEY=VALUE...])");
    specs.push_back(std::move(spec));
  }
  return specs;
}

PredictionReport predictTrack(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors,
                              double horizon_s, int jobs, size_t block_rows) {
  PredictionReport report = emptyReport(track, predictors, horizon_s);
  ErrorSums errors(report, track.hasTruth(), 0);
  ColumnKeeper columns(report, track.size());
  streamPredictions(track, predictors, horizon_s, jobs, block_rows, {&columns, &errors}, report);
  errors.finish();
  return report;
}

namespace {

/// Rows of predictions.csv formatted per work item: about 640 kB of text for 11 predictors and one
/// point, which stays in a core's 1 MB L2 cache until write() copies it into the page cache (16384
/// rows, 5 MB, went to memory and back: 3.2-3.4 s of CPU for the 2 M-row track against 2.4-2.5 s).
constexpr size_t kCsvChunkRows = 2048;

/// A cell of predictions.csv at p: x as csvNumber(x, 10) writes it, nothing for a non-finite x.
/// Needs 32 bytes of room at p (writeGeneral).
inline char* csvCell(char* p, double x) { return std::isfinite(x) ? writeGeneral(p, x, 10) : p; }

/// The most bytes a row of predictions.csv can take (32 per number as writeGeneral asks, the
/// separators, the point name).
size_t csvRowBound(const FeatureTrack& track, const PredictionReport& report) {
  size_t name = 0;
  for (const auto& s : track.point_names) name = std::max(name, s.size());
  return (4 + 2 * report.runs.size()) * 33 + name + 2;
}

/// Writes frames [i0, i1) of predictions.csv (every point of each frame; the frames within `blk`)
/// at p (room for (i1 - i0) * points * csvRowBound bytes); returns the end.
char* writeCsvRows(char* p, const FeatureTrack& track, const PredictionReport& report, const PredictionBlock& blk,
                   size_t i0, size_t i1) {
  // Every column's start and the horizon read once here: the text's char stores may alias anything,
  // so in the loop each would be read again for every cell, from the track and the report, which
  // may lie beside what the other thread writes (docs/PERFORMANCE.md, "A lagging acceleration model
  // in the closed loop", item 8's run).
  const int n = track.points();
  const bool single = n == 1;
  const size_t points = static_cast<size_t>(n), runs = report.runs.size();
  const double horizon_s = report.horizon_s;
  const double* t = track.t_s.data();
  std::vector<const double*> measured(2 * points), predicted(2 * points * runs);
  for (size_t pp = 0; pp < points; ++pp) {
    measured[2 * pp] = track.u_px[pp].data();
    measured[2 * pp + 1] = track.v_px[pp].data();
    for (size_t r = 0; r < runs; ++r)
      for (size_t c = 0; c < 2; ++c) predicted[(pp * runs + r) * 2 + c] = blk.prediction(r, 2 * pp + c);
  }
  for (size_t i = i0; i < i1; ++i)
    for (size_t pp = 0; pp < points; ++pp) {
      p = csvCell(p, t[i]);
      *p++ = ',';
      if (!single) {
        const std::string& name = track.point_names[pp];
        std::memcpy(p, name.data(), name.size());
        p += name.size();
        *p++ = ',';
      }
      p = csvCell(p, measured[2 * pp][i]);
      *p++ = ',';
      p = csvCell(p, measured[2 * pp + 1][i]);
      *p++ = ',';
      p = csvCell(p, t[i] + horizon_s);
      const double* const* column = predicted.data() + pp * runs * 2;
      const size_t in_block = i - blk.i0;
      for (size_t r = 0; r < runs; ++r) {
        *p++ = ',';
        p = csvCell(p, column[2 * r][in_block]);
        *p++ = ',';
        p = csvCell(p, column[2 * r + 1][in_block]);
      }
      *p++ = '\n';
    }
  return p;
}

/// predictions.csv (csvCell's format, 10 significant digits), a BlockConsumer: its items are the
/// block's chunks of kCsvChunkRows frames, formatted on any thread and written in row order (the
/// thread that formatted chunk c waits until chunk c - 1 is written, writes its own and takes the
/// next item), so formatting and writing overlap and the file is the same for any jobs.
class CsvWriter : public BlockConsumer {
 public:
  CsvWriter(const std::string& path, const FeatureTrack& track, const PredictionReport& report)
      : track_(track), report_(report), file_(path) {
    std::string header = track.points() == 1 ? "t,u,v,t_target" : "t,point,u,v,t_target";
    for (const auto& run : report.runs)
      header += "," + run.spec.shownName() + ".u_pred," + run.spec.shownName() + ".v_pred";
    header += '\n';
    file_.write(header.data(), header.size());
    chunk_bytes_ = kCsvChunkRows * static_cast<size_t>(track.points()) * csvRowBound(track, report);
  }
  size_t items(const PredictionBlock& blk) const override { return chunks(blk.i1 - blk.i0); }
  void run(const PredictionBlock& blk, size_t item) override {
    const size_t turn = blk.index * chunks(blk.full_rows) + item;  // the chunk's place in the file
    std::unique_ptr<char[]> text;  // not initialised: only the part written is touched
    size_t size = 0;
    try {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!spare_.empty()) {
          text = std::move(spare_.back());
          spare_.pop_back();
        }
      }
      if (!text) text.reset(new char[chunk_bytes_]);
      const size_t i0 = blk.i0 + item * kCsvChunkRows;
      size = static_cast<size_t>(writeCsvRows(text.get(), track_, report_, blk, i0, std::min(blk.i1, i0 + kCsvChunkRows)) -
                                 text.get());
    } catch (...) {
      markFailed();
      throw;
    }
    {
      std::unique_lock<std::mutex> lock(mutex_);
      turn_changed_.wait(lock, [&] { return next_to_write_ == turn || failed_; });
      if (failed_) return;
    }
    // Written without the lock: only the thread whose turn it is touches the file (the turn passes
    // on below, under the lock, after the write), and the other threads meanwhile take a spare
    // buffer and format their next chunk instead of waiting for the write to end.
    try {
      file_.write(text.get(), size);
    } catch (...) {
      markFailed();
      throw;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    ++next_to_write_;
    // Text buffers handed from chunk to chunk (at most one per thread is in use): a fresh buffer
    // per chunk would be fresh pages from the kernel each time (a page fault and a zeroed page per
    // 4 kB of predictions.csv).
    spare_.push_back(std::move(text));
    turn_changed_.notify_all();
  }
  /// After the last block: writes the rest and closes the file; throws std::runtime_error naming
  /// it if a write failed.
  void finish() { file_.close(); }

 private:
  static size_t chunks(size_t rows) { return (rows + kCsvChunkRows - 1) / kCsvChunkRows; }
  /// A chunk failed (formatting or writing): the chunks after it must not wait for their turn.
  void markFailed() {
    std::lock_guard<std::mutex> lock(mutex_);
    failed_ = true;
    turn_changed_.notify_all();
  }
  const FeatureTrack& track_;
  const PredictionReport& report_;
  StreamingFile file_;  ///< past the page cache where the filesystem allows (streaming_file.h)
  size_t chunk_bytes_ = 0;
  std::mutex mutex_;
  std::condition_variable turn_changed_;
  size_t next_to_write_ = 0;
  bool failed_ = false;
  std::vector<std::unique_ptr<char[]>> spare_;
};

/// The table predictions.png is drawn from (a BlockConsumer, one item per block): the first point's
/// columns t_s u_px v_px t_target_s u_true_px v_true_px, then u_pred v_pred per predictor; every row
/// up to kMaxPlotRows rows, else their envelope of kPlotSlices time slices (EnvelopeBuilder, plots.h).
class alignas(kCacheLineBytes) PlotTable : public BlockConsumer {  // written on every row up to kMaxPlotRows: lines of its own
 public:
  PlotTable(const FeatureTrack& track, const PredictionReport& report)
      : track_(track), report_(report), width_(6 + 2 * report.runs.size()) {
    if (!envelope()) {
      rows_.reserve(track.size() * width_);
      return;
    }
    std::vector<bool> is_x(width_, false);
    is_x[0] = is_x[3] = true;  // t_s and t_target_s
    builder_ = std::make_unique<EnvelopeBuilder>(is_x, track.t_s.front(), track.t_s.back(), kPlotSlices);
  }
  bool envelope() const { return track_.size() > kMaxPlotRows; }
  size_t width() const { return width_; }
  size_t items(const PredictionBlock&) const override { return 1; }
  void run(const PredictionBlock& blk, size_t) override {
    const size_t runs = report_.runs.size(), n = blk.i1 - blk.i0;
    const bool truth = track_.hasTruth();
    const double* t = track_.t_s.data() + blk.i0;
    // The block's columns in the table's order (a null column is NaN in every row).
    std::vector<EnvelopeColumn> columns(width_);
    columns[0].values = t;
    columns[1].values = track_.u_px[0].data() + blk.i0;
    columns[2].values = track_.v_px[0].data() + blk.i0;
    columns[3] = EnvelopeColumn{t, true, true, report_.horizon_s};
    columns[4].values = truth ? track_.u_true_px[0].data() + blk.i0 : nullptr;
    columns[5].values = truth ? track_.v_true_px[0].data() + blk.i0 : nullptr;
    for (size_t k = 0; k < runs; ++k) {
      columns[6 + 2 * k].values = blk.prediction(k, 0);
      columns[7 + 2 * k].values = blk.prediction(k, 1);
    }
    if (builder_) {
      builder_->addBlock(t, n, columns.data());
      return;
    }
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < width_; ++c) rows_.push_back(columns[c].at(i));
  }
  /// The table, row-major, width() numbers per row (after the last block).
  const std::vector<double>& table() { return builder_ ? builder_->table() : rows_; }

 private:
  const FeatureTrack& track_;
  const PredictionReport& report_;
  size_t width_;
  std::vector<double> rows_;  // up to kMaxPlotRows rows (no envelope): its header is in this object's lines
  std::unique_ptr<EnvelopeBuilder> builder_;
};

}  // namespace

namespace {

/// summary.json (see writePredictionOutputs).
void writeSummaryJson(const FeatureTrack& track, const PredictionReport& report, const PredictionFiles& files,
                      const StagedOutputDir& dir) {
  const int delay_frames = files.delay_frames;
  const int n = track.points();
  nlohmann::json summary;
  summary["command"] = files.command_line;
  summary["input"] = track.path;
  summary["format"] = track.format;
  summary["points"] = track.point_names;
  summary["ignored_columns"] = track.ignored_columns;
  summary["rows"] = track.size();
  summary["horizon_s"] = report.horizon_s;
  summary["delay_frames"] = delay_frames >= 0 ? nlohmann::json(delay_frames) : nlohmann::json(nullptr);
  summary["frame_period_s"] = std::isfinite(files.frame_period_s) ? files.frame_period_s
                             : track.size() >= 2                  ? medianPeriod(track.t_s)
                                                                  : kNaN;
  summary["error_reference"] =
      "prediction made at t compared with the measurement (and truth) linearly interpolated at t + horizon_s; "
      "per point, and overall over every (frame, point) pair";
  summary["predictors"] = nlohmann::json::array();
  for (const auto& run : report.runs) {
    nlohmann::json p;
    p["name"] = run.spec.shownName();
    if (!run.spec.label.empty()) p["type"] = run.spec.name;  // a labelled entry: its registry name
    p["params"] = paramsJson(run.spec.params);  // numbers and words (model: ca)
    p["vs_measurement"] = errorsJson(run.vs_measurement);
    p["vs_truth"] = track.hasTruth() ? errorsJson(run.vs_truth) : nlohmann::json(nullptr);
    if (!run.tallies.empty()) p["tallies"] = namedValuesJson(run.tallies);
    p["per_point"] = nlohmann::json::array();
    for (int k = 0; k < n; ++k) {
      const PointPrediction& pt = run.points[static_cast<size_t>(k)];
      nlohmann::json q;
      q["point"] = track.point_names[static_cast<size_t>(k)];
      q["vs_measurement"] = errorsJson(pt.vs_measurement);
      q["vs_truth"] = track.hasTruth() ? errorsJson(pt.vs_truth) : nlohmann::json(nullptr);
      p["per_point"].push_back(q);
    }
    summary["predictors"].push_back(p);
  }
  {
    std::ofstream js(dir.file("summary.json"));
    js << summary.dump(2) << "\n";
    if (!js) throw std::runtime_error(dir.file("summary.json") + ": write failed");
  }
}

/// predictions_plot.dat, predictions_plot.bin and predictions.gp (see predictToFiles) from the
/// plot's table.
void writePlotFiles(const FeatureTrack& track, const PredictionReport& report, int delay_frames, PlotTable& plot,
                    const ErrorSlices& slices, const StagedOutputDir& dir) {
  const int n = track.points();
  const bool single = n == 1;
  // Plot data (the first point): measured points at their time, predictions at the time they are
  // made for; beyond kMaxPlotRows rows, the envelope of kPlotSlices time slices (PlotTable). The
  // text file is for the user; predictions.gp reads the same numbers from predictions_plot.bin (the
  // values of the text, as doubles), which gnuplot takes in once per series without parsing text.
  const bool envelope = plot.envelope();
  const size_t plot_columns = plot.width();
  {
    const std::vector<double>& table = plot.table();
    const size_t plot_rows = table.size() / plot_columns;
    std::string dat = "# t_s u_px v_px t_target_s u_true_px v_true_px";
    for (const auto& run : report.runs) dat += " " + run.spec.shownName() + ".u_pred " + run.spec.shownName() + ".v_pred";
    if (envelope)
      dat += "\n# " + std::to_string(track.size()) + " rows in " + std::to_string(kPlotSlices) +
             " equal time slices: per slice, t_s and t_target_s of its first and last row, every other column's"
             " min and max (the one reached first in the first row)";
    dat += '\n';
    dat.reserve(dat.size() + table.size() * 16);
    std::vector<double> bin;
    bin.reserve(table.size());
    for (size_t r = 0; r < plot_rows; ++r) {
      for (size_t c = 0; c < plot_columns; ++c) {
        if (c) dat += ' ';
        const double x = table[r * plot_columns + c];
        if (!std::isfinite(x)) {  // datNumber's format; the binary value is the text's
          dat += "NaN";
          bin.push_back(kNaN);
          continue;
        }
        char buf[40];
        char* end = writeGeneral(buf, x, 8);
        dat.append(buf, end);
        bin.push_back(textValue(buf, end));
      }
      dat += '\n';
    }
    writeWhole(dir.file("predictions_plot.dat"), dat);
    writeWhole(dir.file("predictions_plot.bin"),
               std::string(reinterpret_cast<const char*>(bin.data()), bin.size() * sizeof(double)));
  }
  // The error panel's data: per slice, the time its forecasts are made for, then each predictor's RMS
  // error (NaN where it scored nothing). A log axis takes only positive values: an exact forecast's 0
  // is drawn as missing, and the axis is linear when no value is positive.
  bool positive = false;
  {
    std::string dat = std::string("# t_target_s, then per predictor its RMS error [px] vs ") +
                      (track.hasTruth() ? "truth" : "measurement") + " over a time slice of the track (every point)\n# t_target_s";
    for (const auto& run : report.runs) dat += " " + run.spec.shownName();
    dat += '\n';
    for (size_t j = 0; j < slices.slices(); ++j) {
      dat += datNumber(slices.targetTime(j, report.horizon_s));
      for (size_t k = 0; k < report.runs.size(); ++k) {
        const double e = slices.rms(k, j);
        positive = positive || e > 0.0;
        dat += ' ' + datNumber(e);
      }
      dat += '\n';
    }
    writeWhole(dir.file("predictions_errors.dat"), dat);
  }
  std::ofstream gp(dir.file("predictions.gp"));
  std::ostringstream title;
  title << "Prediction " << std::setprecision(4) << report.horizon_s << " s ahead";
  if (delay_frames >= 0) title << " (" << delay_frames << " frames)";
  if (!single) title << ", point " << track.point_names[0] << " of " << n << " (all in predictions.csv)";
  if (envelope) title << ", " << track.size() << " rows drawn as the min and max of " << kPlotSlices << " time slices";
  // The binary data and how to read it: the same columns as predictions_plot.dat, doubles in the
  // machine's byte order. Drawing from the text instead gives the same PNG (same values).
  const std::string binary = "binary format='%" + std::to_string(plot_columns) + "float64'";
  gp << "# Regenerate with: gnuplot predictions.gp\n"
     << "# It reads predictions_plot.bin: the numbers of predictions_plot.dat (same rows and columns) as\n"
     << "# " << plot_columns << " doubles per row; to draw from the text file instead, set data = "
     << "'predictions_plot.dat' and fmt = ''.\n"
     << "data = 'predictions_plot.bin'\n"
     << "fmt = \"" << binary << "\"\n"
     << "set terminal pngcairo size 1200,1250 enhanced font 'Sans,10'\n"
     << "set output 'predictions.png'\n"
     << "set datafile missing 'NaN'\n"
     << "set multiplot layout 3,1 title "
     << gnuplotQuote(title.str() + ": each predictor's forecast is drawn at the time it is made for") << "\n"
     << "set grid\nset xlabel 'time t [s]'\n";
  // The same plot area in the three panels: fixed margins, the right one as wide as the longest key
  // entry ("measured" in the upper two) and its sample.
  size_t key_chars = std::string("measured").size();
  for (const auto& run : report.runs) key_chars = std::max(key_chars, run.spec.shownName().size());
  gp << "set lmargin 10\nset rmargin " << key_chars + 8 << "\n";
  // One time axis for the three panels (the forecasts reach the last row's time plus the horizon).
  if (slices.lastTime() + report.horizon_s > slices.firstTime())
    gp << "set xrange [" << datNumber(slices.firstTime()) << ":" << datNumber(slices.lastTime() + report.horizon_s) << "]\n";
  else
    gp << "set autoscale xfix\n";
  gp << "set key outside right top vertical Left reverse samplen 2\n";
  for (int axis = 0; axis < 2; ++axis) {
    const char* name = axis == 0 ? "u" : "v";
    gp << "set title " << gnuplotQuote(std::string("image coordinate ") + name + " (measured vs predicted)") << "\n"
       << "set ylabel '" << name << " [px]'\n"
       << "plot data @fmt using 1:" << (2 + axis);
    // The envelope keeps the measured points at each slice's extremes only; the points of every row,
    // hundreds per pixel column, ink the whole span between them: a black line as wide as a point
    // (5 px, pt 7 ps 0.5) under the points draws that band.
    if (envelope) gp << " with lines lw 5 lc rgb 'black' notitle, '' @fmt using 1:" << (2 + axis);
    gp << " with points pt 7 ps 0.5 lc rgb 'black' title 'measured'";
    for (size_t k = 0; k < report.runs.size(); ++k)
      gp << ", '' @fmt using 4:" << (7 + 2 * k + static_cast<size_t>(axis)) << " with lines lw 1.5 dt "
         << dashType(k / 6) << " lc rgb '" << seriesColor(k) << "' title " << gnuplotQuote(report.runs[k].spec.shownName());
    if (track.hasTruth())
      gp << ", '' @fmt using 1:" << (5 + axis) << " with lines dt 2 lw 2 lc rgb 'black' title 'true'";
    gp << "\n";
  }
  // The third panel: which predictor is better, and where (a turn, a gap), which the forecasts above,
  // a few pixels apart on a track hundreds of pixels long, do not show.
  std::ostringstream error_title;
  error_title << "RMS prediction error vs " << (track.hasTruth() ? "truth" : "measurement") << " per time slice of "
              << std::setprecision(2) << slices.sliceSeconds() << " s (" << std::llround(slices.framesPerSlice())
              << " frames), every point";
  if (slices.scoredFrom() > 0)
    error_title << ", the rows scored (from t = " << std::setprecision(4) << track.t_s[slices.scoredFrom()] << " s)";
  gp << "set title " << gnuplotQuote(error_title.str()) << "\n"
     << "set xlabel 'time the forecast is made for [s]'\n"
     << "set ylabel 'RMS error [px]" << (positive ? " (log scale)" : "") << "'\n"
     << (positive ? "set logscale y\n" : "") << "plot ";
  for (size_t k = 0; k < report.runs.size(); ++k)
    gp << (k ? ", " : "") << "'predictions_errors.dat' using 1:" << (2 + k) << " with lines lw 1.5 dt " << dashType(k / 6)
       << " lc rgb '" << seriesColor(k) << "' title " << gnuplotQuote(report.runs[k].spec.shownName());
  gp << "\nunset multiplot\n";
  gp.close();
}

}  // namespace

PredictionReport predictToFiles(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors,
                                double horizon_s, const PredictionFiles& files, StagedOutputDir& dir, int jobs) {
  PredictionReport report = emptyReport(track, predictors, horizon_s);
  ErrorSums errors(report, track.hasTruth(), files.score_from);
  CsvWriter csv(dir.file("predictions.csv"), track, report);
  std::unique_ptr<PlotTable> plot;
  std::unique_ptr<ErrorSlices> slices;
  std::vector<BlockConsumer*> consumers{&csv, &errors};
  if (files.plots && track.size() > 0) {
    plot = std::make_unique<PlotTable>(track, report);
    slices = std::make_unique<ErrorSlices>(track, report, files.score_from);
    consumers.push_back(plot.get());
    consumers.push_back(slices.get());
  }
  streamPredictions(track, predictors, horizon_s, jobs, files.block_rows, consumers, report);
  errors.finish();
  csv.finish();
  writeSummaryJson(track, report, files, dir);
  if (plot) {
    writePlotFiles(track, report, files.delay_frames, *plot, *slices, dir);
    runGnuplot(dir.staging().string(), "predictions.gp");
  }
  return report;
}

void printPredictionTable(const PredictionReport& report, const FeatureTrack& track, std::ostream& out) {
  const bool has_truth = track.hasTruth();
  size_t w = 9;
  for (const auto& run : report.runs) w = std::max(w, run.spec.shownName().size());
  out << std::left << std::setw(static_cast<int>(w)) << "predictor" << std::right << std::setw(20)
      << "RMSE vs meas [px]";
  if (has_truth) out << std::setw(20) << "RMSE vs truth [px]";
  // The n column fits the largest count with two spaces before it (7 wide up to 5 digits).
  size_t nw = 7;
  for (const auto& run : report.runs) nw = std::max(nw, std::to_string(run.vs_measurement.n).size() + 2);
  out << std::setw(static_cast<int>(nw)) << "n" << "\n";
  for (const auto& run : report.runs) {
    out << std::left << std::setw(static_cast<int>(w)) << run.spec.shownName() << std::right << std::setw(20)
        << fixedNumber(run.vs_measurement.rmse_px, 3);
    if (has_truth) out << std::setw(20) << fixedNumber(run.vs_truth.rmse_px, 3);
    out << std::setw(static_cast<int>(nw)) << run.vs_measurement.n << "\n";
  }
  if (track.points() < 2) return;
  // Per point: one column per point.
  for (int which = 0; which < (has_truth ? 2 : 1); ++which) {
    out << "\nRMSE vs " << (which == 0 ? "measurement" : "truth") << " per point [px]\n";
    size_t cw = 8;
    for (const auto& name : track.point_names) cw = std::max(cw, name.size() + 2);
    out << std::left << std::setw(static_cast<int>(w)) << "predictor" << std::right;
    for (const auto& name : track.point_names) out << std::setw(static_cast<int>(cw)) << name;
    out << "\n";
    for (const auto& run : report.runs) {
      out << std::left << std::setw(static_cast<int>(w)) << run.spec.shownName() << std::right;
      for (const auto& pt : run.points)
        out << std::setw(static_cast<int>(cw)) << fixedNumber(which == 0 ? pt.vs_measurement.rmse_px : pt.vs_truth.rmse_px, 3);
      out << "\n";
    }
  }
}

}  // namespace predvs
