#include "predvs/calibration/camera_calibration.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <visp3/core/vpImage.h>
#include <visp3/core/vpPoint.h>
#include <visp3/detection/vpDetectorAprilTag.h>

#include <cmath>
#include <map>
#include <stdexcept>

namespace predvs {
namespace {

constexpr int kMinViews = 3;

std::vector<cv::Point3f> gridPoints(const PatternSpec& s) {
  std::vector<cv::Point3f> pts;
  for (int r = 0; r < s.rows; ++r)
    for (int c = 0; c < s.cols; ++c)
      pts.emplace_back(static_cast<float>(c * s.spacing_m), static_cast<float>(r * s.spacing_m), 0.0f);
  return pts;
}

PatternDetection detectCircles(const cv::Mat& g, const PatternSpec& s) {
  cv::SimpleBlobDetector::Params p;
  p.filterByColor = true;
  p.blobColor = 0;  // dark dots
  p.filterByArea = true;
  p.minArea = 25.0f;
  p.maxArea = static_cast<float>(0.05 * g.rows * g.cols);
  p.filterByCircularity = true;
  p.minCircularity = 0.6f;
  p.filterByConvexity = true;
  p.minConvexity = 0.8f;
  p.filterByInertia = true;
  p.minInertiaRatio = 0.1f;
  const cv::Ptr<cv::FeatureDetector> blobs = cv::SimpleBlobDetector::create(p);
  std::vector<cv::Point2f> centres;
  PatternDetection d;
  if (cv::findCirclesGrid(g, cv::Size(s.cols, s.rows), centres, cv::CALIB_CB_SYMMETRIC_GRID, blobs)) {
    d.image_px = centres;
    d.board_m = gridPoints(s);
  }
  return d;
}

PatternDetection detectChessboard(const cv::Mat& g, const PatternSpec& s) {
  std::vector<cv::Point2f> corners;
  const cv::Size size(s.cols, s.rows);
  bool ok = cv::findChessboardCorners(g, size, corners,
                                      cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK);
  if (ok)
    cv::cornerSubPix(g, corners, cv::Size(5, 5), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
  else
    ok = cv::findChessboardCornersSB(g, size, corners, cv::CALIB_CB_ACCURACY);
  PatternDetection d;
  if (ok) {
    d.image_px = corners;
    d.board_m = gridPoints(s);
  }
  return d;
}

PatternDetection detectAprilTags(const cv::Mat& g, const PatternSpec& s) {
  vpImage<unsigned char> I(static_cast<unsigned>(g.rows), static_cast<unsigned>(g.cols));
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) I[static_cast<unsigned>(r)][static_cast<unsigned>(c)] = g.at<unsigned char>(r, c);
  vpDetectorAprilTag detector(vpDetectorAprilTag::TAG_36h11);
  detector.detect(I);
  const std::vector<int> ids = detector.getTagsId();
  const std::vector<std::vector<vpImagePoint>> corners = detector.getTagsCorners();
  const double size = s.tag_size_m > 0.0 ? s.tag_size_m : 0.8 * s.spacing_m;
  std::map<int, double> sizes;
  for (int id : ids)
    if (id >= 0 && id < s.rows * s.cols) sizes[id] = size;
  const std::vector<std::vector<vpPoint>> local = detector.getTagsPoints3D(ids, sizes);
  PatternDetection d;
  for (size_t i = 0; i < ids.size(); ++i) {
    const int id = ids[i];
    if (id < 0 || id >= s.rows * s.cols || corners[i].size() != 4 || local[i].size() != 4) continue;
    const double cx = (id % s.cols) * s.spacing_m, cy = (id / s.cols) * s.spacing_m;
    for (size_t k = 0; k < 4; ++k) {
      d.image_px.emplace_back(static_cast<float>(corners[i][k].get_u()), static_cast<float>(corners[i][k].get_v()));
      d.board_m.emplace_back(static_cast<float>(cx + local[i][k].get_oX()), static_cast<float>(cy + local[i][k].get_oY()), 0.0f);
    }
  }
  // Fewer than 2 tags cannot constrain a camera's intrinsics from one view.
  if (d.image_px.size() < 8) return PatternDetection{};
  return d;
}

struct CvCalibration {
  cv::Mat K, D;
  std::vector<cv::Mat> rvecs, tvecs;
  double rms = 0.0;
};

CvCalibration runCalibration(const std::vector<std::vector<cv::Point3f>>& obj,
                             const std::vector<std::vector<cv::Point2f>>& img, cv::Size size, int flags) {
  CvCalibration c;
  c.rms = cv::calibrateCamera(obj, img, size, c.K, c.D, c.rvecs, c.tvecs, flags,
                              cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  return c;
}

CalibratedCamera toCamera(const CvCalibration& c, cv::Size size) {
  CalibratedCamera cam;
  cam.width_px = size.width;
  cam.height_px = size.height;
  cam.fx_px = c.K.at<double>(0, 0);
  cam.fy_px = c.K.at<double>(1, 1);
  cam.cx_px = c.K.at<double>(0, 2);
  cam.cy_px = c.K.at<double>(1, 2);
  for (int i = 0; i < 5 && i < static_cast<int>(c.D.total()); ++i) cam.distortion[static_cast<size_t>(i)] = c.D.at<double>(i);
  cam.rms_px = c.rms;
  return cam;
}

/// Ellipse-centre offset of every dot: fitted centre of its projected outline minus the projection
/// of its centre, with the current model.
std::vector<std::vector<cv::Point2f>> ellipseOffsets(const std::vector<std::vector<cv::Point3f>>& obj, const CvCalibration& c,
                                                     double radius_m) {
  std::vector<std::vector<cv::Point2f>> out(obj.size());
  for (size_t v = 0; v < obj.size(); ++v)
    for (const cv::Point3f& centre : obj[v]) {
      std::vector<cv::Point3f> outline;
      const int n = 72;
      for (int k = 0; k < n; ++k) {
        const double a = 2.0 * M_PI * k / n;
        outline.emplace_back(centre.x + static_cast<float>(radius_m * std::cos(a)),
                             centre.y + static_cast<float>(radius_m * std::sin(a)), 0.0f);
      }
      outline.push_back(centre);
      std::vector<cv::Point2f> proj;
      cv::projectPoints(outline, c.rvecs[v], c.tvecs[v], c.K, c.D, proj);
      const cv::Point2f projected_centre = proj.back();
      proj.pop_back();
      out[v].push_back(cv::fitEllipse(proj).center - projected_centre);
    }
  return out;
}

}  // namespace

PatternKind parsePatternKind(const std::string& name) {
  if (name == "circles") return PatternKind::Circles;
  if (name == "chessboard") return PatternKind::Chessboard;
  if (name == "apriltag") return PatternKind::AprilTag;
  throw std::invalid_argument("--pattern: expected circles, chessboard or apriltag, got '" + name + "'");
}

std::string patternKindName(PatternKind k) {
  switch (k) {
    case PatternKind::Circles: return "circles";
    case PatternKind::Chessboard: return "chessboard";
    case PatternKind::AprilTag: return "apriltag";
  }
  return "?";
}

PatternDetection detectPattern(const cv::Mat& gray8, const PatternSpec& s) {
  if (s.rows < 2 || s.cols < 2) throw std::invalid_argument("--rows/--cols: expected at least 2 each");
  if (!(s.spacing_m > 0.0) || !std::isfinite(s.spacing_m)) throw std::invalid_argument("--spacing: expected a length > 0 (m)");
  if (gray8.empty() || gray8.type() != CV_8UC1) throw std::invalid_argument("detectPattern: expected an 8-bit grey image");
  switch (s.kind) {
    case PatternKind::Circles: return detectCircles(gray8, s);
    case PatternKind::Chessboard: return detectChessboard(gray8, s);
    case PatternKind::AprilTag: return detectAprilTags(gray8, s);
  }
  return {};
}

CameraCalibrationResult calibrateFromViews(const std::vector<CalibrationView>& views, cv::Size size, const PatternSpec& spec) {
  if (static_cast<int>(views.size()) < kMinViews)
    throw std::invalid_argument("the pattern was found in " + std::to_string(views.size()) + " image(s); at least " +
                                std::to_string(kMinViews) + " are needed");
  std::vector<std::vector<cv::Point3f>> obj;
  std::vector<std::vector<cv::Point2f>> observed;
  for (const auto& v : views) {
    obj.push_back(v.detection.board_m);
    observed.push_back(v.detection.image_px);
  }
  std::vector<std::vector<cv::Point2f>> img = observed;
  CvCalibration full = runCalibration(obj, img, size, 0);
  if (spec.kind == PatternKind::Circles) {
    const double radius = 0.5 * (spec.circle_diameter_m > 0.0 ? spec.circle_diameter_m : 2.0 / 3.0 * spec.spacing_m);
    for (int pass = 0; pass < 2; ++pass) {
      const auto offsets = ellipseOffsets(obj, full, radius);
      for (size_t v = 0; v < img.size(); ++v)
        for (size_t i = 0; i < img[v].size(); ++i) img[v][i] = observed[v][i] - offsets[v][i];
      full = runCalibration(obj, img, size, 0);
    }
  }
  const CvCalibration k1 = runCalibration(obj, img, size, cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST);
  const CvCalibration pin = runCalibration(
      obj, img, size, cv::CALIB_FIX_K1 | cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST);
  CameraCalibrationResult r;
  r.full = toCamera(full, size);
  r.k1_only = toCamera(k1, size);
  r.pinhole = toCamera(pin, size);
  double total_sq = 0.0;
  for (size_t v = 0; v < views.size(); ++v) {
    std::vector<cv::Point2f> proj;
    cv::projectPoints(obj[v], full.rvecs[v], full.tvecs[v], full.K, full.D, proj);
    ViewResiduals vr;
    vr.name = views[v].name;
    vr.image_px = img[v];
    double sq = 0.0;
    for (size_t i = 0; i < proj.size(); ++i) {
      const cv::Point2f e = img[v][i] - proj[i];
      vr.residual_px.push_back(e);
      const double d2 = e.x * e.x + e.y * e.y;
      sq += d2;
      vr.max_px = std::max(vr.max_px, std::sqrt(d2));
    }
    vr.rms_px = std::sqrt(sq / static_cast<double>(proj.size()));
    total_sq += sq;
    r.points += static_cast<int>(proj.size());
    r.views.push_back(vr);
  }
  r.full.rms_px = std::sqrt(total_sq / r.points);
  return r;
}

}  // namespace predvs
