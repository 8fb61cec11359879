// Tests of `predvs compare` (app/compare_command.h), in-process through runCli(): the promised
// files, independence of the numbers from --jobs, the failure contract on bad input.
#include "cli.h"
#include "cli_test_utils.h"
#include "gnuplot.h"
#include "scenario.h"
#include "scenario_file.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

using namespace predvs::apptest;  // run(), CliRun, slurp(), ScratchDirTest (cli_test_utils.h)

namespace {

class CompareTest : public ScratchDirTest {
 protected:
  CompareTest() : ScratchDirTest("predvs_compare_test") {}
  void SetUp() override {
    ScratchDirTest::SetUp();
    // Two tiny scenarios: an open-loop E6-like sweep with an occlusion (3 channels), and a 1 s
    // closed loop.
    open_ = write("tiny-open.yaml",
                  "description: tiny open loop\nkind: open-loop\nseed: 3\nruns: 3\nduration_s: 4\n"
                  "timing: {base_period_s: 0.1, delay_frames: 1}\n"
                  "noise: {model: uniform, sigma: 2, round: true}\n"
                  "sweep: {noise.sigma: [0, 2]}\n"
                  "trajectory: {type: e6-target}\n"
                  "occlusions: [{start_s: 1.5, end_s: 2.0}]\n"
                  "predictors: [hold, {name: kf-cv, params: {r: 5, q: 200}}]\n");
    closed_ = write("tiny-closed.yaml",
                    "description: tiny closed loop\nkind: closed-loop\nseed: 5\nruns: 2\nduration_s: 1.0\n"
                    "timing: {base_period_s: 0.04, delay_frames: 2}\n"
                    "predictors: [hold, kf-cv]\n");
  }
  std::vector<std::string> args(const std::string& out, const std::string& jobs) const {
    return {"compare", "--scenarios", open_ + "," + closed_, "--out", out, "--jobs", jobs, "--no-plots"};
  }

  std::string open_, closed_;
};

TEST_F(CompareTest, WritesTheLeaderboardAndPlots) {
  // GIVEN the two tiny scenarios WHEN compared with plots (when gnuplot is there)
  const bool plots = predvs::gnuplotAvailable();
  const std::string out = path("out");
  std::vector<std::string> a = {"compare", "--scenarios", open_ + "," + closed_, "--out", out, "--jobs", "2"};
  if (!plots) a.push_back("--no-plots");
  const CliRun r = run(a);
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN the three leaderboards exist, and the plots: one error plot per variant and the sweep's MSE plot
  for (const char* f : {"leaderboard.csv", "leaderboard.json", "leaderboard.md"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  if (plots) {
    for (const char* f : {"error_tiny-open_sigma0.png", "error_tiny-open_sigma2.png", "error_tiny-closed.png",
                          "mse_vs_sigma_tiny-open.png"}) {
      EXPECT_GT(fs::file_size(out + "/" + std::string(f)), 1000u) << f;
    }
  }
  // AND the JSON records runs, seeds and, per predictor, mean/std/min/max of each metric
  std::ifstream js(out + "/leaderboard.json");
  const auto j = nlohmann::json::parse(js);
  ASSERT_EQ(j["scenarios"].size(), 2u);
  const auto& open = j["scenarios"][0];
  EXPECT_EQ(open["runs"].get<int>(), 3);
  EXPECT_EQ(open["seeds"][0].get<int>(), 3);
  EXPECT_EQ(open["seeds"][1].get<int>(), 5);
  ASSERT_EQ(open["variants"].size(), 2u);  // the sweep
  const auto& kf = open["variants"][1]["predictors"][0]["name"] == "kf-cv" ? open["variants"][1]["predictors"][0]
                                                                            : open["variants"][1]["predictors"][1];
  for (const char* m : {"rmse", "pos_mse_x_i", "vel_mse_d_x", "occl_rmse", "reacq_error"}) {
    const auto& s = kf["metrics"][m];
    EXPECT_EQ(s["n"].get<int>(), 3) << m;
    EXPECT_LE(s["min"].get<double>(), s["mean"].get<double>()) << m;
    EXPECT_LE(s["mean"].get<double>(), s["max"].get<double>()) << m;
    EXPECT_GE(s["std"].get<double>(), 0.0) << m;
  }
  EXPECT_TRUE(j["scenarios"][1]["variants"][0]["predictors"][0]["metrics"]["effort"]["mean"].is_number());
  // AND the CSV has one row per (variant, predictor, metric)
  const std::string csv = slurp(out + "/leaderboard.csv");
  EXPECT_EQ(csv.rfind("scenario,variant,predictor,metric,n,mean,std,min,max,median\n", 0), 0u);
  EXPECT_NE(csv.find("tiny-open,tiny-open@sigma=2,kf-cv,vel_mse_x_i,3,"), std::string::npos);
  // AND the markdown and the printed table name every predictor; progress went to stderr
  const std::string md = slurp(out + "/leaderboard.md");
  EXPECT_NE(md.find("## tiny-closed"), std::string::npos);
  EXPECT_NE(md.find("| kf-cv |"), std::string::npos);
  EXPECT_NE(r.out.find("tiny-open@sigma=2"), std::string::npos);
  EXPECT_NE(r.err.find("runs"), std::string::npos);
}

TEST_F(CompareTest, NumbersDoNotDependOnJobs) {
  // GIVEN the same comparison on 1 and on 2 threads
  ASSERT_EQ(run(args(path("j1"), "1")).code, 0);
  ASSERT_EQ(run(args(path("j2"), "2")).code, 0);
  // THEN the leaderboards are identical byte for byte
  const std::string a = slurp(path("j1/leaderboard.csv")), b = slurp(path("j2/leaderboard.csv"));
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

TEST_F(CompareTest, RunsAndSeedOverrideTheScenarios) {
  const std::string out = path("out");
  const CliRun r = run({"compare", "--scenarios", open_, "--predictors", "kf-cv,stkf", "--runs", "2", "--seed", "7",
                        "--out", out, "--no-plots"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream js(out + "/leaderboard.json");
  const auto j = nlohmann::json::parse(js);
  EXPECT_EQ(j["scenarios"][0]["runs"].get<int>(), 2);
  EXPECT_EQ(j["scenarios"][0]["seeds"][0].get<int>(), 7);
  // kf-cv keeps the parameters its scenario gives it; stkf (not listed there) runs on defaults
  for (const auto& p : j["scenarios"][0]["variants"][0]["predictors"]) {
    if (p["name"] == "kf-cv") {
      EXPECT_EQ(p["params"]["q"].get<double>(), 200.0);
    }
    if (p["name"] == "stkf") {
      EXPECT_TRUE(p["params"].empty());
    }
  }
}

TEST_F(CompareTest, BadInputIsOneLineExit2AndNoDirectory) {
  const std::string out = path("out");
  expectError(run({"compare", "--scenarios", "no-such-scenario", "--out", out}), "--scenarios: unknown scenario", out);
  expectError(run({"compare", "--scenarios", open_, "--predictors", "kf-cv,nope", "--out", out}),
              "--predictors: unknown predictor 'nope'", out);
  expectError(run({"compare", "--scenarios", open_, "--predictors", "all,kf-cv", "--out", out}), "--predictors", out);
  expectError(run({"compare", "--scenarios", open_ + "," + open_, "--out", out}), "listed twice", out);
  expectError(run({"compare", "--scenarios", open_, "--runs", "0", "--out", out}), "--runs", out);
  expectError(run({"compare", "--scenarios", open_, "--jobs", "two", "--out", out}), "--jobs", out);
  expectError(run({"compare", "--scenarios", open_, "--seed", "-1", "--out", out}), "--seed", out);
  expectError(run({"compare", "--scenarios", ",", "--out", out}), "--scenarios", out);
  expectError(run({"compare", "--bogus", "--out", out}), "--bogus", out);
  const std::string bad_sweep = write("bad-sweep.yaml",
                                      "kind: open-loop\ntrajectory: {type: line}\npredictors: [hold]\n"
                                      "sweep: {noise.rho: [1, 2]}\n");
  expectError(run({"compare", "--scenarios", bad_sweep, "--out", out}), "bad-sweep.yaml:4", out);
  const std::string bad_runs = write("bad-runs.yaml", "kind: open-loop\nruns: 0\ntrajectory: {type: line}\npredictors: [hold]\n");
  expectError(run({"compare", "--scenarios", bad_runs, "--out", out}), "bad-runs.yaml:2", out);
}

TEST(CompareScenarios, PaperStudiesHaveThePapersValues) {
  // E6 (paper 001 §5.2): 20 runs per sigma_n = 0..10, uniform rounded noise, T = 0.1 s, 3 channels
  const auto e6 = predvs::loadScenario(predvs::resolveScenario("e6-noise-study"));
  EXPECT_EQ(e6.runs, 20);
  EXPECT_EQ(e6.channels, 3);
  EXPECT_EQ(e6.trajectory, "e6-target");
  EXPECT_EQ(e6.sigma_sweep, (std::vector<double>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
  EXPECT_EQ(e6.open_loop.noise.kind, predvs::NoiseKind::Uniform);
  EXPECT_TRUE(e6.open_loop.noise.round_to_integer);
  EXPECT_EQ(e6.open_loop.timing.base_period_s, 0.1);
  // E7 (paper 001 §5.5): a 3 s occlusion
  const auto e7 = predvs::loadScenario(predvs::resolveScenario("e7-occlusion"));
  ASSERT_EQ(e7.open_loop.occlusions.size(), 1u);
  EXPECT_EQ(e7.open_loop.occlusions[0].end_s - e7.open_loop.occlusions[0].start_s, 3.0);
  // E12 (paper 004 §5): Th = 0.04 s and 0.002 s, period 3 s, amplitude 2 m = 2000 mm
  for (const auto& [name, th] : {std::pair<std::string, double>{"e12-discontinuity", 0.04}, {"e12-discontinuity-2ms", 0.002}}) {
    const auto e12 = predvs::loadScenario(predvs::resolveScenario(name));
    EXPECT_EQ(e12.open_loop.timing.base_period_s, th) << name;
    EXPECT_EQ(e12.trajectory_params.values().at("amplitude"), 2000.0) << name;
    EXPECT_EQ(e12.trajectory_params.values().at("period"), 3.0) << name;
    EXPECT_EQ(e12.channels, 1) << name;
  }
}

}  // namespace
