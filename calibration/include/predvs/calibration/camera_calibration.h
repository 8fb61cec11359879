// predvs calibration — camera intrinsics from images of a planar pattern (OpenCV calibrateCamera).
//
// Patterns (PatternSpec; the board frame has x along a row, y down the columns, z = 0 on the board):
//   circles     a symmetric grid of `rows` x `cols` dark dots on a light background, centres
//               `spacing_m` apart (ViSP's grid2d.pdf: 6 x 6, 0.03 m, dots of 0.02 m diameter).
//               Centres: cv::findCirclesGrid with a cv::SimpleBlobDetector tuned for dark dots
//               whose printed marks (grid2d's dots carry small digits and letters) make them less
//               convex than a clean disc (minConvexity 0.8, minCircularity 0.6, up to 5 % of the
//               image area per dot). The centre of a dot's image is the centre of an ellipse, not
//               the image of the dot's centre; the difference (up to a few tenths of a pixel at a
//               strong tilt) is removed after a first calibration by projecting each dot's outline
//               (diameter `circle_diameter_m`, default 2/3 of the spacing as on grid2d) with the
//               estimated pose and subtracting the offset of its fitted ellipse centre; two passes.
//   chessboard  `rows` x `cols` INNER corners, squares `spacing_m` wide: cv::findChessboardCorners +
//               cv::cornerSubPix (5 x 5 window), falling back to cv::findChessboardCornersSB.
//   apriltag    a grid of `rows` x `cols` tag36h11 tags (vpDetectorAprilTag), tag id r * cols + c
//               at row r, column c, tag centres `spacing_m` apart, black square `tag_size_m` wide,
//               printed upright; each seen tag gives its 4 corners (vpDetectorAprilTag's corner
//               order, getTagsPoints3D for their coordinates in the tag frame). The corners match
//               ViSP's ground truth on AprilTag.pgm; a calibration from a tag board is not
//               validated on a reference image set (ViSP's data has none).
// Calibration: cv::calibrateCamera three times on the same detections: the full 5-coefficient
// model (the OpenCV YAML), k1 only (ViSP's model with distortion: kud = k1) and no distortion
// (ViSP's model without). RMS = sqrt(mean over points of the squared 2-D reprojection distance),
// per image and overall, in pixels.
#pragma once

#include "predvs/calibration/calibrated_camera.h"

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace predvs {

enum class PatternKind { Circles, Chessboard, AprilTag };

/// "circles" | "chessboard" | "apriltag"; throws std::invalid_argument naming --pattern.
PatternKind parsePatternKind(const std::string& name);
std::string patternKindName(PatternKind kind);

struct PatternSpec {
  PatternKind kind = PatternKind::Circles;
  int rows = 6;                    ///< dots, inner corners or tags per column
  int cols = 6;                    ///< per row
  double spacing_m = 0.03;         ///< centre or corner spacing
  double circle_diameter_m = 0.0;  ///< circles: 0 means 2/3 of the spacing (grid2d)
  double tag_size_m = 0.0;         ///< apriltag: black square side; 0 means 0.8 spacing
};

/// Detections of one image: 2-D points (px) and their board coordinates (m); empty when the
/// pattern was not found. Throws std::invalid_argument for a bad spec (rows, cols < 2, spacing <= 0).
struct PatternDetection {
  std::vector<cv::Point2f> image_px;
  std::vector<cv::Point3f> board_m;
  bool found() const { return !image_px.empty(); }
};
PatternDetection detectPattern(const cv::Mat& gray8, const PatternSpec& spec);

/// One image that entered the calibration.
struct CalibrationView {
  std::string name;
  PatternDetection detection;
};

struct ViewResiduals {
  std::string name;
  double rms_px = 0.0;
  double max_px = 0.0;
  std::vector<cv::Point2f> residual_px;  ///< observed - projected, per point (full model)
  std::vector<cv::Point2f> image_px;     ///< the observations (after the ellipse-centre correction)
};

struct CameraCalibrationResult {
  CalibratedCamera full;     ///< k1 k2 p1 p2 k3
  CalibratedCamera k1_only;  ///< kud for ViSP
  CalibratedCamera pinhole;  ///< no distortion
  std::vector<ViewResiduals> views;  ///< per image, full model
  int points = 0;
};

/// Calibrates from at least 3 views of one image size. Throws std::invalid_argument with a
/// one-line reason for fewer views, or views of different sizes.
CameraCalibrationResult calibrateFromViews(const std::vector<CalibrationView>& views, cv::Size image_size,
                                           const PatternSpec& spec);

}  // namespace predvs
