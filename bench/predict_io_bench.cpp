// predvs bench — throughput of `predvs predict` (issue 11 item 8, docs/PERFORMANCE.md "predict
// throughput"): reading a track CSV (readFeatureTrack) and running every registered predictor
// along it (predictTrack), separately, so that the predictors' own share of a run is measured.
//
// The track: PREDVS_BENCH_TRACK=FILE if set (e.g. the 2-million-row `predvs make-track` file of
// docs/PERFORMANCE.md), else a generated one-point track of 200,000 rows at 30 Hz (t,u,v,u_true,
// v_true; a sine sweep with 1.5 px noise, 10 significant digits as the reports write), written once
// to the temp directory. Items per second = rows per second.
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

void BM_ReadFeatureTrack(benchmark::State& state) {
  size_t rows = 0;
  for (auto _ : state) {
    const predvs::FeatureTrack track = predvs::readFeatureTrack(benchTrackPath());
    rows = track.size();
    benchmark::DoNotOptimize(track.t_s.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * rows));
}
BENCHMARK(BM_ReadFeatureTrack)->Unit(benchmark::kMillisecond);

void BM_PredictTrackAll(benchmark::State& state) {
  const predvs::FeatureTrack track = predvs::readFeatureTrack(benchTrackPath());
  std::vector<predvs::PredictorSpec> specs;
  for (const auto& p : predvs::predictorRegistry()) specs.push_back({p.name, {}});
  const double horizon_s = 2 * predvs::medianPeriod(track.t_s);
  for (auto _ : state) {
    const predvs::PredictionReport report = predvs::predictTrack(track, specs, horizon_s);
    benchmark::DoNotOptimize(report.runs.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * track.size()));
}
BENCHMARK(BM_PredictTrackAll)->Unit(benchmark::kMillisecond);

}  // namespace
