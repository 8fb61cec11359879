// predvs bench — throughput of `predvs predict` (issue 11 item 8, docs/PERFORMANCE.md "predict
// throughput"): reading a track CSV (readFeatureTrack, on 1 and 2 threads) and running every registered predictor
// along it (predictTrack, on 1 and 2 threads; and each predictor alone, BM_PredictTrack/<name>),
// and the same streamed to predictions.csv + summary.json (predictToFiles without the plot, 1 and 2
// threads), so that the predictors' own share of a run is measured.
//
// The track: PREDVS_BENCH_TRACK=FILE if set (e.g. the 2-million-row `predvs make-track` file of
// docs/PERFORMANCE.md), else a generated one-point track of 200,000 rows at 30 Hz (t,u,v,u_true,
// v_true; a sine sweep with 1.5 px noise, 10 significant digits as the reports write), written once
// to the temp directory. Items per second = rows per second.
#include "output_dir.h"
#include "predict_command.h"
#include "track_csv.h"

#include "predvs/predictors/predictor.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace {

const std::string& benchTrackPath() {
  static const std::string path = [] {
    if (const char* env = std::getenv("PREDVS_BENCH_TRACK")) return std::string(env);
    const std::string p = (std::filesystem::temp_directory_path() / "predvs_bench_track_200k.csv").string();
    std::ofstream f(p);
    f << "t,u,v,u_true,v_true\n";
    std::mt19937_64 rng(1);
    std::normal_distribution<double> noise(0.0, 1.5);
    char line[160];
    for (int i = 0; i < 200000; ++i) {
      const double t = i / 30.0;
      const double u = 320.0 + 100.0 * std::sin(0.7 * t), v = 240.0 + 80.0 * std::cos(0.45 * t);
      std::snprintf(line, sizeof line, "%.10g,%.10g,%.10g,%.10g,%.10g\n", t, u + noise(rng), v + noise(rng), u, v);
      f << line;
    }
    return p;
  }();
  return path;
}

/// readFeatureTrack on state.range(0) threads (`--jobs`; real time for 2).
void BM_ReadFeatureTrack(benchmark::State& state) {
  size_t rows = 0;
  for (auto _ : state) {
    const predvs::FeatureTrack track = predvs::readFeatureTrack(benchTrackPath(), static_cast<int>(state.range(0)));
    rows = track.size();
    benchmark::DoNotOptimize(track.t_s.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * rows));
}
BENCHMARK(BM_ReadFeatureTrack)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadFeatureTrack)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

const predvs::FeatureTrack& benchTrack() {
  static const predvs::FeatureTrack track = predvs::readFeatureTrack(benchTrackPath());
  return track;
}

std::vector<predvs::PredictorSpec> allPredictors() {
  std::vector<predvs::PredictorSpec> specs;
  for (const auto& p : predvs::predictorRegistry()) specs.push_back({p.name, {}});
  return specs;
}

/// Every registered predictor along the track on state.range(0) threads (`--jobs`). Real time is
/// reported for the threaded runs (CPU time would count the calling thread only).
void BM_PredictTrackAll(benchmark::State& state) {
  const predvs::FeatureTrack& track = benchTrack();
  const auto specs = allPredictors();
  const double horizon_s = 2 * predvs::medianPeriod(track.t_s);
  for (auto _ : state) {
    const predvs::PredictionReport report = predvs::predictTrack(track, specs, horizon_s, static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(report.runs.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * track.size()));
}
BENCHMARK(BM_PredictTrackAll)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PredictTrackAll)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

/// One predictor along the track on one thread (predictTrack with that predictor only): each
/// predictor's own share of BM_PredictTrackAll/1. Registered for every predictor of the registry
/// as BM_PredictTrack/<name>.
void predictTrackOne(benchmark::State& state, const std::string& name) {
  const predvs::FeatureTrack& track = benchTrack();
  const std::vector<predvs::PredictorSpec> specs{{name, {}}};
  const double horizon_s = 2 * predvs::medianPeriod(track.t_s);
  for (auto _ : state) {
    const predvs::PredictionReport report = predvs::predictTrack(track, specs, horizon_s, 1);
    benchmark::DoNotOptimize(report.runs.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * track.size()));
}
const bool kPredictTrackOneRegistered = [] {
  for (const auto& p : predvs::predictorRegistry())
    benchmark::RegisterBenchmark(("BM_PredictTrack/" + p.name).c_str(), predictTrackOne, p.name)
        ->Unit(benchmark::kMillisecond);
  return true;
}();

/// `predvs predict --no-plots` without the reading: every predictor along the track, streamed to
/// predictions.csv and summary.json in a temporary directory (predictToFiles), on state.range(0)
/// threads. Its excess over BM_PredictTrackAll is the formatting and writing.
void BM_PredictToFiles(benchmark::State& state) {
  const predvs::FeatureTrack& track = benchTrack();
  const auto out = std::filesystem::temp_directory_path() / "predvs_bench_predictions";
  predvs::PredictionFiles files;
  files.plots = false;
  files.delay_frames = 2;
  for (auto _ : state) {
    predvs::StagedOutputDir dir(out);
    predvs::predictToFiles(track, allPredictors(), 2 * predvs::medianPeriod(track.t_s), files, dir,
                           static_cast<int>(state.range(0)));
    dir.commit();
  }
  std::filesystem::remove_all(out);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * track.size()));
}
BENCHMARK(BM_PredictToFiles)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PredictToFiles)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
