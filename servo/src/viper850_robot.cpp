// predvs — robot "viper850" (see viper850_robot.h for the model and the choices).
#include "predvs/servo/viper850_robot.h"

#include <visp3/core/vpMatrix.h>
#include <visp3/core/vpVelocityTwistMatrix.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kHalfPi = 1.57079632679489661923;
constexpr double kPi = 3.14159265358979323846;
/// vpRobot::maxRotationVelocityDefault: the per-joint bound vpRobotViper850 applies (rad/s).
constexpr double kDefaultMaxJointSpeed_radps = 0.7;

bool allFinite(const Eigen::VectorXd& v) { return v.allFinite(); }

void requireSize6(const Eigen::VectorXd& command, const char* what) {
  if (command.size() != 6)
    throw std::invalid_argument(std::string("robot 'viper850': ") + what + " expects 6 joint velocities, got " +
                                std::to_string(command.size()));
}

}  // namespace

Viper850Robot::Viper850Robot(const Params& params)
    : command_space_{"joint-velocity",
                     {"qdot1_radps", "qdot2_radps", "qdot3_radps", "qdot4_radps", "qdot5_radps", "qdot6_radps"},
                     std::vector<std::string>(6, "rad/s")},
      q_visp_(6, 0.0) {
  model_.init(vpViper850::TOOL_PTGREY_FLEA2_CAMERA, vpCameraParameters::perspectiveProjWithoutDistortion);
  const vpColVector qmin = model_.getJointMin();
  const vpColVector qmax = model_.getJointMax();
  // vpSimulatorViper850's rest position (reposPos).
  const Joints q0_default = (Joints() << 0.0, -kHalfPi, kPi, 0.0, kHalfPi, 0.0).finished();
  for (int i = 0; i < 6; ++i) {
    const std::string j = std::to_string(i + 1);
    q_min_(i) = qmin[static_cast<unsigned>(i)];
    q_max_(i) = qmax[static_cast<unsigned>(i)];
    q0_(i) = params.get("q0_" + j, q0_default(i), q_min_(i), q_max_(i));
    qdot_max_(i) = params.get("max_qdot_" + j, kDefaultMaxJointSpeed_radps, 0.0, 1e3);
    if (!(qdot_max_(i) > 0.0))
      throw std::invalid_argument("robot 'viper850': parameter 'max_qdot_" + j + "' must be > 0");
  }
  saturation_ = params.get("saturation", 1.0, 0.0, 1.0) != 0.0;
  params.requireAllUsed("robot 'viper850'");
  reset(vpHomogeneousMatrix());
}

void Viper850Robot::reset(const vpHomogeneousMatrix& wMc) {
  q_ = q0_;
  updateKinematics();
  wMf_ = wMc * fMc_.inverse();
  wMc_ = wMc;  // = wMf_ fMc(q0) up to rounding; exact as requested
}

Eigen::VectorXd Viper850Robot::limit(const Eigen::VectorXd& command) const {
  requireSize6(command, "limit()");
  if (!allFinite(command)) return Eigen::VectorXd::Zero(6);
  // A joint resting on a limit does not execute a velocity that pushes it further (step() would
  // clamp it): drop that component, so that the command the loop integrates is the motion made.
  Eigen::VectorXd executed = command;
  for (int i = 0; i < 6; ++i)
    if ((q_(i) >= q_max_(i) && executed(i) > 0.0) || (q_(i) <= q_min_(i) && executed(i) < 0.0)) executed(i) = 0.0;
  if (!saturation_) return executed;
  double scale = 1.0;
  for (int i = 0; i < 6; ++i) {
    const double speed = std::abs(executed(i));
    if (speed > qdot_max_(i)) scale = std::min(scale, qdot_max_(i) / speed);
  }
  return scale * executed;
}

void Viper850Robot::step(const Eigen::VectorXd& command, double dt_s) {
  requireSize6(command, "step()");
  if (!(dt_s >= 0.0) || !std::isfinite(dt_s))
    throw std::invalid_argument("robot 'viper850': step() needs a finite dt_s >= 0");
  if (!allFinite(command)) return;  // a faulty command: hold still
  q_ = (q_ + command * dt_s).cwiseMax(q_min_).cwiseMin(q_max_);
  updateKinematics();
}

bool Viper850Robot::atLimit() const { return (q_.array() <= q_min_.array()).any() || (q_.array() >= q_max_.array()).any(); }

std::vector<std::string> Viper850Robot::stateNames() const { return {"q1", "q2", "q3", "q4", "q5", "q6"}; }

void Viper850Robot::updateKinematics() {
  for (unsigned i = 0; i < 6; ++i) q_visp_[i] = q_(static_cast<int>(i));
  model_.get_fMc(q_visp_, fMc_);
  wMc_ = wMf_ * fMc_;
  vpMatrix eJe;
  model_.get_eJe(q_visp_, eJe);
  vpVelocityTwistMatrix cVe;
  model_.get_cVe(cVe);
  const vpMatrix cJq = cVe * eJe;
  for (unsigned r = 0; r < 6; ++r)
    for (unsigned c = 0; c < 6; ++c) cJq_(static_cast<int>(r), static_cast<int>(c)) = cJq[r][c];
}

}  // namespace predvs
