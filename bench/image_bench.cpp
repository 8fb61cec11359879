// The image path of `predvs track` on ViSP's mire-2 (501 frames, 384x288 grey, five dots):
//   BM_ImageRead_Mire2           reading one frame from disk (ImageSequence on the printf pattern:
//                                 the PGM file read and decoded by vpImageIo), page cache warm;
//   BM_DotsTrack_Mire2           the `dots` tracker on one frame held in memory (vpDot2::track
//                                 of the five dots, the loss checks);
//   BM_DotsTrackPredict_Mire2/P  the same plus, for each of the five dots, the predictor P's
//                                 update with (u, v) and its query 2 frames ahead (what `predvs
//                                 track` and an image feature source do per frame).
// The frames are played forward then backward (1..501..2, 1..) so that the motion stays
// continuous and the tracker never has to re-acquire. frames_per_s = frames processed per second
// of wall time. Skipped with a message when visp-images-data is absent.
// Run: predvs_bench --benchmark_filter='Mire2'
#include "predvs/predictors/predictor.h"
#include "predvs/servo/image_sequence.h"
#include "predvs/servo/image_tracker.h"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace predvs;

const std::string kMire2 = "/usr/share/visp-images-data/ViSP-images/mire-2/image.%04d.pgm";
constexpr double kFramePeriod_s = 1.0 / 30.0;
constexpr int kHorizonFrames = 2;

bool haveMire2() { return std::filesystem::exists("/usr/share/visp-images-data/ViSP-images/mire-2/image.0001.pgm"); }

/// The 501 frames in memory, in ping-pong order 1..501, 500..2.
const std::vector<vpImage<unsigned char>>& frames() {
  static const std::vector<vpImage<unsigned char>> all = [] {
    std::vector<vpImage<unsigned char>> f;
    auto seq = openImageSequence(kMire2);
    ImageFrame frame;
    std::string why;
    while (seq->next(frame, why) == ImageRead::Ok) f.push_back(frame.image);
    for (size_t k = f.size() - 1; k-- > 1;) f.push_back(f[k]);
    return f;
  }();
  return all;
}

void BM_ImageRead_Mire2(benchmark::State& state) {
  if (!haveMire2()) {
    state.SkipWithError("visp-images-data not installed (/usr/share/visp-images-data)");
    return;
  }
  auto seq = openImageSequence(kMire2);
  ImageFrame frame;
  std::string why;
  long n = 0;
  for (auto _ : state) {
    if (seq->next(frame, why) != ImageRead::Ok) {
      state.PauseTiming();
      seq = openImageSequence(kMire2);
      state.ResumeTiming();
      seq->next(frame, why);
    }
    benchmark::DoNotOptimize(frame.image.bitmap);
    ++n;
  }
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ImageRead_Mire2);

void trackAndMaybePredict(benchmark::State& state, const std::string& predictor) {
  if (!haveMire2()) {
    state.SkipWithError("visp-images-data not installed (/usr/share/visp-images-data)");
    return;
  }
  const auto& f = frames();
  auto tracker = makeImageTracker("dots", Params{}, ImageTrackerContext{});
  tracker->track(f[0]);
  const int n_points = tracker->points();
  std::vector<std::unique_ptr<Predictor>> predictors;
  if (!predictor.empty())
    for (int p = 0; p < n_points; ++p) predictors.push_back(makePredictor(predictor, 2));
  Eigen::VectorXd z(2);
  size_t k = 1;
  long n = 0, lost = 0;
  double t = 0.0;
  for (auto _ : state) {
    const TrackedPoints tp = tracker->track(f[k]);
    for (int p = 0; p < static_cast<int>(predictors.size()); ++p) {
      z << tp.points.uv_px(2 * p), tp.points.uv_px(2 * p + 1);
      predictors[p]->update(t, z);
      const Eigen::VectorXd ahead = predictors[p]->predictPositions(t + kHorizonFrames * kFramePeriod_s);
      benchmark::DoNotOptimize(ahead.data());
    }
    for (bool s : tp.points.seen) lost += s ? 0 : 1;
    k = (k + 1) % f.size();
    t += kFramePeriod_s;
    ++n;
  }
  if (lost > 0) state.SkipWithError("the tracker lost dots: the figure would not be the nominal path");
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsRate);
  state.counters["points"] = n_points;
}

void BM_DotsTrack_Mire2(benchmark::State& state) { trackAndMaybePredict(state, ""); }
BENCHMARK(BM_DotsTrack_Mire2);

void BM_DotsTrackPredict_Mire2(benchmark::State& state, const std::string& predictor) {
  trackAndMaybePredict(state, predictor);
}
BENCHMARK_CAPTURE(BM_DotsTrackPredict_Mire2, hold, std::string("hold"));
BENCHMARK_CAPTURE(BM_DotsTrackPredict_Mire2, kf_cv, std::string("kf-cv"));
BENCHMARK_CAPTURE(BM_DotsTrackPredict_Mire2, cs_akf_adaptive, std::string("cs-akf-adaptive"));
BENCHMARK_CAPTURE(BM_DotsTrackPredict_Mire2, st_akf, std::string("st-akf"));
BENCHMARK_CAPTURE(BM_DotsTrackPredict_Mire2, fakf, std::string("fakf"));

}  // namespace
