// Rendering the target (servo/image_renderer.h) and finding it again with the image trackers:
// the committed tag cells are the code of tag 0 of ViSP's 36h11 benchmark image; a tag rendered at
// a known pose is decoded with its id and its corners and centre are found within 0.3 px of their
// true projections; dots likewise (when the `dots` tracker is registered); the camera effects
// (noise, blur, hidden target) do what they say.
#include "predvs/servo/image_renderer.h"
#include "predvs/servo/image_tracker.h"
#include "predvs/servo/scene.h"

#include <visp3/core/vpImagePoint.h>
#include <visp3/detection/vpDetectorAprilTag.h>
#include <visp3/io/vpImageIo.h>

#include <Eigen/Dense>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <sys/stat.h>

namespace predvs {
namespace {

constexpr double kFoundTolerancePx = 0.3;  // the "found within ~0.3 px of its true projection"

bool exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

const std::string kBenchmark =
    "/usr/share/visp-images-data/ViSP-images/AprilTag/benchmark/1920x1080/tag36_11_1920x1080.png";
const std::string kCellsPath = std::string(PREDVS_SOURCE_DIR) + "/data/textures/tag36h11_id0.pgm";

/// The 10 x 10 cells (0 black, 255 white) of the tag `id` in `image`: the cell centres mapped
/// through the homography of its detected corners (the black square's corners; the white margin
/// cells lie outside them), each the mean of a 3 x 3 grid of bilinear samples at +-0.15 cell,
/// thresholded midway between the mean of the white margin and the mean of the black border.
bool extractTagCells(const vpImage<unsigned char>& image, int id, vpImage<unsigned char>& cells, std::string& why) {
  vpDetectorAprilTag detector(vpDetectorAprilTag::TAG_36h11);
  detector.detect(image);
  const auto ids = detector.getTagsId();
  const auto corners = detector.getTagsCorners();
  size_t k = ids.size();
  for (size_t i = 0; i < ids.size(); ++i)
    if (ids[i] == id) k = i;
  if (k == ids.size()) {
    why = "tag " + std::to_string(id) + " not detected";
    return false;
  }
  std::vector<vpImagePoint> c = corners[k];
  // Keep the image's handedness: a runs along c0 -> c1, b along c0 -> c3, with (c1 - c0) x (c2 - c1)
  // > 0 in (u, v) (clockwise on screen, as texture columns then rows).
  const double cross = (c[1].get_u() - c[0].get_u()) * (c[2].get_v() - c[1].get_v()) -
                       (c[1].get_v() - c[0].get_v()) * (c[2].get_u() - c[1].get_u());
  if (cross < 0) std::swap(c[1], c[3]);
  // Homography (a, b) -> (u, v) from the unit square's corners.
  Eigen::Matrix<double, 8, 8> A;
  Eigen::Matrix<double, 8, 1> rhs;
  const double sq[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int i = 0; i < 4; ++i) {
    const double a = sq[i][0], b = sq[i][1], u = c[static_cast<size_t>(i)].get_u(), v = c[static_cast<size_t>(i)].get_v();
    A.row(2 * i) << a, b, 1, 0, 0, 0, -a * u, -b * u;
    A.row(2 * i + 1) << 0, 0, 0, a, b, 1, -a * v, -b * v;
    rhs(2 * i) = u;
    rhs(2 * i + 1) = v;
  }
  const Eigen::Matrix<double, 8, 1> h = A.fullPivLu().solve(rhs);
  double value[10][10];
  for (int r = 0; r < 10; ++r)
    for (int col = 0; col < 10; ++col) {
      double sum = 0.0;
      for (int da = -1; da <= 1; ++da)
        for (int db = -1; db <= 1; ++db) {
          const double a = (col - 1 + 0.5 + 0.15 * da) / 8.0, b = (r - 1 + 0.5 + 0.15 * db) / 8.0;
          const double w = h(6) * a + h(7) * b + 1.0;
          const double u = (h(0) * a + h(1) * b + h(2)) / w, v = (h(3) * a + h(4) * b + h(5)) / w;
          sum += image.getValue(v, u);
        }
      value[r][col] = sum / 9.0;
    }
  double white = 0.0, black = 0.0;
  for (int i = 0; i < 10; ++i) {
    white += value[0][i] + value[9][i] + (i > 0 && i < 9 ? value[i][0] + value[i][9] : 0.0);
    if (i >= 1 && i <= 8) black += value[1][i] + value[8][i] + (i > 1 && i < 8 ? value[i][1] + value[i][8] : 0.0);
  }
  const double threshold = (white / 36.0 + black / 28.0) / 2.0;
  cells.resize(10, 10);
  for (int r = 0; r < 10; ++r)
    for (int col = 0; col < 10; ++col)
      cells[static_cast<unsigned>(r)][static_cast<unsigned>(col)] = value[r][col] > threshold ? 255 : 0;
  return true;
}

TEST(TagCells, CommittedFileIsTag0OfViSPsBenchmarkImage) {
  if (!exists(kBenchmark)) GTEST_SKIP() << kBenchmark << " is absent: install visp-images-data";
  // GIVEN tag 0 of ViSP's 36h11 benchmark image (1920x1080, rendered, about 19 px per cell)
  vpImage<unsigned char> image, cells, committed;
  vpImageIo::read(image, kBenchmark);
  std::string why;
  ASSERT_TRUE(extractTagCells(image, 0, cells, why)) << why;
  // `PREDVS_REGENERATE_GOLDEN=1 servo_tests --gtest_filter=TagCells.*` rewrites the file.
  if (const char* regen = std::getenv("PREDVS_REGENERATE_GOLDEN"); regen && std::string(regen) == "1")
    vpImageIo::write(cells, kCellsPath);
  // THEN the committed cells are exactly its code: white margin, black border, the 6 x 6 bits
  ASSERT_TRUE(exists(kCellsPath)) << kCellsPath;
  vpImageIo::read(committed, kCellsPath);
  ASSERT_EQ(committed.getWidth(), 10u);
  ASSERT_EQ(committed.getHeight(), 10u);
  for (unsigned r = 0; r < 10; ++r)
    for (unsigned c = 0; c < 10; ++c) {
      EXPECT_EQ(committed[r][c], cells[r][c]) << "cell " << r << ", " << c;
      if (r == 0 || r == 9 || c == 0 || c == 9) {
        EXPECT_EQ(cells[r][c], 255) << "margin " << r << ", " << c;
      } else if (r == 1 || r == 8 || c == 1 || c == 8) {
        EXPECT_EQ(cells[r][c], 0) << "border " << r << ", " << c;
      }
    }
}

TEST(TagTexture, BoundaryTexelsAreTheMeanOfTheirCells) {
  vpImage<unsigned char> cells(10, 10, 255);
  cells[1][1] = 0;
  const vpImage<unsigned char> t = tagTexture(cells, 4);
  ASSERT_EQ(t.getWidth(), 41u);
  EXPECT_EQ(t[6][6], 0);      // inside cell (1, 1)
  EXPECT_EQ(t[4][6], 128);    // on its top boundary: mean of 0 and 255
  EXPECT_EQ(t[4][4], 191);    // on its corner: mean of 0 and three 255
  EXPECT_EQ(t[40][40], 255);  // the last texel
  EXPECT_THROW(tagTexture(vpImage<unsigned char>(8, 10)), std::invalid_argument);
}

/// The pose of a point set seen from a camera 0.5 m in front, tilted by 0.3 rad about x and 0.2
/// about y, and shifted off axis: a generic view, not fronto-parallel.
vpHomogeneousMatrix genericView() { return vpHomogeneousMatrix(0.012, -0.008, 0.5, 0.3, 0.2, 0.1); }

PointFeatures project(const Eigen::Matrix3Xd& oP, const vpHomogeneousMatrix& cMo, const CameraIntrinsics& cam) {
  PointFeatures f;
  f.uv_px.resize(2 * oP.cols());
  f.Z_m.resize(oP.cols());
  f.seen.assign(static_cast<size_t>(oP.cols()), true);
  for (Eigen::Index i = 0; i < oP.cols(); ++i) {
    const double X = cMo[0][0] * oP(0, i) + cMo[0][1] * oP(1, i) + cMo[0][2] * oP(2, i) + cMo[0][3];
    const double Y = cMo[1][0] * oP(0, i) + cMo[1][1] * oP(1, i) + cMo[1][2] * oP(2, i) + cMo[1][3];
    const double Z = cMo[2][0] * oP(0, i) + cMo[2][1] * oP(1, i) + cMo[2][2] * oP(2, i) + cMo[2][3];
    f.uv_px(2 * i) = cam.u0 + cam.px * X / Z;
    f.uv_px(2 * i + 1) = cam.v0 + cam.py * Y / Z;
    f.Z_m(i) = Z;
  }
  return f;
}

TEST(ImageRenderer, RenderedTagIsDecodedAndFoundWithinAThirdOfAPixel) {
  // GIVEN a 10 cm tag (corners of squarePoints, then its centre) at a generic pose
  Eigen::Matrix3Xd oP(3, 5);
  oP.leftCols(4) = squarePoints(0.1);
  oP.col(4).setZero();
  CameraIntrinsics cam;
  ImageRenderer renderer(RenderedPattern::AprilTag, oP, cam, ImageRendererOptions{});
  EXPECT_NEAR(renderer.tagSizeM(), 0.1, 1e-12);
  const vpHomogeneousMatrix cMo = genericView();
  vpImage<unsigned char> I;
  renderer.render(cMo, true, I);
  ASSERT_EQ(I.getWidth(), 640u);
  ASSERT_EQ(I.getHeight(), 480u);
  // WHEN the apriltag tracker (camera known, tag size given) looks at it
  ImageTrackerContext ctx;
  ctx.camera = cam;
  ctx.camera_known = true;
  auto tracker = makeImageTracker("apriltag", Params{{"tag_size", 0.1}}, ctx);
  const TrackedPoints r = tracker->track(I);
  // THEN it decodes tag 0 and finds each of the square's corners (in some rotation of the
  // detector's order) and the centre within 0.3 px of the true projection
  ASSERT_EQ(tracker->pointNames().front(), "tag0.c0");
  const PointFeatures truth = project(oP, cMo, cam);
  for (int j = 0; j < 5; ++j) {
    ASSERT_TRUE(r.points.seen[static_cast<size_t>(j)]);
    double best = 1e9;
    for (int i = 0; i < 5; ++i)
      best = std::min(best, std::hypot(r.points.uv_px(2 * j) - truth.uv_px(2 * i),
                                       r.points.uv_px(2 * j + 1) - truth.uv_px(2 * i + 1)));
    EXPECT_LT(best, kFoundTolerancePx) << "tracker point " << j;
  }
  // AND the centre is the centre, with the true depth within 2 mm
  EXPECT_NEAR(r.points.uv_px(8), truth.uv_px(8), kFoundTolerancePx);
  EXPECT_NEAR(r.points.uv_px(9), truth.uv_px(9), kFoundTolerancePx);
  ASSERT_TRUE(r.pose_valid);
  EXPECT_NEAR(r.points.Z_m(4), truth.Z_m(4), 2e-3);
}

TEST(ImageRenderer, RenderedDotsAreFoundWithinAThirdOfAPixel) {
  if (!isImageTracker("dots")) GTEST_SKIP() << "the dots tracker is not registered in this build";
  // GIVEN the default 10 cm square of dots (radius 1 cm) at a generic pose
  const Eigen::Matrix3Xd oP = squarePoints(0.1);
  CameraIntrinsics cam;
  ImageRenderer renderer(RenderedPattern::Dots, oP, cam, ImageRendererOptions{});
  const vpHomogeneousMatrix cMo = genericView();
  vpImage<unsigned char> I;
  renderer.render(cMo, true, I);
  // WHEN the dots tracker starts from the true projections as its hint
  const PointFeatures truth = project(oP, cMo, cam);
  auto tracker = makeImageTracker("dots", Params{}, ImageTrackerContext{cam, true});
  const TrackedPoints r = tracker->track(I, &truth.uv_px);
  // THEN every dot's centre of gravity is within 0.3 px of the projection of its centre
  ASSERT_EQ(tracker->points(), 4);
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(r.points.seen[static_cast<size_t>(i)]) << r.note;
    EXPECT_LT(std::hypot(r.points.uv_px(2 * i) - truth.uv_px(2 * i), r.points.uv_px(2 * i + 1) - truth.uv_px(2 * i + 1)),
              kFoundTolerancePx)
        << "dot " << i;
  }
}

TEST(ImageRenderer, DarkDotCentroidIsTheProjectionOfItsCentre) {
  // GIVEN one dot rendered without noise (independent of any tracker)
  Eigen::Matrix3Xd oP(3, 1);
  oP << 0.01, -0.02, 0.0;
  CameraIntrinsics cam;
  ImageRenderer renderer(RenderedPattern::Dots, oP, cam, ImageRendererOptions{});
  const vpHomogeneousMatrix cMo = genericView();
  vpImage<unsigned char> I;
  renderer.render(cMo, true, I);
  // THEN the darkness-weighted centroid (background 128 minus grey) is within 0.3 px of it
  double s = 0.0, su = 0.0, sv = 0.0;
  for (unsigned i = 0; i < I.getHeight(); ++i)
    for (unsigned j = 0; j < I.getWidth(); ++j) {
      const double w = 128.0 - I[i][j];
      s += w;
      su += w * j;
      sv += w * i;
    }
  const PointFeatures truth = project(oP, cMo, cam);
  ASSERT_GT(s, 0.0);
  EXPECT_NEAR(su / s, truth.uv_px(0), kFoundTolerancePx);
  EXPECT_NEAR(sv / s, truth.uv_px(1), kFoundTolerancePx);
  // AND an area about pi r^2 in pixels (r = 800 * 0.01 / Z): dark mass / 128
  const double r_px = 800.0 * 0.01 / truth.Z_m(0);
  EXPECT_NEAR(s / 128.0, M_PI * r_px * r_px, 0.1 * M_PI * r_px * r_px);
}

TEST(ImageRenderer, HiddenTargetNoiseAndBlur) {
  const Eigen::Matrix3Xd oP = squarePoints(0.1);
  CameraIntrinsics cam;
  const vpHomogeneousMatrix cMo = genericView();
  // A hidden target is the plain background.
  ImageRenderer plain(RenderedPattern::Dots, oP, cam, ImageRendererOptions{});
  vpImage<unsigned char> I;
  plain.render(cMo, false, I);
  for (unsigned k = 0; k < I.getSize(); ++k) ASSERT_EQ(I.bitmap[k], 128);
  // Noise of 4 grey levels: the background's standard deviation is about 4, the same seed gives
  // the same image, another seed another one.
  ImageRendererOptions o;
  o.noise_grey = 4.0;
  o.seed = 7;
  ImageRenderer noisy(RenderedPattern::Dots, oP, cam, o), same(RenderedPattern::Dots, oP, cam, o);
  o.seed = 8;
  ImageRenderer other(RenderedPattern::Dots, oP, cam, o);
  vpImage<unsigned char> A, B, C;
  noisy.render(cMo, false, A);
  same.render(cMo, false, B);
  other.render(cMo, false, C);
  double sum = 0.0, sum2 = 0.0;
  for (unsigned k = 0; k < A.getSize(); ++k) {
    sum += A.bitmap[k];
    sum2 += A.bitmap[k] * static_cast<double>(A.bitmap[k]);
  }
  const double n = A.getSize(), mean = sum / n;
  EXPECT_NEAR(mean, 128.0, 0.1);
  EXPECT_NEAR(std::sqrt(sum2 / n - mean * mean), 4.0, 0.1);  // rounding adds 1/12 to the variance
  EXPECT_TRUE(A == B);
  EXPECT_FALSE(A == C);
  // Blur spreads a dot's edge: fewer pure-background pixels next to it, same dark mass.
  o.noise_grey = 0.0;
  o.blur_px = 1.5;
  ImageRenderer blurred(RenderedPattern::Dots, oP, cam, o);
  vpImage<unsigned char> S, Bl;
  plain.render(cMo, true, S);
  blurred.render(cMo, true, Bl);
  double mass_s = 0.0, mass_b = 0.0;
  for (unsigned k = 0; k < S.getSize(); ++k) {
    mass_s += 128.0 - S.bitmap[k];
    mass_b += 128.0 - Bl.bitmap[k];
  }
  EXPECT_NEAR(mass_b, mass_s, 0.01 * mass_s);
  EXPECT_FALSE(S == Bl);
}

TEST(ImageRenderer, RejectsWhatItCannotDraw) {
  CameraIntrinsics cam;
  Eigen::Matrix3Xd rectangle(3, 4);
  rectangle << -0.1, 0.1, 0.1, -0.1, -0.05, -0.05, 0.05, 0.05, 0, 0, 0, 0;
  EXPECT_THROW(ImageRenderer(RenderedPattern::AprilTag, rectangle, cam, {}), std::invalid_argument);
  EXPECT_THROW(ImageRenderer(RenderedPattern::AprilTag, squarePoints(0.1).leftCols(3), cam, {}), std::invalid_argument);
  ImageRendererOptions o;
  o.noise_grey = -1.0;
  EXPECT_THROW(ImageRenderer(RenderedPattern::Dots, squarePoints(0.1), cam, o), std::invalid_argument);
  o = ImageRendererOptions{};
  o.tag_cells_path = "/nonexistent/tag.pgm";
  EXPECT_THROW(ImageRenderer(RenderedPattern::AprilTag, squarePoints(0.1), cam, o), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
