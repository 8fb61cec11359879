// predvs — the open-loop prediction experiment on N channels (docs/MODELS.md §10: E1-E4, E6, E7, E12).
//
// The same simulation as runPredictionExperiment() (prediction_experiment.h: acquisition at the
// frame ticks, noise per channel in channel order, occlusions, delivery at the release tick,
// prediction at the effect time), for a ChannelTrajectory of any number of channels (E6: x_i,
// y_i, d_x; E12: one channel). On a 2-channel trajectory it produces the same errors, seed for
// seed, as runPredictionExperiment(), which runs through it. In addition it records
//  * the predictor's velocity at the effect time and the true velocity there, so that the
//    velocity error of the estimate can be scored (paper 001 Table 2 reports velocity MSE);
//  * the acquisition time of every frame that raised a discontinuity-monitor alarm (predictors of
//    the st-akf family, docs/MODELS.md §6; never for the others), for detection delay and false alarms.
// With a zero horizon (no vision latency, no command lag) the prediction is the filtered estimate
// x(k|k) at the acquisition time, which is what paper 001 §5.2 and paper 004 §5 score.
#pragma once

#include "predvs/predictors/predictor.h"
#include "predvs/servo/metrics.h"
#include "predvs/servo/paper_trajectories.h"
#include "predvs/servo/prediction_experiment.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace predvs {

/// One row of the trace, per control tick after the first delivered frame.
struct ChannelSample {
  double t_s = 0.0;             ///< control tick time t
  double t_acq_s = 0.0;         ///< acquisition time of the latest delivered frame
  double t_pred_s = 0.0;        ///< effect time the prediction aims at
  bool measured_valid = false;  ///< false while the latest delivered frame was lost (occlusion)
  Eigen::VectorXd measured;     ///< latest delivered measurement (NaN if lost)
  Eigen::VectorXd predicted;    ///< predictor's position at t_pred (NaN while uninitialised)
  Eigen::VectorXd predicted_velocity;  ///< predictor's velocity at t_pred
  Eigen::VectorXd truth;        ///< true position at t_pred
  Eigen::VectorXd true_velocity;  ///< true velocity at t_pred
  double error = 0.0;           ///< ||predicted - truth|| over the channels
  bool lost_expired = false;    ///< some channel was held by the lost-feature policy (lost.timeout_s)
  Eigen::VectorXd diagnostics;  ///< the predictor's diagnostics() values after its last update (e.g. imm's mode probabilities)
};

struct ChannelExperimentResult {
  std::string predictor;
  std::string trajectory;
  std::vector<std::string> channel_names;
  std::vector<std::string> diagnostic_names;  ///< names of ChannelSample::diagnostics (Predictor::diagnostics())
  std::vector<ChannelSample> trace;
  Metrics metrics;                ///< of `error` over the trace (metrics.h)
  /// Per channel: mean over the trace rows with a finite prediction of (predicted - truth)^2 and
  /// of (predicted_velocity - true_velocity)^2 (the MSE of paper 001 Table 2), units^2 and
  /// (units/s)^2. NaN for a channel never predicted.
  Eigen::VectorXd position_mse;
  Eigen::VectorXd velocity_mse;
  /// Acquisition times of the frames whose update raised a monitor alarm, in order.
  std::vector<double> alarm_t_acq_s;
};

/// Runs the experiment (the predictor is reset() first and must have trajectory.channels()
/// channels). Throws std::invalid_argument on a bad config (naming the key) or a channel mismatch.
ChannelExperimentResult runChannelExperiment(const PredictionExperimentConfig& config,
                                             const ChannelTrajectory& trajectory, Predictor& predictor);

}  // namespace predvs
