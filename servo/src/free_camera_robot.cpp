#include "predvs/servo/free_camera_robot.h"

#include <visp3/core/vpColVector.h>
#include <visp3/robot/vpRobot.h>

#include <cmath>
#include <limits>

namespace predvs {
namespace {
// Relative margin of the simulator's own velocity limits over ours: the command is limited
// before it is queued; the simulator must neither rescale it again nor report the rounding-level
// excess.
constexpr double kSimulatorLimitMargin = 1e-6;
// Without saturation the simulator's limits are lifted to this (m/s, rad/s).
constexpr double kUnlimited = 1e12;
}  // namespace

FreeCameraRobot::FreeCameraRobot(const Params& params)
    : space_{"camera-twist", {"vx", "vy", "vz", "wx", "wy", "wz"}, {"m/s", "m/s", "m/s", "rad/s", "rad/s", "rad/s"}},
      max_translation_mps_(params.get("max_translation_mps", 0.2, 1e-9, 1e3)),
      max_rotation_radps_(params.get("max_rotation_radps", 0.7, 1e-9, 1e3)),
      saturation_(params.get("saturation", 1.0, 0.0, 1.0) != 0.0) {
  params.requireAllUsed("robot 'free-camera'");
  sim_.setMaxTranslationVelocity(saturation_ ? max_translation_mps_ * (1.0 + kSimulatorLimitMargin) : kUnlimited);
  sim_.setMaxRotationVelocity(saturation_ ? max_rotation_radps_ * (1.0 + kSimulatorLimitMargin) : kUnlimited);
}

void FreeCameraRobot::reset(const vpHomogeneousMatrix& wMc) {
  sim_.setVelocity(vpRobot::CAMERA_FRAME, vpColVector(6, 0.0));
  sim_.setPosition(wMc);
}

Eigen::VectorXd FreeCameraRobot::limit(const Eigen::VectorXd& command) const {
  if (!saturation_) return command;
  vpColVector v(6), v_max(6);
  for (int i = 0; i < 6; ++i) v[i] = command(i);
  for (int i = 0; i < 3; ++i) v_max[i] = max_translation_mps_;
  for (int i = 3; i < 6; ++i) v_max[i] = max_rotation_radps_;
  const vpColVector s = vpRobot::saturateVelocities(v, v_max);
  Eigen::VectorXd out(6);
  for (int i = 0; i < 6; ++i) out(i) = s[i];
  return out;
}

void FreeCameraRobot::step(const Eigen::VectorXd& command, double dt_s) {
  if (sim_.getSamplingTime() != dt_s) sim_.setSamplingTime(dt_s);
  vpColVector v(6);
  for (int i = 0; i < 6; ++i) v[i] = command(i);
  sim_.setVelocity(vpRobot::CAMERA_FRAME, v);
}

Eigen::VectorXd FreeCameraRobot::state() const {
  const vpHomogeneousMatrix wMc = sim_.getPosition();
  const vpThetaUVector tu(wMc.getRotationMatrix());
  Eigen::VectorXd q(6);
  for (int i = 0; i < 3; ++i) q(i) = wMc[i][3];
  for (int i = 0; i < 3; ++i) q(3 + i) = tu[i];
  return q;
}

std::vector<std::string> FreeCameraRobot::stateNames() const {
  return {"x_m", "y_m", "z_m", "thetaux_rad", "thetauy_rad", "thetauz_rad"};
}

XyStageRobot::XyStageRobot(const Params& params)
    : space_{"camera-xy", {"vx", "vy"}, {"m/s", "m/s"}},
      max_translation_mps_(params.get("max_translation_mps", 0.2, 1e-9, 1e3)),
      saturation_(params.get("saturation", 1.0, 0.0, 1.0) != 0.0) {
  params.requireAllUsed("robot 'xy-stage'");
}

Eigen::VectorXd XyStageRobot::limit(const Eigen::VectorXd& command) const {
  const double speed = command.norm();
  if (!saturation_ || speed <= max_translation_mps_) return command;
  return command * (max_translation_mps_ / speed);
}

void XyStageRobot::step(const Eigen::VectorXd& command, double dt_s) {
  // Translation (vx, vy) in the camera frame, expressed in the world by the camera's rotation.
  for (int r = 0; r < 3; ++r) wMc_[r][3] += (wMc_[r][0] * command(0) + wMc_[r][1] * command(1)) * dt_s;
}

Eigen::MatrixXd XyStageRobot::cameraJacobian() const {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, 2);
  J(0, 0) = J(1, 1) = 1.0;
  return J;
}

Eigen::VectorXd XyStageRobot::state() const {
  Eigen::VectorXd q(2);
  q << wMc_[0][3], wMc_[1][3];
  return q;
}

}  // namespace predvs
