// predvs — variable-structure (sliding-mode) point servoing with a discrete exponential reaching
// law and a scheduled gain (docs/MODELS.md §8; paper 000 §5, whose equations 20-29 are lost).
//
// Model (one control period T = context.base_period_s, features s = image points in pixels):
//     e(k) = s(k) - s*,     e(k+1) = e(k) + T J u(k) + T f_t(k),
// J = ds/du = L_px(s, Z) * robot_jacobian (2N x m; L_px the pixel interaction matrix of
// PointTask), f_t the forecast target-induced feature rate (px/s; empty = no predictor = zero).
// Sliding variable S = C e with C = diag(c_u, c_v, c_u, c_v, ...) > 0 (dimensionless, so S is in
// px). The discrete exponential reaching law with a boundary layer phi (no chattering):
//     S(k+1) = (1 - q T) S(k) - eps_s T sat(S(k) / phi),   sat = clamp to [-1, 1] per component,
// solved for the command through the model:
//     u(k) = (C T J)^+ [ (1 - q T) S(k) - eps_s T sat(S(k) / phi) - C (e(k) + T f_t(k)) ].
// The pseudo-inverse is exact where C T J is well conditioned: each singular value sigma_i of
// C T J is inverted as 1 / sigma_i when sigma_i >= r sigma_max (r = `rcond`) and damped as
// sigma_i / (r sigma_max)^2 below (continuous at the threshold, zero for sigma_i = 0). So the
// reaching law holds exactly for a square or wide full-rank J, in the least-squares sense for a
// tall J, and a singular J never throws. A point that is lost (NaN) or has no usable depth is
// left out of the step (zero rows of J and S).
//
// Gain schedule (the paper's C^-1 W remark: a small gain while the error is large, to avoid an
// excessive first motion, a larger one near the target, for a small final error). Chosen here:
//     q(|S|) = q_far + (q_near - q_far) / (1 + (|S| / s_half)^2),
// smooth in S, q_near at the goal, the midpoint at |S| = s_half, q_far far away; |S| is the RMS
// over the used points of the per-point norm |(S_u, S_v)| (px), so s_half does not depend on N.
// Inside the boundary layer the law acts as a linear contraction of rate q_eff = q + eps_s / phi:
// the parameters must satisfy (q_near + eps_s / phi) T < 1 (q <= q_near everywhere), so every
// component of S decays monotonically (no overshoot, no switching) and u is smooth near the goal.
// Without a feed-forward a target moving at image rate v leaves a steady error of v / q_eff (a
// type-1 loop: a constant delay of the measurement does not change this steady ramp error).
//
// Parameters (task.<key>, defaults): q_near = 4 /s, q_far = min(1 /s, q_near) (<= q_near),
// s_half = 50 px, eps_s = 10 px/s (>= 0), phi = 5 px (> 0), c = 1 (c_u, c_v default to c),
// rcond = 1e-3 in [1e-12, 0.5]. Defaults at T = 0.04 s: q_eff = 6 /s near the goal, contraction 0.76 per tick.
// The depth of a point is the measured one (in.depths_m) when finite and > 0, else the depth of
// the desired point, else the point is left out.
#pragma once

#include "predvs/tasks/point_task.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace predvs {

/// The VSC law's parameters, validated.
struct VscTaskConfig {
  double q_near_per_s = 4.0;  ///< q at the goal (1/s)
  double q_far_per_s = 1.0;   ///< q far from the goal (1/s), <= q_near; default min(1, q_near)
  double s_half_px = 50.0;    ///< |S| at which q is halfway between q_near and q_far
  double eps_px_per_s = 10.0; ///< constant reaching rate eps_s (px/s)
  double phi_px = 5.0;        ///< boundary layer width (px)
  double c_u = 1.0;           ///< C entry of the u channels
  double c_v = 1.0;           ///< C entry of the v channels
  double rcond = 1e-3;        ///< singular values below rcond * sigma_max are damped

  /// Reads task.<key> from `params` (see the file comment); throws std::invalid_argument naming
  /// the key for a value out of range or a (q, eps_s, phi, T) set that would not contract.
  static VscTaskConfig fromParams(const Params& params, double period_s);
  /// The scheduled gain q(|S|) (1/s).
  double gain(double sliding_norm_px) const;
};

class VscTask : public PointTask {
 public:
  /// Throws std::invalid_argument for a bad parameter (naming its key), an unknown parameter, an
  /// empty command space, or a non-positive control period.
  VscTask(const Params& params, const TaskContext& context);

  std::string name() const override { return "vsc"; }
  Eigen::VectorXd computeCommand(const TaskInput& in) override;
  const Eigen::MatrixXd& featureJacobian() const override { return J_; }
  bool canDropFeatures() const override { return true; }  ///< a point with a NaN coordinate is left out
  /// sliding_norm (|S|, px), s_u, s_v (S of the first point, px; 0 when lost), gain_q (1/s).
  NamedValues diagnostics() const override;
  /// sliding_rms_final: RMS of |S| over the last 10 % of the ticks (px; NaN before any tick).
  NamedValues runSummary() const override;

  const VscTaskConfig& config() const { return config_; }
  /// S = C (s - s*) of the last computeCommand() (0 on left-out points).
  const Eigen::VectorXd& slidingVariable() const { return S_; }

 private:
  VscTaskConfig config_;
  double period_s_;
  Eigen::MatrixXd J_;
  Eigen::VectorXd S_;
  double sliding_norm_px_ = 0.0;
  double gain_q_per_s_ = 0.0;
  std::vector<double> sliding_norm_history_;
};

}  // namespace predvs
