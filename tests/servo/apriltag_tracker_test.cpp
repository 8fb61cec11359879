// The `apriltag` tracker on ViSP's own regression image (visp-images-data AprilTag/AprilTag.pgm,
// 640x480, twelve 36h11 tags, ids 8-19) against the package's ground truth files: every id found,
// corners within 0.5 px of ground_truth_detection.txt, poses against ground_truth_pose.txt.
//
// The camera and tag size that produced ground_truth_pose.txt are those of ViSP 3.5's
// modules/detection/test/apriltag-with-dataset/testAprilTag.cpp ("Apriltag regression test"):
// px = 615.1674805, py = 615.1675415, u0 = 312.1889954, v0 = 243.4373779, no distortion, tag size
// 0.053 m, HOMOGRAPHY_VIRTUAL_VS, quad decimate 1. Its tolerances are ours too: 0.5 px per corner
// coordinate, 0.005 on each pose component (m, rad). Note the files' order: each corner is
// written (v, u), row then column (ViSP's vpImagePoint i, j), and in the AprilTag library's pixel
// convention (pixel centres at x + 0.5), which the tracker converts to ViSP's (centres at x): the
// files' corners are compared with ours + 0.5 (apriltag_tracker.cpp, kLibraryToViSPPx).
#include "predvs/servo/apriltag_tracker.h"
#include "predvs/servo/image_tracker.h"

#include <visp3/core/vpPoseVector.h>
#include <visp3/io/vpImageIo.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <string>
#include <sys/stat.h>

namespace predvs {
namespace {

const std::string kAprilTagDir = "/usr/share/visp-images-data/ViSP-images/AprilTag";
constexpr double kCornerTolerancePx = 0.5;  // ViSP's own regression tolerance
constexpr double kPoseTolerance = 0.005;    // m and rad, ViSP's own
constexpr double kDepthToleranceM = 1e-3;   // depths from the same poses: well within the 5 mm
constexpr double kFileConventionPx = 0.5;   // the ground-truth files' pixel convention minus ours

bool exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

/// "36h11_id:_8" -> 8.
int idOf(const std::string& message) { return std::stoi(message.substr(message.rfind('_') + 1)); }

ImageTrackerContext viSPTestCamera() {
  ImageTrackerContext c;
  c.camera.px = 615.1674805;
  c.camera.py = 615.1675415;
  c.camera.u0 = 312.1889954;
  c.camera.v0 = 243.4373779;
  c.camera_known = true;
  return c;
}

#define SKIP_WITHOUT_IMAGES()                                                                          \
  if (!exists(kAprilTagDir + "/AprilTag.pgm"))                                                         \
    GTEST_SKIP() << kAprilTagDir << "/AprilTag.pgm is absent: install the Debian package visp-images-data " \
                                    "(scripts/install-deps.sh)"

TEST(AprilTagTracker, DetectsEveryTagOfViSPsRegressionImageWithinHalfAPixel) {
  SKIP_WITHOUT_IMAGES();
  // GIVEN ViSP's regression image and its ground-truth corners
  vpImage<unsigned char> I;
  vpImageIo::read(I, kAprilTagDir + "/AprilTag.pgm");
  std::map<int, std::array<double, 8>> truth;  // id -> u0 v0 u1 v1 ...
  std::ifstream in(kAprilTagDir + "/ground_truth_detection.txt");
  std::string message;
  std::array<double, 8> vu{};
  while (in >> message >> vu[0] >> vu[1] >> vu[2] >> vu[3] >> vu[4] >> vu[5] >> vu[6] >> vu[7])
    truth[idOf(message)] = {vu[1], vu[0], vu[3], vu[2], vu[5], vu[4], vu[7], vu[6]};
  ASSERT_EQ(truth.size(), 12u);

  // WHEN the tracker (no `ids`: the tags of the first image) runs on it
  auto tracker = makeImageTracker("apriltag", Params{}, ImageTrackerContext{});
  const TrackedPoints r = tracker->track(I);

  // THEN it follows the twelve tags in increasing id order, 5 points each, all seen
  const auto& ids = dynamic_cast<const AprilTagTracker&>(*tracker).ids();
  ASSERT_EQ(ids.size(), truth.size());
  ASSERT_EQ(tracker->points(), 60);
  EXPECT_EQ(tracker->pointNames().front(), "tag8.c0");
  EXPECT_EQ(tracker->pointNames()[4], "tag8.centre");
  size_t t = 0;
  for (const auto& kv : truth) {
    ASSERT_EQ(ids[t], kv.first);
    double su = 0.0, sv = 0.0;
    for (int c = 0; c < 4; ++c) {
      const int i = 5 * static_cast<int>(t) + c;
      ASSERT_TRUE(r.points.seen[static_cast<size_t>(i)]);
      EXPECT_NEAR(r.points.uv_px(2 * i) + kFileConventionPx, kv.second[2 * c], kCornerTolerancePx)
          << "tag " << kv.first << " corner " << c;
      EXPECT_NEAR(r.points.uv_px(2 * i + 1) + kFileConventionPx, kv.second[2 * c + 1], kCornerTolerancePx)
          << "tag " << kv.first << " corner " << c;
      su += kv.second[2 * c];
      sv += kv.second[2 * c + 1];
    }
    // AND the centre lies inside the quadrilateral, near the mean of the corners (perspective
    // moves it by a fraction of a pixel on these small tags)
    const int ic = 5 * static_cast<int>(t) + 4;
    EXPECT_NEAR(r.points.uv_px(2 * ic) + kFileConventionPx, su / 4.0, 2.0);
    EXPECT_NEAR(r.points.uv_px(2 * ic + 1) + kFileConventionPx, sv / 4.0, 2.0);
    ++t;
  }
  // AND without tag size no pose, no depth
  EXPECT_FALSE(r.pose_valid);
  EXPECT_TRUE(std::isnan(r.points.Z_m(0)));
  EXPECT_TRUE(r.note.empty());
}

TEST(AprilTagTracker, PosesMatchViSPsGroundTruth) {
  SKIP_WITHOUT_IMAGES();
  // GIVEN the camera and tag size of ViSP's test and the ground-truth poses
  vpImage<unsigned char> I;
  vpImageIo::read(I, kAprilTagDir + "/AprilTag.pgm");
  std::map<int, vpPoseVector> truth;
  std::ifstream in(kAprilTagDir + "/ground_truth_pose.txt");
  std::string message;
  double p[6];
  while (in >> message >> p[0] >> p[1] >> p[2] >> p[3] >> p[4] >> p[5])
    truth[idOf(message)] = vpPoseVector(p[0], p[1], p[2], p[3], p[4], p[5]);
  ASSERT_EQ(truth.size(), 12u);

  // WHEN the tracker estimates the poses (tag 8 first)
  auto tracker = makeImageTracker("apriltag", Params{{"tag_size", 0.053}}, viSPTestCamera());
  const TrackedPoints r = tracker->track(I);
  ASSERT_EQ(tracker->points(), 60);

  // THEN the pose of tag 8 matches within 0.005 per component
  ASSERT_TRUE(r.pose_valid);
  const vpPoseVector pose8(r.cMo);
  for (unsigned k = 0; k < 6; ++k) EXPECT_NEAR(pose8[k], truth[8][k], kPoseTolerance) << "component " << k;
  // AND every point's depth is that of the ground-truth pose of its tag (corners in the frame of
  // ViSP's pose, vpDetectorAprilTag::getTagsPoints3D(), then the centre) within 1 mm
  const double h = 0.053 / 2.0;
  const double oP[5][2] = {{-h, -h}, {h, -h}, {h, h}, {-h, h}, {0.0, 0.0}};
  int t = 0;
  for (const auto& kv : truth) {
    const vpHomogeneousMatrix M(kv.second);
    for (int j = 0; j < 5; ++j) {
      const int i = 5 * t + j;
      const double Z = M[2][0] * oP[j][0] + M[2][1] * oP[j][1] + M[2][3];
      EXPECT_NEAR(r.points.Z_m(i), Z, kDepthToleranceM) << "tag " << kv.first << " point " << j;
    }
    ++t;
  }
}

TEST(AprilTagTracker, ListedTagNotFoundIsLostNotAnError) {
  SKIP_WITHOUT_IMAGES();
  vpImage<unsigned char> I;
  vpImageIo::read(I, kAprilTagDir + "/AprilTag.pgm");
  // GIVEN ids 9 (in the image) and 42 (not in it)
  Params params;
  params.setText("ids", "42, 9");
  auto tracker = makeImageTracker("apriltag", params, ImageTrackerContext{});
  ASSERT_EQ(tracker->points(), 10);
  const TrackedPoints r = tracker->track(I);
  // THEN tag 9 (first: increasing ids) is seen, tag 42's five points are lost with NaN pixels
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(r.points.seen[static_cast<size_t>(i)]);
  for (int i = 5; i < 10; ++i) {
    EXPECT_FALSE(r.points.seen[static_cast<size_t>(i)]);
    EXPECT_TRUE(std::isnan(r.points.uv_px(2 * i)));
  }
  EXPECT_EQ(r.note, "tag 42 not found");
  // AND a blank image loses everything without throwing
  vpImage<unsigned char> blank(480, 640, 128);
  const TrackedPoints none = tracker->track(blank);
  for (bool s : none.points.seen) EXPECT_FALSE(s);
}

TEST(AprilTagTracker, RejectsBadParameters) {
  EXPECT_THROW(makeImageTracker("apriltag", Params{{"decimation", 0.5}}, {}), std::invalid_argument);
  EXPECT_THROW(makeImageTracker("apriltag", Params{{"tagsize", 0.1}}, {}), std::invalid_argument);
  Params family;
  family.setText("family", "36h12");
  EXPECT_THROW(makeImageTracker("apriltag", family, {}), std::invalid_argument);
  Params ids;
  ids.setText("ids", "8,8");
  EXPECT_THROW(makeImageTracker("apriltag", ids, {}), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
