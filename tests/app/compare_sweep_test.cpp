// Tests of `predvs compare` sweeps over any scenario path (app/compare_command.h, scenario.h):
// `sweep: {PATH: [...]}` in a file and `--sweep PATH=V1,V2`, run in-process through runCli() on
// tiny scenarios written to a scratch directory.
#include "cli_test_utils.h"
#include "gnuplot.h"
#include "scenario.h"
#include "scenario_file.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

using namespace predvs::apptest;  // run(), CliRun, slurp(), ScratchDirTest (cli_test_utils.h)

namespace {

class CompareSweepTest : public ScratchDirTest {
 protected:
  CompareSweepTest() : ScratchDirTest("predvs_compare_sweep_test") {}
  void SetUp() override {
    ScratchDirTest::SetUp();
    // A 2-channel line at 10 px/s per axis seen with a small noise, swept over the vision delay.
    delay_ = write("tiny-delay.yaml",
                   "description: tiny delay sweep\nkind: open-loop\nseed: 11\nruns: 2\nduration_s: 4\n"
                   "timing: {base_period_s: 0.1, delay_frames: 1}\n"
                   "noise: {model: gaussian, sigma: 0.2}\n"
                   "sweep: {timing.delay_frames: [0, 1, 2]}\n"
                   "trajectory: {type: line, vx: 10, vy: 10}\n"
                   "predictors: [hold, {name: kf-cv, params: {r: 1, q: 10}}]\n");
  }
  std::string delay_;
};

TEST_F(CompareSweepTest, FileSweepGivesOneVariantPerValueAndTheValueChangesTheRuns) {
  // GIVEN a scenario swept over timing.delay_frames = 0, 1, 2 WHEN compared
  const std::string out = path("out");
  std::vector<std::string> a = {"compare", "--scenarios", delay_, "--out", out, "--jobs", "2"};
  const bool plots = predvs::gnuplotAvailable();
  if (!plots) a.push_back("--no-plots");
  const CliRun r = run(a);
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN there is one variant per value, named <scenario>@<last path segment>=<value>
  const auto m = leaderboardMeans(out + "/leaderboard.csv");
  for (const char* v : {"0", "1", "2"})
    EXPECT_EQ(m.count(std::string("tiny-delay@delay_frames=") + v + "/hold/rmse"), 1u) << v;
  // AND the delay reaches the runs: hold (the last delivered sample) falls further behind the
  // moving target with every frame of delay
  const double h0 = m.at("tiny-delay@delay_frames=0/hold/rmse"), h1 = m.at("tiny-delay@delay_frames=1/hold/rmse"),
               h2 = m.at("tiny-delay@delay_frames=2/hold/rmse");
  EXPECT_LT(h0, h1);
  EXPECT_LT(h1, h2);
  // AND the JSON records the sweep and each variant's value
  const auto j = readJson(out + "/leaderboard.json");
  const auto& sc = j["scenarios"][0];
  EXPECT_EQ(sc["sweep"]["key"], "timing.delay_frames");
  EXPECT_EQ(sc["sweep"]["from"], "scenario file");
  EXPECT_EQ(sc["sweep"]["values"], nlohmann::json({0.0, 1.0, 2.0}));
  ASSERT_EQ(sc["variants"].size(), 3u);
  EXPECT_EQ(sc["variants"][2]["sweep_value"].get<double>(), 2.0);
  EXPECT_TRUE(j["sweep"].is_null());
  // AND the markdown shows the first and the last value only
  const std::string md = slurp(out + "/leaderboard.md");
  EXPECT_NE(md.find("## tiny-delay@delay_frames=0"), std::string::npos);
  EXPECT_NE(md.find("## tiny-delay@delay_frames=2"), std::string::npos);
  EXPECT_EQ(md.find("## tiny-delay@delay_frames=1"), std::string::npos);
  // AND the plots: error plots of the first and last value, rmse versus the swept key
  if (plots) {
    for (const char* f : {"error_tiny-delay_delay_frames0.png", "error_tiny-delay_delay_frames2.png",
                          "rmse_vs_delay_frames_tiny-delay.png"})
      EXPECT_GT(fs::file_size(out + "/" + std::string(f)), 1000u) << f;
    EXPECT_FALSE(fs::exists(out + "/mse_vs_sigma_tiny-delay.png"));
  }
}

TEST_F(CompareSweepTest, AVariantIsTheScenarioWithTheValueSet) {
  // GIVEN the sweep, and the same scenario without a sweep but with --set timing.delay_frames=2
  ASSERT_EQ(run({"compare", "--scenarios", delay_, "--out", path("sweep"), "--no-plots"}).code, 0);
  ASSERT_EQ(run({"compare", "--scenarios", delay_, "--set", "sweep=", "--set", "timing.delay_frames=2", "--out",
                 path("set"), "--no-plots"})
                .code,
            0);
  // THEN the variant at 2 has exactly the numbers of the --set run (same seeds, same loading)
  const auto swept = leaderboardMeans(path("sweep/leaderboard.csv")), set = leaderboardMeans(path("set/leaderboard.csv"));
  int compared = 0;
  for (const auto& kv : set) {
    const std::string key = "tiny-delay@delay_frames=2" + kv.first.substr(kv.first.find('/'));
    ASSERT_EQ(swept.count(key), 1u) << key;
    EXPECT_EQ(swept.at(key), kv.second) << key;
    ++compared;
  }
  EXPECT_GT(compared, 10);
}

TEST_F(CompareSweepTest, SweepOptionReplacesTheFilesSweep) {
  // GIVEN --sweep noise.sigma=0,3 on the delay-swept scenario, once as a comma list and once as a
  // YAML list
  const CliRun r = run({"compare", "--scenarios", delay_, "--sweep", "noise.sigma=0,3", "--out", path("a"), "--no-plots"});
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(run({"compare", "--scenarios", delay_, "--sweep", "noise.sigma=[0, 3]", "--out", path("b"), "--no-plots"})
                .code,
            0);
  // THEN only the noise values are variants (the file's delay sweep is gone), named @sigma=
  const auto m = leaderboardMeans(path("a/leaderboard.csv"));
  EXPECT_EQ(m.count("tiny-delay@sigma=0/kf-cv/rmse"), 1u);
  EXPECT_EQ(m.count("tiny-delay@sigma=3/kf-cv/rmse"), 1u);
  for (const auto& kv : m) EXPECT_EQ(kv.first.find("delay_frames"), std::string::npos) << kv.first;
  // AND more noise gives kf-cv a larger error
  EXPECT_LT(m.at("tiny-delay@sigma=0/kf-cv/rmse"), m.at("tiny-delay@sigma=3/kf-cv/rmse"));
  // AND both spellings give the same leaderboard, and the JSON records the option
  EXPECT_EQ(slurp(path("a/leaderboard.csv")), slurp(path("b/leaderboard.csv")));
  const auto j = readJson(path("a/leaderboard.json"));
  EXPECT_EQ(j["sweep"], "noise.sigma=[0, 3]");
  EXPECT_EQ(j["scenarios"][0]["sweep"]["from"], "--sweep");
}

TEST_F(CompareSweepTest, NestedSpellingAndHelp) {
  // GIVEN `--set sweep.noise.sigma=[...]` on a scenario without a sweep (it writes the nested
  // mapping {noise: {sigma: [...]}}) THEN it is the sweep of noise.sigma
  const auto sc = predvs::loadScenario(
      delay_, {predvs::parseScenarioOverride("sweep="), predvs::parseScenarioOverride("sweep.noise.sigma=[0, 1]")});
  EXPECT_EQ(sc.sweeps.at(0).key, "noise.sigma");
  EXPECT_EQ(sc.sweeps.at(0).values, (std::vector<std::string>{"0", "1"}));
  EXPECT_EQ(sc.sigma_sweep, (std::vector<double>{0.0, 1.0}));
  // AND compare --help documents --sweep
  const CliRun r = run({"compare", "--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--sweep PATH=V1,V2"), std::string::npos) << r.out;
}

TEST_F(CompareSweepTest, PredictorParameterSweepChangesThatPredictor) {
  // GIVEN a sweep of one of kf-cv's parameters
  const std::string out = path("out");
  const CliRun r = run({"compare", "--scenarios", delay_, "--sweep", "predictors.kf-cv.params.q=0.1,1000", "--out", out,
                        "--no-plots"});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN each variant records its value in kf-cv's params, the other parameters kept
  const auto j = readJson(out + "/leaderboard.json");
  const auto& vars = j["scenarios"][0]["variants"];
  ASSERT_EQ(vars.size(), 2u);
  std::vector<double> qs;
  for (const auto& v : vars)
    for (const auto& p : v["predictors"])
      if (p["name"] == "kf-cv") {
        qs.push_back(p["params"]["q"].get<double>());
        EXPECT_EQ(p["params"]["r"].get<double>(), 1.0);
      }
  EXPECT_EQ(qs, (std::vector<double>{0.1, 1000.0}));
  // AND kf-cv's numbers change with q while hold's do not
  const auto m = leaderboardMeans(out + "/leaderboard.csv");
  EXPECT_NE(m.at("tiny-delay@q=0.1/kf-cv/rmse"), m.at("tiny-delay@q=1000/kf-cv/rmse"));
  EXPECT_EQ(m.at("tiny-delay@q=0.1/hold/rmse"), m.at("tiny-delay@q=1000/hold/rmse"));
}

TEST_F(CompareSweepTest, NoiseSigmaSweepKeepsItsNamesAndPlot) {
  // GIVEN a 3-channel E6-like scenario with the classic noise.sigma sweep
  const std::string e6 = write("tiny-e6.yaml",
                               "kind: open-loop\nseed: 3\nruns: 2\nduration_s: 3\ntiming: {base_period_s: 0.1}\n"
                               "noise: {model: uniform, sigma: 2, round: true}\n"
                               "sweep: {noise.sigma: [0, 2.0]}\ntrajectory: {type: e6-target}\n"
                               "predictors: [hold, kf-cv]\n");
  const auto sc = predvs::loadScenario(e6);
  EXPECT_EQ(sc.sweeps.at(0).key, "noise.sigma");
  EXPECT_EQ(sc.sigma_sweep, (std::vector<double>{0.0, 2.0}));
  const std::string out = path("out");
  std::vector<std::string> a = {"compare", "--scenarios", e6, "--out", out};
  const bool plots = predvs::gnuplotAvailable();
  if (!plots) a.push_back("--no-plots");
  const CliRun r = run(a);
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN the variants are <scenario>@sigma=<value> (2.0 printed as 2), with the MSE columns
  const auto m = leaderboardMeans(out + "/leaderboard.csv");
  EXPECT_EQ(m.count("tiny-e6@sigma=0/kf-cv/pos_mse_x_i"), 1u);
  EXPECT_EQ(m.count("tiny-e6@sigma=2/kf-cv/vel_mse_d_x"), 1u);
  EXPECT_NE(r.out.find("tiny-e6@sigma=2"), std::string::npos);
  // AND the plots keep their names: error_<scenario>_sigma<value>, mse_vs_sigma_<scenario>
  if (plots) {
    for (const char* f : {"error_tiny-e6_sigma0.png", "error_tiny-e6_sigma2.png", "mse_vs_sigma_tiny-e6.png"})
      EXPECT_GT(fs::file_size(out + "/" + std::string(f)), 1000u) << f;
    EXPECT_FALSE(fs::exists(out + "/rmse_vs_sigma_tiny-e6.png"));
  }
}

TEST_F(CompareSweepTest, BadSweepsAreOneLineExit2AndNoDirectory) {
  const std::string out = path("out");
  // a value the scenario rejects, from the file: names the file, the line, the key and the value
  const std::string bad_value = write("bad-value.yaml",
                                      "kind: open-loop\ntrajectory: {type: line}\npredictors: [hold]\n"
                                      "sweep: {timing.delay_frames: [0, 3]}\n");
  expectError(run({"compare", "--scenarios", bad_value, "--out", out}),
              "bad-value.yaml:4: sweep timing.delay_frames=3 (scenario bad-value): 'timing.delay_frames'", out);
  // ... and from --sweep
  expectError(run({"compare", "--scenarios", delay_, "--sweep", "timing.delay_frames=1,2.5", "--out", out}),
              "--sweep timing.delay_frames=2.5 (scenario tiny-delay)", out);
  // a key the scenario kind does not have
  expectError(run({"compare", "--scenarios", delay_, "--sweep", "task.lambda=1,2", "--out", out}),
              "--sweep task.lambda=1 (scenario tiny-delay): unknown key 'task'", out);
  // two keys in one sweep are a grid (compare_grid_test.cpp); the same key twice is an error
  const std::string two = write("two-keys.yaml",
                                "kind: open-loop\ntrajectory: {type: line}\npredictors: [hold]\n"
                                "sweep: {noise.sigma: [0, 1], noise: {sigma: [2]}}\n");
  expectError(run({"compare", "--scenarios", two, "--out", out}), "two-keys.yaml:4: sweep: 'noise.sigma' is swept twice",
              out);
  // malformed option, an empty list, a repeated value, a key that cannot be swept
  expectError(run({"compare", "--scenarios", delay_, "--sweep", "noise.sigma", "--out", out}), "--sweep: expected PATH=",
              out);
  expectError(run({"compare", "--scenarios", delay_, "--sweep", "noise.sigma=[]", "--out", out}),
              "expected a non-empty list", out);
  expectError(run({"compare", "--scenarios", delay_, "--sweep", "noise.sigma=1,1", "--out", out}), "listed twice", out);
  expectError(run({"compare", "--scenarios", delay_, "--sweep", "seed=1,2", "--out", out}), "'seed' cannot be swept", out);
  const std::string empty = write("empty-sweep.yaml",
                                  "kind: open-loop\ntrajectory: {type: line}\npredictors: [hold]\n"
                                  "sweep: {noise.sigma: []}\n");
  expectError(run({"compare", "--scenarios", empty, "--out", out}), "empty-sweep.yaml:4", out);
}

TEST(CompareSweepScenarios, DelayStudySweepsTheDefaultClosedLoopOverTheVisionDelay) {
  // GIVEN the delay-study scenario
  const auto sc = predvs::loadScenario(predvs::resolveScenario("delay-study"));
  // THEN it is the closed loop swept over H = 0, 1, 2 frames with the four predictors of the brief
  EXPECT_EQ(sc.kind, predvs::ScenarioKind::ClosedLoop);
  EXPECT_EQ(sc.sweeps.at(0).key, "timing.delay_frames");
  EXPECT_EQ(sc.sweeps.at(0).values, (std::vector<std::string>{"0", "1", "2"}));
  ASSERT_EQ(sc.predictors.size(), 4u);
  EXPECT_EQ(sc.predictors[0].name, "hold");
  EXPECT_EQ(sc.predictors[3].name, "cs-akf-adaptive");
  // AND each variant loads with its latency t_ac + t_p = H T
  const auto at = predvs::loadSweepVariants(sc, {});
  ASSERT_EQ(at.size(), 3u);
  for (size_t h = 0; h < at.size(); ++h) {
    const auto& t = at[h].closed_loop.timing;
    EXPECT_DOUBLE_EQ(t.acquisition_lag_s + t.processing_lag_s, static_cast<double>(h) * t.base_period_s * t.frame_period_n)
        << h;
  }
}

}  // namespace
