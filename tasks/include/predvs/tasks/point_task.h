// predvs — the base of every law whose features are the image points themselves.
//
// Features s = (u_0, v_0, ..., u_{N-1}, v_{N-1}) in pixels, exactly as the feature source
// delivers them (a lost point is NaN); s* = the points seen from the desired pose. The pixel
// interaction matrix of a point at normalised (x, y) = ((u - u0) / px, (v - v0) / py) and depth Z
// is L_px = diag(px, py) L(x, y, Z), L the classic point interaction matrix (ibvs_task.h); stacked
// over the points and multiplied by the robot's camera Jacobian (6 x m) it gives ds/du.
#pragma once

#include "predvs/tasks/task.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace predvs {

class PointTask : public Task {
 public:
  int featureSize() const override { return static_cast<int>(desired_.size()); }
  std::vector<std::string> featureNames() const override;
  Eigen::VectorXd features(const PointFeatures& points) const override { return points.uv_px; }
  const Eigen::VectorXd& desiredFeatures() const override { return desired_; }

  /// Interaction matrix in pixels (2N x 6) at pixel features s_px with depths Z_m, for camera
  /// `camera`: row pair i is diag(px, py) L(x_i, y_i, Z_i).
  static Eigen::MatrixXd pixelInteraction(const Eigen::VectorXd& s_px, const Eigen::VectorXd& Z_m,
                                          const CameraIntrinsics& camera);

 protected:
  /// Throws std::invalid_argument when the desired points are missing or lost.
  explicit PointTask(const TaskContext& context);
  const TaskContext& context() const { return context_; }

 private:
  TaskContext context_;
  Eigen::VectorXd desired_;
};

}  // namespace predvs
