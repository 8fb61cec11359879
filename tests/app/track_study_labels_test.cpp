// `predvs track-study --predictors` with [LABEL=]TYPE[:KEY=VALUE...] elements (compare's syntax,
// app/scenario_run.h): one predictor under two labels with their own parameters, each its own rows
// of study.csv and of the tables, the same figures as the same parameters given with --param; hold
// listed anywhere is the reference of every ratio.
#include "app/cli_test_utils.h"

#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace predvs {
namespace {

using apptest::CliRun;
using apptest::csvRows;
using apptest::run;
using apptest::slurp;

class TrackStudyLabels : public apptest::ScratchDirTest {
 protected:
  TrackStudyLabels() : ScratchDirTest("predvs_ts_labels_test") {}
  /// track-study on two turns tracks (30 Hz, 1.5 px, seeds 1-2, 8 s) with these --predictors and
  /// extra options; study.csv's RMSE vs truth per (predictor, seed) and its ratio to hold.
  std::map<std::string, std::pair<std::string, std::string>> study(const std::string& dir, const std::string& predictors,
                                                                   const std::vector<std::string>& extra = {}) {
    const CliRun r = run({"track-study", "--kinds", "turns", "--rates", "30", "--noise", "1.5", "--seeds", "2",
                          "--duration-s", "8", "--predictors", predictors, "--out", path(dir)},
                         extra);
    EXPECT_EQ(r.code, 0) << r.err;
    last_out_ = r.out;
    std::map<std::string, std::pair<std::string, std::string>> out;
    // kind,rate_hz,noise_px,seed,predictor,rmse_truth_px,rmse_meas_px,n,ratio_to_hold,fit_variant
    for (const auto& row : csvRows(slurp(path(dir) + "/study.csv")))
      if (row.size() > 8 && row[0] != "kind") out[row[4] + "#" + row[3]] = {row[5], row[8]};
    return out;
  }
  std::string last_out_;
};

TEST_F(TrackStudyLabels, OnePredictorUnderTwoLabelsIsTheSameAsWithParam) {
  // GIVEN imm as itself and labelled with coast_cp 1, hold listed last
  const auto both = study("both", "kf-cv,kf-ca,imm,imm-cp1=imm:coast_cp=1,hold");
  // WHEN the labelled one's parameters are given to imm with --param instead
  const auto plain = study("plain", "kf-cv,kf-ca,imm", {"--param", "imm.coast_cp=1"});
  // THEN the label has rows of its own with the figures of its type run with those parameters,
  // and every ratio is to hold (listed last, still the reference)
  for (const char* seed : {"1", "2"}) {
    const std::string s = seed;
    ASSERT_TRUE(both.count("imm-cp1#" + s)) << s;
    EXPECT_EQ(both.at("imm-cp1#" + s), plain.at("imm#" + s)) << s;
    EXPECT_EQ(both.at("kf-cv#" + s), plain.at("kf-cv#" + s)) << s;
    EXPECT_EQ(both.at("hold#" + s).second, "1") << s;
    EXPECT_LT(std::stod(both.at("kf-cv#" + s).second), 1.0) << s;
  }
  EXPECT_NE(last_out_.find("imm / best of kf-cv, kf-ca"), std::string::npos) << last_out_;
}

TEST_F(TrackStudyLabels, ListsThatCannotRunAreRefused) {
  const std::string none = path("none");
  expectError(run({"track-study", "--predictors", "kf-cv,kf-cv=kf-cv:r=3", "--out", none}), "--predictors: 'kf-cv' is listed twice", none);
  expectError(run({"track-study", "--predictors", "kf-cv,x=nope", "--out", none}), "unknown predictor 'nope'", none);
  expectError(run({"track-study", "--predictors", "hold=kf-cv", "--out", none}), "predictor label 'hold' is the name of another predictor", none);
  expectError(run({"track-study", "--predictors", "k2=kf-cv:zz=1", "--out", none}), "zz", none);
}

TEST_F(TrackStudyLabels, OptionsThatWouldDoNothingAreRefused) {
  // as predict refuses them: the fit's options without --fit, the warm start where it is not used,
  // a parameter of a predictor not run, a seed make-track could not reproduce
  const std::string none = path("none");
  const std::vector<std::string> one = {"track-study", "--kinds", "turns", "--rates", "30", "--seeds", "1", "--out", none};
  const auto with = [&](const std::vector<std::string>& extra) { return run(one, extra); };
  expectError(with({"--fit-split", "0.3"}), "--fit-split: needs --fit", none);
  expectError(with({"--fit-objective", "likelihood"}), "--fit-objective: needs --fit", none);
  expectError(with({"--fit-starts", "2"}), "--fit-starts: needs --fit", none);
  expectError(with({"--fit-select-holdout", "0.5"}), "--fit-select-holdout: needs --fit", none);
  expectError(with({"--fit", "--no-warm-start"}), "--no-warm-start: needs --fit-split 1", none);
  expectError(with({"--predictors", "hold,kf-cv", "--param", "kf-ca.q=5"}), "predictor 'kf-ca' is not being run", none);
  expectError(with({"--seed", "-1"}), "--seed: expected an integer >= 0", none);
  // a grid axis with a value twice (its tracks counted twice), an empty list or element
  expectError(run({"track-study", "--kinds", "turns,turns", "--out", none}), "--kinds: a value listed twice", none);
  expectError(run({"track-study", "--rates", "30,30.0", "--out", none}), "--rates: a value listed twice", none);
  expectError(run({"track-study", "--kinds", "", "--out", none}), "--kinds: expected a comma-separated list, got ''", none);
  expectError(run({"track-study", "--noise", "1,", "--out", none}), "--noise: an empty element in '1,'", none);
  expectError(run({"predict", "--input", write("t.csv", "t,u,v\n0,1,2\n0.1,1,2\n0.2,1,2\n"), "--predictor", "kf-cv",
                   "--delay-frames", "1", "--fit", "--fit-split", "0.5", "--no-warm-start", "--out", none}),
              "--no-warm-start: not with --fit-split", none);
}

TEST_F(TrackStudyLabels, ErrorsNameTheOptionAndTheTrack) {
  // the generator's checks would name its config keys (drop_prob, duration_s): the option is named
  const std::string none = path("none");
  expectError(run({"track-study", "--drop", "2", "--out", none}), "--drop: expected a probability in [0, 0.5]", none);
  expectError(run({"track-study", "--duration-s", "0", "--out", none}), "--duration-s: expected a duration", none);
  expectError(run({"track-study", "--noise", "-1", "--out", none}), "--noise: expected finite standard deviations >= 0 px", none);
  expectError(run({"make-track", "--noise-px", "inf", "--out", path("x.csv")}), "--noise-px: expected a finite");
  // a fit that cannot run names the track and the predictor
  expectError(run({"track-study", "--fit", "--duration-s", "1", "--kinds", "turns", "--rates", "10", "--noise", "1",
                   "--seeds", "1", "--predictors", "hold,kf-cv", "--out", none}),
              "track turns 10 Hz 1 px #1: --fit kf-cv: noise fit: the track has 5 measured rows", none);
}

TEST_F(TrackStudyLabels, DrawsRunEachMotionWithItsOwnNoiseAndDrops) {
  // GIVEN one bursts motion at 60 Hz with 5 % drops, in three draws of its noise and drops
  const std::string dir = path("draws");
  const CliRun r = run({"track-study", "--kinds", "bursts", "--rates", "60", "--noise", "1.5", "--seed", "3", "--seeds", "1",
                        "--draws", "3", "--duration-s", "6", "--drop", "0.05", "--predictors", "hold,kf-cv", "--out", dir});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN study.csv has a row per draw and predictor, the draw in its last column, draw 0 the
  // track of make-track without --draw and draw 2 the one of --draw 2
  const std::string csv = slurp(dir + "/study.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "kind,rate_hz,noise_px,seed,predictor,rmse_truth_px,rmse_meas_px,n,ratio_to_hold,fit_variant,draw");
  std::map<std::string, std::string> rmse;  // predictor#draw -> rmse_truth_px
  for (const auto& row : csvRows(csv))
    if (row[0] != "kind") rmse[row[4] + "#" + row.back()] = row[5];
  ASSERT_EQ(rmse.size(), 6u);
  EXPECT_NE(rmse.at("kf-cv#0"), rmse.at("kf-cv#1"));
  EXPECT_NE(r.out.find("/3"), std::string::npos) << r.out;  // beats hold on N/3
  for (const char* draw : {"0", "2"}) {
    const std::string track = path(std::string("bursts-") + draw + ".csv"), out = path(std::string("pred-") + draw);
    ASSERT_EQ(run({"make-track", "--kind", "bursts", "--rate-hz", "60", "--noise-px", "1.5", "--seed", "3", "--draw", draw,
                   "--duration-s", "6", "--drop", "0.05", "--out", track}).code, 0);
    const CliRun p = run({"predict", "--input", track, "--predictor", "hold,kf-cv", "--delay-frames", "2", "--no-plots", "--out", out});
    ASSERT_EQ(p.code, 0) << p.err;
    // predict's RMSE vs truth (its table: predictor, vs meas, vs truth, n) is the study's within
    // 0.5 %: predict reads the track's 10 digits back and scores one row less at the end, the study
    // scores the generated doubles (draws 0 and 2 differ by a factor of 3 on this motion)
    const auto at = p.out.find("\nkf-cv");
    ASSERT_NE(at, std::string::npos) << p.out;
    std::istringstream line(p.out.substr(at + 1));
    std::string name;
    double vs_meas = 0.0, vs_truth = 0.0;
    line >> name >> vs_meas >> vs_truth;
    EXPECT_NEAR(vs_truth, std::stod(rmse.at(std::string("kf-cv#") + draw)), 0.005 * vs_truth) << draw << ": " << p.out;
  }
  expectError(run({"track-study", "--draws", "0", "--out", path("none")}), "--draws", path("none"));
  expectError(run({"make-track", "--draw", "-1", "--out", path("none.csv")}), "--draw", path("none.csv"));
}

}  // namespace
}  // namespace predvs
