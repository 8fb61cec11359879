#include "predvs/servo/unicycle_tilt_robot.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace predvs {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Optical axis closer than this to the vertical: the heading is undefined (reset() throws).
constexpr double kVerticalAxisTolerance = 1e-6;

UnicycleTiltConfig configFrom(const Params& params) {
  UnicycleTiltConfig c;
  c.tilt_axis_height_m = params.get("tilt_axis_height_m", c.tilt_axis_height_m, -1e3, 1e3);
  c.camera_offset_y_m = params.get("camera_offset_y_m", c.camera_offset_y_m, -1e3, 1e3);
  c.axle_length_m = params.get("axle_length_m", c.axle_length_m, 1e-6, 1e3);
  c.wheel_radius_m = params.get("wheel_radius_m", c.wheel_radius_m, 0.0, 1e3);
  c.max_wheel_speed = params.get("max_wheel_speed", c.max_wheel_speed, 0.0, kInf);
  c.wheel_speed_step = params.get("wheel_speed_step", c.wheel_speed_step, 0.0, kInf);
  c.max_tilt_rate_rad_s = params.get("max_tilt_rate_rad_s", c.max_tilt_rate_rad_s, 0.0, kInf);
  c.tilt_rate_step_rad_s = params.get("tilt_rate_step_rad_s", c.tilt_rate_step_rad_s, 0.0, kInf);
  const std::string q = params.text("quantisation", "floor");
  if (q != "floor" && q != "nearest")
    throw std::invalid_argument("robot 'unicycle-tilt': quantisation must be floor or nearest, got '" + q + "'");
  c.quantise_nearest = q == "nearest";
  params.requireAllUsed("robot 'unicycle-tilt'");
  return c;
}

void checkConfig(const UnicycleTiltConfig& c) {
  auto bad = [](const char* key) { throw std::invalid_argument(std::string("robot 'unicycle-tilt': bad ") + key); };
  if (!std::isfinite(c.tilt_axis_height_m)) bad("tilt_axis_height_m");
  if (!std::isfinite(c.camera_offset_y_m)) bad("camera_offset_y_m");
  if (!(c.axle_length_m > 0.0) || !std::isfinite(c.axle_length_m)) bad("axle_length_m");
  if (!(c.wheel_radius_m >= 0.0) || !std::isfinite(c.wheel_radius_m)) bad("wheel_radius_m");
  if (!(c.max_wheel_speed >= 0.0)) bad("max_wheel_speed");
  if (!(c.wheel_speed_step >= 0.0)) bad("wheel_speed_step");
  if (!(c.max_tilt_rate_rad_s >= 0.0)) bad("max_tilt_rate_rad_s");
  if (!(c.tilt_rate_step_rad_s >= 0.0)) bad("tilt_rate_step_rad_s");
}

// sin(a) / a, with its series near 0.
double sinc(double a) { return std::abs(a) < 1e-4 ? 1.0 - a * a / 6.0 : std::sin(a) / a; }

}  // namespace

UnicycleTiltRobot::UnicycleTiltRobot(const Params& params) : UnicycleTiltRobot(configFrom(params)) {}

UnicycleTiltRobot::UnicycleTiltRobot(const UnicycleTiltConfig& config)
    : config_(config), space_{"unicycle-tilt", {"v_m_s", "omega_rad_s", "tilt_rate_rad_s"}, {"m/s", "rad/s", "rad/s"}} {
  checkConfig(config_);
}

std::vector<std::string> UnicycleTiltRobot::stateNames() const { return {"x_m", "y_m", "heading_rad", "tilt_rad"}; }

vpHomogeneousMatrix UnicycleTiltRobot::cameraPoseAt(const Eigen::Vector4d& q, const UnicycleTiltConfig& config) {
  const double cpsi = std::cos(q(2)), spsi = std::sin(q(2)), cphi = std::cos(q(3)), sphi = std::sin(q(3));
  const Eigen::Vector3d f(cpsi, spsi, 0.0), ez(0.0, 0.0, 1.0);
  const Eigen::Vector3d zc = cphi * f + sphi * ez;
  const Eigen::Vector3d yc = sphi * f - cphi * ez;
  const Eigen::Vector3d xc = yc.cross(zc);
  const Eigen::Vector3d O =
      Eigen::Vector3d(q(0), q(1), config.tilt_axis_height_m) + config.camera_offset_y_m * (cphi * ez - sphi * f);
  vpHomogeneousMatrix wMc;
  for (unsigned r = 0; r < 3; ++r) {
    wMc[r][0] = xc(r);
    wMc[r][1] = yc(r);
    wMc[r][2] = zc(r);
    wMc[r][3] = O(r);
  }
  return wMc;
}

vpHomogeneousMatrix UnicycleTiltRobot::cameraPose() const { return cameraPoseAt(q_, config_); }

Eigen::MatrixXd UnicycleTiltRobot::cameraJacobian() const {
  const double cphi = std::cos(q_(3)), sphi = std::sin(q_(3)), dy = config_.camera_offset_y_m;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(6, 3);
  J.col(0) << 0.0, sphi, cphi, 0.0, 0.0, 0.0;
  J.col(1) << dy * sphi, 0.0, 0.0, 0.0, -cphi, sphi;
  J.col(2) << 0.0, 0.0, -dy, 1.0, 0.0, 0.0;
  return J;
}

void UnicycleTiltRobot::reset(const vpHomogeneousMatrix& wMc) {
  const Eigen::Vector3d zc(wMc[0][2], wMc[1][2], wMc[2][2]);
  const double horizontal = std::hypot(zc(0), zc(1));
  if (horizontal < kVerticalAxisTolerance)
    throw std::invalid_argument(
        "robot 'unicycle-tilt': reset pose has a vertical optical axis (tilt +-90 deg, heading undefined)");
  const double psi = std::atan2(zc(1), zc(0));
  const double phi = std::atan2(zc(2), horizontal);
  // Camera centre O = G + dy (cos phi e_z - sin phi f): the ground point G keeps O's x-y position.
  const Eigen::Vector2d f(std::cos(psi), std::sin(psi));
  const Eigen::Vector2d G = Eigen::Vector2d(wMc[0][3], wMc[1][3]) + config_.camera_offset_y_m * std::sin(phi) * f;
  q_ << G(0), G(1), psi, phi;
}

Eigen::VectorXd UnicycleTiltRobot::limit(const Eigen::VectorXd& command) const {
  if (command.size() != 3)
    throw std::invalid_argument("robot 'unicycle-tilt': a command has 3 components, got " +
                                std::to_string(command.size()));
  if (!command.allFinite()) return Eigen::VectorXd::Zero(3);  // a broken command stops the robot
  const double L = config_.axle_length_m;
  // Wheel speeds in the units of the limits: rim speed (m/s), or rad/s when a radius is given.
  const double to_wheel = config_.wheel_radius_m > 0.0 ? 1.0 / config_.wheel_radius_m : 1.0;
  double vl = (command(0) - L * command(1) / 2.0) * to_wheel;
  double vr = (command(0) + L * command(1) / 2.0) * to_wheel;
  double wt = command(2);

  double scale = 1.0;
  const double wheel_peak = std::max(std::abs(vl), std::abs(vr));
  if (config_.max_wheel_speed > 0.0 && wheel_peak > config_.max_wheel_speed)
    scale = std::min(scale, config_.max_wheel_speed / wheel_peak);
  if (config_.max_tilt_rate_rad_s > 0.0 && std::abs(wt) > config_.max_tilt_rate_rad_s)
    scale = std::min(scale, config_.max_tilt_rate_rad_s / std::abs(wt));
  vl *= scale;
  vr *= scale;
  wt *= scale;

  const bool nearest = config_.quantise_nearest;
  auto quantise = [nearest](double value, double step) {
    if (step <= 0.0) return value;
    return step * (nearest ? std::round(value / step) : std::floor(value / step));
  };
  vl = quantise(vl, config_.wheel_speed_step);
  vr = quantise(vr, config_.wheel_speed_step);
  wt = quantise(wt, config_.tilt_rate_step_rad_s);

  Eigen::VectorXd out(3);
  out << (vl + vr) / (2.0 * to_wheel), (vr - vl) / (L * to_wheel), wt;
  return out;
}

void UnicycleTiltRobot::step(const Eigen::VectorXd& command, double dt_s) {
  if (command.size() != 3)
    throw std::invalid_argument("robot 'unicycle-tilt': a command has 3 components, got " +
                                std::to_string(command.size()));
  const double v = command(0), omega = command(1), omega_t = command(2);
  const double half_turn = omega * dt_s / 2.0;
  const double chord = v * dt_s * sinc(half_turn);
  q_(0) += chord * std::cos(q_(2) + half_turn);
  q_(1) += chord * std::sin(q_(2) + half_turn);
  q_(2) += omega * dt_s;
  q_(3) += omega_t * dt_s;
}

}  // namespace predvs
