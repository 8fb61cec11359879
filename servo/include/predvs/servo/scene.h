// predvs — the simulated scene: target points, their motion, the camera's goal.
//
// The target is a rigid set of N points oP_i given in the object frame. At t = 0 the object frame
// is at wMo0 in the world; it then translates in the world x-y plane by d(t) = p(t) - p(0), p a
// Trajectory (servo/trajectory.h, metres) built by name. The goal is the camera pose cdMo relative
// to the object: the desired features are the points seen from there.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/tasks/camera.h"
#include "predvs/tasks/task.h"
#include "predvs/servo/trajectory.h"

#include <visp3/core/vpHomogeneousMatrix.h>

#include <Eigen/Core>

#include <limits>
#include <memory>
#include <string>

namespace predvs {

using Pose6 = Eigen::Matrix<double, 6, 1>;  ///< (tx, ty, tz) in m then theta-u (rad)

/// vpHomogeneousMatrix from (tx, ty, tz, theta-u).
vpHomogeneousMatrix poseMatrix(const Pose6& p);

/// Plain configuration (YAML: `target.<key>`).
struct SceneConfig {
  /// Points in the object frame (3 x N, metres). Default: the corners of a square of side
  /// square_side_m centred on the origin in the object's x-y plane (see squarePoints()).
  Eigen::Matrix3Xd points;
  double square_side_m = 0.1;    ///< used when `points` is empty
  /// Desired camera pose relative to the object, cdMo. Default: square centred, plane parallel
  /// to the image at desired_depth_m.
  bool desired_pose_given = false;
  Pose6 desired_pose = Pose6::Zero();
  double desired_depth_m = 0.5;  ///< used when !desired_pose_given: cdMo = (0, 0, depth, 0, 0, 0)
  Pose6 object_pose = Pose6::Zero();  ///< wMo0
  std::string trajectory = "circle";
  Params trajectory_params{{"radius", 0.05}, {"omega", 0.5}};
};

/// The corners of a square of side `side` in the object x-y plane: (-a,-a), (a,-a), (a,a), (-a,a).
Eigen::Matrix3Xd squarePoints(double side_m);

class Scene {
 public:
  /// Validates the configuration (std::invalid_argument naming target.<key>).
  explicit Scene(const SceneConfig& config);

  int points() const { return static_cast<int>(oP_.cols()); }
  const Eigen::Matrix3Xd& objectPoints() const { return oP_; }
  /// Object pose in the world at t.
  vpHomogeneousMatrix objectPose(double t_s) const;
  const vpHomogeneousMatrix& desiredCameraToObject() const { return cdMo_; }
  /// World pose of the desired camera frame at t = 0 (wMo0 cdMo^-1).
  vpHomogeneousMatrix desiredCameraPose() const;
  /// Exact projection of every point with the camera at wMc at t: pixels, depths, all seen
  /// (a point behind the camera is lost). The last answer is kept: the loop's truth and the
  /// geometric source's frame at an acquisition tick ask the same question.
  const PointFeatures& project(double t_s, const vpHomogeneousMatrix& wMc, const CameraIntrinsics& camera) const;
  /// The points seen from the desired pose.
  PointFeatures desired(const CameraIntrinsics& camera) const;
  const Trajectory& trajectory() const { return *trajectory_; }

 private:
  Eigen::Matrix3Xd oP_;
  vpHomogeneousMatrix wMo0_, cdMo_;
  std::unique_ptr<Trajectory> trajectory_;
  Eigen::Vector2d p0_;
  // The last projection and its question (time, camera pose, intrinsics).
  mutable PointFeatures last_;
  mutable double last_t_s_ = std::numeric_limits<double>::quiet_NaN();
  mutable Eigen::Matrix<double, 3, 4> last_wMc_;
  mutable CameraIntrinsics last_camera_;
};

}  // namespace predvs
