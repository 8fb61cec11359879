// predvs — N-channel target signals for the open-loop experiments, including the papers' own
// simulation set-ups (docs/MODELS.md §10: E6 / E7 of paper 001, E12 of paper 004).
//
// A ChannelTrajectory is what a camera would measure of a target, channel by channel (E6: the
// image centroid x_i, y_i and the apparent width d_x, px; E12: one position in mm), with the exact
// time derivative of every channel. The planar trajectories of trajectory.h are 2-channel
// ChannelTrajectories (x, y) through makeChannelTrajectory().
//
// Names, keys and defaults (paper values where the paper gives one):
//   e6-target        (3 channels: x_i, y_i, d_x in px; paper 001 §5.1-5.2, eq. 44)
//     Motion in cm and cm/s in the camera frame (x right, y down, z forward):
//       V(n) = v(n) [-sin th(n), 0, cos th(n)],  v(n) = v0 cos(n pi T / 20),  th(n) = th(n-1) + T w,
//     th(0) = 0, integrated as the paper's discrete model P(n) = P(n-1) + T V(n-1). The paper writes
//     the velocity as (v sin th, 0, v cos th) in its frame x LEFT, y up, z forward (its appendix:
//     x_i = -fx x_c / z_c points right, so its x_c points left), hence the minus sign here: the
//     target turns to the left, x_i decreases (e8-target in trajectory.h is the same motion in the
//     plane). An earlier version had +, a mirror image; the E6/E7 statistics are symmetric
//     under that mirror, only their per-seed values changed. Between the samples n T the target
//     moves on the straight segment at V(n), so the samples are exact and the signal is defined
//     at any t >= 0.
//     Image of a static pinhole camera: x_i = fx X / Z, y_i = fy Y / Z, d_x = fx W / Z; the
//     velocity is the exact time derivative of these (the target image velocity of paper 001 eq. 4).
//     Keys: period_s = 0.1 (T of eq. 44), fx = 393.4, fy = 391.8 (px), width_cm = 12 (W),
//     v0_cm_s = 15, turn_rate_rad_s = 5 pi / 72, x0_cm = 0, y0_cm = 10,
//     z0_cm = fx W / 35 = 134.9.
//     Camera placement (choice): the paper's camera follows the target; here it is static at the
//     origin looking along +z. The target starts on the optical axis at the depth where its width
//     is the paper's desired d_x = 35 px, 10 cm below the axis (the paper's camera offset
//     delta_y), so that y_i is non-zero and changes with depth. Over 20 s it moves about 95 cm on
//     a curve and stays in front of the camera (Z >= 134.9 cm).
//   onset-sinusoid   (1 channel: x; paper 004 §5)
//     x(t) = x0 for t < t_start, x0 + amplitude sin(2 pi (t - t_start) / period) after: a target
//     at rest that suddenly starts to oscillate; the position is continuous at t_start, the
//     velocity jumps from 0 to 2 pi amplitude / period.
//     Keys: x0 = 0, amplitude = 2000, period = 3 (s), t_start = 1 (s). Units are the caller's;
//     the E12 scenarios work in mm (2000 mm = the paper's 2 m), so that the predictors' default
//     tunings, made for about 1 unit of measurement noise, fit a 1 mm noise.
//   any name of trajectoryNames() (2 channels: x, y; trajectory.h)
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/servo/trajectory.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace predvs {

class ChannelTrajectory {
 public:
  virtual ~ChannelTrajectory() = default;
  /// Registry name, e.g. "e6-target".
  virtual std::string name() const = 0;
  /// Names of the channels, e.g. {"x_i", "y_i", "d_x"}; their count is channels().
  virtual const std::vector<std::string>& channelNames() const = 0;
  int channels() const { return static_cast<int>(channelNames().size()); }
  /// Value of every channel at t_s.
  virtual Eigen::VectorXd position(double t_s) const = 0;
  /// Exact time derivative of position() at t_s (right derivative at a switching instant).
  virtual Eigen::VectorXd velocity(double t_s) const = 0;
  /// Time at which a discontinuity of the motion starts (onset-sinusoid: t_start), NaN if none.
  virtual double onsetTime() const;
  /// The motion's manoeuvre (trajectory.h; onset-sinusoid: the onset, along the initial motion;
  /// a planar trajectory: its own; e6-target: none).
  virtual Manoeuvre manoeuvre() const { return {}; }
};

/// Names accepted by makeChannelTrajectory: e6-target, onset-sinusoid, then trajectoryNames().
std::vector<std::string> channelTrajectoryNames();
/// Builds `name` from `params` (keys above; unknown keys and bad values throw
/// std::invalid_argument naming the key, an unknown name lists the known ones).
std::unique_ptr<ChannelTrajectory> makeChannelTrajectory(const std::string& name, const Params& params = {});

/// Configuration of e6-target (the keys above, in the same units).
struct E6TargetConfig {
  double period_s = 0.1;
  double fx_px = 393.4;
  double fy_px = 391.8;
  double width_cm = 12.0;
  double v0_cm_s = 15.0;
  double turn_rate_rad_s = 5.0 * 3.14159265358979323846 / 72.0;
  double x0_cm = 0.0;
  double y0_cm = 10.0;
  double z0_cm = 393.4 * 12.0 / 35.0;
};

/// e6-target as a class (tests and benchmarks use it directly).
class E6TargetTrajectory : public ChannelTrajectory {
 public:
  /// Throws std::invalid_argument for a non-positive period, focal length, width or depth.
  explicit E6TargetTrajectory(const E6TargetConfig& config = {});
  std::string name() const override { return "e6-target"; }
  const std::vector<std::string>& channelNames() const override;
  Eigen::VectorXd position(double t_s) const override;
  Eigen::VectorXd velocity(double t_s) const override;
  /// Target position (cm) and velocity (cm/s) in the camera frame at t_s.
  Eigen::Vector3d targetPositionCm(double t_s) const;
  Eigen::Vector3d targetVelocityCmS(double t_s) const;
  const E6TargetConfig& config() const { return config_; }

 private:
  /// Sample index n with n T <= t < (n + 1) T (clamped to >= 0), extending the table as needed.
  size_t segment(double t_s) const;
  E6TargetConfig config_;
  // P(n) and V(n) of eq. 44, computed up to the largest n asked for (mutable cache; the
  // trajectory is not shared between threads).
  mutable std::vector<Eigen::Vector3d> P_cm_, V_cm_s_;
  mutable double heading_rad_ = 0.0;
};

}  // namespace predvs
