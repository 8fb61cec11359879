// predvs — online estimation of a feature Jacobian J = df/dp from paired increments
// (docs/MODELS.md §7; paper 002 §2, eqs. 3-4; Piepmeier, McMurray & Lipkin, IEEE T-RA 20(1), 2004).
//
// Eigen only (no ViSP): the estimator knows nothing of cameras or robots. f (n features) and p
// (m inputs, the integral of the robot command: joint angles on an arm, the integrated camera
// twist on a free camera) are related locally by
//     df = J dp + ft dt + noise,
// where ft is the feature rate the target causes by itself (zero for a static target) and dt the
// time between the two samples of the increment. Each update corrects J by the residual
//     r = df - J dp - ft dt
// projected on dp:
//   * broyden (dynamic Broyden, the secant update):
//         J <- J + r dp' / (dp' dp)
//     J then reproduces the last increment exactly; no memory of older directions beyond J itself.
//   * rls (recursive least squares with forgetting factor lambda in (0, 1], covariance P, m x m):
//         g = P dp / (lambda + dp' P dp)
//         J <- J + r g'
//         P <- (P - P dp dp' P / (lambda + dp' P dp)) / lambda
//     J minimises sum_k lambda^(K-k) |df_k - J dp_k - ft_k dt_k|^2 (+ the prior J0, P0); lambda < 1
//     forgets old increments so a changing J is tracked, lambda = 1 is plain RLS.
//
// Choices the paper leaves open, ours and documented here (the estimator's equations: docs/MODELS.md §7):
//  * No excitation: when |dp| (Euclidean norm in p's units) < min_dp the update is skipped (J and
//    P untouched) and update() returns false. A still robot teaches nothing and, with lambda < 1,
//    would only inflate P.
//  * Lost features: rows whose df (or ft) entry is not finite are left untouched; the other rows
//    are updated with the same gain. P (which describes the inputs, shared by all rows) is
//    updated once. If no row is finite, or dp is not finite, the update is skipped.
//  * Windup: with lambda < 1 and excitation along few directions, P grows as lambda^-k in the
//    unexcited directions. Cap: P is kept symmetric (averaged with its transpose after every
//    update) and its eigenvalues are clipped to [1e-12 cap, cap], cap = the largest eigenvalue of
//    P0: in no direction is the estimator less certain than at its start, and round-off cannot
//    make P indefinite. Clipping eigenvalues (rather than scaling the whole of P back to a trace,
//    tried first) bounds only the unexcited directions: a uniform scaling let the growing
//    directions starve the excited one, whose gain then went to zero and learning stopped.
//    If P stops being finite it is reset to P0 (J kept).
#pragma once

#include <Eigen/Core>

#include <string>

namespace predvs {

/// The update rule (word `method`).
enum class JacobianMethod { Broyden, Rls };
/// "broyden" | "rls"; throws std::invalid_argument naming `key`.
JacobianMethod parseJacobianMethod(const std::string& name, const std::string& key = "method");
std::string jacobianMethodName(JacobianMethod method);

struct JacobianEstimatorConfig {
  JacobianMethod method = JacobianMethod::Rls;
  double lambda = 0.95;  ///< forgetting factor in (0, 1] (rls only)
  double min_dp = 1e-9;  ///< skip the update when |dp| < min_dp (p's units), >= 0
};

class JacobianEstimator {
 public:
  /// n features, m inputs (both >= 1). Starts at J = 0, P = I. Throws std::invalid_argument on
  /// sizes or on lambda outside (0, 1] ('lambda', quoted) or a negative / non-finite min_dp ('min_dp').
  JacobianEstimator(int features, int inputs, const JacobianEstimatorConfig& config = {});

  /// Restarts from J0 (n x m) and P0 (m x m, symmetric positive definite; ignored by broyden but
  /// kept). Throws std::invalid_argument on sizes or a non-finite entry.
  void reset(const Eigen::MatrixXd& J0, const Eigen::MatrixXd& P0);
  /// Same with P0 = p0 I (p0 > 0).
  void reset(const Eigen::MatrixXd& J0, double p0);

  /// One update from the increment (df, dp) observed over dt_s, with the target-induced feature
  /// rate ft (size n, or empty for zero). Returns whether J changed (false: no excitation or
  /// nothing finite). Never throws for data (sizes are checked: std::invalid_argument).
  bool update(const Eigen::VectorXd& df, const Eigen::VectorXd& dp, const Eigen::VectorXd& ft, double dt_s);

  const Eigen::MatrixXd& jacobian() const { return J_; }
  const Eigen::MatrixXd& covariance() const { return P_; }
  const JacobianEstimatorConfig& config() const { return config_; }
  int features() const { return static_cast<int>(J_.rows()); }
  int inputs() const { return static_cast<int>(J_.cols()); }
  /// Number of updates applied since the last reset.
  long updates() const { return updates_; }
  /// Number of times P's eigenvalues were clipped, or P was reset after becoming non-finite.
  long covarianceCaps() const { return caps_; }

 private:
  JacobianEstimatorConfig config_;
  Eigen::MatrixXd J_, P_, P0_;
  double eigen_cap_ = 0.0;
  long updates_ = 0;
  long caps_ = 0;
};

}  // namespace predvs
