// Tests of `predvs compare` grids (app/compare_command.h, scenario.h): several --sweep options or a
// `sweep:` block with several keys run the product of their values; grid_<scenario>.csv and the
// heat maps; the numbers of a cell equal a single run of the scenario at those values; bad grids
// are one-line errors. Also the outcome keys of a scenario (metrics.outcome, camera.width/height).
#include "cli_test_utils.h"
#include "gnuplot.h"
#include "scenario.h"
#include "scenario_file.h"
#include "scenario_run.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace fs = std::filesystem;

using namespace predvs::apptest;  // run(), CliRun, slurp(), readJson(), ScratchDirTest (cli_test_utils.h)

namespace {

/// A CSV text as rows of fields (quoted fields with commas kept whole), the header row included.
std::vector<std::vector<std::string>> parseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1);
  std::string field;
  bool quoted = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().push_back(field), field.clear();
    } else if (c == '\n') {
      rows.back().push_back(field), field.clear();
      rows.emplace_back();
    } else {
      field += c;
    }
  }
  if (rows.back().empty()) rows.pop_back();
  return rows;
}

/// grid_<scenario>.csv as one map per row, column name -> field.
std::vector<std::map<std::string, std::string>> gridRows(const std::string& path) {
  const auto rows = parseCsv(slurp(path));
  std::vector<std::map<std::string, std::string>> out;
  for (size_t r = 1; r < rows.size(); ++r) {
    std::map<std::string, std::string> m;
    for (size_t c = 0; c < rows[0].size() && c < rows[r].size(); ++c) m[rows[0][c]] = rows[r][c];
    out.push_back(m);
  }
  return out;
}

/// Every figure of every predictor of the variant `id` in leaderboard.json: "predictor/metric" ->
/// its {n, mean, std, min, max, median} as JSON text.
std::map<std::string, std::string> variantFigures(const nlohmann::json& j, const std::string& id) {
  std::map<std::string, std::string> out;
  for (const auto& sc : j["scenarios"])
    for (const auto& v : sc["variants"])
      if (v["id"] == id)
        for (const auto& p : v["predictors"])
          for (const auto& m : p["metrics"].items()) out[p["name"].get<std::string>() + "/" + m.key()] = m.value().dump();
  return out;
}

class CompareGridTest : public ScratchDirTest {
 protected:
  CompareGridTest() : ScratchDirTest("predvs_compare_grid_test") {}
  void SetUp() override {
    ScratchDirTest::SetUp();
    // docs/MODELS.md §11 E10's stand-in, small: IBVS on a static 4-point square turned by 150 degrees
    // about the optical axis, no velocity saturation, delta = 10 ms, one frame of latency, 5 s.
    scenario_ = write("tiny-grid.yaml", body_);
  }
  std::vector<std::string> args(const std::string& out, std::vector<std::string> extra) const {
    std::vector<std::string> a = {"compare", "--scenarios", scenario_, "--out", out};
    a.insert(a.end(), extra.begin(), extra.end());
    if (!predvs::gnuplotAvailable()) a.push_back("--no-plots");
    return a;
  }
  const std::string body_ =
      "description: tiny positioning grid\nkind: closed-loop\nseed: 5\nruns: 2\nduration_s: 5\n"
      "timing: {base_period_s: 0.01, frame_period_n: 1, delay_frames: 1}\n"
      "noise: {model: gaussian, sigma: 0.5}\nmetrics: {outcome: true}\n"
      "target: {square_side_m: 0.1, desired_depth_m: 0.5, trajectory: {type: static}}\n"
      "initial_pose: [0, 0, 0, 0, 0, 2.618]\n"
      "task: {lambda: 1.0, interaction: current}\nrobot: {saturation: 0}\npredictors: [hold, kf-cv]\n";
  std::string scenario_;
};

TEST_F(CompareGridTest, TwoSweepsRunTheProductAndWriteTheGridAndTheHeatMap) {
  // GIVEN two --sweep options WHEN compared
  const std::string out = path("out");
  const CliRun r = run(args(out, {"--sweep", "task.lambda=2,4", "--sweep", "timing.frame_period_n=1,16", "--jobs", "2"}));
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN every cell is a variant named SCENARIO@KEY1=v1,KEY2=v2, the first key varying slowest
  const auto j = readJson(out + "/leaderboard.json");
  const auto& vars = j["scenarios"][0]["variants"];
  ASSERT_EQ(vars.size(), 4u);
  EXPECT_EQ(vars[0]["id"], "tiny-grid@lambda=2,frame_period_n=1");
  EXPECT_EQ(vars[1]["id"], "tiny-grid@lambda=2,frame_period_n=16");
  EXPECT_EQ(vars[3]["id"], "tiny-grid@lambda=4,frame_period_n=16");
  EXPECT_EQ(vars[1]["grid_values"]["timing.frame_period_n"].get<double>(), 16.0);
  ASSERT_EQ(j["scenarios"][0]["grid"].size(), 2u);
  EXPECT_EQ(j["scenarios"][0]["grid"][1]["key"], "timing.frame_period_n");
  EXPECT_EQ(j["sweep"].size(), 2u);
  // AND grid_<scenario>.csv has one row per cell and predictor with the outcome of its runs
  const auto rows = gridRows(out + "/grid_tiny-grid.csv");
  ASSERT_EQ(rows.size(), 8u);
  std::map<std::string, std::map<std::string, std::string>> by;
  for (const auto& row : rows) by[row.at("task.lambda") + "/" + row.at("timing.frame_period_n") + "/" + row.at("predictor")] = row;
  // at N = 1 both gains converge (no run fails) and have a steady rmse over both runs
  for (const char* cell : {"2/1/hold", "4/1/hold", "2/1/kf-cv"}) {
    const auto& row = by.at(cell);
    EXPECT_EQ(row.at("n"), "2") << cell;
    EXPECT_EQ(row.at("converged_fraction"), "1") << cell;
    EXPECT_EQ(row.at("failed_fraction"), "0") << cell;
    EXPECT_GT(std::stod(row.at("convergence_time_median_s")), 0.0) << cell;
    EXPECT_EQ(row.at("rmse_n"), "2") << cell;
  }
  // at N = 16 (T = 0.16 s and as much latency) the gain of 4 fails in every run, with no rmse
  const auto& failing = by.at("4/16/hold");
  EXPECT_EQ(failing.at("failed_fraction"), "1");
  EXPECT_EQ(failing.at("converged_fraction"), "0");
  EXPECT_EQ(failing.at("convergence_time_median_s"), "");
  EXPECT_EQ(failing.at("rmse_median"), "");
  EXPECT_EQ(failing.at("rmse_n"), "0");
  EXPECT_DOUBLE_EQ(std::stod(failing.at("fail_behind_fraction")) + std::stod(failing.at("fail_image_fraction")) +
                       std::stod(failing.at("fail_robot_fraction")),
                   1.0);
  // AND a faster gain converges sooner where both converge
  EXPECT_LT(std::stod(by.at("4/1/hold").at("convergence_time_median_s")),
            std::stod(by.at("2/1/hold").at("convergence_time_median_s")));
  // AND the markdown shows the first and the last cell; the heat map is drawn, no rmse_vs plot
  const std::string md = slurp(out + "/leaderboard.md");
  EXPECT_NE(md.find("## tiny-grid@lambda=2,frame_period_n=1"), std::string::npos);
  EXPECT_NE(md.find("## tiny-grid@lambda=4,frame_period_n=16"), std::string::npos);
  EXPECT_EQ(md.find("## tiny-grid@lambda=2,frame_period_n=16"), std::string::npos);
  if (predvs::gnuplotAvailable()) {
    EXPECT_GT(fs::file_size(out + "/heatmap_tiny-grid.png"), 1000u);
    EXPECT_GT(fs::file_size(out + "/error_tiny-grid_lambda2_frame_period_n1.png"), 1000u);
    EXPECT_FALSE(fs::exists(out + "/rmse_vs_lambda_tiny-grid.png"));
  }
}

TEST_F(CompareGridTest, ACellHasTheNumbersOfASingleRunAtItsValuesWhateverTheJobs) {
  // GIVEN the grid on 1 and on 2 threads, and the scenario run alone at lambda 4, N = 16 and at
  // lambda 2, N = 1
  ASSERT_EQ(run({"compare", "--scenarios", scenario_, "--sweep", "task.lambda=2,4", "--sweep",
                 "timing.frame_period_n=1,16", "--jobs", "1", "--no-plots", "--out", path("g1")})
                .code,
            0);
  ASSERT_EQ(run({"compare", "--scenarios", scenario_, "--sweep", "task.lambda=2,4", "--sweep",
                 "timing.frame_period_n=1,16", "--jobs", "2", "--no-plots", "--out", path("g2")})
                .code,
            0);
  for (const auto& [lambda, n] : std::vector<std::pair<std::string, std::string>>{{"4", "16"}, {"2", "1"}}) {
    const std::string single = path("single" + lambda);
    ASSERT_EQ(run({"compare", "--scenarios", scenario_, "--set", "task.lambda=" + lambda, "--set",
                   "timing.frame_period_n=" + n, "--no-plots", "--out", single})
                  .code,
              0);
    // THEN the cell's figures are exactly the single run's (same seeds, same loading)
    const auto cell = variantFigures(readJson(path("g1") + "/leaderboard.json"),
                                     "tiny-grid@lambda=" + lambda + ",frame_period_n=" + n);
    const auto alone = variantFigures(readJson(single + "/leaderboard.json"), "tiny-grid");
    ASSERT_GT(alone.size(), 20u);
    EXPECT_EQ(cell, alone) << lambda << "," << n;
  }
  // AND the grid does not depend on the number of threads
  EXPECT_EQ(slurp(path("g1") + "/grid_tiny-grid.csv"), slurp(path("g2") + "/grid_tiny-grid.csv"));
  EXPECT_EQ(slurp(path("g1") + "/leaderboard.csv"), slurp(path("g2") + "/leaderboard.csv"));
}

TEST_F(CompareGridTest, AFileSweepBlockWithSeveralKeysIsTheSameGrid) {
  // GIVEN the same grid in the file, the second key in the nested spelling
  const std::string file = write("tiny-grid.yaml", body_ + "sweep: {task.lambda: [2, 4], timing: {frame_period_n: [1, 16]}}\n");
  const auto sc = predvs::loadScenario(file);
  ASSERT_EQ(sc.sweeps.size(), 2u);
  EXPECT_EQ(sc.sweeps[1].key, "timing.frame_period_n");
  EXPECT_EQ(predvs::gridCells(sc.sweeps), 4u);
  EXPECT_EQ(predvs::gridIndices(sc.sweeps, 1), (std::vector<size_t>{0, 1}));
  ASSERT_EQ(run({"compare", "--scenarios", file, "--no-plots", "--out", path("file")}).code, 0);
  ASSERT_EQ(run({"compare", "--scenarios", file, "--sweep", "task.lambda=2,4", "--sweep", "timing.frame_period_n=1,16",
                 "--no-plots", "--out", path("cli")})
                .code,
            0);
  // THEN it gives the grid of the two --sweep options
  EXPECT_EQ(slurp(path("file") + "/grid_tiny-grid.csv"), slurp(path("cli") + "/grid_tiny-grid.csv"));
  EXPECT_EQ(readJson(path("file") + "/leaderboard.json")["scenarios"][0]["grid"][0]["from"], "scenario file");
  // AND `predvs servo` names both keys when it says it does not run them
  const CliRun s = run({"servo", "--scenario", file, "--predictors", "hold", "--no-plots", "--out", path("servo")});
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_NE(s.err.find("the sweep over task.lambda x timing.frame_period_n is not run"), std::string::npos) << s.err;
}

TEST_F(CompareGridTest, AThirdKeyMakesOneHeatMapPerValue) {
  if (!predvs::gnuplotAvailable()) GTEST_SKIP() << "gnuplot not installed";
  // GIVEN a 2 x 2 x 2 grid, the third key the noise
  const std::string out = path("out");
  const CliRun r = run({"compare", "--scenarios", scenario_, "--predictors", "hold", "--runs", "1", "--sweep",
                        "task.lambda=2,4", "--sweep", "timing.frame_period_n=1,16", "--sweep", "noise.sigma=0.5,1",
                        "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN there is one heat map per value of the third key, and every cell in the grid CSV
  EXPECT_GT(fs::file_size(out + "/heatmap_tiny-grid_sigma0_5.png"), 1000u);
  EXPECT_GT(fs::file_size(out + "/heatmap_tiny-grid_sigma1.png"), 1000u);
  EXPECT_FALSE(fs::exists(out + "/heatmap_tiny-grid.png"));
  EXPECT_EQ(gridRows(out + "/grid_tiny-grid.csv").size(), 8u);
}

TEST_F(CompareGridTest, RunsThatAllFailAtTheStartStillGiveTheirReports) {
  // GIVEN an image too small for the initial view (the square spans u = 240..400 px): every run
  // fails at t = 0 with no trace row
  const std::string out = path("out");
  const CliRun r = run(args(out, {"--set", "camera.width=200", "--sweep", "task.lambda=2,4", "--sweep",
                                  "timing.frame_period_n=1,16"}));
  // THEN compare writes its files (no error plot for a variant without samples) with every run failed
  ASSERT_EQ(r.code, 0) << r.err;
  for (const auto& row : gridRows(out + "/grid_tiny-grid.csv")) {
    EXPECT_EQ(row.at("failed_fraction"), "1");
    EXPECT_EQ(row.at("fail_image_fraction"), "1");
  }
  EXPECT_FALSE(fs::exists(out + "/error_tiny-grid_lambda2_frame_period_n1.png"));
  if (predvs::gnuplotAvailable()) {
    EXPECT_GT(fs::file_size(out + "/heatmap_tiny-grid.png"), 1000u);
  }
  // AND so does `predvs servo` (its summary and log, no plot of an empty trace), and a one-key
  // sweep without any rmse has no rmse plot
  const CliRun s = run({"servo", "--scenario", scenario_, "--set", "camera.width=200", "--out", path("servo")});
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_EQ(readJson(path("servo") + "/summary.json")["predictors"][0]["metrics"]["failed"], 1.0);
  EXPECT_FALSE(fs::exists(path("servo") + "/error.png"));
  ASSERT_EQ(run(args(path("one"), {"--set", "camera.width=200", "--sweep", "task.lambda=2,4"})).code, 0);
  EXPECT_FALSE(fs::exists(path("one") + "/rmse_vs_lambda_tiny-grid.png"));
}

TEST_F(CompareGridTest, BadGridsAreOneLineExit2AndNoDirectory) {
  const std::string out = path("out");
  // a key twice on the command line
  expectError(run({"compare", "--scenarios", scenario_, "--sweep", "task.lambda=1,2", "--sweep", "task.lambda=3",
                   "--out", out}),
              "--sweep: 'task.lambda' is swept twice", out);
  // an empty list in a grid
  expectError(run({"compare", "--scenarios", scenario_, "--sweep", "task.lambda=1,2", "--sweep",
                   "timing.frame_period_n=[]", "--out", out}),
              "expected a non-empty list", out);
  // a key that would replace an earlier one
  expectError(run({"compare", "--scenarios", scenario_, "--sweep", "task.lambda=1,2", "--sweep",
                   "task=[{lambda: 3}]", "--out", out}),
              "'task' would replace 'task.lambda'", out);
  // the same key twice in a file, once dotted and once nested: the file and the line of the second
  const std::string twice = write("twice.yaml", body_ + "sweep:\n  timing.frame_period_n: [1, 2]\n  timing: {frame_period_n: [4]}\n");
  expectError(run({"compare", "--scenarios", twice, "--out", out}),
              "twice.yaml:16: sweep: 'timing.frame_period_n' is swept twice", out);
  // a cell that the scenario rejects: the cell is named
  expectError(run({"compare", "--scenarios", scenario_, "--sweep", "timing.frame_period_n=1,2", "--sweep",
                   "timing.delay_frames=1,3", "--out", out}),
              "--sweep timing.frame_period_n=1, timing.delay_frames=3 (scenario tiny-grid): 'timing.delay_frames'", out);
  // the outcome in an open-loop scenario
  const std::string open = write("open.yaml",
                                 "kind: open-loop\ntrajectory: {type: line}\npredictors: [hold]\n"
                                 "metrics: {outcome: true}\n");
  expectError(run({"compare", "--scenarios", open, "--out", out}), "open.yaml:4: 'metrics.outcome'", out);
}

TEST(ScenarioOutcomeKeys, ImageSizeDefaultsToTwiceThePrincipalPointAndE5DoesNotFail) {
  // GIVEN the default camera and E5's 1280 x 960 camera (u0 = 640, v0 = 480)
  const auto dflt = predvs::loadScenario(predvs::resolveScenario("ibvs-moving-target"));
  EXPECT_EQ(dflt.closed_loop.image_width_px, 640.0);
  EXPECT_EQ(dflt.closed_loop.image_height_px, 480.0);
  const auto plain = predvs::loadScenario(predvs::resolveScenario("e5-line"));
  EXPECT_EQ(plain.closed_loop.image_width_px, 1280.0);
  EXPECT_EQ(plain.closed_loop.image_height_px, 960.0);
  EXPECT_FALSE(plain.closed_loop.metrics.outcome);
  // WHEN E5's line runs with metrics.outcome (its leader, at v = 480 px, would sit on the border of
  // a 640 x 480 image)
  const auto with = predvs::loadScenario(predvs::resolveScenario("e5-line"),
                                         {predvs::parseScenarioOverride("metrics.outcome=true")});
  EXPECT_TRUE(with.closed_loop.metrics.outcome);
  const auto a = predvs::runScenarioOnce(plain, plain.predictors.front(), plain.seed(), false);
  const auto b = predvs::runScenarioOnce(with, with.predictors.front(), with.seed(), false);
  // THEN it does not fail, and its figures are those of the run without the outcome
  std::map<std::string, double> vb(b.values.begin(), b.values.end());
  EXPECT_EQ(vb.at("failed"), 0.0);
  for (const auto& kv : a.values) {
    const double x = vb.at(kv.first);
    EXPECT_TRUE(x == kv.second || (std::isnan(x) && std::isnan(kv.second))) << kv.first << ": " << x << " vs " << kv.second;
  }
  // AND camera.width / height and the outcome keys are read and checked
  const auto sized = predvs::loadScenario(predvs::resolveScenario("ibvs-moving-target"),
                                          {predvs::parseScenarioOverride("camera.width=1000"),
                                           predvs::parseScenarioOverride("metrics.converge_px=2.5"),
                                           predvs::parseScenarioOverride("metrics.fail_outside_image=false")});
  EXPECT_EQ(sized.closed_loop.image_width_px, 1000.0);
  EXPECT_EQ(sized.closed_loop.metrics.converge_px, 2.5);
  EXPECT_FALSE(sized.closed_loop.metrics.fail_outside_image);
  EXPECT_THROW(predvs::loadScenario(predvs::resolveScenario("ibvs-moving-target"),
                                    {predvs::parseScenarioOverride("metrics.converge_px=0")}),
               std::invalid_argument);
}

}  // namespace
