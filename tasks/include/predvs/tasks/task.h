// predvs — the control-law interface (a "task") and its registry.
//
// The servo loop (servo/servo_loop.h) composes a feature source, a predictor, a task and a robot.
// A task
//  * turns the points a feature source delivers (pixels, with a seen / lost status) into its own
//    feature vector s (point coordinates for IBVS, centroid and width for paper 001's tracking
//    law, ...): the predictor runs on these features, one channel each;
//  * computes the robot command u (in the robot's command space: camera twist, joint velocities,
//    wheel speeds) from the features the loop hands it: the latest delivered measurement, the
//    features to act on (the measurement or its forecast to the effect time) and, when a
//    predictor is used, the forecast target-induced feature rate (feed-forward);
//  * exposes the feature Jacobian J = ds/du it used (features per unit command), so that the
//    loop's ego-motion compensation s - E, dE/dt = J u, uses the law's own model, not an
//    analytic matrix hard-coded in the loop.
// Units: features in pixels (or pixel-like units, e.g. a width in px), time in seconds.
//
// Registry: makeTask(name, params, context) builds a task by name; taskRegistry() lists them
// (`predvs list`). A new law is one file plus one registry line in tasks/src/task_registry.cpp.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/predictors/registry.h"
#include "predvs/tasks/camera.h"

#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace predvs {

/// What a robot takes as its command. `kind` names the physical meaning ("camera-twist",
/// "joint-velocity", "unicycle-tilt"); `names` the components with their units.
struct CommandSpace {
  std::string kind;
  std::vector<std::string> names;
  std::vector<std::string> units = {};  ///< one per name ("m/s", "rad/s") for reports; empty: not stated
  int size() const { return static_cast<int>(names.size()); }
};

/// Image points as a feature source delivers them.
struct PointFeatures {
  Eigen::VectorXd uv_px;  ///< 2N: (u_0, v_0, u_1, v_1, ...) in pixels; NaN for a lost point
  Eigen::VectorXd Z_m;    ///< N depths in metres (NaN when the source does not know them)
  std::vector<bool> seen; ///< N statuses: false = lost (occluded, out of view, tracker failure)
  int points() const { return static_cast<int>(seen.size()); }
};

/// What a task is built with (besides its own parameters).
struct TaskContext {
  CameraIntrinsics camera;       ///< the intrinsics the controller believes (may differ from the truth)
  PointFeatures desired_points;  ///< the points seen from the desired pose (the task's goal)
  CommandSpace command_space;    ///< the robot's command space
  double base_period_s = 0.04;   ///< control period delta
  double frame_period_s = 0.04;  ///< vision period T = N delta
  double nominal_delay_frames = 0.0;  ///< vision latency in frames (TimingModel::nominalHorizonFrames())
  std::uint64_t seed = 1;        ///< the run's seed, for a law's random draws (e.g. model errors)
};

/// Everything the loop hands the task at one control tick (references valid during the call).
/// A feature the loop drops (lost.action: drop, servo/lost_feature_policy.h) is NaN in both
/// `measured` and `used` (its target rate 0); only a law with canDropFeatures() gets such input.
struct TaskInput {
  double t_s;                          ///< control tick time
  double t_acq_s;                      ///< acquisition time of `measured`
  const Eigen::VectorXd& measured;     ///< task features of the latest delivered measurement
  const Eigen::VectorXd& used;         ///< features to act on (measured, or the forecast at the effect time)
  const Eigen::VectorXd& target_rate;  ///< forecast target-induced feature rate (units/s); empty: no feed-forward
  const Eigen::VectorXd& depths_m;     ///< per point depth at acquisition (NaN when unknown)
  const Eigen::MatrixXd& robot_jacobian;  ///< 6 x m: camera twist (camera frame) per unit command, now
  const Eigen::VectorXd& robot_state;  ///< the robot's configuration as its encoders report it
  /// Ground truth for diagnostics only (never for control): d(true point features)/du, 2N x m, at
  /// the true geometry now.
  const Eigen::MatrixXd& true_point_jacobian;
};

/// A delivered measurement, in acquisition order, with the robot's integrated command
/// p(t_acq) = integral of the applied command up to the acquisition (joint positions on an arm).
struct TaskMeasurement {
  double t_acq_s;
  const Eigen::VectorXd& features;   ///< task features (NaN where lost)
  const Eigen::VectorXd& command_integral;  ///< p(t_acq)
  /// The predictor's estimate of the target-induced feature rate at t_acq, after fusing this
  /// frame (the velocity of s - E); empty when the loop has no prediction path.
  const Eigen::VectorXd& target_rate;
};

class Task {
 public:
  virtual ~Task() = default;

  /// Registry name, e.g. "ibvs".
  virtual std::string name() const = 0;
  /// Size of the feature vector (the predictor's channel count).
  virtual int featureSize() const = 0;
  /// Channel names ("u0", "v0", ... or "x_i", "y_i", "d_x").
  virtual std::vector<std::string> featureNames() const = 0;
  /// The task features of `points` (NaN entries where a needed point is lost).
  virtual Eigen::VectorXd features(const PointFeatures& points) const = 0;
  /// The goal s*.
  virtual const Eigen::VectorXd& desiredFeatures() const = 0;

  /// Called for every delivered measurement, in order, before the command of that tick.
  virtual void observe(const TaskMeasurement& /*m*/) {}
  /// The command of this tick, in the robot's command space (size context.command_space.size()).
  virtual Eigen::VectorXd computeCommand(const TaskInput& in) = 0;
  /// ds/du (featureSize() x m) the law used at its last computeCommand().
  virtual const Eigen::MatrixXd& featureJacobian() const = 0;

  /// Tracking error of features s (true features, for scoring): by default the RMS over points
  /// of the pixel distance ||s_i - s*_i|| (pairs of channels). A law with other features says
  /// what it uses.
  virtual double trackingError(const Eigen::VectorXd& s) const;
  /// Per-tick diagnostics of the last computeCommand() (the sliding variable, the Jacobian
  /// estimation error, the Lyapunov term, ...), always the same names in the same order.
  virtual NamedValues diagnostics() const { return {}; }
  /// Whether the law's diagnostics need TaskInput::true_point_jacobian (computing it costs a
  /// matrix product per tick, so the loop fills it only for a law that asks; otherwise empty).
  virtual bool needsTrueJacobian() const { return false; }
  /// Whether computeCommand() runs on the remaining features when some are NaN in
  /// TaskInput::measured / ::used (the loop's lost.action: drop): a point law then leaves out every
  /// point with a NaN coordinate. The loop refuses lost.action drop for a law that returns false
  /// (the default: a law whose features are all needed, e.g. a centroid and a width).
  virtual bool canDropFeatures() const { return false; }
  /// Per-run figures the law computes over the run (e.g. the fraction of time a Lyapunov bound
  /// holds); reported beside the loop's metrics.
  virtual NamedValues runSummary() const { return {}; }
};

/// One entry of the task registry.
using TaskInfo = RegistryInfo;

const std::vector<TaskInfo>& taskRegistry();
bool isTask(const std::string& name);
/// Builds task `name`. Throws std::invalid_argument naming an unknown task ("unknown task 'x'
/// (known: ...)"), an unknown or out-of-range parameter, or a robot the law cannot drive.
std::unique_ptr<Task> makeTask(const std::string& name, const Params& params, const TaskContext& context);

}  // namespace predvs
