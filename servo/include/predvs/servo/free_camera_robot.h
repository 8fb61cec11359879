// predvs — the free-flying camera (ViSP's vpSimulatorCamera) and the x-y stage carrying a camera.
//
// `free-camera`: the command is the camera twist (vx, vy, vz, wx, wy, wz) in the camera frame
// (m/s, rad/s), integrated by vpSimulatorCamera over each control period. Velocity limits
// (choice): vpRobot::saturateVelocities at max_translation_mps / max_rotation_radps, which scales
// the whole twist by the largest excess so that its direction is kept; vpSimulatorCamera's own
// defaults (0.2 m/s, 0.7 rad/s) are ours, because that is what a plain ViSP user gets.
// `saturation: 0` switches the limits off (the simulator's own limits are then lifted too).
//
// `xy-stage`: the same camera on a two-axis gantry that only translates it parallel to its image
// plane: the command is (vx, vy) in the camera frame, camera Jacobian [I2; 0] (paper 000's
// image-space follower plant M(k+1) = M(k) + T J u, with J = -diag(px, py) / Z for a point at depth Z).
// Its limit is max_translation_mps on the speed, direction kept.
#pragma once

#include "predvs/servo/robot.h"

#include <visp3/robot/vpSimulatorCamera.h>

namespace predvs {

class FreeCameraRobot : public Robot {
 public:
  /// Params: max_translation_mps (0.2), max_rotation_radps (0.7), saturation (1 = on, 0 = off).
  explicit FreeCameraRobot(const Params& params);
  std::string name() const override { return "free-camera"; }
  const CommandSpace& commandSpace() const override { return space_; }
  void reset(const vpHomogeneousMatrix& wMc) override;
  Eigen::VectorXd limit(const Eigen::VectorXd& command) const override;
  void step(const Eigen::VectorXd& command, double dt_s) override;
  vpHomogeneousMatrix cameraPose() const override { return sim_.getPosition(); }
  Eigen::MatrixXd cameraJacobian() const override { return Eigen::MatrixXd::Identity(6, 6); }
  Eigen::VectorXd state() const override;
  std::vector<std::string> stateNames() const override;

 private:
  CommandSpace space_;
  double max_translation_mps_, max_rotation_radps_;
  bool saturation_;
  vpSimulatorCamera sim_;
};

class XyStageRobot : public Robot {
 public:
  /// Params: max_translation_mps (0.2), saturation (1 = on, 0 = off).
  explicit XyStageRobot(const Params& params);
  std::string name() const override { return "xy-stage"; }
  const CommandSpace& commandSpace() const override { return space_; }
  void reset(const vpHomogeneousMatrix& wMc) override { wMc_ = wMc; }
  Eigen::VectorXd limit(const Eigen::VectorXd& command) const override;
  void step(const Eigen::VectorXd& command, double dt_s) override;
  vpHomogeneousMatrix cameraPose() const override { return wMc_; }
  Eigen::MatrixXd cameraJacobian() const override;
  Eigen::VectorXd state() const override;
  std::vector<std::string> stateNames() const override { return {"x_m", "y_m"}; }

 private:
  CommandSpace space_;
  double max_translation_mps_;
  bool saturation_;
  vpHomogeneousMatrix wMc_;
};

}  // namespace predvs
