// predvs calibration — pinhole camera intrinsics with their two distortion conventions.
//
// Pixel coordinates (u, v) of a normalised image point (x, y) = (X/Z, Y/Z):
//   OpenCV (Brown–Conrady, 5 coefficients k1 k2 p1 p2 k3), r^2 = x^2 + y^2:
//     x' = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
//     y' = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y
//     u = cx + fx x',  v = cy + fy y'
//   ViSP (vpCameraParameters::perspectiveProjWithDistortion): one radial term each way,
//     u = u0 + px x (1 + kud r^2)                     (undistorted -> distorted, kud)
//     x = (u - u0)/px (1 + kdu r'^2), r'^2 from (u,v)  (distorted -> undistorted, kdu)
//   so kud is OpenCV's k1 with k2 = p1 = p2 = k3 = 0, and kdu is its least-squares inverse.
// Units: focal lengths and principal point in pixels; distortion coefficients dimensionless.
#pragma once

#include <array>

#include <visp3/core/vpCameraParameters.h>

namespace predvs {

/// One calibrated camera: image size and the pinhole + distortion parameters.
struct CalibratedCamera {
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0.0;
  double fy_px = 0.0;
  double cx_px = 0.0;
  double cy_px = 0.0;
  /// OpenCV order k1 k2 p1 p2 k3 (all zero: no distortion).
  std::array<double, 5> distortion{};
};

/// ViSP camera without distortion (px = fx, py = fy, u0 = cx, v0 = cy).
vpCameraParameters toVispWithoutDistortion(const CalibratedCamera& camera);

}  // namespace predvs
