// predvs — classic image-based visual servoing of image points through ViSP's vpServo
// (eye-in-hand, METHODS §10 E9/E10; paper 003 §2).
//
// Features: s = (x_1, y_1, ..., x_n, y_n) in normalised image coordinates (metres on the unit
// image plane, x = (u - u0) / px, y = (v - v0) / py), each point with its depth Z. Error
// e = s - s*. Interaction matrix of one point:
//     L = [ -1/Z   0    x/Z   x y      -(1 + x^2)   y ]
//         [  0   -1/Z   y/Z   1 + y^2  -x y        -x ]
// stacked over the points and evaluated at the CURRENT features, the DESIRED ones or their MEAN
// (vpServo::CURRENT / DESIRED / MEAN). The camera velocity (v, w) in the camera frame is
//     v_c = -lambda L^+ e  -  L^+ de/dt|_target
// where the second (feed-forward) term is optional: de/dt|_target is the part of the feature
// velocity caused by the target's own motion (what remains when the camera is still), which a
// P-controller otherwise follows with a steady lag of (image speed) / lambda.
#pragma once

#include <Eigen/Core>

#include <memory>
#include <string>

namespace predvs {

/// Which features the interaction matrix is evaluated at (vpServo::vpServoIteractionMatrixType).
enum class InteractionMatrixType { Current, Desired, Mean };

/// "current" | "desired" | "mean"; throws std::invalid_argument naming task.interaction.
InteractionMatrixType parseInteractionMatrixType(const std::string& name);
std::string interactionMatrixTypeName(InteractionMatrixType type);

/// Plain configuration (YAML: `task.<key>`).
struct IbvsTaskConfig {
  double lambda = 1.0;  ///< task.lambda > 0, gain (1/s)
  /// task.interaction. CURRENT with the measured depth is ViSP's default choice for point IBVS.
  InteractionMatrixType interaction = InteractionMatrixType::Current;
};

/// 6-vector camera velocity twist (vx, vy, vz, wx, wy, wz) in the camera frame (m/s, rad/s).
using CameraTwist = Eigen::Matrix<double, 6, 1>;

/// Classic point IBVS on vpServo configured as EYEINHAND_CAMERA with a pseudo-inverse.
class IbvsTask {
 public:
  /// desired_xy: (x*_1, y*_1, ...) normalised, size 2n (n >= 1); desired_Z: n depths (> 0) used
  /// by the DESIRED and MEAN interaction matrices. Throws std::invalid_argument on sizes or bad
  /// config (naming task.lambda / the size).
  IbvsTask(const IbvsTaskConfig& config, const Eigen::VectorXd& desired_xy, const Eigen::VectorXd& desired_Z);
  ~IbvsTask();
  IbvsTask(IbvsTask&&) noexcept;
  IbvsTask& operator=(IbvsTask&&) noexcept;

  int points() const;
  const IbvsTaskConfig& config() const { return config_; }

  /// v_c = -lambda L^+ (s - s*) [- L^+ target_feature_rate], with s = current_xy (size 2n) and
  /// depths Z (size n, > 0). target_feature_rate (size 2n, normalised units per second) is the
  /// feed-forward de/dt|_target; pass an empty vector for none.
  CameraTwist computeVelocity(const Eigen::VectorXd& current_xy, const Eigen::VectorXd& current_Z,
                              const Eigen::VectorXd& target_feature_rate = Eigen::VectorXd());

  /// Error s - s* of the last computeVelocity() call.
  const Eigen::VectorXd& error() const { return error_; }
  /// Interaction matrix (2n x 6) used by the last call.
  const Eigen::MatrixXd& interactionMatrix() const { return L_; }

  /// Interaction matrix of one point at (x, y, Z) (the formula above).
  static Eigen::Matrix<double, 2, 6> pointInteraction(double x, double y, double Z);

 private:
  struct Impl;
  IbvsTaskConfig config_;
  std::unique_ptr<Impl> impl_;
  Eigen::VectorXd error_;
  Eigen::MatrixXd L_;
};

}  // namespace predvs
