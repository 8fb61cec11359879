// E8 (paper 001 §5.3, §5.5; docs/MODELS.md §10-11 E8): the scenario files e8-vtc, e8-vtc-occlusion and
// e8-ibvs, loaded as `predvs` loads them and run as `predvs compare` runs them (run r: seed S + r,
// the same for every predictor). Checks the set-up they document, the headline comparison on
// their 20 seeds, a static board driven to convergence through the ServoLoop, and the one-line
// error for a bad vtc key. The 20-seed tests also print figures of docs/REPRODUCTION.md (E8) that
// `predvs compare` does not report (the Lyapunov bound over the first 3 s, the estimate's error at
// the end of the occlusion):
//     build/tests/app_tests --gtest_filter='E8*'
#include "cli_test_utils.h"
#include "scenario.h"
#include "scenario_file.h"
#include "scenario_override.h"

#include "predvs/predictors/predictor.h"
#include "predvs/servo/servo_loop.h"
#include "predvs/servo/unicycle_tilt_robot.h"
#include "predvs/tasks/vtc_task.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The first 3 s of a run: the initial 29 px error in y_i decays with kg_y = 0.75 /s (2.3 time
// constants); "the transient" of docs/MODELS.md §11.
constexpr double kTransientEnd_s = 3.0;

Scenario e8(const std::string& name, const std::vector<std::string>& sets = {}) {
  std::vector<ScenarioOverride> overrides;
  for (const auto& s : sets) overrides.push_back(parseScenarioOverride(s));
  return loadScenario(resolveScenario(name), overrides);
}

const ScenarioPredictor& predictorOf(const Scenario& sc, const std::string& name) {
  for (const auto& p : sc.predictors)
    if (p.name == name) return p;
  throw std::invalid_argument("scenario " + sc.name + " has no predictor " + name);
}

/// One run exactly as `predvs compare` makes it (app/compare_command.cpp, runOne).
ServoResult runSeed(const Scenario& sc, const std::string& predictor, std::uint64_t seed) {
  ServoConfig cfg = sc.closed_loop;
  cfg.seed = seed;
  const ScenarioPredictor& p = predictorOf(sc, predictor);
  auto filter = makePredictor(p.name, sc.channels, p.params);
  return runServoLoop(cfg, *filter);
}

/// Figures of one run that compare does not print for a closed loop.
struct RunFigures {
  double rmse = kNaN, final_error = kNaN;
  std::vector<double> steady_rms, steady_mean;  ///< per task feature: RMS and mean of truth - goal
  double bound_fraction = kNaN, bound_fraction_transient = kNaN;  ///< lyap_bound > 0 (vtc)
  // Occlusion (NaN without one): over the ticks whose latest frame was acquired inside it.
  double occl_estimate_rms = kNaN;  ///< RMS over channels of (features the task acts on - truth)
  double occl_estimate_end = kNaN;  ///< the same at the last of those ticks
  double occl_track_rms = kNaN;  ///< tracking error through it
  double reacq_error = kNaN;  ///< tracking error at the first tick with a new frame
  double reacq_1s_rms = kNaN;  ///< and its RMS over the next second
};

int columnOf(const ServoResult& r, const std::string& name) {
  const auto it = std::find(r.columns.begin(), r.columns.end(), name);
  return it == r.columns.end() ? -1 : static_cast<int>(it - r.columns.begin());
}

RunFigures figuresOf(const Scenario& sc, const ServoResult& r) {
  RunFigures f;
  for (const auto& kv : r.values) {
    if (kv.first == "rmse") f.rmse = kv.second;
    if (kv.first == "final") f.final_error = kv.second;
    if (kv.first == "lyap_bound_positive_fraction") f.bound_fraction = kv.second;
  }
  const int n = static_cast<int>(r.desired.size());
  const double t_end = r.trace.back().t_s;
  const double steady_from = sc.closed_loop.metrics.steady_start_fraction * t_end;
  std::vector<double> sq(static_cast<size_t>(n), 0.0), sum(static_cast<size_t>(n), 0.0);
  int count = 0;
  for (const auto& s : r.trace) {
    if (s.t_s < steady_from) continue;
    ++count;
    for (int i = 0; i < n; ++i) {
      const double e = s.truth(i) - r.desired(i);
      sq[static_cast<size_t>(i)] += e * e;
      sum[static_cast<size_t>(i)] += e;
    }
  }
  for (int i = 0; i < n; ++i) {
    f.steady_rms.push_back(std::sqrt(sq[static_cast<size_t>(i)] / count));
    f.steady_mean.push_back(sum[static_cast<size_t>(i)] / count);
  }
  // The Lyapunov bound of eq. 45 (a diagnostic of vtc) during the transient.
  const int bound_col = columnOf(r, "lyap_bound");
  if (bound_col >= 0) {
    const int first_diag = static_cast<int>(r.columns.size()) - static_cast<int>(r.trace.front().diagnostics.size());
    int ticks = 0, positive = 0;
    for (const auto& s : r.trace) {
      const double lb = s.diagnostics(bound_col - first_diag);
      if (s.t_s >= kTransientEnd_s || !std::isfinite(lb)) continue;
      ++ticks;
      positive += lb > 0.0 ? 1 : 0;
    }
    f.bound_fraction_transient = ticks > 0 ? static_cast<double>(positive) / ticks : kNaN;
  }
  if (!sc.closed_loop.occlusions.empty()) {
    const OcclusionInterval o = sc.closed_loop.occlusions.front();
    double est_sq = 0.0, track_sq = 0.0;
    int lost = 0;
    for (size_t k = 0; k < r.trace.size(); ++k) {
      const ServoSample& s = r.trace[k];
      const bool hidden = s.t_acq_s >= o.start_s && s.t_acq_s < o.end_s;
      if (hidden) {
        const double e = std::sqrt((s.predicted - s.truth).squaredNorm() / n);
        est_sq += e * e;
        track_sq += s.error * s.error;
        f.occl_estimate_end = e;
        ++lost;
      } else if (lost > 0 && std::isnan(f.reacq_error)) {
        f.reacq_error = s.error;
        double s2 = 0.0;
        int m = 0;
        for (size_t j = k; j < r.trace.size() && r.trace[j].t_s < s.t_s + 1.0; ++j, ++m)
          s2 += r.trace[j].error * r.trace[j].error;
        f.reacq_1s_rms = std::sqrt(s2 / m);
      }
    }
    f.occl_estimate_rms = std::sqrt(est_sq / lost);
    f.occl_track_rms = std::sqrt(track_sq / lost);
  }
  return f;
}

struct MeanStd {
  double mean = 0.0, std = 0.0, max = -1e300;
};

MeanStd over(const std::vector<RunFigures>& runs, double (*get)(const RunFigures&)) {
  MeanStd m;
  for (const auto& r : runs) m.mean += get(r), m.max = std::max(m.max, get(r));
  m.mean /= static_cast<double>(runs.size());
  for (const auto& r : runs) m.std += (get(r) - m.mean) * (get(r) - m.mean);
  m.std = std::sqrt(m.std / static_cast<double>(runs.size() - 1));
  return m;
}

/// Every predictor of scenario `name` on its `runs` seeds S..S+runs-1, as compare runs them.
std::map<std::string, std::vector<RunFigures>> runAll(const Scenario& sc) {
  std::map<std::string, std::vector<RunFigures>> out;
  for (const auto& p : sc.predictors)
    for (int r = 0; r < sc.runs; ++r)
      out[p.name].push_back(figuresOf(sc, runSeed(sc, p.name, sc.seed() + static_cast<std::uint64_t>(r))));
  return out;
}

std::string cell(const MeanStd& m) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f ± %.2f", m.mean, m.std);
  return buf;
}

/// Prints the Markdown rows docs/REPRODUCTION.md (E8) quotes.
void printFigures(const Scenario& sc, const std::map<std::string, std::vector<RunFigures>>& all) {
  std::printf("\n%s, %d runs, seeds %llu..%llu (mean ± std over runs):\n", sc.name.c_str(), sc.runs,
              static_cast<unsigned long long>(sc.seed()), static_cast<unsigned long long>(sc.seed() + sc.runs - 1));
  const bool vtc = sc.closed_loop.task.name == "vtc";
  const bool occl = !sc.closed_loop.occlusions.empty();
  std::printf("| predictor | rmse | final |%s%s\n",
              vtc ? " x_e rms | y_e rms | d_e rms | x_e mean | y_e mean | d_e mean | LB>0 run | LB>0 first 3 s |" : "",
              occl ? " estimate err. through | at its end | tracking through | re-acq. | next 1 s |" : "");
  for (const auto& p : sc.predictors) {
    const auto& runs = all.at(p.name);
    std::printf("| %s | %s | %s |", p.name.c_str(),
                cell(over(runs, [](const RunFigures& f) { return f.rmse; })).c_str(),
                cell(over(runs, [](const RunFigures& f) { return f.final_error; })).c_str());
    if (vtc) {
      for (int i = 0; i < 3; ++i) {
        MeanStd m;
        for (const auto& f : runs) m.mean += f.steady_rms[static_cast<size_t>(i)] / runs.size();
        for (const auto& f : runs) m.std += std::pow(f.steady_rms[static_cast<size_t>(i)] - m.mean, 2);
        m.std = std::sqrt(m.std / (runs.size() - 1));
        std::printf(" %s |", cell(m).c_str());
      }
      for (int i = 0; i < 3; ++i) {
        MeanStd m;
        for (const auto& f : runs) m.mean += f.steady_mean[static_cast<size_t>(i)] / runs.size();
        for (const auto& f : runs) m.std += std::pow(f.steady_mean[static_cast<size_t>(i)] - m.mean, 2);
        m.std = std::sqrt(m.std / (runs.size() - 1));
        std::printf(" %s |", cell(m).c_str());
      }
      std::printf(" %s | %s |", cell(over(runs, [](const RunFigures& f) { return f.bound_fraction; })).c_str(),
                  cell(over(runs, [](const RunFigures& f) { return f.bound_fraction_transient; })).c_str());
    }
    if (occl) {
      for (auto get :
           {+[](const RunFigures& f) { return f.occl_estimate_rms; },
            +[](const RunFigures& f) { return f.occl_estimate_end; },
            +[](const RunFigures& f) { return f.occl_track_rms; }, +[](const RunFigures& f) { return f.reacq_error; },
            +[](const RunFigures& f) { return f.reacq_1s_rms; }})
        std::printf(" %s |", cell(over(runs, get)).c_str());
    }
    std::printf("\n");
  }
}

double steadyRms(const RunFigures& f, int channel) { return f.steady_rms[static_cast<size_t>(channel)]; }

// ---------------------------------------------------------------------------------------------

TEST(E8Scenarios, LoadWithTheRobotAtTheOriginAndTheLawsParametersEqualToTheWorlds) {
  for (const char* name : {"e8-vtc", "e8-vtc-occlusion", "e8-ibvs"}) {
    SCOPED_TRACE(name);
    // GIVEN the scenario file as predvs loads it
    const Scenario sc = e8(name);
    ASSERT_EQ(sc.kind, ScenarioKind::ClosedLoop);
    EXPECT_EQ(sc.closed_loop.robot.name, "unicycle-tilt");
    EXPECT_EQ(sc.closed_loop.scene.trajectory, "e8-target");
    EXPECT_EQ(sc.runs, 20);
    EXPECT_NEAR(sc.closed_loop.timing.base_period_s, 0.1, 1e-15);
    auto hold = makePredictor("hold", sc.channels);
    const ServoLoop loop(sc.closed_loop, *hold);
    // THEN initial_pose puts the robot at (x, y, heading, tilt) = (0, 0, 0, 0) (paper Table 1): the
    // poses in the file are given to 1e-7 m / rad
    constexpr double kPoseDigits = 1e-6;
    EXPECT_LT(loop.robot().state().cwiseAbs().maxCoeff(), kPoseDigits) << loop.robot().state().transpose();
    const auto* robot = dynamic_cast<const UnicycleTiltRobot*>(&loop.robot());
    ASSERT_NE(robot, nullptr);
    EXPECT_NEAR(robot->config().tilt_axis_height_m + robot->config().camera_offset_y_m, 0.40, 1e-15);
    if (sc.closed_loop.task.name == "vtc") {
      // AND the law's W and dy are the board's and the robot's, with one rho for all four (eq. 43)
      const auto& task = dynamic_cast<const VtcTask&>(loop.task());
      EXPECT_EQ(task.trueModel().width_m, sc.closed_loop.scene.square_side_m);
      EXPECT_EQ(task.trueModel().camera_offset_y_m, robot->config().camera_offset_y_m);
      const VtcModel &t = task.trueModel(), &e = task.estimatedModel();
      const double rho = e.fx_px / t.fx_px - 1.0;
      EXPECT_GT(std::abs(rho), 0.0);
      EXPECT_LE(std::abs(rho), 0.1);
      EXPECT_NEAR(e.fy_px / t.fy_px - 1.0, rho, 1e-12);
      EXPECT_NEAR(e.width_m / t.width_m - 1.0, rho, 1e-12);
      EXPECT_NEAR(e.camera_offset_y_m / t.camera_offset_y_m - 1.0, rho, 1e-12);
      EXPECT_TRUE(task.desiredFeatures().isApprox(Eigen::Vector3d(0.0, 0.0, 35.0)));
    } else {
      // AND e8-ibvs's goal pose is one the unicycle can take: reset there, its camera is there
      UnicycleTiltRobot r(robot->config());
      const Scene scene(sc.closed_loop.scene);
      const vpHomogeneousMatrix want = scene.desiredCameraPose();
      r.reset(want);
      const vpHomogeneousMatrix got = r.cameraPose();
      for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = 0; j < 4; ++j) EXPECT_NEAR(got[i][j], want[i][j], kPoseDigits) << i << "," << j;
    }
  }
  // AND e8-vtc's cdMo (straight in front of the board, at its height) is not reachable: the camera
  // ends 10 cm too high (the reason e8-ibvs uses the pose above)
  const Scenario vtc = e8("e8-vtc");
  const Scene scene(vtc.closed_loop.scene);
  UnicycleTiltRobot r(Params{{"camera_offset_y_m", 0.10}, {"axle_length_m", 0.40}, {"tilt_axis_height_m", 0.30}});
  r.reset(scene.desiredCameraPose());
  constexpr double kPoseDigits = 1e-6;  // theta-u written to 7 digits in the file
  EXPECT_NEAR(r.cameraPose()[2][3] - scene.desiredCameraPose()[2][3], 0.10, kPoseDigits);
}

TEST(E8Vtc, DrivesAStaticBoardToTheGoalThroughTheServoLoop) {
  // GIVEN e8-vtc with the board at rest, no pixel noise, 40 s, and its parameter error (rho of
  // seed 800)
  const Scenario sc =
      e8("e8-vtc", {"target.trajectory={type: static}", "noise.model=none", "noise.round=false", "duration_s=40"});
  for (const char* predictor : {"hold", "stkf"}) {
    SCOPED_TRACE(predictor);
    ServoConfig cfg = sc.closed_loop;
    const ScenarioPredictor& p = predictorOf(sc, predictor);
    auto filter = makePredictor(p.name, sc.channels, p.params);
    ServoLoop loop(cfg, *filter);
    const ServoResult r = loop.run();
    // THEN the plain law (hold) and the law on the STKF's estimate remove the initial 16.8 px
    // (29 px in y_i): the goal is a fixed point whatever rho (measured after 40 s: hold 1.4e-9 px,
    // stkf 3.3e-9 px)
    EXPECT_NEAR(r.trace.front().error, 16.77, 0.01);
    constexpr double kConverged_px = 1e-6;
    EXPECT_LT(r.trace.back().error, kConverged_px);
    // AND the camera looks down at the board centre (1.3488, 0, 0.30) m from fx W / 35 = 1.3488 m
    // away whatever rho (the features, not the model, reach the goal): tilt -atan(0.10 / 1.3488);
    // the tolerances are the perspective of the board, tilted by 0.074 rad against the image plane
    // (the centroid of the projected corners is not the projected centre; measured 0.015 mm and
    // 1.5e-4 rad)
    const vpHomogeneousMatrix wMc = loop.robot().cameraPose();
    const Eigen::Vector3d to_board(1.3488 - wMc[0][3], 0.0 - wMc[1][3], 0.30 - wMc[2][3]);
    constexpr double kPerspective_m = 1e-4, kPerspective_rad = 5e-4;
    EXPECT_NEAR(to_board.norm(), 1.3488, kPerspective_m);
    EXPECT_NEAR(loop.robot().state()(3), -std::atan(0.10 / 1.3488), kPerspective_rad);
  }
}

TEST(E8Vtc, TracksTheMovingBoardWithAnEstimatorAndLagsWithout) {
  // GIVEN e8-vtc on its 20 seeds (compare's runs)
  const Scenario sc = e8("e8-vtc");
  const auto all = runAll(sc);
  printFigures(sc, all);
  const auto& stkf = all.at("stkf");
  const auto& kf = all.at("kf-cv");
  const auto& hold = all.at("hold");
  auto finalOf = [](const RunFigures& f) { return f.final_error; };
  auto rmseOf = [](const RunFigures& f) { return f.rmse; };
  // THEN with an estimator the error settles at a few px (measured mean final: stkf 5.2, kf-cv
  // 2.8 px; hold 13.4 px): the feed-forward of the estimated target rate removes most of the lag
  EXPECT_LT(over(stkf, finalOf).max, 8.0);
  EXPECT_LT(over(kf, finalOf).max, 5.0);
  EXPECT_GT(over(hold, finalOf).mean, 10.0);
  EXPECT_GT(over(hold, rmseOf).mean, 1.8 * over(stkf, rmseOf).mean);  // measured 2.2x
  // AND y_e and d_e settle at the noise floor (measured steady RMS 0.6-0.7 and 1.3-1.4 px) while x_e
  // keeps the CV model's lag, larger with the STKF than with the plain KF (docs/MODELS.md §11: measured
  // 6.6 against 3.6 px)
  for (const auto* runs : {&stkf, &kf}) {
    EXPECT_LT(over(*runs, [](const RunFigures& f) { return steadyRms(f, 1); }).mean, 1.5);
    EXPECT_LT(over(*runs, [](const RunFigures& f) { return steadyRms(f, 2); }).mean, 2.0);
  }
  const double x_stkf = over(stkf, [](const RunFigures& f) { return steadyRms(f, 0); }).mean;
  const double x_kf = over(kf, [](const RunFigures& f) { return steadyRms(f, 0); }).mean;
  EXPECT_GT(x_stkf, 1.4 * x_kf);
  EXPECT_LT(x_stkf, 0.7 * over(hold, [](const RunFigures& f) { return steadyRms(f, 0); }).mean);
  // AND the Lyapunov bound of eq. 45 is positive during the transient (measured: every tick of
  // the first 3 s with stkf, 99.5 % with kf-cv, whose noisier velocity enters delta f) but not
  // throughout the run (docs/MODELS.md §11; measured 97 % and 93 % of the ticks)
  for (const auto* runs : {&stkf, &kf}) {
    EXPECT_GT(over(*runs, [](const RunFigures& f) { return f.bound_fraction_transient; }).mean, 0.98);
    const MeanStd run = over(*runs, [](const RunFigures& f) { return f.bound_fraction; });
    EXPECT_LT(run.mean, 1.0);
    EXPECT_GT(run.mean, 0.5);
  }
}

TEST(E8Vtc, TheRangeWidthLeavesTheRobotTooFarAndTheSpreadDoesNot) {
  // GIVEN e8-vtc with the STKF on its 20 seeds, d_x measured as max - min of the noisy corners
  // (width: range) and as their spread (width: spread, the scenario's)
  auto meanDe = [](const Scenario& sc) {
    double sum = 0.0;
    for (int r = 0; r < sc.runs; ++r)
      sum += figuresOf(sc, runSeed(sc, "stkf", sc.seed() + static_cast<std::uint64_t>(r))).steady_mean[2];
    return sum / sc.runs;
  };
  const double range = meanDe(e8("e8-vtc", {"task.width=range"}));
  const double spread = meanDe(e8("e8-vtc"));
  std::printf("\ne8-vtc, stkf, steady mean of d_e (true d_x - 35 px): width range %.2f px, spread %.2f px\n", range,
              spread);
  // THEN with the range the true width settles about 2a/3 = 3.3 px short of 35 px (the robot stands
  // too far: measured -3.8 px, an 11 % distance error); with the spread the bias is the lag's
  // (measured -0.7 px)
  EXPECT_LT(range, -2.5);
  EXPECT_GT(spread, -1.2);
}

TEST(E8Vtc, TheStkfEstimateContinuesThroughTheOcclusion) {
  // GIVEN e8-vtc-occlusion (board hidden 12-15 s) on its 20 seeds
  const Scenario sc = e8("e8-vtc-occlusion");
  const auto all = runAll(sc);
  printFigures(sc, all);
  const auto& stkf = all.at("stkf");
  const auto& hold = all.at("hold");
  auto estimateEnd = [](const RunFigures& f) { return f.occl_estimate_end; };
  // THEN the STKF's estimate follows the hidden board: at the end of the 3 s it is 7.5 px (RMS over
  // x_i, y_i, d_x; worst run 15 px) from the truth, where hold's frozen image is 17.7 px off
  EXPECT_LT(over(stkf, estimateEnd).max, 20.0);
  EXPECT_GT(over(hold, estimateEnd).mean, 1.8 * over(stkf, estimateEnd).mean);
  // AND the robot keeps tracking blind: the error through the occlusion (measured 6.2 px, hold
  // 11.5) stays below hold's, and after re-acquisition it returns to the unoccluded level (final
  // 4.7 px, against 5.2 px without the occlusion)
  auto through = [](const RunFigures& f) { return f.occl_track_rms; };
  EXPECT_LT(over(stkf, through).mean, 0.7 * over(hold, through).mean);
  EXPECT_LT(over(stkf, [](const RunFigures& f) { return f.final_error; }).max, 8.0);
}

TEST(E8Ibvs, PointIbvsOnTheUnicycleAlsoNeedsTheEstimator) {
  // GIVEN e8-ibvs (4-point IBVS, lambda 0.5, reachable goal) on its 20 seeds
  const Scenario sc = e8("e8-ibvs");
  const auto all = runAll(sc);
  printFigures(sc, all);
  auto rmseOf = [](const RunFigures& f) { return f.rmse; };
  // THEN the estimators' feed-forward divides the steady error (measured 14.5 px hold, 8.5 stkf,
  // 3.8 kf-cv)
  EXPECT_GT(over(all.at("hold"), rmseOf).mean, 1.4 * over(all.at("stkf"), rmseOf).mean);
  EXPECT_GT(over(all.at("stkf"), rmseOf).mean, 1.4 * over(all.at("kf-cv"), rmseOf).mean);
}

class E8Cli : public apptest::ScratchDirTest {
 protected:
  E8Cli() : ScratchDirTest("predvs_e8_test") {}
};

TEST_F(E8Cli, ABadVtcValueInAScenarioFileIsOneLineNamingTheKeyAndItsLine) {
  // GIVEN e8-vtc.yaml with a negative gain, then with an unknown width
  const std::string text = apptest::slurp(resolveScenario("e8-vtc"));
  ASSERT_FALSE(text.empty());
  struct Case {
    std::string from, to, key;
  };
  for (const Case& c :
       {Case{"  kg_x: 0.5\n", "  kg_x: -0.5\n", "kg_x"}, Case{"  width: spread\n", "  width: median\n", "width"}}) {
    SCOPED_TRACE(c.key);
    std::string bad = text;
    const size_t at = bad.find(c.from);
    ASSERT_NE(at, std::string::npos);
    bad.replace(at, c.from.size(), c.to);
    const int line = 1 + static_cast<int>(std::count(bad.begin(), bad.begin() + static_cast<long>(at), '\n'));
    const std::string file = write("bad.yaml", bad);
    // WHEN predvs servo runs it THEN one line "predvs: error: FILE:LINE: ..." names the key and
    // the line it is on, exit 2, no output directory
    const apptest::CliRun r = apptest::run({"servo", "--scenario", file, "--out", path("out"), "--no-plots"});
    expectError(r, "'" + c.key + "'", path("out"));
    EXPECT_NE(r.err.find(file + ":" + std::to_string(line) + ":"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace predvs
