// predvs — robot "viper850": an eye-in-hand 6-DOF arm (Adept Viper 850) in joint-velocity
// control, integrated from ViSP's kinematic model vpViper850 (forward kinematics fMc(q), joint
// Jacobian eJe(q), joint limits, the camera tool eMc).
//
// Model. Joint positions q (6, rad) follow the command qdot (rad/s), held constant over a step:
//     q(t + dt) = clamp(q(t) + qdot dt, q_min, q_max)
// (exact integration of a held joint velocity; a joint that reaches a limit stops there while the
// other joints keep moving — ViSP's threaded vpSimulatorViper850 instead stops the whole arm.)
// The camera pose and Jacobian follow from the joint positions:
//     wMc(q) = wMf fMc(q),        v_c = cVe eJe(q) qdot   (camera twist in the camera frame)
// where f is the robot's reference (base) frame, e its end-effector frame, cVe the constant twist
// transform of the tool. Limits and the tool are those of vpViper850 with the PTGrey Flea2 camera
// (vpViper850::TOOL_PTGREY_FLEA2_CAMERA, perspective projection without distortion), the camera
// ViSP's own Viper850 simulations mount.
//
// reset(wMc) puts the joints at q0 and places the base so that the camera is exactly at wMc:
//     wMf = wMc fMc(q0)^-1
// Default q0 = (0, -pi/2, pi, 0, pi/2, 0): the rest position ("reposPos") vpSimulatorViper850
// starts in, used by ViSP's servoSimuViper850FourPoints2DCamVelocity example. There the camera
// Jacobian's condition number (largest over smallest singular value, m/s and rad/s mixed) is
// about 9.4; the nearest limit is joint 5 at 30 degrees.
//
// Velocity limit. Each joint i has a maximal speed max_qdot_i; a command exceeding any of them is
// scaled as a whole, u' = s u with s = min(1, min_i max_qdot_i / |u_i|), so its direction in
// joint space (and hence the direction of the camera motion) is kept. This is exactly what ViSP's
// vpRobot::saturateVelocities does, which vpRobotViper850::setVelocity applies to joint
// velocities. Default max_qdot_i = 0.7 rad/s for every joint: vpRobot::maxRotationVelocityDefault,
// the bound vpRobotViper850 applies to each joint (joint 6 included) unless told otherwise. The
// arm's hardware can go faster; ViSP's sources give no per-joint datasheet speeds, so this
// software bound is the documented default.
//
// `saturation: 0` switches the speed scaling off (the command is executed at any speed), as the
// free camera's key of the same name does: docs/MODELS.md §11 E10 shows that a velocity bound alone can
// keep a single-rate loop convergent, so a reachability map is drawn without it. The joint limits
// stay (they are the arm's geometry, not a software bound).
//
// Parameters (all numbers; unknown keys rejected):
//   q0_1 .. q0_6       initial joint positions, rad, within vpViper850's joint limits
//   max_qdot_1 .. _6   per-joint speed bounds, rad/s, > 0 (default 0.7)
//   saturation         1 (default): scale to max_qdot_i; 0: no speed bound
//
// atLimit(): some joint rests on its limit (q_i == q_min_i or q_max_i, as step() clamps it); a
// positioning run counts that as a failure when it asks for outcomes (metrics.h).
//
// Joint limits in limit(). A joint resting on a limit cannot execute a velocity pushing it further
// (step() clamps it), so limit() sets that component to zero before the speed scaling: the command
// the loop integrates (its command integral p, the ego-motion E = integral of J u, and the task's
// online Jacobian increments, docs/MODELS.md §7) is then the motion the arm made, not a motion it refused.
// (Until this was added p kept growing while the joint stood still, which fed the Jacobian
// estimator increments dp the image never saw.) A joint that reaches its limit within a step still
// overshoots in p for that one step: limit() does not know the step's duration.
//
// A non-finite command (NaN, inf) is an expected fault inside the loop, not a configuration error:
// limit() turns it into a zero command and step() treats it as zero (the arm holds still).
#pragma once

#include "predvs/servo/robot.h"

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/robot/vpViper850.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace predvs {

class Viper850Robot : public Robot {
 public:
  using Joints = Eigen::Matrix<double, 6, 1>;

  /// Throws std::invalid_argument naming the key for an out-of-range or unknown parameter.
  explicit Viper850Robot(const Params& params = {});

  std::string name() const override { return "viper850"; }
  const CommandSpace& commandSpace() const override { return command_space_; }

  /// q = q0, wMf = wMc fMc(q0)^-1: the camera is exactly at wMc. Never throws.
  void reset(const vpHomogeneousMatrix& wMc) override;
  /// Zero for a joint pushed against the limit it rests on, then (with saturation) uniform scaling
  /// to the per-joint speed bounds (see the file comment). Throws std::invalid_argument if command
  /// is not of size 6.
  Eigen::VectorXd limit(const Eigen::VectorXd& command) const override;
  /// q <- clamp(q + command dt_s, q_min, q_max). Throws std::invalid_argument on a command of
  /// size other than 6 or a negative / non-finite dt_s.
  void step(const Eigen::VectorXd& command, double dt_s) override;
  /// Some joint at its lower or upper limit.
  bool atLimit() const override;

  vpHomogeneousMatrix cameraPose() const override { return wMc_; }
  /// cVe eJe(q), 6 x 6.
  Eigen::MatrixXd cameraJacobian() const override { return cJq_; }
  /// Joint positions q1..q6 (rad).
  Eigen::VectorXd state() const override { return q_; }
  std::vector<std::string> stateNames() const override;

  const Joints& jointPositions() const { return q_; }
  const Joints& initialJointPositions() const { return q0_; }
  const Joints& jointMin() const { return q_min_; }
  const Joints& jointMax() const { return q_max_; }
  const Joints& maxJointSpeeds() const { return qdot_max_; }
  /// Whether limit() scales the command to maxJointSpeeds() (parameter `saturation`).
  bool saturation() const { return saturation_; }
  /// Pose of the robot's reference frame f in the world, set by reset().
  const vpHomogeneousMatrix& baseInWorld() const { return wMf_; }
  /// The ViSP kinematic model used (tool: PTGrey Flea2).
  const vpViper850& model() const { return model_; }

 private:
  /// Recomputes fMc_, wMc_ and cJq_ from q_.
  void updateKinematics();

  CommandSpace command_space_;
  vpViper850 model_;
  Joints q0_, q_min_, q_max_, qdot_max_;
  bool saturation_ = true;
  Joints q_;
  vpHomogeneousMatrix wMf_;
  vpHomogeneousMatrix fMc_;
  vpHomogeneousMatrix wMc_;
  Eigen::Matrix<double, 6, 6> cJq_;
  vpColVector q_visp_;  ///< scratch for ViSP calls
};

}  // namespace predvs
