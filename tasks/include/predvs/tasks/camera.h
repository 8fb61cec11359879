// predvs — pinhole camera intrinsics and pixel <-> normalised conversions.
#pragma once

#include <Eigen/Core>

namespace predvs {

/// Pinhole intrinsics without distortion (camera.<key>).
struct CameraIntrinsics {
  double px = 800.0;  ///< focal length / pixel width (px)
  double py = 800.0;  ///< focal length / pixel height (px)
  double u0 = 320.0;  ///< principal point (px)
  double v0 = 240.0;  ///< principal point (px)

  /// (u, v) pairs in pixels -> (x, y) pairs on the unit image plane: x = (u - u0) / px.
  Eigen::VectorXd toNormalized(const Eigen::VectorXd& uv_px) const {
    Eigen::VectorXd xy(uv_px.size());
    for (Eigen::Index i = 0; i + 1 < uv_px.size(); i += 2) {
      xy(i) = (uv_px(i) - u0) / px;
      xy(i + 1) = (uv_px(i + 1) - v0) / py;
    }
    return xy;
  }
  /// The inverse of toNormalized().
  Eigen::VectorXd toPixels(const Eigen::VectorXd& xy) const {
    Eigen::VectorXd uv(xy.size());
    for (Eigen::Index i = 0; i + 1 < xy.size(); i += 2) {
      uv(i) = u0 + px * xy(i);
      uv(i + 1) = v0 + py * xy(i + 1);
    }
    return uv;
  }
};

}  // namespace predvs
