// `predvs servo` and `predvs compare` report the same figures (app/report.h, servo/run_metrics.h):
// the same names and, on the same scenario and seed, the same values; servo runs every scenario
// `predvs list` shows (open loop of any channel count) and draws a law's diagnostics.
#include "cli_test_utils.h"
#include "gnuplot.h"
#include "plots.h"
#include "scenario.h"
#include "scenario_file.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using namespace predvs::apptest;

namespace {

/// The metric names of `predictor`'s rows of a leaderboard.csv, in the file's order.
std::vector<std::string> csvMetrics(const std::string& csv, const std::string& predictor) {
  std::vector<std::string> metrics;
  for (const auto& cells : csvRows(csv))
    if (cells.size() >= 6 && cells[2] == predictor) metrics.push_back(cells[3]);
  return metrics;
}

class ServoReportTest : public ScratchDirTest {
 protected:
  ServoReportTest() : ScratchDirTest("predvs_servo_report_test") {}

  /// Runs `predvs servo` and `predvs compare --runs 1` on the same scenario and seed (and the same
  /// --set arguments), then checks that for every predictor summary.json has exactly the figures
  /// of leaderboard.json and leaderboard.csv, with the same values, and that both commands print
  /// the same table columns.
  void expectSameFigures(const std::string& scenario, const std::string& seed, const std::vector<std::string>& sets) {
    std::vector<std::string> servo = {"servo", "--scenario", scenario, "--seed", seed, "--out", path("servo"), "--no-plots"};
    std::vector<std::string> compare = {"compare", "--scenarios", scenario, "--runs", "1", "--seed", seed,
                                        "--out",   path("compare"), "--no-plots", "--jobs", "2"};
    for (const auto& s : sets) {
      servo.insert(servo.end(), {"--set", s});
      compare.insert(compare.end(), {"--set", s});
    }
    const CliRun rs = run(servo), rc = run(compare);
    ASSERT_EQ(rs.code, 0) << rs.err;
    ASSERT_EQ(rc.code, 0) << rc.err;
    const auto summary = readJson(fs::path(path("servo")) / "summary.json");
    const auto board = readJson(fs::path(path("compare")) / "leaderboard.json");
    const std::string csv = slurp(path("compare") + "/leaderboard.csv");
    const auto& variant = board["scenarios"][0]["variants"][0];
    ASSERT_EQ(summary["predictors"].size(), variant["predictors"].size());
    for (const auto& sp : summary["predictors"]) {
      const std::string name = sp["name"];
      const nlohmann::json* cp = nullptr;
      for (const auto& p : variant["predictors"])
        if (p["name"] == name) cp = &p;
      ASSERT_NE(cp, nullptr) << name;
      const auto& sm = sp["metrics"];
      const auto& cm = (*cp)["metrics"];
      EXPECT_EQ(sm.size(), cm.size()) << name;
      for (const auto& [metric, value] : sm.items()) {
        ASSERT_TRUE(cm.contains(metric)) << name << " " << metric;
        const auto& stats = cm[metric];
        if (value.is_null()) {
          EXPECT_EQ(stats["n"].get<int>(), 0) << name << " " << metric;
        } else {
          // One run: the mean is the run's value itself (a sum of one term divided by one).
          EXPECT_EQ(stats["mean"].get<double>(), value.get<double>()) << name << " " << metric;
        }
      }
      // The CSV has one row per figure, each a figure servo wrote.
      const auto rows = csvMetrics(csv, name);
      EXPECT_EQ(rows.size(), sm.size()) << name;
      for (const auto& m : rows) EXPECT_TRUE(sm.contains(m)) << name << " " << m;
    }
    // Both commands print the same table columns: the header line of servo's table is in compare's output.
    const std::string servo_header = rs.out.substr(rs.out.find("\npredictor") + 1);
    const std::string first_line = servo_header.substr(0, servo_header.find('\n'));
    EXPECT_NE(rc.out.find(first_line), std::string::npos) << first_line << "\n---\n" << rc.out;
  }
};

TEST_F(ServoReportTest, ClosedLoopServoAndCompareReportTheSameFigures) {
  // GIVEN a 1.5 s closed loop WHEN servo and compare --runs 1 run it on seed 4
  const std::string f = write("closed.yaml",
                              "kind: closed-loop\nduration_s: 1.5\ntiming: {base_period_s: 0.04, delay_frames: 2}\n"
                              "predictors: [hold, kf-cv]\n");
  // THEN the figures (rmse .. effort) have the same names and values
  expectSameFigures(f, "4", {});
}

TEST_F(ServoReportTest, ClosedLoopWithARunSummaryReportsTheLawsFigures) {
  // GIVEN the same loop with the sliding-mode law, whose run summary is sliding_rms_final
  const std::string f = write("closed.yaml",
                              "kind: closed-loop\nduration_s: 1.5\ntiming: {base_period_s: 0.04, delay_frames: 2}\n"
                              "predictors: [hold, kf-cv]\n");
  expectSameFigures(f, "4", {"task.type=vsc"});
  // THEN that figure is in servo's summary with a definition pointing at the task
  const auto summary = readJson(fs::path(path("servo")) / "summary.json");
  EXPECT_TRUE(summary["predictors"][1]["metrics"]["sliding_rms_final"].is_number());
  EXPECT_NE(summary["metric_definitions"]["sliding_rms_final"].get<std::string>().find("vsc"), std::string::npos);
}

TEST_F(ServoReportTest, OpenLoopServoAndCompareReportTheSameFigures) {
  // GIVEN an E7-like open loop (3 channels, an occlusion) cut to 4 s
  const std::string f = write("open.yaml",
                              "kind: open-loop\nduration_s: 4\ntiming: {base_period_s: 0.1, delay_frames: 1}\n"
                              "noise: {model: uniform, sigma: 2, round: true}\ntrajectory: {type: e6-target}\n"
                              "occlusions: [{start_s: 1.5, end_s: 2.0}]\n"
                              "predictors: [hold, {name: kf-cv, params: {r: 5, q: 200}}, stkf]\n");
  // THEN per-channel MSEs, occlusion and alarm figures agree between the commands
  expectSameFigures(f, "11", {});
  const auto summary = readJson(fs::path(path("servo")) / "summary.json");
  for (const char* m : {"pos_mse_d_x", "occl_rmse", "reacq_1s_rmse", "false_alarms_per_min"})
    EXPECT_TRUE(summary["predictors"][0]["metrics"].contains(m)) << m;
}

TEST_F(ServoReportTest, ServoRunsTheOcclusionStudyWithPlotsForThreeChannels) {
  if (!predvs::gnuplotAvailable()) GTEST_SKIP() << "gnuplot not on PATH";
  // GIVEN e7-occlusion (E6 target: x_i, y_i, d_x; hidden from 8 s to 11 s)
  const std::string out = path("e7");
  const CliRun r = run({"servo", "--scenario", "e7-occlusion", "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN the log has a column per channel and the plots are drawn (a plane of x_i, y_i and a
  // panel per channel versus time)
  std::ifstream csv(out + "/log.csv");
  std::string header;
  std::getline(csv, header);
  for (const char* c : {"meas_x_i", "pred_y_i", "true_d_x", "error"})
    EXPECT_NE(header.find(c), std::string::npos) << c << " in " << header;
  for (const char* png : {"error.png", "trajectories.png"}) EXPECT_GT(fs::file_size(out + "/" + png), 1000u) << png;
  const std::string gp = slurp(out + "/trajectories.gp");
  EXPECT_NE(gp.find("d_x versus time"), std::string::npos);
  EXPECT_NE(slurp(out + "/error.gp").find("occlusion (shaded)"), std::string::npos);
  // AND the table shows the occlusion figures under compare's names
  EXPECT_NE(r.out.find("occl_rmse"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reacq_error"), std::string::npos) << r.out;
}

TEST_F(ServoReportTest, EveryListedScenarioRunsInServo) {
  // GIVEN every scenario file `predvs list` shows, cut to 1 s
  for (const auto& s : predvs::listScenarios()) {
    const std::string out = path("run-" + s.name);
    // WHEN servo runs it without plots
    const CliRun r = run({"servo", "--scenario", s.name, "--set", "duration_s=1", "--out", out, "--no-plots"});
    // THEN it succeeds and writes its summary with an rmse per predictor
    ASSERT_EQ(r.code, 0) << s.name << ": " << r.err;
    const auto j = readJson(fs::path(out) / "summary.json");
    for (const auto& p : j["predictors"]) EXPECT_TRUE(p["metrics"].contains("rmse")) << s.name;
    // and a scenario with a sweep says on stderr and in the summary that the sweep was not run
    const auto sc = predvs::loadScenario(predvs::resolveScenario(s.name));
    EXPECT_EQ(j["sweep_not_run"].is_string(), !sc.sweeps.empty()) << s.name;
    EXPECT_EQ(r.err.find("is not run by `predvs servo`") != std::string::npos, !sc.sweeps.empty()) << s.name;
  }
}

TEST_F(ServoReportTest, ALawWithDiagnosticsGetsDiagnosticsAndCommandPlots) {
  if (!predvs::gnuplotAvailable()) GTEST_SKIP() << "gnuplot not on PATH";
  // GIVEN the sliding-mode law (diagnostics sliding_norm, s_u, s_v, gain_q) on a 1 s loop
  const std::string f = write("vsc.yaml",
                              "kind: closed-loop\nduration_s: 1\ntask: {type: vsc}\npredictors: [hold, kf-cv]\n");
  const std::string out = path("vsc");
  const CliRun r = run({"servo", "--scenario", f, "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN diagnostics.png, command.png and features.png are drawn and named on stdout
  for (const char* png : {"diagnostics.png", "command.png", "features.png", "trajectories.png"}) {
    EXPECT_GT(fs::file_size(out + "/" + png), 1000u) << png;
    EXPECT_NE(r.out.find(png), std::string::npos) << png;
  }
  // AND s_u and s_v share a panel (one prefix), the others have one each: 3 panels, 8 curves
  const std::string gp = slurp(out + "/diagnostics.gp");
  EXPECT_NE(gp.find("set multiplot layout 3,1"), std::string::npos) << gp;
  EXPECT_NE(gp.find("title \"hold s_u\""), std::string::npos) << gp;
  EXPECT_NE(gp.find("title \"kf-cv s_v\""), std::string::npos) << gp;
  // (ibvs, which has no diagnostics, gets none: CliTest.ServoShortClosedLoopWritesAllFiles)
  // AND the command's panels carry the units the robot states (CommandSpace::units)
  const std::string command = slurp(out + "/command.gp");
  EXPECT_NE(command.find("set ylabel \"vx [m/s]\""), std::string::npos) << command;
  EXPECT_NE(command.find("set ylabel \"wz [rad/s]\""), std::string::npos) << command;
}

TEST_F(ServoReportTest, EveryPanelVersusTimeMarksTheOcclusion) {
  if (!predvs::gnuplotAvailable()) GTEST_SKIP() << "gnuplot not on PATH";
  // GIVEN a closed loop with one occlusion (e8-vtc-occlusion: 12-15 s), 16 s long
  const std::string out = path("occ");
  const CliRun r = run({"servo", "--scenario", "e8-vtc-occlusion", "--set", "duration_s=16", "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN every panel of the plots versus time shades it, once per panel (a multiplot keeps labels
  // from panel to panel unless each panel unsets them)
  for (const char* gp_file : {"error.gp", "features.gp", "command.gp", "diagnostics.gp"}) {
    const std::string gp = slurp(out + "/" + gp_file);
    size_t panels = 0, shaded = 0, resets = 0;
    for (size_t at = gp.find("\nplot "); at != std::string::npos; at = gp.find("\nplot ", at + 1)) ++panels;
    for (size_t at = gp.find("set object rect from 12"); at != std::string::npos; at = gp.find("set object rect from 12", at + 1)) ++shaded;
    for (size_t at = gp.find("unset label"); at != std::string::npos; at = gp.find("unset label", at + 1)) ++resets;
    EXPECT_GT(panels, 0u) << gp_file;
    EXPECT_EQ(shaded, panels) << gp_file;
    EXPECT_EQ(resets, panels) << gp_file;
  }
}

TEST_F(ServoReportTest, BadPredictorListIsOneLineExit2AndNoDirectory) {
  const std::string out = path("out");
  expectError(run({"servo", "--scenario", "e7-occlusion", "--predictors", "hold,hold", "--out", out}), "listed twice", out);
  expectError(run({"servo", "--scenario", "e7-occlusion", "--set", "trajectory.type=nope", "--out", out}),
              "nope", out);
}

TEST(Plots, RelatedDiagnosticsShareAPanel) {
  // GIVEN vtc's and vsc's diagnostic names
  using predvs::groupByPrefix;
  // THEN names sharing the text before the first '_' share a panel, in order of appearance
  EXPECT_EQ(groupByPrefix({"lyap_f", "lyap_bound", "lyap_f_bar", "stopped"}),
            (std::vector<std::vector<size_t>>{{0, 1, 2}, {3}}));
  EXPECT_EQ(groupByPrefix({"sliding_norm", "s_u", "s_v", "gain_q"}),
            (std::vector<std::vector<size_t>>{{0}, {1, 2}, {3}}));
  EXPECT_EQ(groupByPrefix({"jacobian_error", "updated", "exploring"}),
            (std::vector<std::vector<size_t>>{{0}, {1}, {2}}));
}

}  // namespace
