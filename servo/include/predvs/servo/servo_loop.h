// predvs — the closed loop, a composition: a feature source, a predictor, a task (control law)
// and a robot, timed by the timing model (docs/MODELS.md §0; default scenario data/scenarios/ibvs-moving-target.yaml).
//
// The loop knows none of them by name: it asks their interfaces (task.h, robot.h,
// feature_source.h, predictor.h). A new law, robot or source is new files plus one registry line.
//
// World: a Scene (scene.h): N target points translating in the world x-y plane along a
// Trajectory, and the goal camera pose cdMo. The robot starts with its camera at `initial_pose`
// relative to the desired camera frame (robot.h: reset()).
//
// Per control tick k, t = k delta (TimingModel decides every instant):
//  1. true features: the task's features of the scene's exact projection with the robot's camera
//     pose now (for scoring only);
//  2. at an acquisition tick the source delivers a frame stamped t_acq (its points with a status
//     each; noise is the source's); the loop stamps it with the ego-motion displacement E(t_acq)
//     and the robot's command integral p(t_acq);
//  3. frames whose release tick has come are delivered in order: the task features f are
//     computed, the task observes (f, p(t_acq)) (online Jacobian estimators pair increments this
//     way, docs/MODELS.md §7), and the predictor is updated with f - E(t_acq) when the prediction path is
//     on, with f otherwise (NaN where a point is lost: predict-only for that channel). The latest
//     finite value of every channel is kept: for `hold`, a lost feature stays at its last value;
//  4. the task computes the command u at t_c = t from:
//     - no prediction path (a predictor that does not extrapolate, i.e. `hold`, with compensation
//       auto, or compensation off): the latest delivered features (compensation off: the
//       predictor's forecast of the raw features, `feature` mode only); this is exactly a plain
//       ViSP loop on the last delayed image;
//     - prediction path: the predictor runs on the ego-motion compensated features
//           s_c(t_acq) = f(t_acq) - E(t_acq),   E(t) = integral_0^t J_task u_applied dt,
//       where J_task = ds/du is the Jacobian the task itself used (Task::featureJacobian()), so the
//       compensation uses the law's own model. At the effect time t_eff = effectTime(t)
//           s_hat(t_eff) = s_c_hat(t_eff) + E(t_eff)   (E(t_eff) includes the queued commands)
//           ds_c/dt(t_eff) = the predictor's velocity: the target-induced feature rate
//       and `forecast` decides what the task gets:
//         feature      acts on s_hat(t_eff), no feed-forward
//         feedforward  acts on the latest measurement, feeds the target rate forward (default)
//         both         acts on s_hat(t_eff) and feeds the target rate forward
//       where the rate is Predictor::feedforwardVelocity(), judged at a law's bandwidth (in `both`
//       until 2026-12-05 the forecast's own predictVelocity(), blended with hold as its position:
//       on e5's slow leaders that was about 0, and every predictor with its defaults fell behind
//       hold there);
//       (the task observes the same rate with each delivered frame);
//     A channel lost for lost.timeout_s or more (acquisition times; lost_feature_policy.h) is no
//     longer extrapolated: with lost.action hold the predictor's position for it is replaced by the
//     last value it was fed (with the prediction path the last ego-compensated measurement, so
//     s_hat = that + E(t_eff): the target held where it was last seen, the camera's own motion
//     still counted; in feedforward mode the task acts on the last measurement as for every
//     channel) and its target rate by 0; with drop the feature is NaN in both TaskInput::measured
//     and ::used (and its rate 0), so the law runs on the others (Task::canDropFeatures(); the
//     loop refuses drop for a law that cannot, naming lost.action); the trace's pred_<f> is NaN
//     then. When every channel had expired, the predictor is reset() at the first frame that
//     measures one again (lost_feature_policy.h says why);
//  5. the robot limits the command (velocity limits, quantisation); the limited command is
//     queued and applied from commandApplyTick(k); E and p integrate the applied command.
// Why feedforward is the default (measured on the default scenario, `predvs servo --predictors
// hold,kf-cv,kf-ca --set servo.forecast=MODE`, see docs/DESIGN.md): on a moving target a
// P-controller's steady error is the lag (image speed) / lambda, which the delay hardly changes,
// so forecasting the features to the effect time alone buys about 1 %; only the target-rate
// feed-forward removes the lag. Its price is control effort: it passes the filter's velocity
// noise to the robot (which `ibvs` keeps low by feeding the rate forward through a damped inverse,
// ibvs_task.h).
//
// Error per step: Task::trackingError of the true features (point tasks: RMS over the points of
// the pixel distance ||s_i - s*_i||); metrics.h defines the metrics over the run.
//
// Outcome (only with metrics.outcome; metrics.h, Outcome): after every control step (and at t = 0)
// the loop checks the true state the step led to, for a point behind the camera (Z <= 0), a point
// outside the image_width_px x image_height_px image (metrics.fail_outside_image) and the robot at
// a hard limit (Robot::atLimit(), metrics.fail_robot_limit). The first failing state ends the run
// (done() turns true; the state itself is not a trace row: a point behind the camera has no
// projection). Stopping saves the rest of a diverging run, which a large grid of runs would
// otherwise spend; metrics.h says what the figures of a stopped run are. Without metrics.outcome
// none of this runs: no check, no early stop, the figures exactly as before.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/feature_source.h"
#include "predvs/servo/lost_feature_policy.h"
#include "predvs/servo/metrics.h"
#include "predvs/servo/noise.h"
#include "predvs/servo/robot.h"
#include "predvs/servo/scene.h"
#include "predvs/servo/timing_model.h"
#include "predvs/tasks/camera.h"
#include "predvs/tasks/task.h"

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
  Auto,  ///< on unless the predictor does not extrapolate (`hold` stays the plain-ViSP baseline)
  On,    ///< always (with `hold` this is a Smith predictor with a zero-velocity target model)
  Off,   ///< never: the predictor is fed raw features and only the `feature` forecast is used
};
Compensation parseCompensation(const std::string& name);  ///< "auto" | "on" | "off"
std::string compensationName(Compensation c);

/// A component chosen by name with its parameters (task, robot, feature source).
struct ComponentSpec {
  std::string name;
  Params params;
};

/// Every default of the `ibvs-moving-target` scenario; the app overrides what the YAML names.
struct ServoConfig {
  TimingConfig timing;       ///< default delta = T = 0.04 s, vision latency 0.08 s (2 frames), parallel
  double duration_s = 25.0;  ///< duration_s > 0
  std::uint64_t seed = 1;    ///< seeds the measurement noise and the task's random draws
  CameraIntrinsics camera;   ///< the true intrinsics (the task is given the same)
  /// Image size in pixels (camera.width / camera.height; a scenario's default is 2 u0 x 2 v0, the
  /// principal point at the centre). Used by the outside-image failure check of metrics.outcome,
  /// where both must be > 0, and as the size of the images the rendered-image sources (`dots`,
  /// `apriltag`) draw; the geometric source does not crop to it.
  double image_width_px = 640.0;
  double image_height_px = 480.0;
  /// Target and goal. Default: a 10 cm square, goal 0.5 m in front of it, moving on a 5 cm
  /// radius circle at 0.5 rad/s (2.5 cm/s, about 40 px/s in the image at 0.5 m).
  SceneConfig scene;
  /// Initial camera pose in the desired camera frame: (tx, ty, tz) in m, then theta-u (rad)
  /// (initial_pose). Default: 3 cm right, 2 cm up, 10 cm further back, 0.2 rad about the axis.
  Pose6 initial_pose = (Pose6() << 0.03, -0.02, -0.1, 0.0, 0.0, 0.2).finished();
  NoiseConfig noise;                          ///< default gaussian, sigma 0.5 px
  std::vector<OcclusionInterval> occlusions;   ///< frames acquired inside are lost
  ComponentSpec task{"ibvs", {}};             ///< task.type and its keys (default lambda 1, current)
  ComponentSpec robot{"free-camera", {}};     ///< robot.type and its keys
  ComponentSpec source{"geometric", {}};      ///< source.type and its keys
  ForecastMode forecast = ForecastMode::Feedforward;  ///< servo.forecast
  Compensation compensation = Compensation::Auto;     ///< servo.compensation
  LostFeatureConfig lost;     ///< lost: {timeout_s: 1, action: hold} (lost_feature_policy.h)
  MetricsOptions metrics;
  /// Record the predictor's diagnostics() in the trace (ServoSample::predictor_diagnostics) after
  /// each delivered frame; off saves building them (imm: 6 named values per channel) where no trace
  /// is kept.
  bool predictor_diagnostics = true;
};

/// One row of the closed-loop trace (features in the task's feature space, see Task).
struct ServoSample {
  double t_s = 0.0;            ///< control tick time t
  double t_acq_s = 0.0;        ///< acquisition time of the latest delivered measurement (NaN before)
  bool frame_lost = false;     ///< the latest delivered frame saw no point (occlusion)
  bool lost_expired = false;   ///< some channel was past lost.timeout_s (held or dropped) at this tick
  Eigen::VectorXd measured;    ///< latest delivered (delayed, noisy) features; NaN before the first
  Eigen::VectorXd predicted;   ///< features the task acted on (= measured for hold / feedforward mode)
  Eigen::VectorXd truth;       ///< true features at t
  double error = 0.0;          ///< Task::trackingError(truth)
  Eigen::VectorXd command;     ///< applied command during [t, t + delta) (after the robot's limits)
  Eigen::VectorXd diagnostics; ///< the task's diagnostics of its last command (Task::diagnostics())
  /// The predictor's diagnostics after its last update (Predictor::diagnostics(), e.g. imm's mode
  /// probabilities and forecast weights; NaN before the first; empty for a predictor without any,
  /// and with ServoConfig::predictor_diagnostics off).
  Eigen::VectorXd predictor_diagnostics;
};

struct ServoResult {
  std::string predictor;         ///< predictor.name()
  bool prediction_used = false;  ///< whether the compensation + prediction path was active
  Eigen::VectorXd desired;       ///< s*
  std::vector<std::string> columns;  ///< trace columns (ServoLoop::traceColumns())
  std::vector<std::string> command_units;  ///< the robot's CommandSpace::units (reports)
  std::vector<ServoSample> trace;
  std::vector<std::string> predictor_diagnostic_names;  ///< of ServoSample::predictor_diagnostics
  Metrics metrics;               ///< of the error, with control effort (steady figures NaN after a failure)
  Outcome outcome;               ///< with metrics.outcome: converged / failed (metrics.h); default otherwise
  NamedValues values;            ///< metricValues(metrics), then the task's run summary
};

/// The loop, stepwise (the app and the benchmark drive it; runServoLoop() is the one-call form).
class ServoLoop {
 public:
  /// Builds the scene, source, task and robot from `config` and validates everything
  /// (std::invalid_argument naming the key); resets `predictor`, which must have one channel per
  /// task feature and outlive the loop.
  ServoLoop(const ServoConfig& config, Predictor& predictor);
  ~ServoLoop();
  ServoLoop(const ServoLoop&) = delete;
  ServoLoop& operator=(const ServoLoop&) = delete;

  /// True once the run has covered duration_s, or (metrics.outcome) has failed.
  bool done() const;
  /// With metrics.outcome: the failure detected so far (None otherwise) and its time (NaN if none).
  FailureKind failure() const;
  double failureTime() const;
  /// Advances one control tick and returns its trace row.
  const ServoSample& step();
  /// Steps until done() and returns the trace and metrics.
  ServoResult run();
  bool predictionUsed() const;
  const Eigen::VectorXd& desiredFeatures() const;
  const Task& task() const;
  const Robot& robot() const;

  /// Names of ServoResult::values, in order: metricValues(), with metrics.outcome
  /// outcomeValues(), with metrics.per_feature the
  /// per-feature errors (featureErrorValues()), with occlusions occlusionValues() and
  /// lost_policy_s (lostPolicyValue(), metrics.h), then the task's
  /// run summary (before the run: the task's run summary names are
  /// fixed per law).
  std::vector<std::string> valueNames() const;
  /// Column names of a trace row, in order: t_s, t_acq_s, meas_<f>.., pred_<f>.., true_<f>..
  /// (f the task's feature names), error_px, the robot's command names, the task's diagnostic
  /// names. The golden trace data/golden/ibvs-moving-target.csv uses these columns (kf-cv on the
  /// default ServoConfig).
  std::vector<std::string> traceColumns() const;
  /// Values of one row in the order of traceColumns().
  static std::vector<double> traceRow(const ServoSample& sample);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

ServoResult runServoLoop(const ServoConfig& config, Predictor& predictor);

/// The number of predictor channels the loop of `config` needs (the task's feature count).
int servoChannels(const ServoConfig& config);

}  // namespace predvs
