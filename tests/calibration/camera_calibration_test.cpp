// Camera calibration (calibration/camera_calibration.h) on ViSP's grid36 images against the
// reference figures (OpenCV's circle grid: about 0.26 px RMS, fx about 550 px), a synthetic
// chessboard with known intrinsics, and the ViSP XML round trip.
#include "predvs/calibration/camera_calibration.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <filesystem>
#include <unistd.h>
#include <string>

namespace predvs {
namespace {

const std::string kGridDir = "/usr/share/visp-images-data/ViSP-images/calibration/";

std::vector<CalibrationView> gridViews(const PatternSpec& spec, cv::Size& size) {
  std::vector<CalibrationView> views;
  for (int i = 1; i <= 4; ++i) {
    const std::string name = "grid36-0" + std::to_string(i) + ".pgm";
    const cv::Mat g = cv::imread(kGridDir + name, cv::IMREAD_GRAYSCALE);
    if (g.empty()) continue;
    size = g.size();
    const PatternDetection d = detectPattern(g, spec);
    EXPECT_TRUE(d.found()) << name;
    if (d.found()) views.push_back({name, d});
  }
  return views;
}

TEST(CameraCalibration, Grid36MatchesTheReference) {
  if (!std::filesystem::exists(kGridDir + "grid36-01.pgm")) GTEST_SKIP() << "visp-images-data is not installed";
  // GIVEN the four grid36 images, a 6 x 6 dot grid with 3 cm spacing
  PatternSpec spec;
  cv::Size size;
  const auto views = gridViews(spec, size);
  ASSERT_EQ(views.size(), 4u);
  // WHEN calibrated
  const CameraCalibrationResult r = calibrateFromViews(views, size, spec);
  // THEN the RMS is at least as good as the reference (0.26 px) and the intrinsics agree with it
  // (fx about 550 px); tolerances: 1 % on the focal lengths, 5 px on the principal point
  EXPECT_LE(r.full.rms_px, 0.26);
  EXPECT_NEAR(r.full.fx_px, 550.0, 5.5);
  EXPECT_NEAR(r.full.fy_px, 542.5, 5.5);
  EXPECT_NEAR(r.full.cx_px, 310.0, 5.0);
  EXPECT_NEAR(r.full.cy_px, 244.0, 5.0);
  EXPECT_EQ(r.points, 4 * 36);
  for (const auto& v : r.views) EXPECT_LT(v.rms_px, 0.35) << v.name;
  // the simpler models fit worse, but not much (the lens distorts little)
  EXPECT_GE(r.pinhole.rms_px, r.k1_only.rms_px - 1e-9);
  EXPECT_LT(r.pinhole.rms_px, 0.35);
  EXPECT_NEAR(r.pinhole.fx_px, r.full.fx_px, 10.0);
}

TEST(CameraCalibration, NoPatternInABlankImage) {
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(200));
  for (const char* kind : {"circles", "chessboard", "apriltag"}) {
    PatternSpec spec;
    spec.kind = parsePatternKind(kind);
    EXPECT_FALSE(detectPattern(blank, spec).found()) << kind;
  }
  EXPECT_THROW(parsePatternKind("dots"), std::invalid_argument);
}

TEST(CameraCalibration, TooFewViewsIsAnError) {
  PatternSpec spec;
  std::vector<CalibrationView> two(2);
  EXPECT_THROW(calibrateFromViews(two, cv::Size(640, 480), spec), std::invalid_argument);
}

/// A chessboard seen by a known camera: the board image warped by K [r1 r2 t].
cv::Mat renderChessboard(const cv::Mat& K, const cv::Vec3d& rvec, const cv::Vec3d& tvec, int rows, int cols, double square_m) {
  const int px_per_square = 40;
  const int W = (cols + 1) * px_per_square, H = (rows + 1) * px_per_square;
  cv::Mat board(H + 2 * px_per_square, W + 2 * px_per_square, CV_8UC1, cv::Scalar(255));
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c <= cols; ++c)
      if ((r + c) % 2 == 0)
        board(cv::Rect((c + 1) * px_per_square, (r + 1) * px_per_square, px_per_square, px_per_square)).setTo(0);
  // Board pixel (bx, by) -> metres: the first inner corner is at board pixel (2, 2) squares.
  const double s = square_m / px_per_square;
  const cv::Mat S = (cv::Mat_<double>(3, 3) << s, 0, -2 * px_per_square * s, 0, s, -2 * px_per_square * s, 0, 0, 1);
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  cv::Mat Rt(3, 3, CV_64F);
  R.col(0).copyTo(Rt.col(0));
  R.col(1).copyTo(Rt.col(1));
  cv::Mat(tvec).copyTo(Rt.col(2));
  const cv::Mat Hm = K * Rt * S;
  cv::Mat img;
  cv::warpPerspective(board, img, Hm, cv::Size(640, 480), cv::INTER_AREA, cv::BORDER_CONSTANT, cv::Scalar(128));
  return img;
}

TEST(CameraCalibration, SyntheticChessboardRecoversTheCamera) {
  // GIVEN five views of a 7 x 5 inner-corner chessboard (3 cm squares) by a camera fx = 600,
  // fy = 590, cx = 330, cy = 235, without distortion
  const cv::Mat K = (cv::Mat_<double>(3, 3) << 600, 0, 330, 0, 590, 235, 0, 0, 1);
  PatternSpec spec;
  spec.kind = PatternKind::Chessboard;
  spec.rows = 5;
  spec.cols = 7;
  spec.spacing_m = 0.03;
  const std::vector<std::pair<cv::Vec3d, cv::Vec3d>> poses = {
      {{0.0, 0.0, 0.0}, {-0.1, -0.07, 0.5}},   {{0.35, 0.0, 0.0}, {-0.1, -0.07, 0.5}},
      {{0.0, -0.35, 0.0}, {-0.09, -0.07, 0.5}}, {{-0.3, 0.2, 0.1}, {-0.1, -0.05, 0.45}},
      {{0.2, 0.3, -0.1}, {-0.12, -0.08, 0.55}}};
  std::vector<CalibrationView> views;
  for (size_t i = 0; i < poses.size(); ++i) {
    const cv::Mat img = renderChessboard(K, poses[i].first, poses[i].second, spec.rows, spec.cols, spec.spacing_m);
    const PatternDetection d = detectPattern(img, spec);
    ASSERT_TRUE(d.found()) << "view " << i;
    views.push_back({"view" + std::to_string(i), d});
  }
  // WHEN calibrated THEN the intrinsics are recovered to 0.5 % and the RMS is small
  const CameraCalibrationResult r = calibrateFromViews(views, cv::Size(640, 480), spec);
  EXPECT_NEAR(r.pinhole.fx_px, 600.0, 3.0);
  EXPECT_NEAR(r.pinhole.fy_px, 590.0, 3.0);
  EXPECT_NEAR(r.pinhole.cx_px, 330.0, 3.0);
  EXPECT_NEAR(r.pinhole.cy_px, 235.0, 3.0);
  EXPECT_LT(r.full.rms_px, 0.2);
}

TEST(CalibratedCamera, VispXmlRoundTrip) {
  // GIVEN a pinhole model and a k1-only model
  CalibratedCamera pin{640, 480, 552.5, 544.8, 308.7, 245.8, {}, 0.29};
  CalibratedCamera k1{640, 480, 551.0, 543.2, 309.2, 245.6, {0.0111, 0, 0, 0, 0}, 0.28};
  const std::string path = (std::filesystem::temp_directory_path() / ("predvs_camera_" + std::to_string(::getpid()) + ".xml")).string();
  // WHEN written and read back through ViSP's parser
  saveVispCameraXml(path, "grid36", pin, k1);
  const VispCameraFile a = loadVispCameraXml(path, "grid36", vpCameraParameters::perspectiveProjWithoutDistortion);
  const VispCameraFile b = loadVispCameraXml(path, "", vpCameraParameters::perspectiveProjWithDistortion);
  // THEN both models come back (ViSP writes 10 significant digits), with the image size
  EXPECT_NEAR(a.camera.get_px(), 552.5, 1e-6);
  EXPECT_NEAR(a.camera.get_py(), 544.8, 1e-6);
  EXPECT_NEAR(a.camera.get_u0(), 308.7, 1e-6);
  EXPECT_NEAR(a.camera.get_v0(), 245.8, 1e-6);
  EXPECT_EQ(a.width_px, 640u);
  EXPECT_EQ(a.height_px, 480u);
  EXPECT_NEAR(b.camera.get_px(), 551.0, 1e-6);
  EXPECT_NEAR(b.camera.get_kud(), 0.0111, 1e-9);
  EXPECT_NEAR(b.camera.get_kdu(), inverseRadialTerm(k1), 1e-9);
  // kdu inverts kud to first order: opposite sign, about the same size
  EXPECT_LT(b.camera.get_kdu(), 0.0);
  EXPECT_NEAR(-b.camera.get_kdu(), 0.0111, 0.002);
  // a missing camera name and a missing file are errors naming the file
  EXPECT_THROW(loadVispCameraXml(path, "other", vpCameraParameters::perspectiveProjWithoutDistortion), std::invalid_argument);
  EXPECT_THROW(loadVispCameraXml(path + ".none", "", vpCameraParameters::perspectiveProjWithoutDistortion), std::invalid_argument);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace predvs

namespace predvs {
namespace {

TEST(CameraCalibration, AprilTagCornersMatchViSPGroundTruth) {
  const std::string dir = "/usr/share/visp-images-data/ViSP-images/AprilTag/";
  if (!std::filesystem::exists(dir + "AprilTag.pgm")) GTEST_SKIP() << "visp-images-data is not installed";
  // GIVEN ViSP's AprilTag image and its ground-truth corners ("36h11_id:_N" then 4 lines "v u":
  // row first)
  std::map<int, std::vector<cv::Point2f>> truth;
  std::ifstream in(dir + "ground_truth_detection.txt");
  std::string line;
  int id = -1;
  while (std::getline(in, line)) {
    if (line.rfind("36h11_id:_", 0) == 0) {
      id = std::stoi(line.substr(10));
    } else if (id >= 0) {
      std::istringstream s(line);
      float u = 0, v = 0;
      if (s >> v >> u) truth[id].emplace_back(u, v);
    }
  }
  ASSERT_FALSE(truth.empty());
  // WHEN detected as a board large enough for every id (6 x 6: ids 0..35), tags 4 cm apart
  PatternSpec spec;
  spec.kind = PatternKind::AprilTag;
  spec.spacing_m = 0.04;
  spec.tag_size_m = 0.03;
  const cv::Mat g = cv::imread(dir + "AprilTag.pgm", cv::IMREAD_GRAYSCALE);
  const PatternDetection d = detectPattern(g, spec);
  ASSERT_TRUE(d.found());
  // THEN every ground-truth tag on the board is found with its 4 corners within 0.5 px, in order,
  // and its board corners form a 3 cm square around the tag's board position
  size_t matched = 0;
  for (size_t k = 0; k + 3 < d.image_px.size(); k += 4) {
    const cv::Point3f centre = 0.25f * (d.board_m[k] + d.board_m[k + 1] + d.board_m[k + 2] + d.board_m[k + 3]);
    const int tag = static_cast<int>(std::lround(centre.y / 0.04)) * spec.cols + static_cast<int>(std::lround(centre.x / 0.04));
    EXPECT_NEAR(cv::norm(d.board_m[k] - d.board_m[k + 1]), 0.03, 1e-6);
    EXPECT_NEAR(cv::norm(d.board_m[k] - d.board_m[k + 2]), 0.03 * std::sqrt(2.0), 1e-6);
    auto it = truth.find(tag);
    if (it == truth.end() || it->second.size() != 4) continue;
    for (size_t c = 0; c < 4; ++c) EXPECT_LT(cv::norm(d.image_px[k + c] - it->second[c]), 0.5) << "tag " << tag << " corner " << c;
    ++matched;
  }
  size_t on_board = 0;
  for (const auto& kv : truth) on_board += kv.first < 36 ? 1 : 0;
  EXPECT_EQ(matched, on_board);
  EXPECT_GT(matched, 0u);
}

}  // namespace
}  // namespace predvs
