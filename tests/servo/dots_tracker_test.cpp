// The `dots` image tracker (servo/dots_tracker.h) and image sequences (servo/image_sequence.h) on
// ViSP's mire-2 sequence (five white dots on a black plate, 501 frames 384x288, hand-held camera
// over a cluttered scene) and on sequences built from it in a scratch directory. Skipped, with
// a message, when the Debian package visp-images-data is not installed.
#include "predvs/servo/dots_tracker.h"
#include "predvs/servo/image_sequence.h"

#include <visp3/io/vpImageIo.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace predvs {
namespace {

namespace fs = std::filesystem;

const std::string kImages = "/usr/share/visp-images-data/ViSP-images";
const std::string kMire2 = kImages + "/mire-2/image.%04d.pgm";

std::string mire2Frame(int index) {
  char name[64];
  std::snprintf(name, sizeof(name), "/mire-2/image.%04d.pgm", index);
  return kImages + name;
}

#define REQUIRE_VISP_IMAGES()                                                                          \
  if (!fs::exists(kImages + "/mire-2/image.0001.pgm"))                                               \
  GTEST_SKIP() << "ViSP-images not found under " << kImages                                          \
               << ": install the Debian package visp-images-data (scripts/install-deps.sh does)"

/// A scratch directory per test, removed afterwards.
class ScratchImages : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("predvs_images_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// Copies mire-2 frames first..last to DIR/img_%03d.pgm numbered from 0.
  void copyMire2(int first, int last) const {
    for (int i = first; i <= last; ++i) {
      char name[32];
      std::snprintf(name, sizeof(name), "img_%03d.pgm", i - first);
      fs::copy_file(mire2Frame(i), dir_ / name);
    }
  }
  fs::path dir_;
};

// --------------------------------------------------------------------------------------------
TEST(DotsTracker, TracksTheFiveMire2DotsThroughTheWholeSequenceWithoutLoss) {
  REQUIRE_VISP_IMAGES();
  // GIVEN the whole of mire-2 and the tracker with its defaults (no hint, no click)
  auto seq = openImageSequence(kMire2);
  auto tracker = makeImageTracker("dots", Params{}, ImageTrackerContext{});
  ImageFrame f;
  std::string why;
  int frames = 0, lost = 0;
  Eigen::VectorXd first, previous;
  double max_step_px = 0.0;
  // WHEN every frame is tracked
  for (ImageRead r; (r = seq->next(f, why)) != ImageRead::End;) {
    ASSERT_EQ(r, ImageRead::Ok) << f.origin << ": " << why;
    const TrackedPoints tp = tracker->track(f.image);
    ASSERT_EQ(tp.points.points(), 5) << "frame " << f.index << ": " << tp.note;
    for (bool s : tp.points.seen) lost += s ? 0 : 1;
    if (frames == 0) first = tp.points.uv_px;
    if (frames > 0)
      for (int p = 0; p < 5; ++p)
        max_step_px = std::max(max_step_px, std::hypot(tp.points.uv_px(2 * p) - previous(2 * p),
                                                       tp.points.uv_px(2 * p + 1) - previous(2 * p + 1)));
    previous = tp.points.uv_px;
    ++frames;
  }
  // THEN 501 frames, five dots, none lost, no jump to another blob (the largest frame-to-frame
  // motion of a dot in mire-2 is about 15 px; a swap between dots would be > 60 px)
  EXPECT_EQ(frames, 501);
  EXPECT_EQ(lost, 0);
  EXPECT_LT(max_step_px, 30.0);
  // AND the order is rows then columns on the first frame: v non-decreasing between rows, and
  // the two dots of the top row (v within a dot height) left to right.
  EXPECT_LT(first(0), first(2));                    // dot0 left of dot1 (same row)
  EXPECT_LT(std::fabs(first(1) - first(3)), 15.0);  // ... whose v differ by less than a dot
  EXPECT_LT(first(3), first(5));                    // then the centre dot's row, ...
  EXPECT_LT(first(5), first(7));
  EXPECT_LT(first(7), first(9));
  EXPECT_EQ(tracker->pointNames(), (std::vector<std::string>{"dot0", "dot1", "dot2", "dot3", "dot4"}));
}

TEST(DotsTracker, AHintOrdersThePointsAndAnExpectedCountKeepsTheMostTypicalDots) {
  REQUIRE_VISP_IMAGES();
  vpImage<unsigned char> I;
  vpImageIo::read(I, mire2Frame(1));
  auto plain = makeImageTracker("dots", Params{}, ImageTrackerContext{});
  const Eigen::VectorXd uv = plain->track(I).points.uv_px;
  ASSERT_EQ(uv.size(), 10);
  // GIVEN a hint listing the dots in reverse order, 3 px off
  Eigen::VectorXd hint(10);
  for (int p = 0; p < 5; ++p) {
    hint(2 * p) = uv(2 * (4 - p)) + 3.0;
    hint(2 * p + 1) = uv(2 * (4 - p) + 1) - 3.0;
  }
  auto hinted = makeImageTracker("dots", Params{}, ImageTrackerContext{});
  const TrackedPoints tp = hinted->track(I, &hint);
  // THEN point p is the dot nearest hint point p
  ASSERT_EQ(tp.points.points(), 5);
  for (int p = 0; p < 5; ++p) {
    EXPECT_NEAR(tp.points.uv_px(2 * p), uv(2 * (4 - p)), 1e-9);
    EXPECT_NEAR(tp.points.uv_px(2 * p + 1), uv(2 * (4 - p) + 1), 1e-9);
  }
  // AND points = 4 drops the big centre dot (its area is the farthest from the median)
  auto four = makeImageTracker("dots", Params{{"points", 4.0}}, ImageTrackerContext{});
  const TrackedPoints tp4 = four->track(I);
  ASSERT_EQ(tp4.points.points(), 4);
  for (int p = 0; p < 4; ++p) EXPECT_GT(std::hypot(tp4.points.uv_px(2 * p) - uv(4), tp4.points.uv_px(2 * p + 1) - uv(5)), 20.0);
  // AND points = 6 (more than there are) does not initialise: no point, a note, no exception
  auto six = makeImageTracker("dots", Params{{"points", 6.0}}, ImageTrackerContext{});
  const TrackedPoints tp6 = six->track(I);
  EXPECT_EQ(tp6.points.points(), 0);
  EXPECT_NE(tp6.note.find("6 expected"), std::string::npos) << tp6.note;
}

TEST(DotsTracker, BlankFramesLoseEveryDotAndTheDotsAreReacquiredAfterwards) {
  REQUIRE_VISP_IMAGES();
  auto tracker = makeImageTracker("dots", Params{}, ImageTrackerContext{});
  vpImage<unsigned char> I;
  vpImageIo::read(I, mire2Frame(1));
  const Eigen::VectorXd before = tracker->track(I).points.uv_px;
  // GIVEN three blank (uniform grey) frames
  vpImage<unsigned char> blank(I.getHeight(), I.getWidth(), 128);
  for (int k = 0; k < 3; ++k) {
    const TrackedPoints tp = tracker->track(blank);
    ASSERT_EQ(tp.points.points(), 5);  // N never changes
    for (int p = 0; p < 5; ++p) EXPECT_FALSE(tp.points.seen[p]);
    EXPECT_TRUE(std::isnan(tp.points.uv_px(0)));
    EXPECT_NE(tp.note.find("all 5 dots lost"), std::string::npos) << tp.note;
  }
  // WHEN the target comes back (frame 2, a few px from frame 1)
  vpImageIo::read(I, mire2Frame(2));
  const TrackedPoints back = tracker->track(I);
  // THEN every dot is re-acquired near where it was, in the same order
  auto fresh = makeImageTracker("dots", Params{}, ImageTrackerContext{});
  fresh->track(I);  // a tracker initialised on frame 2 directly, for reference
  const Eigen::VectorXd reference = fresh->track(I).points.uv_px;
  for (int p = 0; p < 5; ++p) {
    EXPECT_TRUE(back.points.seen[p]) << back.note;
    EXPECT_NEAR(back.points.uv_px(2 * p), reference(2 * p), 0.5);
    EXPECT_NEAR(back.points.uv_px(2 * p + 1), reference(2 * p + 1), 0.5);
    EXPECT_LT(std::hypot(back.points.uv_px(2 * p) - before(2 * p), back.points.uv_px(2 * p + 1) - before(2 * p + 1)), 20.0);
  }
}

TEST(DotsTracker, BadParametersAreRejectedNamingTheKey) {
  const auto message = [](const Params& p) {
    try {
      makeImageTracker("dots", p, ImageTrackerContext{});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(Params{{"sise_px", 3.0}}).find("sise_px"), std::string::npos);
  EXPECT_NE(message(Params{{"points", 2.5}}).find("points"), std::string::npos);
  EXPECT_NE(message(Params{{"polarity", 0.5}}).find("polarity"), std::string::npos);
  EXPECT_NE(message(Params{{"min_size_px", 20.0}, {"max_size_px", 10.0}}).find("max_size_px"), std::string::npos);
  try {
    makeImageTracker("blobs", Params{}, ImageTrackerContext{});
    ADD_FAILURE() << "no error for an unknown tracker";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown image tracker 'blobs' (known: dots"), std::string::npos) << e.what();
  }
}

TEST(DotDetection, FindsSyntheticDiscsOfBothPolaritiesAndNothingOnAUniformImage) {
  // GIVEN dark discs of radius 6 px on a light background, centres known to 1e-9 px
  vpImage<unsigned char> I(120, 160, 200);
  const double cu[2] = {40.0, 110.0}, cv[2] = {50.0, 70.0};
  for (unsigned v = 0; v < I.getHeight(); ++v)
    for (unsigned u = 0; u < I.getWidth(); ++u)
      for (int k = 0; k < 2; ++k)
        if (std::hypot(u - cu[k], v - cv[k]) <= 6.0) I[v][u] = 30;
  int polarity = 0;
  const auto found = detectDots(I, DotDetectionOptions{}, 0, 0, 160, 120, &polarity);
  // THEN both are found at their centres (symmetric discs: exact centroids), dark polarity
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(polarity, -1);
  EXPECT_NEAR(found[0].u_px, 40.0, 1e-9);
  EXPECT_NEAR(found[0].v_px, 50.0, 1e-9);
  EXPECT_NEAR(found[1].u_px, 110.0, 1e-9);
  // AND the same discs in bright on dark are found with polarity +1
  for (unsigned v = 0; v < I.getHeight(); ++v)
    for (unsigned u = 0; u < I.getWidth(); ++u) I[v][u] = static_cast<unsigned char>(255 - I[v][u]);
  EXPECT_EQ(detectDots(I, DotDetectionOptions{}, 0, 0, 160, 120, &polarity).size(), 2u);
  EXPECT_EQ(polarity, +1);
  // AND a uniform image, or one with faint noise, has no candidate
  vpImage<unsigned char> flat(120, 160, 90);
  EXPECT_TRUE(detectDots(flat, DotDetectionOptions{}, 0, 0, 160, 120).empty());
  for (unsigned v = 0; v < flat.getHeight(); ++v)
    for (unsigned u = 0; u < flat.getWidth(); ++u) flat[v][u] = static_cast<unsigned char>(90 + (u * 7 + v * 13) % 9);
  EXPECT_TRUE(detectDots(flat, DotDetectionOptions{}, 0, 0, 160, 120).empty());
  // AND a long bar (not an ellipse-like blob of plain surround) is not a dot
  vpImage<unsigned char> bar(120, 160, 200);
  for (unsigned v = 50; v < 60; ++v)
    for (unsigned u = 20; u < 140; ++u) bar[v][u] = 30;
  EXPECT_TRUE(detectDots(bar, DotDetectionOptions{}, 0, 0, 160, 120).empty());
}

// --------------------------------------------------------------------------------------------
TEST(ImageSequence, Mire2PatternHas501FramesStampedByTheFramePeriod) {
  REQUIRE_VISP_IMAGES();
  ImageSequenceOptions o;
  o.frame_period_s = 0.04;
  auto seq = openImageSequence(kMire2, o);
  EXPECT_EQ(seq->size(), 501);
  ImageFrame f;
  std::string why;
  ASSERT_EQ(seq->next(f, why), ImageRead::Ok);
  EXPECT_EQ(f.index, 1);
  EXPECT_EQ(f.t_s, 0.0);
  EXPECT_EQ(seq->width(), 384u);
  EXPECT_EQ(seq->height(), 288u);
  ASSERT_EQ(seq->next(f, why), ImageRead::Ok);
  EXPECT_EQ(f.index, 2);
  EXPECT_NEAR(f.t_s, 0.04, 1e-15);
  EXPECT_EQ(f.origin, mire2Frame(2));
  EXPECT_NE(seq->describe().find("501 frames"), std::string::npos) << seq->describe();
}

TEST_F(ScratchImages, APatternSequenceSkipsMissingCorruptAndResizedFramesWithAReason) {
  REQUIRE_VISP_IMAGES();
  // GIVEN frames 0..9 of which 3 is missing, 5 is a truncated PGM and 7 is 200x100
  copyMire2(1, 10);
  fs::remove(path("img_003.pgm"));
  std::ofstream(path("img_005.pgm"), std::ios::binary) << "P5\n384 288\n255\n" << std::string(1000, '\x10');
  vpImageIo::write(vpImage<unsigned char>(100, 200, 50), path("img_007.pgm"));
  auto seq = openImageSequence(path("img_%03d.pgm"));
  ASSERT_EQ(seq->size(), 10);
  ImageFrame f;
  std::string why;
  std::vector<std::string> reasons(10);
  std::vector<ImageRead> status;
  for (ImageRead r; (r = seq->next(f, why)) != ImageRead::End;) {
    status.push_back(r);
    if (r == ImageRead::Skipped) reasons[static_cast<size_t>(f.index)] = why;
    if (r == ImageRead::Ok) {
      EXPECT_EQ(f.image.getWidth(), 384u);
    }
    EXPECT_NEAR(f.t_s, f.index / 30.0, 1e-12);
  }
  // THEN 10 frames, 3 skipped with their reasons, the others read
  ASSERT_EQ(status.size(), 10u);
  for (int i = 0; i < 10; ++i)
    EXPECT_EQ(status[static_cast<size_t>(i)] == ImageRead::Skipped, i == 3 || i == 5 || i == 7) << i;
  EXPECT_EQ(reasons[3], "missing file");
  EXPECT_NE(reasons[5].find("corrupt"), std::string::npos) << reasons[5];
  EXPECT_NE(reasons[7].find("size 200x100 differs from the sequence's 384x288"), std::string::npos) << reasons[7];
}

TEST_F(ScratchImages, DirectoryAndSingleImageAndFrameBudget) {
  REQUIRE_VISP_IMAGES();
  copyMire2(1, 4);
  std::ofstream(path("notes.txt")) << "not an image";
  ImageSequenceOptions o;
  o.max_frames = 3;
  auto dir = openImageSequence(dir_.string(), o);
  ImageFrame f;
  std::string why;
  std::vector<std::string> origins;
  for (ImageRead r; (r = dir->next(f, why)) != ImageRead::End;) {
    EXPECT_EQ(r, ImageRead::Ok) << why;
    origins.push_back(fs::path(f.origin).filename().string());
  }
  EXPECT_EQ(origins, (std::vector<std::string>{"img_000.pgm", "img_001.pgm", "img_002.pgm"}));
  auto one = openImageSequence(path("img_002.pgm"));
  EXPECT_EQ(one->size(), 1);
  EXPECT_EQ(one->next(f, why), ImageRead::Ok);
  EXPECT_EQ(one->next(f, why), ImageRead::End);
}

TEST_F(ScratchImages, SpecificationsThatCannotBeOpenedThrowOneLineNamingThem) {
  const auto message = [](const std::string& spec) {
    try {
      openImageSequence(spec);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(path("nothing.avi")), "images '" + path("nothing.avi") + "': no such file or directory");
  EXPECT_NE(message(path("none_%04d.pgm")).find("no file matches the pattern"), std::string::npos);
  EXPECT_NE(message("/nonexistent/dir/im_%04d.pgm").find("no directory"), std::string::npos);
  EXPECT_NE(message(path("a_%d_%d.pgm")).find("exactly one integer conversion"), std::string::npos);
  EXPECT_NE(message(dir_.string()).find("no image file"), std::string::npos);
  std::ofstream(path("garbage.avi"), std::ios::binary) << std::string(4096, 'x');
  EXPECT_NE(message(path("garbage.avi")).find("cannot open the video"), std::string::npos) << message(path("garbage.avi"));
  for (const auto& m : {message(path("garbage.avi")), message(path("nothing.avi"))})
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

TEST(ImageSequence, ReadsTheCubeVideoFromTheFirstFrameOnce) {
  REQUIRE_VISP_IMAGES();
  const std::string video = kImages + "/video/cube.mpeg";
  if (!fs::exists(video)) GTEST_SKIP() << video << " not found";
  ImageSequenceOptions o;
  o.max_frames = 5;
  auto seq = openImageSequence(video, o);
  ImageFrame f;
  std::string why;
  std::vector<vpImage<unsigned char>> frames;
  for (ImageRead r; (r = seq->next(f, why)) != ImageRead::End;) {
    ASSERT_EQ(r, ImageRead::Ok) << why;
    EXPECT_EQ(f.index, static_cast<long>(frames.size()));
    frames.push_back(f.image);
  }
  ASSERT_EQ(frames.size(), 5u);
  EXPECT_GT(frames[0].getWidth(), 0u);
  // The first frame is delivered once (vpVideoReader's repeated first frame does not occur):
  // consecutive frames of this moving-cube video differ.
  for (size_t k = 1; k < frames.size(); ++k) EXPECT_FALSE(frames[k] == frames[k - 1]) << "frames " << k - 1 << " and " << k;
}

}  // namespace
}  // namespace predvs
