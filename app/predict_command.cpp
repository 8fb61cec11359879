#include "predict_command.h"

#include "predictor_choice.h"
#include "number_text.h"

#include "general_number.h"
#include "gnuplot.h"
#include "large_buffer.h"
#include "output_dir.h"
#include "parallel_for.h"
#include "plots.h"

#include "predvs/predictors/predictor.h"

#include <nlohmann/json.hpp>

#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <future>
#include <algorithm>
#include <iomanip>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <sstream>
#include <stdexcept>

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

/// predictionErrors against references already interpolated at t + horizon (interpolateShifted).
PredictionErrors errorsAgainst(const std::vector<double>& u_pred, const std::vector<double>& v_pred,
                               const std::vector<double>& u_ref_at, const std::vector<double>& v_ref_at) {
  double su = 0.0, sv = 0.0;
  int n = 0;
  for (size_t i = 0; i < u_pred.size(); ++i) {
    if (!std::isfinite(u_pred[i]) || !std::isfinite(v_pred[i])) continue;
    const double ur = u_ref_at[i], vr = v_ref_at[i];
    if (!std::isfinite(ur) || !std::isfinite(vr)) continue;
    su += (u_pred[i] - ur) * (u_pred[i] - ur);
    sv += (v_pred[i] - vr) * (v_pred[i] - vr);
    ++n;
  }
  return fromSquareSums(su, sv, n);
}

}  // namespace

PredictionErrors predictionErrors(const std::vector<double>& t_s, const std::vector<double>& u_pred,
                                  const std::vector<double>& v_pred, double horizon_s,
                                  const std::vector<double>& u_ref, const std::vector<double>& v_ref) {
  return errorsAgainst(u_pred, v_pred, interpolateShifted(t_s, u_ref, horizon_s), interpolateShifted(t_s, v_ref, horizon_s));
}

PredictionErrors pooledErrors(const std::vector<PredictionErrors>& parts) {
  double su = 0.0, sv = 0.0;
  int n = 0;
  for (const auto& p : parts) {
    if (p.n == 0) continue;
    su += p.rmse_u_px * p.rmse_u_px * p.n;
    sv += p.rmse_v_px * p.rmse_v_px * p.n;
    n += p.n;
  }
  return fromSquareSums(su, sv, n);
}

namespace {

/// Runs one channel of a predictor along the track: appends to `out` (empty) the position at
/// t_i + horizon of a 1-channel instance after its update with z[i] (NaN: predict-only), for rows
/// i in [0, rows). The channels of a predictor are independent (predictor.h), so this is channel c
/// of the instance that runs every channel, bit for bit
/// (PredictorProperty.EachChannelIsThatOfAOneChannelPredictor, tests/predictors/property_test.cpp).
void runChannel(Predictor& predictor, const std::vector<double>& t_s, const std::vector<double>& z, double horizon_s,
                size_t rows, std::vector<double>& out) {
  Eigen::VectorXd zi(1);
  for (size_t i = 0; i < rows; ++i) {
    zi(0) = z[i];
    predictor.update(t_s[i], zi);
    out.push_back(predictor.predictPosition(0, t_s[i] + horizon_s));
  }
}

/// The order in which the threads take the predictors: longest first (their wall time on the first
/// kTrialRows rows of the first point's u, measured on a throw-away 1-channel instance), so that the
/// last ones to finish are short. Only the speed depends on it, never the results. Registry order
/// for one thread.
std::vector<size_t> longestFirst(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors,
                                 double horizon_s, int jobs) {
  std::vector<size_t> order(predictors.size());
  std::iota(order.begin(), order.end(), size_t{0});
  constexpr size_t kTrialRows = 2000;
  if (jobs < 2 || predictors.size() < 2 || track.size() < 10 * kTrialRows) return order;
  std::vector<double> cost(predictors.size());
  for (size_t k = 0; k < predictors.size(); ++k) {
    std::vector<double> trial;
    trial.reserve(kTrialRows);
    auto predictor = makePredictor(predictors[k].name, 1, predictors[k].params);
    const auto t0 = std::chrono::steady_clock::now();
    try {
      runChannel(*predictor, track.t_s, track.u_px[0], horizon_s, kTrialRows, trial);
    } catch (...) {
      // The real run reports it.
    }
    cost[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return cost[a] > cost[b]; });
  return order;
}

}  // namespace

void requirePredictor(const std::string& option, const std::string& name) {
  if (isPredictor(name)) return;
  std::string known;
  for (const auto& p : predictorRegistry()) known += (known.empty() ? "" : ", ") + p.name;
  throw std::invalid_argument(option + ": unknown predictor '" + name + "' (known: " + known + ")");
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
                              double horizon_s, int jobs) {
  if (!(horizon_s >= 0.0) || !std::isfinite(horizon_s))
    throw std::invalid_argument("the prediction horizon must be a finite number >= 0 s");
  PredictionReport report;
  report.horizon_s = horizon_s;
  const int n = track.points();
  const size_t np = static_cast<size_t>(n);
  // Every predictor built first, in order (an unknown name or parameter throws as before).
  report.runs.resize(predictors.size());
  for (size_t k = 0; k < predictors.size(); ++k) {
    makePredictor(predictors[k].name, 2 * n, predictors[k].params);
    PredictionRun& run = report.runs[k];
    run.spec = predictors[k];
    run.points.resize(np);  // their vectors are filled, and moved in, by the pool's items
  }
  // The references at t + horizon, per point: measured and (if any) true. Items of the same pool
  // as the predictors, after them: short ones that fill the gaps at the end.
  std::vector<std::vector<double>> u_meas_at(np), v_meas_at(np), u_true_at(np), v_true_at(np);
  std::vector<std::pair<const std::vector<double>*, std::vector<double>*>> references;
  for (size_t p = 0; p < np; ++p) {
    references.emplace_back(&track.u_px[p], &u_meas_at[p]);
    references.emplace_back(&track.v_px[p], &v_meas_at[p]);
    if (!track.hasTruth()) continue;
    references.emplace_back(&track.u_true_px[p], &u_true_at[p]);
    references.emplace_back(&track.v_true_px[p], &v_true_at[p]);
  }
  const std::vector<size_t> order = longestFirst(track, predictors, horizon_s, jobs);
  // One work item per predictor and channel (u and v of every point), longest predictor first:
  // items of a channel's work balance the threads to within one such item (the gain on the
  // 2-million-row track was about 1 %, docs/PERFORMANCE.md "Seventh pass"). Each item owns its
  // output column; an exception is kept per item and the first in registry order (then channel
  // order) is rethrown, as the serial loop would have.
  const size_t nc = 2 * np;
  const size_t channel_items = order.size() * nc;
  std::vector<std::exception_ptr> errors(predictors.size() * nc);
  parallelFor(channel_items + references.size(), jobs, [&](size_t item) {
    if (item >= channel_items) {
      const auto& ref = references[item - channel_items];
      *ref.second = interpolateShifted(track.t_s, *ref.first, horizon_s);  // once per point, for every predictor
      return;
    }
    const size_t k = order[item / nc];
    const size_t c = item % nc;
    try {
      PointPrediction& pt = report.runs[k].points[c / 2];
      // Reserved here, on the thread that fills it, in huge pages where the kernel offers them, and
      // filled without zeroing first (large_buffer.h). Filled as a local vector and moved into the
      // report at the end: the u and v columns' vector objects can share a cache line, and the
      // items of a predictor's u and v run at the same time on two threads; a push_back into the
      // report's vectors wrote that line on every frame from both threads (false sharing: 2 s more
      // CPU on the 2-million-row track, docs/PERFORMANCE.md "Seventh pass").
      std::vector<double> out;
      reserveLarge(out, track.size());
      // The instance that runs is built here, on the thread that runs it: built in a row on the
      // calling thread, the predictors' states were neighbours on its heap, and two predictors
      // running at once on the two threads could share cache lines (false sharing: about half of
      // the runs on the 2-million-row track took 1 s more CPU, docs/PERFORMANCE.md). The instances
      // built above only check the names and parameters.
      const std::unique_ptr<Predictor> predictor = makePredictor(predictors[k].name, 1, predictors[k].params);
      runChannel(*predictor, track.t_s, c % 2 == 0 ? track.u_px[c / 2] : track.v_px[c / 2], horizon_s, track.size(),
                 out);
      (c % 2 == 0 ? pt.u_pred_px : pt.v_pred_px) = std::move(out);
    } catch (...) {
      errors[k * nc + c] = std::current_exception();
    }
  });
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  parallelFor(report.runs.size(), jobs, [&](size_t k) {
    PredictionRun& run = report.runs[k];
    std::vector<PredictionErrors> meas, truth;
    for (size_t p = 0; p < np; ++p) {
      PointPrediction& pt = run.points[p];
      pt.vs_measurement = errorsAgainst(pt.u_pred_px, pt.v_pred_px, u_meas_at[p], v_meas_at[p]);
      meas.push_back(pt.vs_measurement);
      if (track.hasTruth()) {
        pt.vs_truth = errorsAgainst(pt.u_pred_px, pt.v_pred_px, u_true_at[p], v_true_at[p]);
        truth.push_back(pt.vs_truth);
      }
    }
    run.vs_measurement = pooledErrors(meas);
    if (track.hasTruth()) run.vs_truth = pooledErrors(truth);
  });
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

/// Writes rows [i0, i1) of predictions.csv (every point of each frame) at p (room for
/// (i1 - i0) * points * csvRowBound bytes); returns the end.
char* writeCsvRows(char* p, const FeatureTrack& track, const PredictionReport& report, size_t i0, size_t i1) {
  const int n = track.points();
  const bool single = n == 1;
  for (size_t i = i0; i < i1; ++i)
    for (int k = 0; k < n; ++k) {
      const size_t pp = static_cast<size_t>(k);
      p = csvCell(p, track.t_s[i]);
      *p++ = ',';
      if (!single) {
        const std::string& name = track.point_names[pp];
        std::memcpy(p, name.data(), name.size());
        p += name.size();
        *p++ = ',';
      }
      p = csvCell(p, track.u_px[pp][i]);
      *p++ = ',';
      p = csvCell(p, track.v_px[pp][i]);
      *p++ = ',';
      p = csvCell(p, track.t_s[i] + report.horizon_s);
      for (const auto& run : report.runs) {
        *p++ = ',';
        p = csvCell(p, run.points[pp].u_pred_px[i]);
        *p++ = ',';
        p = csvCell(p, run.points[pp].v_pred_px[i]);
      }
      *p++ = '\n';
    }
  return p;
}

/// predictions.csv (csvCell's format, 10 significant digits). Chunks of kCsvChunkRows rows are
/// formatted on `jobs` threads and written in row order: the thread that formatted chunk c waits
/// until chunk c - 1 is written, writes its own, and takes the next one, so formatting and writing
/// overlap and the file is the same for any jobs.
void writePredictionsCsv(const std::string& path, const FeatureTrack& track, const PredictionReport& report,
                         int jobs) {
  const bool single = track.points() == 1;
  std::ofstream file(path, std::ios::binary);
  std::string header = single ? "t,u,v,t_target" : "t,point,u,v,t_target";
  for (const auto& run : report.runs) header += "," + run.spec.shownName() + ".u_pred," + run.spec.shownName() + ".v_pred";
  header += '\n';
  file.write(header.data(), static_cast<std::streamsize>(header.size()));
  const size_t chunks = (track.size() + kCsvChunkRows - 1) / kCsvChunkRows;
  std::mutex turn_mutex;
  std::condition_variable turn_changed;
  size_t next_to_write = 0;
  bool failed = false;
  const size_t chunk_bytes = kCsvChunkRows * static_cast<size_t>(track.points()) * csvRowBound(track, report);
  // Text buffers handed from chunk to chunk (at most one per thread is in use): a fresh buffer
  // per chunk would be fresh pages from the kernel each time (a page fault and a zeroed
  // page per 4 kB of predictions.csv).
  std::vector<std::unique_ptr<char[]>> spare;
  parallelFor(chunks, jobs, [&](size_t c) {
    std::unique_ptr<char[]> text;  // not initialised: only the part written is touched
    size_t size = 0;
    try {
      {
        std::lock_guard<std::mutex> lock(turn_mutex);
        if (!spare.empty()) {
          text = std::move(spare.back());
          spare.pop_back();
        }
      }
      if (!text) text.reset(new char[chunk_bytes]);
      size = static_cast<size_t>(writeCsvRows(text.get(), track, report, c * kCsvChunkRows,
                                              std::min(track.size(), (c + 1) * kCsvChunkRows)) -
                                 text.get());
    } catch (...) {
      std::lock_guard<std::mutex> lock(turn_mutex);
      failed = true;  // the chunks after this one must not wait for it
      turn_changed.notify_all();
      throw;
    }
    {
      std::unique_lock<std::mutex> lock(turn_mutex);
      turn_changed.wait(lock, [&] { return next_to_write == c || failed; });
      if (failed) return;
    }
    // Written without the lock: only the thread whose turn it is touches the file (the turn passes
    // on below, under the lock, after the write), and the other threads meanwhile take a spare
    // buffer and format their next chunk instead of waiting for the kernel's copy to end.
    file.write(text.get(), static_cast<std::streamsize>(size));
    std::lock_guard<std::mutex> lock(turn_mutex);
    ++next_to_write;
    spare.push_back(std::move(text));
    turn_changed.notify_all();
  });
  file.flush();
  if (!file) throw std::runtime_error(path + ": write failed");
}

}  // namespace

namespace {

/// summary.json (see writePredictionOutputs).
void writeSummaryJson(const FeatureTrack& track, const PredictionReport& report, int delay_frames,
                      const std::string& command_line, const StagedOutputDir& dir) {
  const int n = track.points();
  nlohmann::json summary;
  summary["command"] = command_line;
  summary["input"] = track.path;
  summary["format"] = track.format;
  summary["points"] = track.point_names;
  summary["ignored_columns"] = track.ignored_columns;
  summary["rows"] = track.size();
  summary["horizon_s"] = report.horizon_s;
  summary["delay_frames"] = delay_frames >= 0 ? nlohmann::json(delay_frames) : nlohmann::json(nullptr);
  summary["frame_period_s"] = track.size() >= 2 ? medianPeriod(track.t_s) : kNaN;
  summary["error_reference"] =
      "prediction made at t compared with the measurement (and truth) linearly interpolated at t + horizon_s; "
      "per point, and overall over every (frame, point) pair";
  summary["predictors"] = nlohmann::json::array();
  for (const auto& run : report.runs) {
    nlohmann::json p;
    p["name"] = run.spec.shownName();
    if (!run.spec.label.empty()) p["type"] = run.spec.name;  // a labelled entry: its registry name
    p["params"] = nlohmann::json::object();
    for (const auto& kv : run.spec.params.values()) p["params"][kv.first] = kv.second;
    p["vs_measurement"] = errorsJson(run.vs_measurement);
    p["vs_truth"] = track.hasTruth() ? errorsJson(run.vs_truth) : nlohmann::json(nullptr);
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

/// predictions_plot.dat, predictions_plot.bin and predictions.gp (see writePredictionOutputs).
void writePlotFiles(const FeatureTrack& track, const PredictionReport& report, int delay_frames,
                    const StagedOutputDir& dir) {
  const int n = track.points();
  const bool single = n == 1;
  // Plot data (the first point): measured points at their time, predictions at the time they are
  // made for; beyond kMaxPlotRows rows, the envelope of kPlotSlices time slices (plotEnvelope(),
  // plots.h: per slice the first and last time, every other column's min and max). The text file
  // is for the user; predictions.gp reads the same numbers from predictions_plot.bin (the values of
  // the text, as doubles), which gnuplot takes in once per series without parsing text.
  const bool envelope = track.size() > kMaxPlotRows;
  const size_t plot_columns = 6 + 2 * report.runs.size();
  size_t plot_rows = track.size();
  {
    std::string dat = "# t_s u_px v_px t_target_s u_true_px v_true_px";
    for (const auto& run : report.runs) dat += " " + run.spec.shownName() + ".u_pred " + run.spec.shownName() + ".v_pred";
    std::vector<double> bin;
    auto num = [&](double x) {  // datNumber's format; the binary value is the text's
      if (!std::isfinite(x)) {
        dat += "NaN";
        bin.push_back(kNaN);
        return;
      }
      char buf[40];
      char* end = writeGeneral(buf, x, 8);
      dat.append(buf, end);
      bin.push_back(textValue(buf, end));
    };
    if (envelope) {
      std::vector<double> t_target(track.size()), none;
      for (size_t i = 0; i < track.size(); ++i) t_target[i] = track.t_s[i] + report.horizon_s;
      if (!track.hasTruth()) none.assign(track.size(), kNaN);
      std::vector<EnvelopeColumn> columns{{track.t_s.data(), true},
                                          {track.u_px[0].data(), false},
                                          {track.v_px[0].data(), false},
                                          {t_target.data(), true},
                                          {track.hasTruth() ? track.u_true_px[0].data() : none.data(), false},
                                          {track.hasTruth() ? track.v_true_px[0].data() : none.data(), false}};
      for (const auto& run : report.runs) {
        columns.push_back({run.points[0].u_pred_px.data(), false});
        columns.push_back({run.points[0].v_pred_px.data(), false});
      }
      const std::vector<double> table = plotEnvelope(track.t_s, columns, kPlotSlices);
      plot_rows = table.size() / plot_columns;
      dat += "\n# " + std::to_string(track.size()) + " rows in " + std::to_string(kPlotSlices) +
             " equal time slices: per slice, t_s and t_target_s of its first and last row, every other column's"
             " min and max (the one reached first in the first row)";
      dat += '\n';
      dat.reserve(dat.size() + table.size() * 16);
      bin.reserve(table.size());
      for (size_t r = 0; r < plot_rows; ++r) {
        for (size_t c = 0; c < plot_columns; ++c) {
          if (c) dat += ' ';
          num(table[r * plot_columns + c]);
        }
        dat += '\n';
      }
    } else {
      dat += '\n';
      bin.reserve(track.size() * plot_columns);
      for (size_t i = 0; i < track.size(); ++i) {
        num(track.t_s[i]);
        dat += ' ';
        num(track.u_px[0][i]);
        dat += ' ';
        num(track.v_px[0][i]);
        dat += ' ';
        num(track.t_s[i] + report.horizon_s);
        dat += ' ';
        num(track.hasTruth() ? track.u_true_px[0][i] : kNaN);
        dat += ' ';
        num(track.hasTruth() ? track.v_true_px[0][i] : kNaN);
        for (const auto& run : report.runs) {
          dat += ' ';
          num(run.points[0].u_pred_px[i]);
          dat += ' ';
          num(run.points[0].v_pred_px[i]);
        }
        dat += '\n';
      }
    }
    writeWhole(dir.file("predictions_plot.dat"), dat);
    writeWhole(dir.file("predictions_plot.bin"),
               std::string(reinterpret_cast<const char*>(bin.data()), bin.size() * sizeof(double)));
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
     << "set terminal pngcairo size 1200,850 enhanced font 'Sans,10'\n"
     << "set output 'predictions.png'\n"
     << "set datafile missing 'NaN'\n"
     << "set multiplot layout 2,1 title "
     << gnuplotQuote(title.str() + ": each predictor's forecast is drawn at the time it is made for") << "\n"
     << "set grid\nset autoscale xfix\nset xlabel 'time t [s]'\n"
     << "set key outside right top vertical Left reverse samplen 2\n";
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
      gp << ", '' @fmt using 4:" << (7 + 2 * k + static_cast<size_t>(axis)) << " with lines lw 1.5 lc rgb '"
         << seriesColor(k) << "' title " << gnuplotQuote(report.runs[k].spec.shownName());
    if (track.hasTruth())
      gp << ", '' @fmt using 1:" << (5 + axis) << " with lines dt 2 lw 2 lc rgb 'black' title 'true'";
    gp << "\n";
  }
  gp << "unset multiplot\n";
  gp.close();
}

}  // namespace

void writePredictionOutputs(const FeatureTrack& track, const PredictionReport& report, int delay_frames,
                            const std::string& command_line, bool plots, StagedOutputDir& dir, int jobs) {
  if (jobs < 2) {
    writeSummaryJson(track, report, delay_frames, command_line, dir);
    if (plots) writePlotFiles(track, report, delay_frames, dir);
    writePredictionsCsv(dir.file("predictions.csv"), track, report, jobs);
    if (plots) runGnuplot(dir.staging().string(), "predictions.gp");
    return;
  }
  // With threads to spare, everything but predictions.csv (summary.json, the plot's data and script,
  // gnuplot drawing predictions.png: another process, one core) is one task on its own thread while
  // the pool formats and writes predictions.csv; its error, if any, is reported after the CSV's.
  std::future<void> side = std::async(std::launch::async, [&] {
    writeSummaryJson(track, report, delay_frames, command_line, dir);
    if (!plots) return;
    writePlotFiles(track, report, delay_frames, dir);
    runGnuplot(dir.staging().string(), "predictions.gp");
  });
  writePredictionsCsv(dir.file("predictions.csv"), track, report, jobs);  // on throwing, ~future waits
  side.get();
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
