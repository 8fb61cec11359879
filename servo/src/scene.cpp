#include "predvs/servo/scene.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace predvs {

vpHomogeneousMatrix poseMatrix(const Pose6& p) { return vpHomogeneousMatrix(p(0), p(1), p(2), p(3), p(4), p(5)); }

Eigen::Matrix3Xd squarePoints(double side_m) {
  const double a = 0.5 * side_m;
  Eigen::Matrix3Xd oP(3, 4);
  oP << -a, a, a, -a,  //
      -a, -a, a, a,    //
      0, 0, 0, 0;
  return oP;
}

Scene::Scene(const SceneConfig& c) {
  if (c.points.cols() == 0) {
    if (!(c.square_side_m > 0.0) || !std::isfinite(c.square_side_m))
      throw std::invalid_argument("target.square_side_m must be > 0");
    oP_ = squarePoints(c.square_side_m);
  } else {
    if (!c.points.allFinite()) throw std::invalid_argument("target.points must be finite");
    oP_ = c.points;
  }
  if (c.desired_pose_given) {
    if (!c.desired_pose.allFinite()) throw std::invalid_argument("target.desired_pose must be finite");
    cdMo_ = poseMatrix(c.desired_pose);
  } else {
    if (!(c.desired_depth_m > 0.0) || !std::isfinite(c.desired_depth_m))
      throw std::invalid_argument("target.desired_depth_m must be > 0");
    cdMo_ = vpHomogeneousMatrix(0, 0, c.desired_depth_m, 0, 0, 0);
  }
  if (!c.object_pose.allFinite()) throw std::invalid_argument("target.pose must be finite");
  wMo0_ = poseMatrix(c.object_pose);
  trajectory_ = makeTrajectory(c.trajectory, c.trajectory_params);
  p0_ = trajectory_->position(0.0);
  for (Eigen::Index i = 0; i < oP_.cols(); ++i) {
    const double Z = cdMo_[2][0] * oP_(0, i) + cdMo_[2][1] * oP_(1, i) + cdMo_[2][2] * oP_(2, i) + cdMo_[2][3];
    if (!(Z > 0.0)) throw std::invalid_argument("target.desired_pose: point " + std::to_string(i) + " is behind the desired camera");
  }
}

vpHomogeneousMatrix Scene::objectPose(double t_s) const {
  const Eigen::Vector2d d = trajectory_->position(t_s) - p0_;
  vpHomogeneousMatrix wMo = wMo0_;
  wMo[0][3] += d.x();
  wMo[1][3] += d.y();
  return wMo;
}

vpHomogeneousMatrix Scene::desiredCameraPose() const { return wMo0_ * cdMo_.inverse(); }

namespace {
/// Pixels and depths of the points oP seen through cMo (3 x 4 rows of the homogeneous matrix).
void projectPoints(const Eigen::Matrix3Xd& oP, const Eigen::Matrix<double, 3, 4>& cMo, const CameraIntrinsics& cam,
                   PointFeatures& f) {
  const Eigen::Index n = oP.cols();
  f.uv_px.resize(2 * n);
  f.Z_m.resize(n);
  f.seen.assign(static_cast<size_t>(n), true);
  for (Eigen::Index i = 0; i < n; ++i) {
    double c[3];
    for (int r = 0; r < 3; ++r) c[r] = cMo(r, 0) * oP(0, i) + cMo(r, 1) * oP(1, i) + cMo(r, 2) * oP(2, i) + cMo(r, 3);
    f.Z_m(i) = c[2];
    if (!(c[2] > 0.0)) {  // behind the camera: not imaged
      f.seen[static_cast<size_t>(i)] = false;
      f.uv_px(2 * i) = f.uv_px(2 * i + 1) = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    f.uv_px(2 * i) = cam.u0 + cam.px * c[0] / c[2];
    f.uv_px(2 * i + 1) = cam.v0 + cam.py * c[1] / c[2];
  }
}

Eigen::Matrix<double, 3, 4> topRows(const vpHomogeneousMatrix& M) {
  Eigen::Matrix<double, 3, 4> out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out(r, c) = M[r][c];
  return out;
}

bool sameCamera(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  return a.px == b.px && a.py == b.py && a.u0 == b.u0 && a.v0 == b.v0;
}
}  // namespace

const PointFeatures& Scene::project(double t_s, const vpHomogeneousMatrix& wMc, const CameraIntrinsics& camera) const {
  const Eigen::Matrix<double, 3, 4> wMc34 = topRows(wMc);
  if (t_s == last_t_s_ && wMc34 == last_wMc_ && sameCamera(camera, last_camera_)) return last_;
  // cMo = wMc^-1 wMo(t), with wMc^-1 = [R' | -R' t] (a rigid transformation).
  const Eigen::Matrix3d R = wMc34.leftCols<3>();
  const Eigen::Vector3d t = wMc34.col(3);
  const Eigen::Matrix<double, 3, 4> wMo = topRows(objectPose(t_s));
  Eigen::Matrix<double, 3, 4> cMo;
  cMo.leftCols<3>() = R.transpose() * wMo.leftCols<3>();
  cMo.col(3) = R.transpose() * (wMo.col(3) - t);
  projectPoints(oP_, cMo, camera, last_);
  last_t_s_ = t_s;
  last_wMc_ = wMc34;
  last_camera_ = camera;
  return last_;
}

PointFeatures Scene::desired(const CameraIntrinsics& camera) const {
  PointFeatures f;
  projectPoints(oP_, topRows(cdMo_), camera, f);
  return f;
}

}  // namespace predvs
