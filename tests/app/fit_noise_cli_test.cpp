// `predvs make-track`, `fit-noise`, `predict --params / --fit / --fit-split`, `track-study`
// (app/track_commands.h, app/fit_command.h), in process.
#include "app/cli_test_utils.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

namespace predvs {
namespace {

using apptest::CliRun;
using apptest::run;
using apptest::slurp;

class FitNoiseCli : public apptest::ScratchDirTest {
 protected:
  FitNoiseCli() : ScratchDirTest("predvs_fitcli_test") {}
  /// A 2,000-frame turns track at 30 Hz with 1.5 px noise.
  std::string track() const {
    const std::string f = path("track.csv");
    const CliRun r = run({"make-track", "--kind", "turns", "--rate-hz", "30", "--noise-px", "1.5", "--duration-s",
                          "66.65", "--seed", "3", "--out", f});
    EXPECT_EQ(r.code, 0) << r.err;
    return f;
  }
};

TEST_F(FitNoiseCli, MakeTrackWritesPredictInputWithTruth) {
  const std::string f = track();
  const std::string csv = slurp(f);
  EXPECT_EQ(csv.rfind("t,u,v,u_true,v_true\n", 0), 0u);
  EXPECT_EQ(apptest::csvRows(csv).size(), 2000u);
  const CliRun p = run({"predict", "--input", f, "--predictor", "all", "--delay-frames", "2", "--no-plots", "--out",
                        path("pred")});
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_NE(p.out.find("imm"), std::string::npos);
  expectError(run({"make-track", "--kind", "spiral", "--out", path("x.csv")}), "unknown track kind 'spiral'");
  EXPECT_FALSE(std::filesystem::exists(path("x.csv")));
  expectError(run({"make-track", "--rate-hz", "0", "--out", path("x.csv")}), "--rate-hz");
}

TEST_F(FitNoiseCli, AParamsFileWithoutTheirEntryAndAZeroPredictionHorizonAreRefused) {
  const std::string f = track();
  const std::string params = path("imm.yaml");
  std::ofstream(params) << "predictors:\n  - {name: imm, params: {q_cv: 5}}\n";
  expectError(run({"fit-noise", "--input", f, "--predictor", "kf-cv", "--params", params, "--out", path("fit")}),
              "--params " + params + ": has no entry for kf-cv");
  expectError(run({"fit-noise", "--input", f, "--predictor", "kf-cv", "--objective", "prediction", "--horizon-frames", "0",
                   "--out", path("fit")}),
              "--horizon-frames: expected an integer >= 1 with --objective prediction");
  EXPECT_FALSE(std::filesystem::exists(path("fit")));
}

TEST_F(FitNoiseCli, FitNoiseWritesAParamsFileThatPredictAccepts) {
  const std::string f = track();
  // GIVEN a fit of kf-cv on a track with 1.5 px noise (r = 2.25 px^2)
  const CliRun fit = run({"fit-noise", "--input", f, "--predictor", "kf-cv", "--out", path("fit")});
  ASSERT_EQ(fit.code, 0) << fit.err;
  // THEN it prints the fitted values with an interval and the likelihood before and after
  EXPECT_NE(fit.out.find("95% interval"), std::string::npos) << fit.out;
  EXPECT_NE(fit.out.find("log-likelihood"), std::string::npos) << fit.out;
  const nlohmann::json j = apptest::readJson(path("fit") + "/fit.json");
  EXPECT_GE(j["loglik_after"].get<double>(), j["loglik_before"].get<double>());
  const double r = j["params"]["r"].get<double>();
  EXPECT_NEAR(r / 2.25, 1.0, 0.15);  // turns: the CV model absorbs a little of the turns into r
  // AND predict --params uses those values (recorded in summary.json)
  const CliRun p = run({"predict", "--input", f, "--predictor", "kf-cv", "--delay-frames", "2", "--no-plots",
                        "--params", path("fit") + "/params.yaml", "--out", path("pred")});
  ASSERT_EQ(p.code, 0) << p.err;
  const nlohmann::json s = apptest::readJson(path("pred") + "/summary.json");
  EXPECT_NEAR(s["predictors"][0]["params"]["r"].get<double>(), r, 1e-10 * r);  // 12 digits in the file
  // AND servo accepts the file too (as --set overrides)
  const CliRun sv = run({"servo", "--scenario", "e1-line", "--predictors", "kf-cv", "--no-plots", "--params",
                         path("fit") + "/params.yaml", "--set", "duration_s=3", "--out", path("servo")});
  EXPECT_EQ(sv.code, 0) << sv.err;
}

TEST_F(FitNoiseCli, PredictFitSplitScoresTheRest) {
  const std::string f = track();
  const CliRun p = run({"predict", "--input", f, "--predictor", "all", "--delay-frames", "2", "--fit", "--fit-split",
                        "0.5", "--no-plots", "--out", path("pred")});
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_NE(p.out.find("fitted on rows 1..1000, scored on rows 1001..2000"), std::string::npos) << p.out;
  const nlohmann::json s = apptest::readJson(path("pred") + "/summary.json");
  for (const auto& pr : s["predictors"]) {
    EXPECT_LE(pr["vs_truth"]["n"].get<int>(), 1000) << pr["name"];
    if (pr["name"] != "hold") {
      EXPECT_TRUE(pr["params"].contains("r")) << pr["name"];
    }
  }
  expectError(run({"predict", "--input", f, "--predictor", "kf-cv", "--delay-frames", "2", "--fit-split", "0.5",
                   "--no-plots", "--out", path("p2")}),
              "--fit-split: needs --fit", path("p2"));
}

TEST_F(FitNoiseCli, BadInputsAreOneLineErrors) {
  const std::string f = track();
  expectError(run({"fit-noise", "--input", f, "--predictor", "hold", "--out", path("o")}), "no parameters to fit",
              path("o"));
  expectError(run({"fit-noise", "--input", path("missing.csv"), "--predictor", "kf-cv", "--out", path("o")}),
              "missing.csv", path("o"));
  const std::string bad = write("bad.yaml", "predictors:\n  - {name: kf-cv, params: {q: fast}}\n");
  expectError(run({"predict", "--input", f, "--predictor", "kf-cv", "--delay-frames", "2", "--no-plots", "--params",
                   bad, "--out", path("o")}),
              "bad.yaml:2", path("o"));
  const std::string other = write("other.yaml", "predictors:\n  - {name: stkf, params: {r: 2}}\n");
  expectError(run({"predict", "--input", f, "--predictor", "kf-cv", "--delay-frames", "2", "--no-plots", "--params",
                   other, "--out", path("o")}),
              "names none of the predictors", path("o"));
  const std::string unknown = write("unk.yaml", "predictors:\n  - {name: kf-cv, params: {qq: 2}}\n");
  expectError(run({"fit-noise", "--input", f, "--predictor", "kf-cv", "--params", unknown, "--out", path("o")}),
              "unknown parameter 'qq'", path("o"));
}

TEST_F(FitNoiseCli, FitNoiseAcceptsThePredictionObjective) {
  const std::string f = track();
  // GIVEN the prediction objective 2 frames ahead
  const CliRun fit = run({"fit-noise", "--input", f, "--predictor", "kf-ca", "--objective", "prediction",
                          "--horizon-frames", "2", "--out", path("fit")});
  ASSERT_EQ(fit.code, 0) << fit.err;
  // THEN the h-step RMSE is what was minimised, it did not go up, r is held, fit.json says so
  EXPECT_NE(fit.out.find("px  [minimised]"), std::string::npos) << fit.out;
  EXPECT_NE(fit.out.find("(held: start value)"), std::string::npos) << fit.out;
  const nlohmann::json j = apptest::readJson(path("fit") + "/fit.json");
  EXPECT_EQ(j["objective_name"], "prediction");
  EXPECT_EQ(j["horizon_frames"], 2);
  EXPECT_NEAR(j["horizon_s"].get<double>(), 2.0 / 30.0, 1e-6);  // 2 x the median period of t rounded in the CSV
  EXPECT_LE(j["rmse_after_px"].get<double>(), j["rmse_before_px"].get<double>());
  EXPECT_TRUE(j.contains("loglik_after"));  // the likelihood fields stay
  expectError(run({"fit-noise", "--input", f, "--predictor", "kf-ca", "--objective", "mse", "--out", path("o")}),
              "--objective: unknown fit objective 'mse'", path("o"));
  expectError(run({"fit-noise", "--input", f, "--predictor", "kf-ca", "--horizon-frames", "-1", "--out", path("o")}),
              "--horizon-frames", path("o"));
  expectError(run({"predict", "--input", f, "--predictor", "kf-cv", "--delay-frames", "2", "--fit-objective",
                   "likelihood", "--no-plots", "--out", path("o")}),
              "--fit-objective: needs --fit", path("o"));
}

TEST_F(FitNoiseCli, TrackStudyFitDoesNotDependOnJobs) {
  // GIVEN a small fitted study (prediction objective by default) WHEN run on 1 and 2 threads
  // THEN study.csv is identical, and the fit line names the objective.
  std::string csv[2];
  for (int jobs = 1; jobs <= 2; ++jobs) {
    const std::string dir = path("study" + std::to_string(jobs));
    const CliRun r = run({"track-study", "--kinds", "stops", "--rates", "15", "--noise", "1", "--seeds", "2",
                          "--duration-s", "10", "--predictors", "kf-cv,stkf", "--fit", "--jobs", std::to_string(jobs),
                          "--out", dir});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("by prediction (squared error of the 2-frame prediction"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("stkf"), std::string::npos);
    csv[jobs - 1] = slurp(dir + "/study.csv");
  }
  EXPECT_EQ(csv[0], csv[1]);
  expectError(run({"track-study", "--fit", "--fit-objective", "mse"}), "--fit-objective");
  expectError(run({"track-study", "--jobs", "0"}), "--jobs");
}

TEST_F(FitNoiseCli, TrackStudyPrintsWinsAgainstHold) {
  const CliRun r = run({"track-study", "--kinds", "turns", "--rates", "30", "--noise", "1", "--seeds", "1",
                        "--predictors", "kf-cv,kf-ca,imm", "--out", path("study")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("beats hold"), std::string::npos);
  EXPECT_NE(r.out.find("imm / best of kf-cv, kf-ca"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("within 10%"), std::string::npos) << r.out;  // imm against the best fixed KF
  EXPECT_EQ(apptest::csvRows(slurp(path("study") + "/study.csv")).size(), 4u);  // hold + 3
  expectError(run({"track-study", "--kinds", "spiral"}), "unknown track kind");
  // A word for a predictor's key (stkf's model: ca) is passed on; the predictor rejects a bad one.
  const CliRun ca = run({"track-study", "--kinds", "turns", "--rates", "30", "--noise", "1", "--seeds", "1",
                         "--duration-s", "5", "--predictors", "stkf", "--param", "stkf.model=ca"});
  EXPECT_EQ(ca.code, 0) << ca.err;
  expectError(run({"track-study", "--predictors", "stkf", "--param", "stkf.model=cx"}), "'model' must be cv or ca");
}

}  // namespace
}  // namespace predvs
