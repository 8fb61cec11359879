// predvs — a unicycle carrying a camera on a tilt joint (paper 001 §2, Fig. 1, appendix; docs/MODELS.md
// §10 E8).
//
// World frame: z up, the robot drives on the x-y plane. State q = (x, y, psi, phi): the ground
// position of the tilt axis (m), the heading psi (rad, 0 = along +x, positive turns left) and the
// tilt phi (rad, 0 = optical axis horizontal, positive looks UP, as the paper's tilt angle).
// Command u = (v, omega, omega_t): forward speed (m/s), turn rate (rad/s), tilt rate (rad/s), the
// paper's u = [v_f^m, w_f^m, w_t^m]. Kinematics (paper eq. 1):
//     xdot = v cos psi,  ydot = v sin psi,  psidot = omega,  phidot = omega_t.
// Geometry (paper Fig. 1(b), appendix eq. A.1): the tilt axis is horizontal and lateral, at height
// h above the ground over (x, y); the camera centre sits dy from the tilt axis along the camera's
// "up" axis (dy = the paper's delta_y, 10 cm). With f = (cos psi, sin psi, 0) and e_z up, the
// camera frame (ViSP: x right, y down, z optical axis) is
//     z_c = cos phi f + sin phi e_z,   y_c = sin phi f - cos phi e_z,   x_c = y_c x z_c (right),
//     O   = (x, y, h) + dy (cos phi e_z - sin phi f).
// Camera twist in the camera frame per unit command (cameraJacobian(), columns v, omega, omega_t):
//     v:       (0, sin phi, cos phi,  0, 0, 0)
//     omega:   (dy sin phi, 0, 0,      0, -cos phi, sin phi)
//     omega_t: (0, 0, -dy,             1, 0, 0)
// (the tilt turns about x_c; the negated translation part is the paper's B_c of eq. A.2 once its
// x-left / y-up axes are flipped to ViSP's x-right / y-down).
//
// limit() (paper §5.4 steps (4)-(6)): the command becomes wheel rim speeds v_l = v - L omega / 2,
// v_r = v + L omega / 2 (L the axle length, the paper's D = 40 cm) and the tilt rate; the triple
// (v_l, v_r, omega_t) is scaled by ONE factor so that |v_l|, |v_r| <= max wheel speed and
// |omega_t| <= max tilt rate (the direction of the command is kept), then each is quantised to its
// step: floor(value / step) * step as the paper's 8-bit card does (2.9925 -> 2 cm/s), or to the
// nearest step (quantisation: nearest); then converted back. The paper's acceleration limit needs
// the previous command and is not modelled (limit() is stateless).
#pragma once

#include "predvs/servo/robot.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace predvs {

/// Plain configuration (YAML: `robot.<key>`); 0 for a limit or a step means none.
struct UnicycleTiltConfig {
  double tilt_axis_height_m = 0.30;  ///< h: height of the tilt axis (not in the paper; choice)
  double camera_offset_y_m = 0.10;   ///< dy: tilt axis to camera centre (paper Table 1: 10 cm)
  double axle_length_m = 0.40;       ///< L: distance between the drive wheels (paper Table 1: D = 40 cm)
  /// 0: max_wheel_speed and wheel_speed_step are rim speeds in m/s (the paper's card commands
  /// linear wheel speeds); > 0: they are wheel angular speeds in rad/s (rim speed = radius * rate).
  double wheel_radius_m = 0.0;
  double max_wheel_speed = 0.0;      ///< paper's card: 1.27 m/s
  double wheel_speed_step = 0.0;     ///< paper's card: 0.01 m/s (integer cm/s)
  double max_tilt_rate_rad_s = 0.0;
  double tilt_rate_step_rad_s = 0.0;
  bool quantise_nearest = false;     ///< quantisation: floor (paper, default) | nearest
};

class UnicycleTiltRobot : public Robot {
 public:
  /// Keys: tilt_axis_height_m, camera_offset_y_m, axle_length_m, wheel_radius_m,
  /// max_wheel_speed, wheel_speed_step, max_tilt_rate_rad_s, tilt_rate_step_rad_s (numbers) and
  /// quantisation (floor | nearest). Unknown keys or bad values throw std::invalid_argument naming
  /// the key.
  explicit UnicycleTiltRobot(const Params& params = {});
  explicit UnicycleTiltRobot(const UnicycleTiltConfig& config);

  std::string name() const override { return "unicycle-tilt"; }
  const CommandSpace& commandSpace() const override { return space_; }

  /// Puts the robot at rest with the camera's optical axis along that of wMc: the heading is the
  /// azimuth of the optical axis and the tilt its elevation; the ground position is chosen so that
  /// the camera centre has the x-y position of wMc. What the kinematics cannot follow is dropped:
  /// the roll about the optical axis (the camera's x axis is always horizontal) and the height
  /// (the camera height is h + dy cos(tilt)). Throws std::invalid_argument (naming "reset pose")
  /// when the optical axis is within 1e-6 rad of vertical (heading undefined, tilt at +-90 deg).
  void reset(const vpHomogeneousMatrix& wMc) override;
  Eigen::VectorXd limit(const Eigen::VectorXd& command) const override;
  /// Exact integration for a constant command: the ground point moves on an arc of curvature
  /// omega / v (a chord of length v dt sinc(omega dt / 2) along psi + omega dt / 2).
  void step(const Eigen::VectorXd& command, double dt_s) override;

  vpHomogeneousMatrix cameraPose() const override;
  Eigen::MatrixXd cameraJacobian() const override;
  /// (x_m, y_m, heading_rad, tilt_rad).
  Eigen::VectorXd state() const override { return q_; }
  std::vector<std::string> stateNames() const override;

  /// Sets the state directly (tests, scenarios): (x, y, heading, tilt).
  void setState(const Eigen::Vector4d& q) { q_ = q; }
  const UnicycleTiltConfig& config() const { return config_; }

  /// Camera pose for a state q (the formula above).
  static vpHomogeneousMatrix cameraPoseAt(const Eigen::Vector4d& q, const UnicycleTiltConfig& config);

 private:
  UnicycleTiltConfig config_;
  CommandSpace space_;
  Eigen::Vector4d q_ = Eigen::Vector4d::Zero();
};

}  // namespace predvs
