// predvs — the open-loop prediction experiment (docs/MODELS.md §10, E1–E4, E7): a target moves on a 2D
// trajectory in the image, a camera observes it with noise and delay, and a predictor must say
// where the target will be when a command computed now would take effect.
//
// Simulation, per control tick k (t = k delta, TimingModel):
//  1. at an acquisition tick, the camera measures z = p(t) + n (NoiseModel, seeded), stamped
//     t_acq = t; unless t_acq falls in an occlusion interval, in which case the frame is lost;
//  2. every frame whose release tick (t_acq + t_ac + t_p, rounded up to a tick) has come is
//     delivered in acquisition order: predictor.update(t_acq, z) (predict-only update(t_acq) for
//     a lost frame, so the filter keeps running through an occlusion);
//     A channel without a measurement for lost.timeout_s or more is then held at its last measured
//     value (lost_feature_policy.h; lost.action extrapolate: the predictor's extrapolation);
//  3. the predictor is queried at the effect time t_eff = effectTime(t) (horizon
//     (t - t_acq) + t_c1 + t_c2 (+ t_m/2) from the latest delivered frame); the error is
//     ||p_hat(t_eff) - p(t_eff)||.
// No row is produced before the first delivered frame. The predictor must have 2 channels
// (x, y); it is reset() at the start of the run.
#pragma once

#include "predvs/predictors/predictor.h"
#include "predvs/servo/lost_feature_policy.h"
#include "predvs/servo/metrics.h"
#include "predvs/servo/noise.h"
#include "predvs/servo/timing_model.h"
#include "predvs/servo/trajectory.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace predvs {

/// Frames acquired at t_acq in [start_s, end_s) are lost (target fully hidden).
struct OcclusionInterval {
  double start_s = 0.0;
  double end_s = 0.0;
};

/// Plain configuration (YAML: the scenario's top-level keys). Defaults: 20 s at delta = T = 40 ms
/// with a two-frame latency (TimingConfig defaults), Gaussian noise of 1 unit, seed 1.
struct PredictionExperimentConfig {
  TimingConfig timing;
  double duration_s = 20.0;  ///< duration_s > 0
  NoiseConfig noise{NoiseKind::Gaussian, 1.0, false};
  std::uint64_t seed = 1;
  std::vector<OcclusionInterval> occlusions;  ///< each needs start_s < end_s
  MetricsOptions metrics;
  /// lost: {timeout_s: 1, action: hold | extrapolate} (lost_feature_policy.h): a channel lost for
  /// timeout_s or more is predicted at its last measured value, velocity 0, instead of the
  /// predictor's extrapolation; `drop` is refused (no task to drop it from).
  LostFeatureConfig lost;
};

/// One row of the trace, per control tick after the first delivered frame.
struct PredictionSample {
  double t_s = 0.0;          ///< control tick time t
  double t_acq_s = 0.0;      ///< acquisition time of the latest delivered frame
  double t_pred_s = 0.0;     ///< effect time the prediction aims at
  double horizon_s = 0.0;    ///< t_pred - t_acq
  bool measured_valid = false;  ///< false while the latest delivered frame was lost (occlusion)
  Eigen::Vector2d measured;  ///< latest delivered (noisy, delayed) measurement; NaN if lost
  Eigen::Vector2d predicted; ///< predictor's position at t_pred
  Eigen::Vector2d truth;     ///< true position at t_pred
  double error = 0.0;        ///< ||predicted - truth||
};

struct PredictionResult {
  std::string predictor;   ///< predictor.name()
  std::string trajectory;  ///< trajectory.name()
  std::vector<PredictionSample> trace;
  Metrics metrics;         ///< of `error` over the trace
};

/// Runs the experiment. Throws std::invalid_argument on a bad config (naming the key) or when the
/// predictor does not have 2 channels.
PredictionResult runPredictionExperiment(const PredictionExperimentConfig& config,
                                         const Trajectory& trajectory, Predictor& predictor);

/// Column names of a trace row, in order: t_s, t_acq_s, t_pred_s, horizon_s, meas_x, meas_y,
/// pred_x, pred_y, true_x, true_y, error.
const std::vector<std::string>& predictionTraceColumns();
/// Values of one row in the order of predictionTraceColumns().
std::vector<double> predictionTraceRow(const PredictionSample& sample);

}  // namespace predvs
