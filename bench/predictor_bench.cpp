// Predictor cost: nanoseconds per frame for the work a servo loop asks of a predictor, i.e. one
// update with a 2-channel measurement (a feature point's u and v) followed by the horizon query
// 2 frames ahead (state and covariance of both channels). Every registered predictor is benchmarked
// (registered dynamically from predictorRegistry(), so a new predictor appears here on its own),
// side by side with the same work done by
//   * ViSP's vpLinearKalmanFilterInstantiation (stateConstVel_MeasurePos, 2 signals): filter()
//     (update + its one-step prediction), then the 2-frame state and covariance from Xpre / Ppre;
//   * OpenCV's cv::KalmanFilter (CV model, 4 states, 2 measurements, CV_64F): predict() + correct(),
//     then the 2-frame state and covariance from statePost / errorCovPost.
// Same frame period, same noise densities and the same pre-generated measurement sequence for all.
// The references are plain CV Kalman filters with fixed noise; so is BM_PredictorPlain/kf-cv (kf-cv
// with q and r fixed, no blend with hold: plain_kf_cv.h, as the scenario files pin it), the like-for-
// like row. BM_Predictor/kf-cv runs the defaults, which add issue 11's layers (the start-up R
// estimate, the raise of q, the blend with hold on two horizons: channel_predictor.h).
// Run: predvs_bench --benchmark_filter=Predictor
#include "plain_kf_cv.h"
#include "predvs/predictors/predictor.h"

#include <benchmark/benchmark.h>
#include <opencv2/video/tracking.hpp>
#include <visp3/core/vpLinearKalmanFilterInstantiation.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace predvs;

constexpr double kFramePeriod_s = 1.0 / 30.0;
constexpr int kHorizonFrames = 2;
constexpr double kQ = kPlainKfCvQ;  // white-acceleration density (px^2/s^3), as the scenario files pin kf-cv's q
constexpr double kR = kPlainKfCvR;  // measurement variance (px^2)

/// 4096 frames of a feature point on a circle with 1 px noise, cycled through by every benchmark.
const std::vector<Eigen::Vector2d>& measurements() {
  static const std::vector<Eigen::Vector2d> z = [] {
    std::mt19937 rng(2024);
    std::normal_distribution<double> n(0.0, 1.0);
    std::vector<Eigen::Vector2d> out;
    for (int k = 0; k < 4096; ++k) {
      const double t = k * kFramePeriod_s;
      out.emplace_back(320.0 + 100.0 * std::cos(0.5 * t) + n(rng), 240.0 + 100.0 * std::sin(0.5 * t) + n(rng));
    }
    return out;
  }();
  return z;
}

void predvsPredictor(benchmark::State& state, const std::string& name, const Params& params = {}) {
  auto p = makePredictor(name, 2, params);
  const auto& zs = measurements();
  Eigen::VectorXd z(2);
  double t = 0.0;
  size_t k = 0;
  for (auto _ : state) {
    z = zs[k++ & 4095];
    p->update(t, z);
    const double th = t + kHorizonFrames * kFramePeriod_s;
    for (int c = 0; c < 2; ++c) {
      ChannelEstimate e = p->predict(c, th);
      benchmark::DoNotOptimize(e);
    }
    t += kFramePeriod_s;
  }
}

void BM_PredictorViSPLinearKalman(benchmark::State& state) {
  vpLinearKalmanFilterInstantiation kf;
  kf.setStateModel(vpLinearKalmanFilterInstantiation::stateConstVel_MeasurePos);
  vpColVector sigma_state(4, kQ), sigma_measure(2, kR);  // ViSP uses sigma_state[2i] as the density
  kf.initStateConstVel_MeasurePos(2, sigma_state, sigma_measure, kFramePeriod_s);
  const auto& zs = measurements();
  vpColVector z(2);
  size_t k = 0;
  for (auto _ : state) {
    const Eigen::Vector2d& m = zs[k++ & 4095];
    z[0] = m(0);
    z[1] = m(1);
    kf.filter(z);  // update with z(k), then Xpre / Ppre = one frame ahead
    // one more frame: the 2-frame horizon (state and covariance)
    vpColVector x2 = kf.F * kf.Xpre;
    vpMatrix P2 = kf.F * kf.Ppre * kf.F.t() + kf.Q;
    benchmark::DoNotOptimize(x2.data);
    benchmark::DoNotOptimize(P2.data);
  }
}
BENCHMARK(BM_PredictorViSPLinearKalman);

void BM_PredictorOpenCvKalman(benchmark::State& state) {
  cv::KalmanFilter kf(4, 2, 0, CV_64F);
  const double T = kFramePeriod_s;
  // state [u, v_u, v, v_v]: two independent CV channels
  kf.transitionMatrix = (cv::Mat_<double>(4, 4) << 1, T, 0, 0, 0, 1, 0, 0, 0, 0, 1, T, 0, 0, 0, 1);
  kf.measurementMatrix = (cv::Mat_<double>(2, 4) << 1, 0, 0, 0, 0, 0, 1, 0);
  const double T2 = T * T, T3 = T2 * T;
  kf.processNoiseCov = (cv::Mat_<double>(4, 4) << kQ * T3 / 3, kQ * T2 / 2, 0, 0, kQ * T2 / 2, kQ * T, 0, 0, 0, 0,
                        kQ * T3 / 3, kQ * T2 / 2, 0, 0, kQ * T2 / 2, kQ * T);
  kf.measurementNoiseCov = cv::Mat::eye(2, 2, CV_64F) * kR;
  kf.errorCovPost = cv::Mat::diag((cv::Mat_<double>(4, 1) << kR, 1e4, kR, 1e4));
  const auto& zs = measurements();
  kf.statePost = (cv::Mat_<double>(4, 1) << zs[0](0), 0, zs[0](1), 0);
  cv::Mat z(2, 1, CV_64F);
  size_t k = 0;
  for (auto _ : state) {
    const Eigen::Vector2d& m = zs[k++ & 4095];
    z.at<double>(0) = m(0);
    z.at<double>(1) = m(1);
    kf.predict();
    kf.correct(z);
    // the 2-frame horizon from the corrected estimate (state and covariance)
    const cv::Mat& F = kf.transitionMatrix;
    cv::Mat x2 = F * (F * kf.statePost);
    cv::Mat P1 = F * kf.errorCovPost * F.t() + kf.processNoiseCov;
    cv::Mat P2 = F * P1 * F.t() + kf.processNoiseCov;
    benchmark::DoNotOptimize(x2.data);
    benchmark::DoNotOptimize(P2.data);
  }
}
BENCHMARK(BM_PredictorOpenCvKalman);

/// One benchmark per registered predictor, named BM_Predictor/<name>.
const bool kRegistered = [] {
  for (const auto& info : predictorRegistry()) {
    const std::string name = info.name;
    benchmark::RegisterBenchmark(("BM_Predictor/" + name).c_str(),
                                 [name](benchmark::State& s) { predvsPredictor(s, name); });
  }
  benchmark::RegisterBenchmark("BM_PredictorPlain/kf-cv",
                               [](benchmark::State& s) { predvsPredictor(s, "kf-cv", plainKfCvParams()); });
  // What each of kf-cv's default layers costs: the defaults with one key changed (channel_predictor.h,
  // kalman_baselines.h): no blend with hold; the blend on one horizon; one blend weight instead of
  // two; r fixed (no start-up estimate); q fixed (no raise).
  const std::vector<std::pair<const char*, double>> layers = {
      {"hold_blend_tau_s", 0.0}, {"hold_blend_frames", 1.0}, {"hold_blend_split", 0.0}, {"r", kR}, {"q", 1e4}};
  for (const auto& [key, value] : layers) {
    const Params p{{key, value}};
    char label[96];
    std::snprintf(label, sizeof label, "BM_PredictorLayer/kf-cv/%s=%g", key, value);
    benchmark::RegisterBenchmark(label, [p](benchmark::State& s) { predvsPredictor(s, "kf-cv", p); });
  }
  return true;
}();

}  // namespace
