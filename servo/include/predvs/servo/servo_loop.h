// predvs — the closed loop: eye-in-hand IBVS of a moving four-point target, with delayed, noisy
// vision and a predictor ahead of the task (METHODS §0, §10; default scenario
// `ibvs-moving-target`).
//
// World: four coplanar points, the corners of a square of side `square_side_m`, on a target
// plane. At the desired pose the camera looks at the square's centre from `desired_depth_m`, the
// plane parallel to the image plane and the square's sides aligned with the image axes. The target
// translates in its own plane by d(t) = p(t) - p(0), p from a Trajectory in metres (built by name
// from `target_trajectory` / `target_params`). The camera is a vpSimulatorCamera integrating the
// applied twist over each control period delta (its sampling time is set to delta); it starts at
// `initial_pose` relative to the desired camera frame.
//
// Velocity saturation (choice): the command is saturated with vpRobot::saturateVelocities at
// `max_translation_mps` / `max_rotation_radps` before it is queued, with vpSimulatorCamera's own
// defaults (0.2 m/s, 0.7 rad/s, set on the simulator too) as our defaults, because that is what a
// plain ViSP user gets; the ego-motion compensation below uses the saturated (applied) twist.
//
// Per control tick k, t = k delta (TimingModel decides every instant):
//  1. true pixel features s(t) = projection of the points (intrinsics px, py, u0, v0);
//  2. at an acquisition tick a measurement z = s(t) + n (NoiseModel seeded from `seed`) with its
//     per-point depth Z(t) (depth assumed known, as in ViSP's simulated IBVS) is stamped t_acq;
//  3. measurements whose release tick has come are delivered to the predictor (in order);
//  4. the task (tasks/IbvsTask, vpServo EYEINHAND_CAMERA) computes v_c at t_c = t from:
//     - `hold` baseline (no prediction, no compensation): s = the latest delivered measurement;
//       this is exactly IBVS on the last delayed image;
//     - with prediction (the predictor is not `hold`, or `compensation = on`): ego-motion
//       compensated features are fed to the predictor,
//           s_c(t_acq) = z(t_acq) - E(t_acq),   E(t) = integral_0^t L_px(s_hat, Z) v_applied dt,
//       where E is the image displacement the camera's own applied motion has caused (known
//       exactly from the applied commands; L_px = diag(px, py) L evaluated at the features the
//       task used at that tick). The predictor then only has to estimate the target-induced
//       image motion (a P-controller keeps the raw features almost still on a constant-velocity
//       target, so a predictor on raw features would see ~zero velocity). At the effect time
//       t_eff = effectTime(t) (horizon (t - t_acq) + t_c1 + t_c2 (+ t_m/2)):
//           s_hat(t_eff) = s_c_hat(t_eff) + E(t_eff)   (Smith-predictor-like; E(t_eff) includes
//                                                      the queued commands that will act by then)
//           ds_c/dt(t_eff) = predictor velocity, the target-motion rate
//       and `forecast` decides how they enter the task:
//         feature      s = s_hat(t_eff), no feed-forward
//         feedforward  s = latest delivered measurement, v_c -= L^+ ds_c/dt (target feed-forward)
//         both         s = s_hat(t_eff) and the feed-forward
//  5. the command is queued and applied from commandApplyTick(k); the camera and target move.
// Default forecast mode, chosen by measurement on the default scenario (seed 1, steady RMSE of
// the tracking error; hold = 36.5 px): feature 36.0 / 35.8 px, feedforward 5.1 / 1.0 px, both
// 5.7 / 1.1 px for kf-cv / kf-ca. `feedforward` is the default. Why: on a moving target a
// P-controller's steady error is the lag (image speed) / lambda, which the delay hardly changes,
// so forecasting the features to the effect time alone buys ~1 %; only the target-rate
// feed-forward removes the lag. `both` was a little worse than `feedforward` for lambda 0.5-4
// (command lag 0-80 ms, N = 1-2); at high gain, where the delay matters to the loop dynamics,
// `both` can win for the CA filter (lambda = 8: hold 5.4 px, kf-ca feature 4.9, feedforward
// 1.3, both 0.7 px) but not for kf-cv (lambda = 6: feedforward 1.26, both 1.67 px), so try
// `both` when raising lambda with kf-ca. Reproduce with
// `predvs servo --predictors hold,kf-cv,kf-ca --set servo.forecast=MODE --set task.lambda=L`. The price of the feed-forward is control effort: it passes
// the filter's velocity noise to the camera (lambda = 1: effort 0.72 / 1.36 vs 0.10 for hold
// over 25 s); the `feature` mode alone lowers the effort (it filters the measurement noise).
//
// Error per step: RMS over the 4 points of the pixel distance between the true features s(t) and
// the desired features s* (the tracking error), see metrics.h for the metric definitions.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/metrics.h"
#include "predvs/servo/noise.h"
#include "predvs/servo/timing_model.h"
#include "predvs/tasks/ibvs_task.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace predvs {

/// How the forecast enters the task (servo.forecast: feature | feedforward | both).
enum class ForecastMode { Feature, Feedforward, Both };
ForecastMode parseForecastMode(const std::string& name);  ///< throws naming servo.forecast
std::string forecastModeName(ForecastMode mode);

/// When the ego-motion compensation + prediction path is used (servo.compensation).
enum class Compensation {
  Auto,  ///< on unless the predictor is `hold` (default: `hold` stays the plain-ViSP baseline)
  On,    ///< always (with `hold` this is a Smith predictor with a zero-velocity target model)
  Off,   ///< never: the predictor is fed raw features and only the `feature` forecast is used
};
Compensation parseCompensation(const std::string& name);  ///< "auto" | "on" | "off"
std::string compensationName(Compensation c);

/// Pinhole intrinsics without distortion (camera.<key>).
struct CameraIntrinsics {
  double px = 800.0;  ///< focal length / pixel width (px)
  double py = 800.0;  ///< focal length / pixel height (px)
  double u0 = 320.0;  ///< principal point (px)
  double v0 = 240.0;  ///< principal point (px)
};

/// Every default of the `ibvs-moving-target` scenario; the app overrides what the YAML names.
struct ServoConfig {
  TimingConfig timing;       ///< default delta = T = 0.04 s, vision latency 0.08 s (2 frames), parallel
  double duration_s = 25.0;  ///< duration_s > 0
  std::uint64_t seed = 1;    ///< seeds the measurement noise
  CameraIntrinsics camera;
  double square_side_m = 0.1;    ///< target.square_side_m > 0
  double desired_depth_m = 0.5;  ///< target.desired_depth_m > 0: camera-plane distance at the goal
  /// Initial camera pose in the desired camera frame: (tx, ty, tz) in m, then theta-u (rad)
  /// (initial_pose). Default: 3 cm right, 2 cm up, 10 cm further back, 0.2 rad about the axis.
  Eigen::Matrix<double, 6, 1> initial_pose = (Eigen::Matrix<double, 6, 1>() << 0.03, -0.02, -0.1, 0.0, 0.0, 0.2).finished();
  /// target.trajectory and target.params (metres). When the app changes the trajectory name it
  /// must replace the params wholesale (unused keys are rejected). Default: a 5 cm radius circle
  /// at 0.5 rad/s (2.5 cm/s, about 40 px/s in the image at 0.5 m).
  std::string target_trajectory = "circle";
  Params target_params{{"radius", 0.05}, {"omega", 0.5}};
  NoiseConfig noise;         ///< default gaussian, sigma 0.5 px
  IbvsTaskConfig task;       ///< default lambda 1.0 /s, CURRENT interaction matrix
  ForecastMode forecast = ForecastMode::Feedforward;  ///< servo.forecast: measured best (header comment)
  Compensation compensation = Compensation::Auto;     ///< servo.compensation
  double max_translation_mps = 0.2;  ///< robot.max_translation_mps > 0 (vpRobot default)
  double max_rotation_radps = 0.7;   ///< robot.max_rotation_radps > 0 (vpRobot default)
  MetricsOptions metrics;
};

using FeatureVector = Eigen::Matrix<double, 8, 1>;  ///< (u0, v0, u1, v1, u2, v2, u3, v3) in px

/// One row of the closed-loop trace.
struct ServoSample {
  double t_s = 0.0;            ///< control tick time t
  double t_acq_s = 0.0;        ///< acquisition time of the latest delivered measurement (NaN before)
  FeatureVector measured_px;   ///< latest delivered (delayed, noisy) measurement; NaN before the first
  FeatureVector predicted_px;  ///< features the task used (= measured for hold / feedforward mode)
  FeatureVector true_px;       ///< true features at t
  double error_px = 0.0;       ///< RMS over points of ||true - desired|| (px)
  CameraTwist velocity;        ///< applied camera twist during [t, t + delta) (after saturation)
};

struct ServoResult {
  std::string predictor;      ///< predictor.name()
  bool prediction_used = false;  ///< whether the compensation + prediction path was active
  FeatureVector desired_px;   ///< s* in pixels
  std::vector<ServoSample> trace;
  Metrics metrics;            ///< of error_px, with control effort
};

/// The loop, stepwise (the app and the benchmark drive it; runServoLoop() is the one-call form).
class ServoLoop {
 public:
  /// Validates `config` (std::invalid_argument naming the key) and resets `predictor`, which must
  /// have 8 channels and outlive the loop.
  ServoLoop(const ServoConfig& config, Predictor& predictor);
  ~ServoLoop();
  ServoLoop(const ServoLoop&) = delete;
  ServoLoop& operator=(const ServoLoop&) = delete;

  /// True once the run has covered duration_s.
  bool done() const;
  /// Advances one control tick and returns its trace row.
  const ServoSample& step();
  /// Steps until done() and returns the trace and metrics.
  ServoResult run();
  bool predictionUsed() const;
  const FeatureVector& desiredFeatures() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

ServoResult runServoLoop(const ServoConfig& config, Predictor& predictor);

/// Column names of a closed-loop trace row, in order: t_s, t_acq_s, meas_u0 .. meas_v3,
/// pred_u0 .. pred_v3, true_u0 .. true_v3, error_px, vx, vy, vz, wx, wy, wz. The golden trace
/// data/golden/ibvs-moving-target.csv uses these columns (kf-cv on the default ServoConfig).
const std::vector<std::string>& servoTraceColumns();
/// Values of one row in the order of servoTraceColumns().
std::vector<double> servoTraceRow(const ServoSample& sample);

}  // namespace predvs
