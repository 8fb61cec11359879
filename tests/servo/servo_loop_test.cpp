// Closed loop on the default scenario `ibvs-moving-target` (data/scenarios/ibvs-moving-target.yaml): convergence on a static
// target, prediction versus the hold baseline on the same seed, determinism and the golden trace.
#include "predvs/predictors/predictor.h"
#include "predvs/servo/servo_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace predvs {
namespace {

/// The predictor defaults before issue 11, which the figures of these closed-loop tests (and the
/// golden trace) were measured with; data/scenarios/ibvs-moving-target.yaml pins them too.
/// (With the issue-11 defaults, tuned on open-loop maneuvering tracks, kf-ca's rmse on this loop is
/// 24 px against hold's 36 px instead of under half of it, and kf-cv's velocity on a static target
/// is noisier: 16 px/s instead of under 5.)
Params preIssue11(const std::string& name) {
  if (name == "kf-cv" || name == "fakf-classic") return {{"q", 100.0}, {"r", 1.0}, {"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}};
  if (name == "kf-ca") return {{"q", 1000.0}, {"r", 1.0}, {"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}};
  if (name == "cs-akf-adaptive" || name == "fakf")
    return {{"sigma_min_sq", 10.0}, {"sigma_max_sq", 1000.0}, {"r", 1.0}, {"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}};
  return {};
}

ServoResult run(const std::string& predictor, const ServoConfig& c = {}) {
  auto p = makePredictor(predictor, 8, preIssue11(predictor));
  return runServoLoop(c, *p);
}

TEST(ServoLoop, StaticTargetConverges) {
  // GIVEN the default scenario with the target at rest
  ServoConfig c;
  c.scene.trajectory = "static";
  c.scene.trajectory_params = Params{};
  for (const char* name : {"hold", "kf-cv"}) {
    const ServoResult r = run(name, c);
    // THEN the error goes from ~57 px to the level the 0.5 px noise leaves (well under 1 px)
    EXPECT_GT(r.trace.front().error, 40.0) << name;
    EXPECT_LT(r.metrics.final_error, 1.0) << name;
    EXPECT_LT(r.metrics.settling_time_s, 10.0) << name;
  }
}

TEST(ServoLoop, HoldIsThePlainViSPBaseline) {
  // GIVEN hold with the default compensation (auto)
  const ServoResult r = run("hold");
  // THEN no prediction path is used: the task acts on the latest delayed measurement
  EXPECT_FALSE(r.prediction_used);
  for (const auto& s : r.trace)
    if (!std::isnan(s.t_acq_s)) {
      EXPECT_EQ(s.predicted, s.measured);
      EXPECT_NEAR(s.t_s - s.t_acq_s, 0.08, 1e-9);
    }
  EXPECT_TRUE(run("kf-cv").prediction_used);
}

TEST(ServoLoop, PredictionBeatsHoldOnMovingTarget) {
  // GIVEN the default scenario (circle r = 5 cm at 0.5 rad/s, 80 ms latency, 0.5 px noise, seed 1)
  const double e_hold = run("hold").metrics.rmse;
  // THEN a plain P-controller lags the target by ~ image speed / lambda (tens of pixels)
  EXPECT_GT(e_hold, 20.0);
  // and the Kalman predictors with feed-forward cut the steady error at least by the papers' 2x
  // (measured: about 7x for kf-cv and 35x for kf-ca on this seed)
  std::vector<std::string> names = {"kf-cv", "kf-ca"};
  if (isPredictor("cs-akf-adaptive")) names.push_back("cs-akf-adaptive");
  for (const auto& n : names) {
    const double e = run(n).metrics.rmse;
    EXPECT_LT(e, e_hold / 2.0) << n << ": " << e << " px vs hold " << e_hold << " px";
  }
}

TEST(ServoLoop, ForecastModesAllTrack) {
  // GIVEN kf-cv in each forecast mode
  ServoConfig c;
  std::map<std::string, double> e;
  for (ForecastMode m : {ForecastMode::Feature, ForecastMode::Feedforward, ForecastMode::Both}) {
    c.forecast = m;
    e[forecastModeName(m)] = run("kf-cv", c).metrics.rmse;
  }
  // THEN feature prediction alone does not remove a P-controller's steady lag (within 10 % of
  // hold), while the feed-forward modes do; the default (feedforward) is the best of the three
  const double e_hold = run("hold").metrics.rmse;
  EXPECT_GT(e["feature"], 0.9 * e_hold);
  EXPECT_LT(e["feedforward"], e_hold / 2.0);
  EXPECT_LT(e["both"], e_hold / 2.0);
  EXPECT_LE(e["feedforward"], e["both"]);
  EXPECT_EQ(ServoConfig{}.forecast, ForecastMode::Feedforward);
}

TEST(ServoLoop, EgoMotionCompensationRemovesCameraInducedMotion) {
  // GIVEN a static target and kf-cv fed with compensated features s_c = s - E
  ServoConfig c;
  c.scene.trajectory = "static";
  c.scene.trajectory_params = Params{};
  auto p = makePredictor("kf-cv", 8, preIssue11("kf-cv"));
  const ServoResult r = runServoLoop(c, *p);
  // WHEN the camera has moved the features by ~57 px (RMS) to the goal
  const Eigen::VectorXd moved = r.trace.back().truth - r.trace.front().truth;
  ASSERT_GT(moved.cwiseAbs().maxCoeff(), 50.0);
  // THEN the compensated features stay where the first image put them: what is left is the
  // first-order error of E (L evaluated at estimated features over a large motion), a few px
  const Eigen::VectorXd s_c = p->predictPositions(p->time());
  constexpr double kLinearisationTolPx = 4.0;
  EXPECT_LT((s_c - r.trace.front().truth).cwiseAbs().maxCoeff(), kLinearisationTolPx);
  // and the predictor sees no target motion (velocity at the noise level of a 0.5 px, 25 Hz KF)
  constexpr double kVelocityNoisePxPerS = 5.0;
  EXPECT_LT(p->predictVelocities(p->time()).cwiseAbs().maxCoeff(), kVelocityNoisePxPerS);
}

TEST(ServoLoop, CommandLagAndDualRate) {
  // GIVEN a 40 ms controller lag (horizon 0.12 s) and vision at half the control rate (N = 2)
  ServoConfig c;
  c.timing.controller_lag_s = 0.04;
  c.timing.base_period_s = 0.02;
  c.timing.frame_period_n = 2;
  const double e_hold = run("hold", c).metrics.rmse;
  const ServoResult r = run("kf-ca", c);
  // THEN the loop stays stable and prediction still removes most of the lag error
  EXPECT_LT(r.metrics.final_error, 3.0);
  EXPECT_LT(r.metrics.rmse, e_hold / 2.0);
  EXPECT_EQ(r.trace.size(), 1251u);  // 25 s at 20 ms, both ends included
}

TEST(ServoLoop, CompensationSwitch) {
  // GIVEN compensation off: kf-cv on raw features, forecast used as the current feature only
  ServoConfig c;
  c.compensation = Compensation::Off;
  const ServoResult off = run("kf-cv", c);
  const double e_hold = run("hold").metrics.rmse;
  // THEN the raw-feature predictor sees an almost still image and cannot remove the lag
  EXPECT_FALSE(off.prediction_used);
  EXPECT_GT(off.metrics.rmse, 0.9 * e_hold);
  // GIVEN compensation on with hold (a Smith predictor with a still-target model)
  c.compensation = Compensation::On;
  c.forecast = ForecastMode::Feature;
  const ServoResult smith = run("hold", c);
  // THEN the path is active and the loop still tracks (a still-target model has no feed-forward)
  EXPECT_TRUE(smith.prediction_used);
  EXPECT_LT(smith.metrics.rmse, 1.1 * e_hold);
}

TEST(ServoLoop, DeterministicForASeed) {
  const ServoResult a = run("kf-cv"), b = run("kf-cv");
  ASSERT_EQ(a.trace.size(), b.trace.size());
  EXPECT_EQ(a.trace.back().truth, b.trace.back().truth);
  ServoConfig c;
  c.seed = 2;
  EXPECT_NE(run("kf-cv", c).trace.back().truth, a.trace.back().truth);
}

TEST(ServoLoop, TraceHasThePredictorsDiagnostics) {
  // GIVEN the default loop (4 points, 8 feature channels) with imm, and with kf-cv
  const ServoResult imm = run("imm");
  const ServoResult kf = run("kf-cv");
  // THEN imm's trace rows carry its diagnostics (6 per channel: mode probabilities, forecast
  // weights) under its names, NaN before the first delivered frame and each group summing to one
  // after; kf-cv has none
  ASSERT_EQ(imm.predictor_diagnostic_names.size(), 48u);
  EXPECT_EQ(imm.predictor_diagnostic_names.front(), "mu_cp_0");
  EXPECT_EQ(imm.predictor_diagnostic_names[1], "mu_cv_0");
  EXPECT_EQ(imm.predictor_diagnostic_names[23], "mu_ca_7");
  EXPECT_EQ(imm.predictor_diagnostic_names[24], "fw_cp_0");
  EXPECT_TRUE(kf.predictor_diagnostic_names.empty());
  EXPECT_EQ(kf.trace.back().predictor_diagnostics.size(), 0);
  ASSERT_FALSE(imm.trace.empty());
  EXPECT_TRUE(std::isnan(imm.trace.front().predictor_diagnostics(0)));
  int rows = 0;
  for (const ServoSample& s : imm.trace) {
    ASSERT_EQ(s.predictor_diagnostics.size(), 48);
    if (std::isnan(s.t_acq_s)) continue;
    ++rows;
    for (int c = 0; c < 8; ++c) {
      const Eigen::VectorXd& d = s.predictor_diagnostics;  // mu_cp_c, mu_cv_c, mu_ca_c, ..., then fw_*
      EXPECT_NEAR(d(3 * c) + d(3 * c + 1) + d(3 * c + 2), 1.0, 1e-9);
      EXPECT_NEAR(d(24 + 3 * c) + d(24 + 3 * c + 1) + d(24 + 3 * c + 2), 1.0, 1e-9);
    }
  }
  EXPECT_GT(rows, 100);
  // AND the values change over the run (they are the filter's, not a constant)
  EXPECT_NE(imm.trace[imm.trace.size() / 4].predictor_diagnostics(1), imm.trace.back().predictor_diagnostics(1));
  // AND with the recording off (no kept trace) there are none, and the run is the same
  ServoConfig off;
  off.predictor_diagnostics = false;
  const ServoResult quiet = run("imm", off);
  EXPECT_TRUE(quiet.predictor_diagnostic_names.empty());
  EXPECT_EQ(quiet.trace.back().predictor_diagnostics.size(), 0);
  EXPECT_EQ(quiet.trace.back().error, imm.trace.back().error);
}

TEST(ServoLoop, ValidatesConfig) {
  auto p = makePredictor("kf-cv", 8, preIssue11("kf-cv"));
  ServoConfig c;
  c.scene.square_side_m = 0.0;
  EXPECT_THROW(ServoLoop(c, *p), std::invalid_argument);
  auto two = makePredictor("kf-cv", 2, preIssue11("kf-cv"));
  EXPECT_THROW(ServoLoop(ServoConfig{}, *two), std::invalid_argument);
  c = ServoConfig{};
  c.scene.trajectory_params.set("radiuss", 1.0);
  EXPECT_THROW(ServoLoop(c, *p), std::invalid_argument);
  EXPECT_THROW(parseForecastMode("smith"), std::invalid_argument);
  EXPECT_THROW(parseCompensation("maybe"), std::invalid_argument);
}

// ---- Golden trace -------------------------------------------------------------------------
// data/golden/ibvs-moving-target.csv holds the trace of kf-cv on the default ServoConfig with
// the columns ServoLoop::traceColumns() (extra columns are ignored; an empty cell or "nan" is NaN).
// Two files are accepted: the CLI's log.csv (`make golden`: a leading `predictor` column, one
// block of rows per predictor, of which the kf-cv rows are compared) or the test's own output,
// regenerated with
//   PREDVS_REGENERATE_GOLDEN=1 build/tests/servo_tests --gtest_filter='ServoGolden.*'
// A difference is a change indicator: regenerate only when the change of behaviour is intended,
// and say so in the commit.

// Relative tolerance: same code and seed give identical numbers on one platform; this leaves
// room for a different compiler or libm, not for a change of behaviour.
constexpr double kGoldenRelTol = 1e-6;
constexpr double kGoldenAbsTol = 1e-6;  // px, m/s, rad/s near zero

const std::string kGoldenPath = std::string(PREDVS_SOURCE_DIR) + "/data/golden/ibvs-moving-target.csv";

TEST(ServoGolden, DefaultScenarioMatchesGoldenTrace) {
  const ServoResult r = run("kf-cv");
  auto p = makePredictor("kf-cv", 8, preIssue11("kf-cv"));
  ServoLoop loop(ServoConfig{}, *p);
  const auto cols = loop.traceColumns();
  const char* regen = std::getenv("PREDVS_REGENERATE_GOLDEN");
  if (regen && std::string(regen) == "1") {
    std::ofstream out(kGoldenPath);
    ASSERT_TRUE(out) << "cannot write " << kGoldenPath;
    for (size_t i = 0; i < cols.size(); ++i) out << (i ? "," : "") << cols[i];
    out << "\n";
    char buf[64];
    for (const auto& s : r.trace) {
      const auto row = ServoLoop::traceRow(s);
      for (size_t i = 0; i < row.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.12g", row[i]);
        out << (i ? "," : "") << buf;
      }
      out << "\n";
    }
    SUCCEED() << "regenerated " << kGoldenPath;
    return;
  }
  std::ifstream in(kGoldenPath);
  ASSERT_TRUE(in) << kGoldenPath << " missing: regenerate with PREDVS_REGENERATE_GOLDEN=1";
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    std::string h;
    while (std::getline(ss, h, ',')) header.push_back(h);
  }
  std::vector<int> where(cols.size(), -1);
  for (size_t c = 0; c < cols.size(); ++c)
    for (size_t h = 0; h < header.size(); ++h)
      if (header[h] == cols[c]) where[c] = static_cast<int>(h);
  for (size_t c = 0; c < cols.size(); ++c) ASSERT_GE(where[c], 0) << "golden lacks column " << cols[c];
  int predictor_col = -1;
  for (size_t h = 0; h < header.size(); ++h)
    if (header[h] == "predictor") predictor_col = static_cast<int>(h);

  size_t row_index = 0;
  int mismatches = 0;
  while (std::getline(in, line) && !line.empty()) {
    std::vector<std::string> cells;
    {
      std::stringstream ss(line);
      std::string cell;
      while (std::getline(ss, cell, ',')) cells.push_back(cell);
      if (!line.empty() && line.back() == ',') cells.emplace_back();  // trailing empty cell
    }
    if (predictor_col >= 0 && cells.at(static_cast<size_t>(predictor_col)) != "kf-cv") continue;
    ASSERT_LT(row_index, r.trace.size()) << "golden has more rows than the run";
    std::vector<double> golden;
    for (const auto& cell : cells) golden.push_back(cell == "nan" || cell.empty() ? NAN : std::strtod(cell.c_str(), nullptr));
    const auto fresh = ServoLoop::traceRow(r.trace[row_index]);
    for (size_t c = 0; c < cols.size(); ++c) {
      const double g = golden.at(static_cast<size_t>(where[c])), f = fresh[c];
      const bool ok = (std::isnan(g) && std::isnan(f)) ||
                      std::abs(g - f) <= kGoldenAbsTol + kGoldenRelTol * std::abs(g);
      if (!ok && ++mismatches <= 5)
        ADD_FAILURE() << "row " << row_index << " column " << cols[c] << ": golden " << g << ", run " << f;
    }
    ++row_index;
  }
  EXPECT_EQ(row_index, r.trace.size()) << "row count differs";
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
}  // namespace predvs
