// predvs tests — reference trajectories of the papers' simulation studies (header only, Eigen).
// The servo layer has these as trajectory types (servo/paper_trajectories.h: e6-target,
// onset-sinusoid); tests/predictors cannot include servo, so this copy stays, and
// tests/servo/paper_trajectories_test.cpp checks that both give the same E6 samples.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <random>
#include <vector>

namespace predvs {
namespace paper {

/// E6 (docs/MODELS.md §10, paper 001 §5.1-5.2): a target moving in a horizontal plane, seen by a static
/// pinhole camera, observed as Xi = [x_i, y_i, d_x] (image centroid and image width, px).
///
/// Target motion (paper 001 eq. 44), in cm and cm/s, camera frame (x right, y down, z forward):
///   V(n) = v(n) [-sin th(n), 0, cos th(n)],  v(n) = v0 cos(n pi T / 20),  th(n) = th(n-1) + T w,
/// (minus: the paper's x axis points left, so its target turns to the left of the camera), with
/// v0 = 15 cm/s, w = 5 pi / 72 rad/s, th(0) = 0; the position is integrated as in the paper's
/// discrete model, P(n) = P(n-1) + T V(n-1).
/// Image: x_i = fx X / Z, y_i = fy Y / Z, d_x = fx W / Z, and the ideal image velocity is the
/// time derivative of these at V(n) (the target image velocity Jt Vt of paper 001 eq. 4).
///
/// Camera placement (choice, documented): the camera is static at the origin looking along +z,
/// the target starts on the optical axis at the depth where its width is the paper's desired
/// d_x = 35 px (Z0 = fx W / 35 = 134.9 cm) and 10 cm below it (the paper's camera offset
/// delta_y), so that y_i is non-zero and changes with depth. Over 20 s the target then moves
/// about 95 cm along a curve and stays in front of the camera.
struct E6Config {
  double period_s = 0.1;
  double duration_s = 20.0;
  double fx_px = 393.4;
  double fy_px = 391.8;
  double width_cm = 12.0;
  double v0_cm_s = 15.0;
  double turn_rate_rad_s = 5.0 * M_PI / 72.0;
  double x0_cm = 0.0;
  double y0_cm = 10.0;
  double z0_cm = 393.4 * 12.0 / 35.0;
};

struct E6Trajectory {
  std::vector<double> t_s;
  std::vector<Eigen::Vector3d> X_px;        ///< [x_i, y_i, d_x]
  std::vector<Eigen::Vector3d> Xdot_px_s;   ///< ideal image velocity
};

inline E6Trajectory e6Trajectory(const E6Config& cfg = E6Config{}) {
  E6Trajectory out;
  const int n_samples = static_cast<int>(std::lround(cfg.duration_s / cfg.period_s)) + 1;
  Eigen::Vector3d P(cfg.x0_cm, cfg.y0_cm, cfg.z0_cm);
  double heading = 0.0;
  for (int n = 0; n < n_samples; ++n) {
    const double T = cfg.period_s;
    const double speed = cfg.v0_cm_s * std::cos(n * M_PI * T / 20.0);
    const Eigen::Vector3d V(-speed * std::sin(heading), 0.0, speed * std::cos(heading));
    const double X = P.x(), Y = P.y(), Z = P.z();
    out.t_s.push_back(n * T);
    out.X_px.emplace_back(cfg.fx_px * X / Z, cfg.fy_px * Y / Z, cfg.fx_px * cfg.width_cm / Z);
    out.Xdot_px_s.emplace_back(cfg.fx_px * (V.x() * Z - X * V.z()) / (Z * Z), -cfg.fy_px * Y * V.z() / (Z * Z),
                               -cfg.fx_px * cfg.width_cm * V.z() / (Z * Z));
    P += T * V;
    heading += T * cfg.turn_rate_rad_s;
  }
  return out;
}

/// The paper's measurement: round(X + sigma_n (2 w - 1)) with w ~ U[0, 1] per entry
/// (paper 001 eq. 42; uniform noise of variance sigma_n^2 / 3, then integer pixels).
inline Eigen::Vector3d e6Measure(const Eigen::Vector3d& X_px, double sigma_n, std::mt19937& rng) {
  std::uniform_real_distribution<double> w(0.0, 1.0);
  Eigen::Vector3d z;
  for (int i = 0; i < 3; ++i) z(i) = std::round(X_px(i) + sigma_n * (2.0 * w(rng) - 1.0));
  return z;
}

/// E12 (docs/MODELS.md §10, paper 004 §5): a target at rest at 0 until t_start_s, then moving on a
/// sinusoid x(t) = A sin(2 pi (t - t_start) / period) (metres). Position is continuous at the
/// start, the velocity jumps from 0 to 2 pi A / period (4.19 m/s for A = 2 m, period 3 s).
struct E12Config {
  double amplitude_m = 2.0;
  double period_s = 3.0;
  double t_start_s = 1.0;
};

inline double e12Position(const E12Config& cfg, double t_s) {
  if (t_s < cfg.t_start_s) return 0.0;
  return cfg.amplitude_m * std::sin(2.0 * M_PI * (t_s - cfg.t_start_s) / cfg.period_s);
}

}  // namespace paper
}  // namespace predvs
