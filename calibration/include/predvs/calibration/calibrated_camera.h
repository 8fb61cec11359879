// predvs calibration — a calibrated pinhole camera, its two distortion conventions and its files.
//
// Pixel coordinates (u, v) of a normalised image point (x, y) = (X/Z, Y/Z):
//   OpenCV (Brown–Conrady, 5 coefficients k1 k2 p1 p2 k3), r^2 = x^2 + y^2:
//     x' = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
//     y' = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y
//     u = cx + fx x',  v = cy + fy y'
//   ViSP (vpCameraParameters::perspectiveProjWithDistortion): one radial term each way,
//     u = u0 + px x (1 + kud r^2)                        (undistorted -> distorted: kud)
//     x = (u - u0)/px (1 + kdu r'^2), r'^2 = ((u-u0)/px)^2 + ((v-v0)/py)^2   (distorted -> undistorted: kdu)
//   so kud is OpenCV's k1 of a calibration with k2 = p1 = p2 = k3 = 0, and kdu is fitted by least
//   squares as its inverse over the image (inverseRadialTerm()).
// Files: a ViSP camera XML (vpXmlParserCamera) holding the camera under a name with both ViSP
// models, and an OpenCV YAML (cv::FileStorage: camera_matrix, distortion_coefficients, image
// size, the RMS). Units: focal lengths and principal point in pixels, distortion dimensionless.
#pragma once

#include <array>
#include <string>

#include <visp3/core/vpCameraParameters.h>

namespace predvs {

/// One calibrated camera model: image size and the pinhole + distortion parameters.
struct CalibratedCamera {
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0.0;
  double fy_px = 0.0;
  double cx_px = 0.0;
  double cy_px = 0.0;
  /// OpenCV order k1 k2 p1 p2 k3 (all zero: no distortion).
  std::array<double, 5> distortion{};
  double rms_px = 0.0;  ///< reprojection RMS of the calibration that produced it
};

/// ViSP camera without distortion (px = fx, py = fy, u0 = cx, v0 = cy).
vpCameraParameters toVispWithoutDistortion(const CalibratedCamera& camera);
/// ViSP camera with distortion from a k1-only model: kud = k1, kdu = inverseRadialTerm().
vpCameraParameters toVispWithDistortion(const CalibratedCamera& k1_only);
/// kdu minimising sum |x_u - x_d (1 + kdu r_d^2)|^2 over a 20 x 20 grid of pixels covering the
/// image, x_u the undistorted point of the distorted x_d under u = u0 + px x (1 + kud r^2).
double inverseRadialTerm(const CalibratedCamera& k1_only);

/// Writes `path` with camera `name`: the model without distortion from `pinhole`, the model with
/// distortion from `k1_only` (toVispWithDistortion). Throws std::runtime_error naming the file.
void saveVispCameraXml(const std::string& path, const std::string& name, const CalibratedCamera& pinhole,
                       const CalibratedCamera& k1_only);

/// A camera read back from a ViSP XML: px, py, u0, v0 (and kud, kdu with distortion) and the size
/// the file gives (0 when absent).
struct VispCameraFile {
  vpCameraParameters camera;
  unsigned width_px = 0, height_px = 0;
  std::string name;
};

/// Reads camera `name` (empty: the first camera in the file) with the given projection model.
/// Throws std::invalid_argument "FILE: ..." when the file is missing or unreadable, the camera or
/// the model is not in it.
VispCameraFile loadVispCameraXml(const std::string& path, const std::string& name,
                                 vpCameraParameters::vpCameraParametersProjType model);

/// Writes the OpenCV YAML of `camera` (5 coefficients) to `path`. Throws std::runtime_error.
void saveOpenCvYaml(const std::string& path, const CalibratedCamera& camera);

}  // namespace predvs
