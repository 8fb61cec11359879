// predvs — paper 001's visual tracking controller (VTC) for a unicycle with a tilt camera
// (paper 001 §2-3 and appendix; docs/MODELS.md §4, §10 E8).
//
// Features X = (x_i, y_i, d_x) in pixels, from the N points of the source (all of them are the
// target's outline, e.g. the 4 corners of a board):
//     x_i = mean(u_k) - u0,   y_i = mean(v_k) - v0,
//     d_x = max(u_k) - min(u_k)                     (width: range, the default: any outline)
//     d_x = 2 mean(|u_k - mean(u)|)                 (width: spread)
// (u0, v0) the principal point the controller believes. Any lost point makes all three NaN.
// Under zero-mean pixel noise the range is biased upwards: where two corners share a column
// (an upright board) max and min each pick the more extreme of two noisy values, +2a/3 px for
// uniform noise of half-width a, +1.13 sigma for Gaussian noise, a steady depth error no
// estimator can remove (the paper's d_x noise is zero-mean, its eq. 42). The spread equals the
// range exactly when the points lie on two columns symmetric about their mean (the corners of an
// upright rectangle parallel to the image) and is then unbiased to first order (a point's
// deviation keeps its sign unless the noise exceeds half the width); its noise is that of one
// coordinate, sigma, against about 1.17 sigma for the range. For a dense outline (a circle of
// points) it is not the width: keep the range there.
// Axes: x_i right and y_i DOWN as the pixels (the paper's y_i points up: its y_i is our -y_i; its
// eq. 18 below is written in our sign). The paper's model of these features is the projection of
// the target centre (X, Y, Z) in the camera frame and a width that depends on depth only:
//     x_i = fx X / Z,   y_i = fy Y / Z,   d_x = fx W / Z          (appendix eq. A.3),
// which the point features equal exactly for a symmetric outline parallel to the image plane (the
// board at the goal) and to first order in its tilt otherwise (perspective): that difference is a
// model error the law has to live with, like the paper's face.
//
// Robot image Jacobian B_i = dX/du, u = (v, omega, omega_t) (paper eq. 4, Box I, lost in our copy;
// re-derived from the appendix). The camera twist per unit command is the robot's (see
// servo/unicycle_tilt_robot.h: columns (0, s, c, 0, 0, 0), (dy s, 0, 0, 0, -c, s),
// (0, 0, -dy, 1, 0, 0), s = sin phi, c = cos phi, phi the tilt, dy the camera offset). A static
// point moves in the camera frame as P' = -v_c - w_c x P, so (x, y) = (X, Y) / Z follow the
// classic point interaction matrix and Z' = -v_z - Z (w_x y - w_y x), hence
// d_x' = d_x (v_z / Z + w_x y - w_y x). Multiplying out, with k = 1 / Z = d_x / (fx W),
// x = x_i / fx, y = y_i / fy:
//            v                       omega                                 omega_t
//   x_i [ x_i c k          fx ((y - dy k) s + (1 + x^2) c)           x_i (y - dy k)        ]
//   y_i [ fy k (y c - s)   fy x (y c - s)                            fy (1 + y^2 - dy k y) ]
//   d_x [ d_x c k          d_x x c                                   d_x (y - dy k)        ]
// Its determinant is det B_i = fx^2 fy W (Z c + (Y - dy) s)^2 / Z^4: B_i is singular exactly when
// the target centre has no horizontal forward offset from the tilt axis, Z cos phi + (Y - dy)
// sin phi = 0, i.e. fy = (S d_x - y_i) tan phi with S = fy dy / (fx W) (paper eqs. 18-19 in our
// y-down sign). The law evaluates B_i at the features it acts on (in.used) and the tilt the
// encoders report (in.robot_state(3)), with its own estimates of fx, fy, W, dy.
//
// Law (paper eqs. 5, 7, 13, 25): X_e = X_desired - X (desired minus current, paper eq. 5),
//     u = B_i^-1 (K_g X_e - Xdot_t),   K_g = diag(kg_x, kg_y, kg_d) (paper Table 1: 1/2, 3/4, 1/3),
// Xdot_t = in.target_rate (the forecast target-induced feature rate; zero when empty), so that
// Xdot = Xdot_t + B_i u = K_g X_e. Solved with a full-pivot LU, never an inverse.
// Robust form: under parameter errors the paper keeps the same law with the estimated parameters
// (eq. 25, Theorem 1: stable while min(K_g) > lambda_max(Q~), Q~ bounding delta f below); there
// is no alternative law to switch to. Its robust law against wheel-speed quantisation is in its
// ref. [25], not in the paper, and is not implemented.
// Near the singularity (|Z c + (Y - dy) s| / |P - C| < singular_tolerance, P - C the target seen
// from the tilt axis) or with lost features the robot stops (zero command): the paper's "the
// robot should stop tracking temporarily" (§3.2).
//
// Parameter errors (paper eq. 43): the controller uses fx (1 + rho_fx), fy (1 + rho_fy),
// W (1 + rho_W), dy (1 + rho_dy), fx, fy from the context's camera. With param_error = a > 0 the
// rhos are drawn once from U[-a, a] by std::mt19937_64 seeded with context.seed, in the order
// fx, fy, W, dy, independently, or one rho for all four with param_error_common = 1 (eq. 43 as
// written); an explicit rho_fx / rho_fy / rho_W / rho_dy replaces the draw for that parameter.
//
// Lyapunov terms (paper eqs. 14-15, 22, 45), at every tick where a command was computed, with
// V = |X_e|^2 / 2, Vdot = -f(u):
//     f_bar(u) = X_e' (Xdot_t + B_bar u)         (the law's own model: = X_e' K_g X_e)
//     delta f  = X_e' (B_bar - B) u              (B: B_i with the exact parameters)
//     f(u)     = f_bar - delta f = X_e' (Xdot_t + B u)                 diagnostic "lyap_f"
//     LB       = min(K_g) |X_e|^2 - delta f <= f(u)  (eq. 45)           diagnostic "lyap_bound"
// The target-rate error delta Xdot_t of eq. 22 is unknown to the law and taken as 0: f is the true
// Lyapunov decrease when the feed-forward is exact. u is the command the law sends (before the
// robot's limit()). runSummary(): lyap_bound_positive_fraction and lyap_f_positive_fraction over
// the ticks with a command, stopped_fraction over all ticks.
// trackingError(s): RMS of (x_e, y_e, d_e) in px, sqrt((x_e^2 + y_e^2 + d_e^2) / 3).
#pragma once

#include "predvs/tasks/task.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace predvs {

/// The controller's model parameters (fx, fy px; W, dy m).
struct VtcModel {
  double fx_px = 393.4;
  double fy_px = 391.8;
  double width_m = 0.12;
  double camera_offset_y_m = 0.10;
};

class VtcTask : public Task {
 public:
  /// Keys (defaults): kg_x 0.5, kg_y 0.75, kg_d 1/3 (1/s, > 0); desired_x_px 0, desired_y_px 0,
  /// desired_d_px 35; desired_source: params | points (points: features(context.desired_points));
  /// target_width_m 0.12; camera_offset_y_m 0.10; param_error 0 (in [0, 0.9]);
  /// param_error_common 0 | 1; rho_fx, rho_fy, rho_W, rho_dy (in [-0.9, 0.9]);
  /// singular_tolerance 0.02 (in [0, 1)); width: range | spread (d_x, header). fx, fy, u0, v0
  /// come from context.camera.
  /// Throws std::invalid_argument naming the key, or when context.command_space.kind is not
  /// "unicycle-tilt".
  VtcTask(const Params& params, const TaskContext& context);

  std::string name() const override { return "vtc"; }
  int featureSize() const override { return 3; }
  std::vector<std::string> featureNames() const override { return {"x_i", "y_i", "d_x"}; }
  Eigen::VectorXd features(const PointFeatures& points) const override;
  const Eigen::VectorXd& desiredFeatures() const override { return desired_; }

  /// Needs in.robot_state = (x, y, heading, tilt) (throws std::invalid_argument otherwise).
  Eigen::VectorXd computeCommand(const TaskInput& in) override;
  const Eigen::MatrixXd& featureJacobian() const override { return B_; }

  double trackingError(const Eigen::VectorXd& s) const override;
  /// "lyap_f", "lyap_bound", "lyap_f_bar", "stopped" (1 when the robot was stopped this tick).
  NamedValues diagnostics() const override;
  NamedValues runSummary() const override;

  /// B_i of the header at features X (px) and tilt phi (rad) for `model`.
  static Eigen::Matrix3d robotImageJacobian(const Eigen::Vector3d& X, double tilt_rad, const VtcModel& model);
  /// Z cos phi + (Y - dy) sin phi over |P - C| (the singularity indicator, in [-1, 1]).
  static double singularityIndicator(const Eigen::Vector3d& X, double tilt_rad, const VtcModel& model);

  const VtcModel& trueModel() const { return true_; }
  const VtcModel& estimatedModel() const { return estimated_; }

 private:
  TaskContext context_;
  VtcModel true_, estimated_;
  Eigen::Vector3d kg_;
  double singular_tolerance_;
  bool width_spread_ = false;  ///< width: spread (else range)
  Eigen::VectorXd desired_;
  Eigen::MatrixXd B_ = Eigen::MatrixXd::Zero(3, 3);
  double lyap_f_ = 0.0, lyap_bound_ = 0.0, lyap_f_bar_ = 0.0;
  bool stopped_ = true;
  long ticks_ = 0, control_ticks_ = 0, bound_positive_ = 0, f_positive_ = 0;
};

}  // namespace predvs
