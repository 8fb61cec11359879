// predvs — the figures of one run as named values: the names `predvs servo` (one run per
// predictor) and `predvs compare` (many seeded runs, aggregated) both print and write.
//
// Closed loop: ServoResult::values (servo_loop.h): metricValues() of the tracking error with the
// control effort; with metrics.outcome the outcome of a positioning run, outcomeValues() (metrics.h:
// converged, convergence_time_s, failed, failure_time_s, fail_behind, fail_image, fail_robot; a
// failed run stops there and its steady-window figures are NaN); with metrics.per_feature the
// per-feature errors; with occlusions occlusionValues() and lost_policy_s; then the task's run summary
// (Task::runSummary(), e.g. jacobian_error_final, sliding_rms_final, lyap_bound_positive_fraction).
// Open loop: openLoopRunValues() of a runChannelExperiment() result, in this order (e is
// ||predicted - true|| over the channels at the effect time, in the trajectory's units):
//   rmse, final, max, peak, iae, settling_s   metricValues() of e (metrics.h); no effort (no command)
//   pos_mse_<ch>, vel_mse_<ch>                per channel: MSE of the position and of the velocity
//                                             over the run (paper 001 Table 2)
//   occl_rmse, occl_max                       with occlusions: RMS / max of e over the ticks whose
//                                             latest delivered frame was lost
//   occl_end_error                            with occlusions: e at the last tick before a frame is
//                                             delivered again (the extrapolation over the whole gap)
//   reacq_error, reacq_1s_rmse                with occlusions: e at the first tick after a frame is
//                                             delivered again, and its RMS over the following 1 s
//                                             (these three: means over the occlusions of the run)
//   lost_policy_s                             with occlusions: time during which the lost-feature
//                                             policy held at least one channel (lostPolicyValue())
//   alarms, false_alarms_per_min              discontinuity-monitor alarms (st-akf family; 0 for the
//                                             others), and those that are not the detection of the
//                                             onset, per minute of run
//   detected, detect_delay_frames             trajectory with an onset after t = 0 (E12): 1 if an alarm
//                                             came from a frame acquired in
//                                             [t_onset, t_onset + kDetectWindowS), and its delay in
//                                             frames after the first frame at or after the onset
//                                             (NaN when not detected)
//   resp_max_lag, resp_overshoot,             trajectory with a manoeuvre (E1 start, E2 jump, E3
//   resp_mean_3s, resp_time_s                 switch, E12 onset; trajectory.h): computeResponse()
//                                             (metrics.h) on the effect-time axis: the largest lag
//                                             behind and overshoot past the change within
//                                             metrics.response_window_s (3 s) after it, the mean error
//                                             over the 3 s after it, the time until e settles
// Which names a run has depends only on the configuration and the trajectory (never on the
// predictor or the seed), so every run of a scenario has the same names in the same order.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/servo/channel_experiment.h"
#include "predvs/servo/paper_trajectories.h"
#include "predvs/servo/prediction_experiment.h"

#include <string>

namespace predvs {

/// An alarm counts as detecting the onset when it comes from a frame acquired within this long
/// after the onset (s).
constexpr double kDetectWindowS = 0.5;

/// The figures of an open-loop run (header list). `config` and `trajectory` are those the run used.
NamedValues openLoopRunValues(const ChannelExperimentResult& result, const PredictionExperimentConfig& config,
                              const ChannelTrajectory& trajectory);

/// One line defining a figure named above (the open-loop ones and metricValues(); "" for any other
/// name, e.g. a task's run summary, which its task header defines).
std::string runMetricDefinition(const std::string& name);

}  // namespace predvs
