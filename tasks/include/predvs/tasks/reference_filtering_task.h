// predvs — paper 003's single- and dual-rate IBVS laws, with and without reference filtering
// (paper 003 §2.2-§3.3, Algorithms 1-5; docs/MODELS.md §9, §10 E10-E11).
//
// Features. Each point i is f_i = (x_i, y_i, Z_i): normalised image coordinates x = (u - u0) / px,
// y = (v - v0) / py (the controller's intrinsics) and depth (paper §2.2). The loop hands the task
// pixels (PointTask) and the depths at acquisition; the `depth` parameter replaces the depth by a
// constant (E11): then every point of s and of s* is at that depth, the controller's belief.
// Interaction matrix of a point with the depth row (paper eq. 2):
//     L_f = [ -1/Z   0    x/Z   x y      -(1 + x^2)   y ]
//           [  0   -1/Z   y/Z   1 + y^2  -x y        -x ]
//           [  0    0    -1    -y Z      x Z          0 ]
// stacked over the n points (3n x 6) and evaluated at the CURRENT features, the DESIRED ones or
// the MEAN of the two matrices (`interaction`, as `ibvs`). J = L J_c (3n x m) with J_c the robot's
// camera Jacobian (6 x m, camera twist per unit command; the identity on the free-flying camera).
//
// Law (paper eq. 3, "a pure image-based controller"): u = -lambda (H J)^+ H (s - s_ref),
// H = blockdiag(diag(1, 1, 0)): the depth is neither servoed nor constrained, so with s_ref = s*
// this is exactly classic IBVS of the points (the `ibvs` task, tested equal). Choice: eq. 3 reads
// J^+ H; keeping the depth rows in J (`depth_rows = 1`) makes the least-squares command also hold
// every depth still, which turns the 150 deg task into a pure rotation for every law (measured on
// the test plant, N = 8, one frame of latency: sr-lf-ibvs then converges up to lambda = 6, while
// the classic law the paper compares against fails from 1.4, docs/MODELS.md §11). The pseudo-inverse is
// an SVD with singular values below kPinvRelTolerance of the largest dropped.
//
// The five laws (the paper's names, §2.3), T = N delta the frame period, h the horizon in frames:
//  * sr-lf-ibvs       once per frame, s_ref = s*, the command held for the N base periods.
//  * sr-hf-ibvs       every base period on the latest (stale) frame (or on the loop's forecast
//                     when it gives one), s_ref = s*.
//  * sr-lf-ekfs-ibvs  once per frame, s_ref = s_hat*(t+1|T) of Algorithm 4 run at the frame
//                     period (h steps of T), held for N base periods.
//  * sr-hf-ekfs-ibvs  every base period, s_ref = s_hat*(t+1|T) of Algorithm 4 at the base period
//                     (h N steps of delta).
//  * dr-ekfs-ibvs     Algorithm 1: at each new frame the dual-rate KF (Algorithm 2) fuses the
//                     frame at its acquisition time and predicts s(t+i|t_acq) to every base period
//                     of the coming frame; the DR-EKFS (Algorithm 3) smooths the references
//                     s_hat*(t+i|T), i = 1..N, from the prediction at the current tick; the DR-IBVS
//                     (Algorithm 5) computes N commands
//                      u_i = -lambda (H J(s(t+i|t_acq)))^+ H (s(t+i+1|t_acq) - s_hat*(t+i+1|T)),
//                     applied one per base period (inverse lifting, eq. 22). Latency: the frame
//                     acquired at t_acq is used at the tick t it is delivered, and the predictions
//                     run from t_acq over t - t_acq + i delta (the timing model's horizon, not a
//                     constant). Without a new frame after N base periods it plans again from the
//                     KF's prediction (predict-only). It acts on the delivered measurement
//                     (TaskInput::measured), being its own predictor. The KF's constant-velocity
//                     model does not know the law's own commands (paper Algorithm 2): its
//                     extrapolation over the latency and the frame is what limits the gain at
//                     long frame periods (measured on E10 with one frame of latency, gains in
//                     steps of 0.2: converges up to 4, the largest tried, at N = 8; up to 2.6 at
//                     N = 12 and 1.8 at N = 16).
// Every command of a frame is computed with the robot Jacobian at the tick of the plan (the
// paper's J(s, q_t)). The EKFS covariances (eqs. 18-21) use J of the same `interaction` choice,
// evaluated where the filter starts, with Qc = qc I_m and Rc = diag(rc, rc, rc_z) per point.
//
// Parameters (task.<key>, defaults):
//   lambda = 1 (1/s, > 0); interaction = current (current | desired | mean);
//   depth = 0 (m; 0 = the measured depth, > 0 = this constant for every point);
//   depth_rows = 0 (1: invert L J_c with its depth rows, see above);
//   EKFS laws: horizon = 8 (h, frames, >= 1; paper E10); qc = 1 (command noise density,
//     (command unit)^2/s, > 0); rc = 1 (normalised^2 s, > 0); rc_z = rc (m^2 s, > 0). With these
//     the forward pass reaches the R-weighted projection of s* onto s_t + range(J) within a few
//     steps, so h hardly matters (measured on E10 at N = 16: h = 2, 8, 16 give the same runs);
//     a smaller qc / rc makes the reference advance over the horizon and the law slower (qc =
//     0.01: 17.6 s instead of 8.2 s to 1 px at lambda = 1).
//   dr-ekfs-ibvs: kf_accel = 2000 (px/s^2, sigma_a of x and y, >= 0: the order of lambda^2 times
//     an error of a few hundred pixels); kf_sigma = 0.5 (px, > 0: the geometric source's noise);
//     kf_accel_z = 2 (m/s^2, >= 0); kf_sigma_z = 0.001 (m, > 0); the initial velocity standard
//     deviation is kf_accel x 1 s.
// Diagnostics: feature_error_norm (|H (s - s*)| of the features the command acted on,
// normalised), and for the EKFS laws reference_error_norm (|H (s_ref - s*)|). Run summary:
// peak_command, the largest |u| over the ticks (paper Fig. 5).
// The target-rate feed-forward of the loop is not used (paper 003's target is static).
#pragma once

#include "predvs/tasks/ibvs_task.h"
#include "predvs/tasks/point_task.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace predvs {

enum class ReferenceFilteringLaw { SrLfIbvs, SrHfIbvs, SrLfEkfsIbvs, SrHfEkfsIbvs, DrEkfsIbvs };

/// The registry name of a law ("sr-lf-ibvs", ..., "dr-ekfs-ibvs").
std::string referenceFilteringLawName(ReferenceFilteringLaw law);

/// Singular values below this fraction of the largest are dropped from J^+ (vpMatrix's default).
constexpr double kPinvRelTolerance = 1e-6;

class ReferenceFilteringTask : public PointTask {
 public:
  /// Throws std::invalid_argument naming task.<key> for a bad or unknown parameter, a non-positive
  /// period, an empty command space or a desired point without a positive depth.
  ReferenceFilteringTask(ReferenceFilteringLaw law, const Params& params, const TaskContext& context);
  ~ReferenceFilteringTask() override;

  std::string name() const override { return referenceFilteringLawName(law_); }
  Eigen::VectorXd computeCommand(const TaskInput& in) override;
  const Eigen::MatrixXd& featureJacobian() const override { return J_px_; }
  NamedValues diagnostics() const override;
  NamedValues runSummary() const override;

  ReferenceFilteringLaw law() const { return law_; }
  double lambda() const { return lambda_; }
  InteractionMatrixType interaction() const { return interaction_; }
  double depth() const { return depth_m_; }
  int horizonFrames() const { return horizon_frames_; }
  /// s* in (x, y, Z) per point.
  const Eigen::VectorXd& desiredXyz() const { return desired_xyz_; }
  /// (x, y, Z) per point of pixel features s_px with depths Z_m (the `depth` parameter applied; a
  /// non-finite or non-positive depth falls back to the desired point's depth).
  Eigen::VectorXd toXyz(const Eigen::VectorXd& s_px, const Eigen::VectorXd& Z_m) const;
  /// The reference the last command servoed to (s* for the laws without a filter).
  const Eigen::VectorXd& reference() const { return reference_; }

  /// L_f of one point (the formula above).
  static Eigen::Matrix<double, 3, 6> pointInteraction(double x, double y, double Z);
  /// L_f stacked over the points of xyz (3n x 6).
  static Eigen::MatrixXd interactionMatrix(const Eigen::VectorXd& xyz);

 private:
  struct Impl;
  /// The interaction matrix of the `interaction` choice at features s.
  Eigen::MatrixXd chosenInteraction(const Eigen::VectorXd& s) const;
  /// The Jacobian the law inverts at s: H L J_c, or L J_c with depth_rows.
  Eigen::MatrixXd lawJacobian(const Eigen::VectorXd& s, const Eigen::MatrixXd& robot_jacobian) const;
  /// -lambda lawJacobian(s)^+ H (s - s_ref).
  Eigen::VectorXd law(const Eigen::VectorXd& s, const Eigen::VectorXd& s_ref, const Eigen::MatrixXd& robot_jacobian) const;
  /// Runs the single-rate EKFS from s and returns s_hat*(t+1|T).
  Eigen::VectorXd singleRateReference(const Eigen::VectorXd& s, const Eigen::MatrixXd& robot_jacobian, double dt,
                                      int steps);
  void planFrame(const TaskInput& in, bool new_frame);
  /// featureJacobian(): diag(px, py) times the x, y rows of chosenInteraction(xyz) J_c.
  void setPixelJacobian(const Eigen::VectorXd& xyz, const Eigen::MatrixXd& robot_jacobian);

  ReferenceFilteringLaw law_;
  double lambda_;
  InteractionMatrixType interaction_;
  double depth_m_;
  bool depth_rows_;
  int horizon_frames_ = 0;
  double qc_ = 1.0;
  Eigen::VectorXd rc_diag_;
  double delta_s_;
  int N_;
  Eigen::VectorXd desired_xyz_;
  Eigen::VectorXd H_diag_;  // 1, 1, 0 per point
  std::unique_ptr<Impl> impl_;
  Eigen::MatrixXd J_px_;
  Eigen::VectorXd reference_;
  double feature_error_norm_ = 0.0;
  double reference_error_norm_ = 0.0;
  double peak_command_ = 0.0;
};

/// The five registry entries (one class each, so the registry builds them by type).
class SrLfIbvsTask : public ReferenceFilteringTask {
 public:
  SrLfIbvsTask(const Params& p, const TaskContext& c) : ReferenceFilteringTask(ReferenceFilteringLaw::SrLfIbvs, p, c) {}
};
class SrHfIbvsTask : public ReferenceFilteringTask {
 public:
  SrHfIbvsTask(const Params& p, const TaskContext& c) : ReferenceFilteringTask(ReferenceFilteringLaw::SrHfIbvs, p, c) {}
};
class SrLfEkfsIbvsTask : public ReferenceFilteringTask {
 public:
  SrLfEkfsIbvsTask(const Params& p, const TaskContext& c)
      : ReferenceFilteringTask(ReferenceFilteringLaw::SrLfEkfsIbvs, p, c) {}
};
class SrHfEkfsIbvsTask : public ReferenceFilteringTask {
 public:
  SrHfEkfsIbvsTask(const Params& p, const TaskContext& c)
      : ReferenceFilteringTask(ReferenceFilteringLaw::SrHfEkfsIbvs, p, c) {}
};
class DrEkfsIbvsTask : public ReferenceFilteringTask {
 public:
  DrEkfsIbvsTask(const Params& p, const TaskContext& c) : ReferenceFilteringTask(ReferenceFilteringLaw::DrEkfsIbvs, p, c) {}
};

}  // namespace predvs
