// `predvs calibrate camera|latency`, `--camera` and `--set-file` through the CLI: the grid36
// reference, a servo log with a known delay end to end, and the bad inputs (one-line error,
// status 2, no output).
#include "cli_test_utils.h"

#include "predvs/calibration/calibrated_camera.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>

namespace predvs {
namespace {

using apptest::run;

const std::string kGrid = "/usr/share/visp-images-data/ViSP-images/calibration/";

class Calibrate : public apptest::ScratchDirTest {
 protected:
  Calibrate() : ScratchDirTest("predvs_calibrate") {}
  void SetUp() override {
    ScratchDirTest::SetUp();
    if (!std::filesystem::exists(kGrid + "grid36-01.pgm")) GTEST_SKIP() << "visp-images-data is not installed";
  }
  /// A `predvs servo` log of the default scenario (hold only, no plots) with that vision delay.
  std::string servoLog(const std::string& name, const std::string& delay_frames) {
    const auto r = run({"servo", "--predictors", "hold", "--set", "duration_s=3", "--set", "timing.delay_frames=" + delay_frames,
                        "--no-plots", "--out", path(name)});
    EXPECT_EQ(r.code, 0) << r.err;
    return path(name) + "/log.csv";
  }
};

TEST_F(Calibrate, CameraOnGrid36WritesFilesTheServoAccepts) {
  // GIVEN the grid36 images WHEN calibrated through the CLI
  const auto r = run({"calibrate", "camera", "--images", kGrid + "grid36-*.pgm", "--pattern", "circles", "--no-plots",
                      "--name", "grid36", "--out", path("cam")});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN the per-image and overall RMS are printed and the files are there
  EXPECT_NE(r.out.find("grid36-03.pgm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("OpenCV k1 k2 p1 p2 k3"), std::string::npos) << r.out;
  const auto summary = apptest::readJson(path("cam/summary.json"));
  EXPECT_LE(summary["models"]["opencv_5_coefficients"]["rms_px"].get<double>(), 0.26);
  EXPECT_EQ(summary["images_used"].size(), 4u);
  EXPECT_TRUE(std::filesystem::exists(path("cam/camera.yaml")));
  const VispCameraFile cam = loadVispCameraXml(path("cam/camera.xml"), "grid36", vpCameraParameters::perspectiveProjWithoutDistortion);
  EXPECT_NEAR(cam.camera.get_px(), 553.0, 6.0);
  // AND `predvs servo --camera` takes the XML into the scenario's camera keys
  const auto s = run({"servo", "--camera", path("cam/camera.xml"), "--camera-name", "grid36", "--predictors", "hold", "--set",
                      "duration_s=1", "--no-plots", "--out", path("servo")});
  ASSERT_EQ(s.code, 0) << s.err;
  const auto overrides = apptest::readJson(path("servo/summary.json"))["overrides"];
  ASSERT_GE(overrides.size(), 6u);
  EXPECT_EQ(overrides[0].get<std::string>().rfind("camera.px=553.", 0), 0u) << overrides.dump();
  // a bad name or file is one error line naming it
  expectError(run({"servo", "--camera", path("cam/camera.xml"), "--camera-name", "nope", "--out", path("s2")}), "no camera 'nope'",
              path("s2"));
  expectError(run({"compare", "--camera", path("none.xml"), "--out", path("c2")}), "--camera " + path("none.xml"), path("c2"));
}

TEST_F(Calibrate, CameraRejectsAnImageWithoutThePatternByName) {
  std::filesystem::create_directories(path("mix"));
  for (int i = 1; i <= 4; ++i) {
    const std::string f = "grid36-0" + std::to_string(i) + ".pgm";
    std::filesystem::copy_file(kGrid + f, path("mix/") + f);
  }
  cv::imwrite(path("mix/blank.pgm"), cv::Mat(480, 640, CV_8UC1, cv::Scalar(200)));
  const auto r = run({"calibrate", "camera", "--images", path("mix"), "--no-plots", "--out", path("cam")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("blank.pgm: circles pattern 6 x 6 not found, image rejected"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("4 of 5 images used (rejected: blank.pgm)"), std::string::npos) << r.out;
  EXPECT_EQ(apptest::readJson(path("cam/summary.json"))["images_rejected"].dump(), "[\"blank.pgm\"]");
}

TEST_F(Calibrate, CameraBadInputs) {
  // no pattern in any image
  std::filesystem::create_directories(path("blank"));
  cv::imwrite(path("blank/a.png"), cv::Mat(240, 320, CV_8UC1, cv::Scalar(200)));
  cv::imwrite(path("blank/b.png"), cv::Mat(240, 320, CV_8UC1, cv::Scalar(90)));
  expectError(run({"calibrate", "camera", "--images", path("blank"), "--no-plots", "--out", path("o1")}), "found in none of the 2 images",
              path("o1"));
  // an unreadable image
  std::filesystem::create_directories(path("junk"));
  std::filesystem::copy_file(kGrid + "grid36-01.pgm", path("junk/grid36-01.pgm"));
  write("junk/grid36-02.pgm", "not an image");
  expectError(run({"calibrate", "camera", "--images", path("junk"), "--no-plots", "--out", path("o2")}), "cannot read this image",
              path("o2"));
  // too few images with the pattern
  std::filesystem::create_directories(path("two"));
  for (const char* f : {"grid36-01.pgm", "grid36-02.pgm"}) std::filesystem::copy_file(kGrid + f, path("two/") + f);
  cv::imwrite(path("two/blank.pgm"), cv::Mat(480, 640, CV_8UC1, cv::Scalar(200)));
  expectError(run({"calibrate", "camera", "--images", path("two"), "--no-plots", "--out", path("o3")}), "at least 3 are needed",
              path("o3"));
  expectError(run({"calibrate", "camera", "--images", path("nothing-*.png"), "--out", path("o4")}), "no file matches", path("o4"));
  expectError(run({"calibrate", "camera", "--images", path("two"), "--pattern", "dots", "--out", path("o5")}), "--pattern", path("o5"));
  // a pattern size given must be > 0 and of the pattern's kind (0 meant the default, silently)
  expectError(run({"calibrate", "camera", "--images", path("two"), "--diameter", "0", "--out", path("o6")}),
              "--diameter: expected a length > 0 (m), got '0'", path("o6"));
  expectError(run({"calibrate", "camera", "--images", path("two"), "--tag-size", "0.02", "--out", path("o6")}),
              "--tag-size: only with --pattern apriltag", path("o6"));
  expectError(run({"calibrate", "camera", "--images", path("two"), "--pattern", "chessboard", "--diameter", "0.01", "--out",
                   path("o6")}),
              "--diameter: only with --pattern circles", path("o6"));
}

TEST_F(Calibrate, LatencyOfAServoLogFeedsTheServo) {
  for (const std::string delay : {"1", "2"}) {
    // GIVEN a servo log with a vision delay of `delay` frames (40 ms each)
    const std::string log = servoLog("s" + delay, delay);
    // WHEN the latency is calibrated from it
    const auto r = run({"calibrate", "latency", "--log", log, "--no-plots", "--out", path("lat" + delay)});
    ASSERT_EQ(r.code, 0) << r.err;
    // THEN the vision delay is recovered within one base period, with its uncertainty
    const auto j = apptest::readJson(path("lat" + delay + "/latency.json"));
    EXPECT_NEAR(j["delivery_fit"]["delay_s"].get<double>(), 0.04 * std::stod(delay), 0.04) << j.dump(2);
    EXPECT_GT(j["vision_sigma_s"].get<double>(), 0.0);
    EXPECT_NE(r.out.find("vision delay"), std::string::npos);
    // AND its fragment runs the servo with the same timing (recorded as overrides)
    const auto s = run({"servo", "--set-file", path("lat" + delay + "/timing.yaml"), "--predictors", "kf-cv", "--set", "duration_s=1",
                        "--no-plots", "--out", path("again" + delay)});
    ASSERT_EQ(s.code, 0) << s.err;
    const std::string ov = apptest::readJson(path("again" + delay + "/summary.json"))["overrides"].dump();
    const std::string half = delay == "1" ? "0.02" : "0.04";
    EXPECT_NE(ov.find("timing.acquisition_lag_s=" + half), std::string::npos) << ov;
  }
}

TEST_F(Calibrate, LatencyPointModelOnAPredictorRun) {
  // GIVEN the default scenario's log of kf-cv (prediction path on) with a 2-frame delay
  const auto r0 = run({"servo", "--predictors", "hold,kf-cv", "--set", "duration_s=8", "--no-plots", "--out", path("s")});
  ASSERT_EQ(r0.code, 0) << r0.err;
  // WHEN the point model is fitted with the scenario's camera (800 px, 320, 240)
  const auto r = run({"calibrate", "latency", "--log", path("s/log.csv"), "--predictor", "kf-cv", "--intrinsics", "800,800,320,240",
                      "--no-plots", "--out", path("lat")});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN the 80 ms delay is recovered within one base period (40 ms)
  const auto j = apptest::readJson(path("lat/latency.json"));
  EXPECT_NEAR(j["delivery_fit"]["delay_s"].get<double>(), 0.08, 0.04) << j.dump(2);
  EXPECT_EQ(j["predictor"].get<std::string>(), "kf-cv");
  expectError(run({"calibrate", "latency", "--log", path("s/log.csv"), "--intrinsics", "800,800,320", "--out", path("l1")}),
              "--intrinsics", path("l1"));
}

TEST_F(Calibrate, LatencyBadInputs) {
  expectError(run({"calibrate", "latency", "--log", write("empty.csv", ""), "--out", path("l1")}), "the log is empty", path("l1"));
  expectError(run({"calibrate", "latency", "--log", path("missing.csv"), "--out", path("l2")}), "cannot open the log", path("l2"));
  std::string constant = "t_s,t_acq_s,meas_u0,vx\n";
  for (int k = 0; k < 100; ++k) constant += std::to_string(0.04 * k) + "," + std::to_string(0.04 * k) + ",100,0.1\n";
  expectError(run({"calibrate", "latency", "--log", write("const.csv", constant), "--out", path("l3")}), "the command never changes",
              path("l3"));
  expectError(run({"calibrate", "latency", "--log", write("nomeas.csv", "t_s,vx\n0,1\n"), "--out", path("l4")}), "no meas_", path("l4"));
  const std::string log = servoLog("s", "2");
  expectError(run({"calibrate", "latency", "--log", log, "--predictor", "kf-ca", "--out", path("l5")}), "no run of 'kf-ca'", path("l5"));
  expectError(run({"calibrate", "latency", "--log", log, "--commands", "q1", "--out", path("l6")}), "no column 'q1'", path("l6"));
  expectError(run({"servo", "--set-file", write("bad.yaml", "timing: {nonsense: 1}\n"), "--out", path("l7")}), "--set-file", path("l7"));
}

}  // namespace
}  // namespace predvs
