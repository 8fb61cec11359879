// The horizon the commands ask for, passed to the predictors as `horizon_frames` (predictor.h,
// app/predict_command.h setHorizonFrames): predict (--delay-frames or --horizon-s), track-study and
// fit-noise, and the scenario runs of servo and compare (their timing's longest horizon); the blend
// with hold then learns on the horizons 1..ceil(horizon_frames)
// (channel_predictor.h, "The horizons asked for"), unless hold_blend_frames is given.
#include "app/cli_test_utils.h"
#include "scenario.h"
#include "scenario_file.h"
#include "scenario_run.h"

#include "predvs/servo/timing_model.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace predvs {
namespace {

using apptest::CliRun;
using apptest::run;
using apptest::slurp;

class HorizonFrames : public apptest::ScratchDirTest {
 protected:
  HorizonFrames() : ScratchDirTest("predvs_horizon_frames_test") {}
  void SetUp() override {
    ScratchDirTest::SetUp();  // the scratch directory first: every path() is inside it
    ASSERT_EQ(run({"make-track", "--kind", "hand", "--rate-hz", "30", "--noise-px", "1.5", "--duration-s", "20",
                   "--seed", "3", "--out", path("t.csv")})
                  .code,
              0);
  }
  /// predictions.csv of predict on t.csv with these further arguments.
  std::string predictions(const std::string& out, const std::vector<std::string>& args) {
    std::vector<std::string> cmd = {"predict", "--input", path("t.csv"), "--predictor", "hold,kf-cv,imm", "--no-plots",
                                    "--out", path(out)};
    cmd.insert(cmd.end(), args.begin(), args.end());
    const CliRun r = run(cmd);
    EXPECT_EQ(r.code, 0) << r.err;
    return slurp(path(out) + "/predictions.csv");
  }
};

TEST_F(HorizonFrames, PredictTellsThePredictorsItsHorizon) {
  // GIVEN predict 5 frames ahead, as frames and as seconds (5 periods of 30 Hz), and with the blend
  // horizons given explicitly
  const std::string told = predictions("told", {"--delay-frames", "5"});
  const std::string seconds = predictions("seconds", {"--horizon-s", "0.16666666666666666"});
  const std::string given = predictions(
      "given", {"--delay-frames", "5", "--param", "kf-cv.hold_blend_frames=5", "--param", "imm.hold_blend_frames=5"});
  const std::string two = predictions(
      "two", {"--delay-frames", "5", "--param", "kf-cv.hold_blend_frames=2", "--param", "imm.hold_blend_frames=2"});
  // THEN the predictions told the horizon are those of hold_blend_frames 5, not those of the
  // default 2 (the forecasts and the file's other columns alike)
  ASSERT_FALSE(told.empty());
  EXPECT_EQ(told, given);
  EXPECT_NE(told, two);
  // AND --horizon-s gives the same horizon in frames (the file differs only where the horizon's
  // seconds are written, so compare the blend's effect: hold_blend_frames 5 again)
  const std::string seconds_given =
      predictions("seconds-given", {"--horizon-s", "0.16666666666666666", "--param", "kf-cv.hold_blend_frames=5", "--param",
                                    "imm.hold_blend_frames=5"});
  EXPECT_EQ(seconds, seconds_given);
}

TEST_F(HorizonFrames, TwoFramesAheadIsTheDefaultAsBefore) {
  // GIVEN predict 2 frames ahead, told and with the default blend horizons spelt out
  const std::string told = predictions("told", {"--delay-frames", "2"});
  const std::string spelt = predictions(
      "spelt", {"--delay-frames", "2", "--param", "kf-cv.hold_blend_frames=2", "--param", "imm.hold_blend_frames=2"});
  // THEN they are the same: at 2 frames (or fewer) nothing changes
  EXPECT_EQ(told, spelt);
}

/// A number of fit-noise's DIR/fit.json ("KEY": value).
double jsonNumber(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\": ";
  const auto at = json.find(tag);
  EXPECT_NE(at, std::string::npos) << key << " in " << json;
  return at == std::string::npos ? 0.0 : std::stod(json.substr(at + tag.size()));
}

TEST_F(HorizonFrames, FitNoiseFitsAtItsHorizonAndLeavesTheKeyOutOfParamsYaml) {
  // GIVEN fit-noise of kf-cv on the prediction objective 5 frames ahead, as it is and with the blend
  // on 5 and on 2 horizons given (a given hold_blend_frames is kept as it is: no forecast variant)
  const auto fit = [&](const std::string& out, const std::vector<std::string>& more) {
    std::vector<std::string> cmd = {"fit-noise", "--input", path("t.csv"), "--predictor", "kf-cv", "--objective",
                                    "prediction", "--horizon-frames", "5", "--out", path(out)};
    cmd.insert(cmd.end(), more.begin(), more.end());
    const CliRun r = run(cmd);
    EXPECT_EQ(r.code, 0) << r.err;
    return slurp(path(out) + "/fit.json");
  };
  const std::string told = fit("fit", {});
  const std::string five = fit("fit5", {"--param", "hold_blend_frames=5"});
  const std::string two = fit("fit2", {"--param", "hold_blend_frames=2"});
  // THEN the fit's own forecast, before and after, is the one on 5 horizons (the same bits), not
  // the one on 2
  EXPECT_EQ(jsonNumber(told, "rmse_before_px"), jsonNumber(five, "rmse_before_px"));
  EXPECT_EQ(jsonNumber(told, "rmse_own_forecast_px"), jsonNumber(five, "rmse_after_px"));
  EXPECT_NE(jsonNumber(told, "rmse_before_px"), jsonNumber(two, "rmse_before_px"));
  // AND params.yaml has the fitted noise but not the horizon, which is the caller's
  // (the entries only: the comment lines name the input, whose scratch path has the test's name)
  const std::string file = slurp(path("fit") + "/params.yaml");
  const std::string yaml = file.substr(file.find("predictors:"));
  EXPECT_NE(yaml.find("q:"), std::string::npos) << yaml;
  EXPECT_EQ(yaml.find("horizon_frames"), std::string::npos) << yaml;
  // AND a horizon_frames given by the user is kept, as any key of theirs
  const CliRun g = run({"fit-noise", "--input", path("t.csv"), "--predictor", "kf-cv", "--param", "horizon_frames=3",
                        "--out", path("fit3")});
  ASSERT_EQ(g.code, 0) << g.err;
  const std::string kept = slurp(path("fit3") + "/params.yaml");
  EXPECT_NE(kept.substr(kept.find("predictors:")).find("horizon_frames"), std::string::npos) << kept;
}

TEST_F(HorizonFrames, TrackStudyTellsThePredictorsItsHorizon) {
  // GIVEN track-study 5 frames ahead, told and with the blend horizons given
  const std::vector<std::string> grid = {"track-study", "--kinds", "hand", "--rates", "10", "--noise", "3", "--seeds", "1",
                                         "--duration-s", "10", "--delay-frames", "5"};
  std::vector<std::string> told = grid, given = grid;
  told.insert(told.end(), {"--predictors", "hold,kf-cv", "--out", path("told")});
  given.insert(given.end(), {"--predictors", "hold,kf-cv", "--param", "kf-cv.hold_blend_frames=5", "--out", path("given")});
  ASSERT_EQ(run(told).code, 0);
  ASSERT_EQ(run(given).code, 0);
  // THEN study.csv is the same
  EXPECT_EQ(slurp(path("told") + "/study.csv"), slurp(path("given") + "/study.csv"));
}

TEST(HorizonFramesScenario, ScenarioRunsTellThePredictorsTheLongestHorizonOfTheirTiming) {
  // GIVEN e5-line (80 ms of latency and 40 ms of command lag at 25 Hz: 3 frames) in `both` mode, where
  // the task acts on the forecast (in feedforward mode imm's velocity is its feed-forward's, whose
  // weights the blend's horizons do not change: imm.h), and e4-circle-large (open loop, 0.5 s at
  // 10 Hz: 5 frames), each with imm at its defaults
  for (const char* name : {"e5-line", "e4-circle-large"}) {
    SCOPED_TRACE(name);
    Scenario sc = loadScenario(resolveScenario(name));
    sc.closed_loop.forecast = ForecastMode::Both;
    const double h = TimingModel(sc.kind == ScenarioKind::ClosedLoop ? sc.closed_loop.timing : sc.open_loop.timing).longestHorizonFrames();
    EXPECT_GE(h, 3.0 - 1e-9);
    auto figures = [&](Params params) {
      return runScenarioOnce(sc, ScenarioPredictor{"imm", std::move(params), 0, ""}, sc.seed(), false).error;  // per tick
    };
    Params told, two;
    told.set("horizon_frames", h);
    two.set("hold_blend_frames", 2.0);
    // WHEN it runs imm with no key THEN imm runs as told the horizon, not as on the default two
    EXPECT_EQ(figures({}), figures(told));
    EXPECT_NE(figures({}), figures(two));
    // AND a horizon_frames the scenario gives is kept
    Params given;
    given.set("horizon_frames", 2.0);
    EXPECT_EQ(figures(given), figures(two));
  }
}

TEST(HorizonFramesScenario, ClosedLoopRunsTellThePredictorsSoOpenLoopRunsDoNot) {
  // GIVEN kf-cv with its defaults in a closed-loop scenario (ibvs-moving-target) and an open-loop
  // one (e4-circle)
  auto errors = [](const Scenario& sc, Params params) {
    return runScenarioOnce(sc, ScenarioPredictor{"kf-cv", std::move(params), 0, ""}, sc.seed(), false).error;
  };
  auto closed_loop = [](double v) {
    Params p;
    p.set("closed_loop", v);
    return p;
  };
  // WHEN they run THEN the closed loop's kf-cv is told closed_loop: 1 (predictor.h closedLoopParam:
  // its q matched to its innovations), unless the scenario says otherwise; the open loop's is not
  const Scenario loop = loadScenario(resolveScenario("ibvs-moving-target"));
  EXPECT_EQ(errors(loop, {}), errors(loop, closed_loop(1.0)));
  EXPECT_NE(errors(loop, {}), errors(loop, closed_loop(0.0)));
  const Scenario open = loadScenario(resolveScenario("e4-circle"));
  EXPECT_EQ(errors(open, {}), errors(open, closed_loop(0.0)));
  EXPECT_NE(errors(open, {}), errors(open, closed_loop(1.0)));
}

}  // namespace
}  // namespace predvs
