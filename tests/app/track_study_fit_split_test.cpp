// `predvs track-study --fit --fit-split 1` (app/track_commands.h): each predictor fitted on the
// whole track and scored on the whole track, exactly as `predict --fit` without --fit-split does
// (issue 11 item 3's --fit); and --fit-split F < 1 still fits the first F and scores the rest.
#include "app/cli_test_utils.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace predvs {
namespace {

using apptest::CliRun;
using apptest::csvRows;
using apptest::run;
using apptest::slurp;

class TrackStudyFitSplit : public apptest::ScratchDirTest {
 protected:
  TrackStudyFitSplit() : ScratchDirTest("predvs_fitsplit_test") {}
  /// track-study on one turns track (30 Hz, 1.5 px, seed 1, 10 s) with extra options; the rows of study.csv.
  std::vector<std::vector<std::string>> study(const std::string& dir, const std::vector<std::string>& extra) {
    const CliRun r = run({"track-study", "--kinds", "turns", "--rates", "30", "--noise", "1.5", "--seeds", "1",
                          "--duration-s", "10", "--predictors", "kf-cv,st-akf", "--out", path(dir)},
                         extra);
    EXPECT_EQ(r.code, 0) << r.err;
    last_out_ = r.out;
    return csvRows(slurp(path(dir) + "/study.csv"));
  }
  std::string last_out_;
};

// Columns of study.csv: kind,rate_hz,noise_px,seed,predictor,rmse_truth_px,rmse_meas_px,n,ratio_to_hold,fit_variant
constexpr size_t kPredictor = 4, kRmseTruth = 5, kN = 7;

TEST_F(TrackStudyFitSplit, WholeTrackIsWhatPredictFitDoes) {
  // GIVEN the same track as make-track writes it
  const std::string track = path("t.csv");
  ASSERT_EQ(run({"make-track", "--kind", "turns", "--rate-hz", "30", "--noise-px", "1.5", "--duration-s", "10",
                 "--seed", "1", "--drop", "0.02", "--out", track})
                .code,
            0);
  // WHEN track-study fits with --fit-split 1, and predict fits without --fit-split
  const auto whole = study("whole", {"--fit", "--fit-split", "1"});
  EXPECT_NE(last_out_.find("fitted on the whole of each track"), std::string::npos) << last_out_;
  EXPECT_NE(last_out_.find("scored on the whole track"), std::string::npos) << last_out_;
  const auto unfitted = study("plain", {});
  const auto half = study("half", {"--fit", "--fit-split", "0.5"});
  const CliRun p = run({"predict", "--input", track, "--predictor", "kf-cv,st-akf", "--delay-frames", "2", "--fit",
                        "--no-plots", "--out", path("p")});
  ASSERT_EQ(p.code, 0) << p.err;
  const auto j = apptest::readJson(path("p") + "/summary.json");

  // THEN every row of the track is scored (as without --fit; the 0.5 split scores about half) ...
  ASSERT_EQ(whole.size(), 3u);  // hold, kf-cv, st-akf
  ASSERT_EQ(unfitted.size(), 3u);
  ASSERT_EQ(half.size(), 3u);
  for (size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(whole[i][kN], unfitted[i][kN]) << whole[i][kPredictor];
    EXPECT_LT(std::stoi(half[i][kN]), std::stoi(whole[i][kN]) * 6 / 10) << half[i][kPredictor];
  }
  // ... and each fitted predictor's RMSE vs truth is predict --fit's (fitted on all rows: the same
  // fitted values, the same score; the track goes through the CSV text, hence the tolerance).
  constexpr double kCsvRoundTripPx = 1e-6;
  ASSERT_EQ(j["predictors"].size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(j["predictors"][k]["name"].get<std::string>(), whole[k + 1][kPredictor]);
    EXPECT_EQ(j["predictors"][k]["vs_truth"]["n"].get<int>(), std::stoi(whole[k + 1][kN]));
    EXPECT_NEAR(j["predictors"][k]["vs_truth"]["rmse_px"].get<double>(), std::stod(whole[k + 1][kRmseTruth]),
                kCsvRoundTripPx)
        << whole[k + 1][kPredictor];
    // the fit did something: not the unfitted default's score
    EXPECT_NE(whole[k + 1][kRmseTruth], unfitted[k + 1][kRmseTruth]);
  }
}

TEST_F(TrackStudyFitSplit, SplitOutsideZeroOneIsRejected) {
  for (const char* f : {"0", "1.01", "2"})
    expectError(run({"track-study", "--fit", "--fit-split", f, "--out", path("bad")}), "--fit-split", path("bad"));
}

}  // namespace
}  // namespace predvs
