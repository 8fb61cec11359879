// `--set PATH=VALUE` on `predvs servo` / `predvs compare` (app/scenario_override.h): the override
// reaches the strict scenario parse, its errors name the override (exit 2, one line, no output
// directory), and it is recorded in summary.json / leaderboard.json.
#include "cli_test_utils.h"
#include "scenario.h"
#include "scenario_file.h"
#include "scenario_override.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace predvs::apptest;

namespace {

class SetOverrideTest : public ScratchDirTest {
 protected:
  SetOverrideTest() : ScratchDirTest("predvs_set_test") {}

  /// The shared failure contract, with every needle in the one error line.
  void expectError(const CliRun& r, const std::vector<std::string>& needles, const std::string& out_dir) const {
    for (const auto& n : needles) ScratchDirTest::expectError(r, n, out_dir);
  }

  /// Steady RMSE of kf-cv on the default scenario cut to 6 s, with extra --set arguments.
  double kfCvRmse(const std::vector<std::string>& sets, const std::string& out) {
    std::vector<std::string> args = {"servo", "--predictors", "kf-cv", "--set", "duration_s=6", "--out", out,
                                     "--no-plots"};
    for (const auto& s : sets) {
      args.push_back("--set");
      args.push_back(s);
    }
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 0) << r.err;
    const auto j = readJson(fs::path(out) / "summary.json");
    EXPECT_EQ(j["duration_s"].get<double>(), 6.0);
    return j["predictors"][0]["metrics"]["rmse"].get<double>();
  }
};

/// predictors.NAME.params of a loaded scenario (empty Params when NAME is not listed).
const predvs::ScenarioPredictor* findPredictor(const predvs::Scenario& sc, const std::string& name) {
  for (const auto& p : sc.predictors)
    if (p.name == name) return &p;
  return nullptr;
}

TEST_F(SetOverrideTest, ForecastModeOverrideChangesTheClosedLoopResult) {
  // GIVEN the default closed-loop scenario (target on a circle, 2-frame delay), cut to 6 s
  // WHEN kf-cv's forecast only replaces the features (feature) instead of the default
  //      feedforward of the predicted feature velocity
  const double feedforward = kfCvRmse({}, path("ff"));
  const double feature = kfCvRmse({"servo.forecast=feature"}, path("feature"));
  // THEN the steady tracking error is much larger (measured 36.2 px against 4.9 px at seed 1: with
  // only the feature forecast the proportional law keeps a velocity lag, as without prediction).
  // A factor 2 separates the modes with a wide margin yet fails if the override were ignored
  // (identical runs give equal numbers).
  constexpr double kMinRatio = 2.0;
  EXPECT_GT(feature, kMinRatio * feedforward) << "feature " << feature << " px, feedforward " << feedforward << " px";
  // AND the overrides are recorded, in order
  const auto j = readJson(fs::path(path("feature")) / "summary.json");
  ASSERT_TRUE(j["overrides"].is_array());
  EXPECT_EQ(j["overrides"], nlohmann::json({"duration_s=6", "servo.forecast=feature"}));
  EXPECT_EQ(readJson(fs::path(path("ff")) / "summary.json")["overrides"], nlohmann::json({"duration_s=6"}));
}

TEST_F(SetOverrideTest, UnknownKeyViaSetIsOneLineNamingTheOverride) {
  // GIVEN a misspelt key WHEN set on the command line THEN exit 2, one line that says it came from
  // --set and lists the keys of the section, no output directory
  const std::string out = path("out");
  expectError(run({"servo", "--set", "servo.forcast=feature", "--out", out, "--no-plots"}),
              {"--set servo.forcast=feature", "ibvs-moving-target", "unknown key 'servo.forcast'", "forecast"}, out);
  // AND a bad value is reported the same way by the existing validation
  expectError(run({"servo", "--set", "task.lambda=abc", "--out", out, "--no-plots"}),
              {"--set task.lambda=abc", "parameter 'lambda' expects a number, got 'abc'"}, out);
  expectError(run({"servo", "--set", "servo.forecast=sideways", "--out", out, "--no-plots"}),
              {"--set servo.forecast=sideways", "sideways"}, out);
  // AND a missing section is created, so the strict parser rejects an unknown top-level key
  expectError(run({"servo", "--set", "trajectory.type=line", "--out", out, "--no-plots"}),
              {"--set trajectory.type=line", "unknown key 'trajectory' for a closed-loop scenario"}, out);
}

TEST_F(SetOverrideTest, ErrorNamesTheOverrideThatBrokeTheScenario) {
  // GIVEN three overrides of which only the second is invalid (it conflicts with the file's
  // timing.delay_frames) WHEN servo runs THEN the error names that one
  const std::string out = path("out");
  expectError(run({"servo", "--set", "task.lambda=2", "--set", "timing.acquisition_lag_s=0.1", "--set",
                   "duration_s=3", "--out", out, "--no-plots"}),
              {"--set timing.acquisition_lag_s=0.1 (scenario ibvs-moving-target)", "not both"}, out);
  // AND a defect of the file itself is still reported at its file and line, not blamed on --set
  const std::string bad = path("bad.yaml");
  std::ofstream(bad) << "kind: closed-loop\nduration_s: abc\npredictors: [hold]\n";
  expectError(run({"servo", "--scenario", bad, "--set", "task.lambda=2", "--out", out, "--no-plots"}),
              {bad + ":2:", "'duration_s'"}, out);
}

TEST_F(SetOverrideTest, MalformedSetIsOneLineError) {
  const std::string out = path("out");
  for (const char* arg : {"noequals", "=3", "a..b=1", ".a=1", "a.=1"})
    expectError(run({"servo", "--set", arg, "--out", out, "--no-plots"}), {"--set: expected PATH=VALUE", arg}, out);
  expectError(run({"compare", "--scenarios", "e1-line", "--set", "noequals", "--out", out, "--no-plots"}),
              {"--set: expected PATH=VALUE"}, out);
  // VALUE must be YAML
  expectError(run({"servo", "--set", "initial_pose=[1, 2", "--out", out, "--no-plots"}),
              {"--set initial_pose=[1, 2: VALUE is not valid YAML"}, out);
}

TEST_F(SetOverrideTest, ScalarIntermediateAndIndexOutOfRangeAreErrors) {
  const std::string out = path("out");
  // GIVEN task.lambda is a number WHEN a key inside it is set THEN an error naming the scalar
  expectError(run({"servo", "--set", "task.lambda.x=1", "--out", out, "--no-plots"}),
              {"--set task.lambda.x=1", "'task.lambda' is a value", "no key 'x'"}, out);
  // AND a list index beyond the list
  expectError(run({"servo", "--set", "predictors.3=kf-ca", "--out", out, "--no-plots"}),
              {"--set predictors.3=kf-ca", "3 element(s)", "out of range"}, out);
  // AND a bare-name list element selected by index has no keys either
  expectError(run({"servo", "--set", "predictors.0.params.q=1", "--out", out, "--no-plots"}),
              {"'predictors.0' is a value ('hold')"}, out);
}

TEST_F(SetOverrideTest, PathsReachListElementsAndDottedKeys) {
  using predvs::parseScenarioOverride;
  // GIVEN the default scenario, which lists hold, kf-cv, cs-akf-adaptive by bare name
  const std::string ibvs = predvs::resolveScenario("ibvs-moving-target");
  // WHEN a parameter of a listed predictor is set by name THEN the element becomes {name, params}
  auto sc = predvs::loadScenario(ibvs, {parseScenarioOverride("predictors.kf-cv.params.q=50")});
  ASSERT_EQ(sc.predictors.size(), 3u);
  ASSERT_NE(findPredictor(sc, "kf-cv"), nullptr);
  EXPECT_EQ(findPredictor(sc, "kf-cv")->params.values().at("q"), 50.0);
  // WHEN the name is not listed THEN it is appended with its parameters
  sc = predvs::loadScenario(ibvs, {parseScenarioOverride("predictors.cs-akf.params.a_max=100")});
  ASSERT_EQ(sc.predictors.size(), 4u);
  EXPECT_EQ(sc.predictors.back().name, "cs-akf");
  EXPECT_EQ(sc.predictors.back().params.values().at("a_max"), 100.0);
  // WHEN an element is replaced by index THEN the list keeps its length
  sc = predvs::loadScenario(ibvs, {parseScenarioOverride("predictors.0=kf-ca")});
  ASSERT_EQ(sc.predictors.size(), 3u);
  EXPECT_EQ(sc.predictors[0].name, "kf-ca");
  // WHEN a whole section is given as a YAML mapping THEN it replaces the file's
  sc = predvs::loadScenario(ibvs, {parseScenarioOverride("task={lambda: 3}")});
  EXPECT_EQ(sc.closed_loop.task.params.get("lambda", 0.0), 3.0);
  // WHEN a key containing a dot exists (sweep's noise.sigma in e6) THEN the path finds it
  const auto e6 = predvs::loadScenario(predvs::resolveScenario("e6-noise-study"),
                                       {parseScenarioOverride("sweep.noise.sigma=[0.5, 2]")});
  EXPECT_EQ(e6.sigma_sweep, (std::vector<double>{0.5, 2.0}));
  // WHEN an empty VALUE follows a value for the same key THEN the key takes the layer's default
  // (null = absent), not the earlier value
  sc = predvs::loadScenario(ibvs, {parseScenarioOverride("noise.sigma=2")});
  EXPECT_EQ(sc.closed_loop.noise.sigma, 2.0);
  sc = predvs::loadScenario(ibvs, {parseScenarioOverride("noise.sigma=2"), parseScenarioOverride("noise.sigma=")});
  EXPECT_EQ(sc.closed_loop.noise.sigma, predvs::NoiseConfig{}.sigma);
}

TEST_F(SetOverrideTest, OneOverrideAppliedToManyDocumentsDoesNotShareItsValue) {
  // GIVEN one override whose value is a mapping, applied to two documents
  const auto o = predvs::parseScenarioOverride("task={lambda: 3}");
  YAML::Node a = YAML::Load("kind: closed-loop");
  YAML::Node b = YAML::Load("kind: closed-loop");
  predvs::applyScenarioOverride(a, o);
  predvs::applyScenarioOverride(b, o);
  // WHEN a later override changes the first document inside that value
  predvs::applyScenarioOverride(a, predvs::parseScenarioOverride("task.lambda=7"));
  // THEN the second document and the override itself are unchanged
  EXPECT_EQ(a["task"]["lambda"].as<double>(), 7.0);
  EXPECT_EQ(b["task"]["lambda"].as<double>(), 3.0);
  EXPECT_EQ(o.value["lambda"].as<double>(), 3.0);
}

TEST_F(SetOverrideTest, ServoPredictorsKeepTheParamsGivenWithSet) {
  // GIVEN --predictors naming a predictor whose params come from --set WHEN servo runs THEN those
  // params are used (not dropped in favour of the defaults)
  const std::string out = path("out");
  const CliRun r = run({"servo", "--predictors", "kf-cv", "--set", "predictors.kf-cv.params.q=50", "--set",
                        "duration_s=1", "--out", out, "--no-plots"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = readJson(fs::path(out) / "summary.json");
  ASSERT_EQ(j["predictors"].size(), 1u);
  EXPECT_EQ(j["predictors"][0]["params"]["q"].get<double>(), 50.0);
}

TEST_F(SetOverrideTest, CompareAppliesOverridesToEveryScenario) {
  // GIVEN two open-loop scenarios without a runs: key WHEN compare sets runs and duration
  const std::string out = path("out");
  const CliRun r = run({"compare", "--scenarios", "e1-line,e2-accel-jump", "--predictors", "kf-cv", "--set",
                        "runs=2", "--set", "duration_s=3", "--jobs", "1", "--out", out, "--no-plots"});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN both scenarios ran twice (the default would be compare's 20) and the overrides are recorded
  const auto j = readJson(fs::path(out) / "leaderboard.json");
  ASSERT_EQ(j["scenarios"].size(), 2u);
  for (const auto& s : j["scenarios"]) EXPECT_EQ(s["runs"].get<int>(), 2) << s["name"];
  EXPECT_EQ(j["overrides"], nlohmann::json({"runs=2", "duration_s=3"}));
  // AND a key one of the chosen scenarios lacks is an error naming that scenario, nothing written
  const std::string out2 = path("out2");
  expectError(run({"compare", "--scenarios", "ibvs-moving-target,e1-line", "--set", "task.lambda=2", "--runs", "1",
                   "--out", out2, "--no-plots"}),
              {"--set task.lambda=2 (scenario e1-line)", "unknown key 'task'"}, out2);
}

TEST_F(SetOverrideTest, HelpMentionsSet) {
  for (const char* sub : {"servo", "compare"}) {
    const CliRun r = run({sub, "--help"});
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("--set PATH=VALUE"), std::string::npos) << sub;
  }
}

}  // namespace
