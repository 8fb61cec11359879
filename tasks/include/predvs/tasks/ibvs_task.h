// predvs — `ibvs`: classic image-based visual servoing of image points through ViSP's vpServo
// (eye-in-hand, docs/MODELS.md §10 E9/E10; paper 003 §2).
//
// Features: the N points in pixels (PointTask), converted to normalised coordinates
// x = (u - u0) / px, y = (v - v0) / py with the controller's intrinsics, each with its depth Z.
// Error e = s - s*. Interaction matrix of one point:
//     L = [ -1/Z   0    x/Z   x y      -(1 + x^2)   y ]
//         [  0   -1/Z   y/Z   1 + y^2  -x y        -x ]
// stacked over the points and evaluated at the CURRENT features, the DESIRED ones or their MEAN
// (vpServo::CURRENT / DESIRED / MEAN). The robot's command u comes through its camera Jacobian
// J_c (6 x m, camera twist per unit command; identity for the free-flying camera), as vpServo's
// EYEINHAND_L_cVe_eJe form with cVe = I and eJe = J_c:
//     u = -lambda (L J_c)^+ e  -  (L J_c)^#_kappa de/dt|_target
// where the second (feed-forward) term is used when the loop gives a target rate: de/dt|_target is
// the part of the feature velocity caused by the target's own motion (what remains when the camera
// is still), which a P-controller otherwise follows with a steady lag of (image speed) / lambda.
//
// The feed-forward's inverse is damped (task.feedforward_damping, kappa, default 0.02): with the thin
// SVD L J_c = U diag(s_i) V', the target rate is mapped by V diag(s_i / (s_i^2 + mu^2)) U', mu =
// kappa s_0 (s_0 the largest singular value; kappa = 0: the Moore-Penrose inverse, the papers' law,
// which the paper scenarios pin). Why: a small square target makes L J_c ill-conditioned (4 points
// 0.1 m apart at 0.5 m: singular values 4.48 down to 0.018, the translation-rotation ambiguity
// vx / wy and vy / wx). A target's own motion lies almost wholly on the large singular directions
// (a translation of the target plane: on s_0), but each channel's rate is estimated on its own, so
// its noise falls on every direction alike, and the plain inverse multiplies the share on the
// smallest ones by 1 / 0.018. The camera then swung between translating one way and rotating the
// other, tick after tick, at the robot's velocity limits. kappa = 0.02 divides the gain of those
// directions by about 26 and changes the gain of s_0's by 0.04 %, of s_0 / 8 by 2.5 %. The feedback
// term is vpServo's own law, undamped. Figures: docs/PERFORMANCE.md "The feed-forward through a damped
// inverse"; docs/MODELS.md §12.
//
// Parameters: lambda (1/s, default 1), interaction (current | desired | mean, default current),
// feedforward_damping (kappa in [0, 1], default 0.02).
// featureJacobian() is diag(px, py) L J_c with the L vpServo used.
// Dropped points (NaN in TaskInput::used, the loop's lost.action: drop): vpServo's feature list is
// fixed at construction, so with any point dropped the same law (the same L: current, desired or
// mean; the same Moore-Penrose pseudo-inverse) is computed in Eigen on the remaining points' rows;
// the rows of a dropped point in featureJacobian(), error() and interactionMatrix() keep their
// values from the last command that used the point. No point left: the command is zero.
#pragma once

#include "predvs/tasks/point_task.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace predvs {

/// Which features the interaction matrix is evaluated at (vpServo::vpServoIteractionMatrixType).
enum class InteractionMatrixType { Current, Desired, Mean };

/// "current" | "desired" | "mean"; throws std::invalid_argument naming task.interaction.
InteractionMatrixType parseInteractionMatrixType(const std::string& name);
std::string interactionMatrixTypeName(InteractionMatrixType type);

/// task.feedforward_damping's default, kappa (header comment).
constexpr double kDefaultFeedforwardDamping = 0.02;

/// 6-vector camera velocity twist (vx, vy, vz, wx, wy, wz) in the camera frame (m/s, rad/s).
using CameraTwist = Eigen::Matrix<double, 6, 1>;

class IbvsTask : public PointTask {
 public:
  /// Throws std::invalid_argument naming task.lambda / task.interaction / task.feedforward_damping or
  /// an unknown key.
  IbvsTask(const Params& params, const TaskContext& context);
  ~IbvsTask() override;

  std::string name() const override { return "ibvs"; }
  Eigen::VectorXd computeCommand(const TaskInput& in) override;
  const Eigen::MatrixXd& featureJacobian() const override { return J_px_; }
  bool canDropFeatures() const override { return true; }

  double lambda() const { return lambda_; }
  InteractionMatrixType interaction() const { return interaction_; }
  /// Error s - s* (normalised) of the last computeCommand() call.
  const Eigen::VectorXd& error() const { return error_; }
  /// Interaction matrix L (2N x 6, normalised) used by the last call.
  const Eigen::MatrixXd& interactionMatrix() const { return L_; }

  /// Interaction matrix of one point at (x, y, Z) (the formula above).
  static Eigen::Matrix<double, 2, 6> pointInteraction(double x, double y, double Z);
  /// The damped inverse V diag(s_i / (s_i^2 + mu^2)) U' of J = U diag(s_i) V' (thin SVD), mu =
  /// damping * s_0 (the largest); singular values below 1e-6 s_0 are dropped, as in
  /// vpMatrix::pseudoInverse(). damping = 0: the Moore-Penrose inverse.
  static Eigen::MatrixXd dampedPseudoInverse(const Eigen::MatrixXd& J, double damping);
  double feedforwardDamping() const { return feedforward_damping_; }

 private:
  /// The law on the points in `active` only (some point dropped; header comment).
  Eigen::VectorXd commandOnPoints(const TaskInput& in, const std::vector<Eigen::Index>& active);

  struct Impl;
  double lambda_;
  InteractionMatrixType interaction_;
  double feedforward_damping_;
  std::unique_ptr<Impl> impl_;
  Eigen::VectorXd error_;
  Eigen::MatrixXd L_, J_px_;
};

}  // namespace predvs
