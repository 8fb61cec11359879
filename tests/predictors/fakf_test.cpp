// Tests of the fuzzy adaptive Kalman filters (docs/MODELS.md §3): R adaptation follows the real noise,
// R stays inside [r_min, r_max], P inflation fires on a manoeuvre, and the E4 circle ranking.
#include "predvs/predictors/fakf.h"
#include "predvs/predictors/predictor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <functional>
#include <random>

namespace predvs {
namespace {

constexpr double kPeriodS = 0.1;  // frame period T of the paper-000 simulations (10 Hz; choice)

/// Runs a one-channel predictor on a ramp p = 5 t px with Gaussian noise of std sigma_px.
template <class P>
void runRamp(P& f, double sigma_px, int frames, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_px);
  Eigen::VectorXd z(1);
  for (int k = 0; k <= frames; ++k) {
    const double t = k * kPeriodS;
    z(0) = 5.0 * t + noise(rng);
    f.update(t, z);
  }
}

/// Feeds `frames` frames of 0 px with a 1e6 px outlier of alternating sign on every 7th, and
/// asserts after every update that R is inside [r_min, r_max] and the state and P are finite.
template <class P>
void expectRClampedUnderOutliers(P& f, int frames, double r_min, double r_max) {
  Eigen::VectorXd z(1);
  for (int k = 0; k < frames; ++k) {
    z(0) = (k % 7 == 0) ? 1e6 * ((k % 2) ? 1.0 : -1.0) : 0.0;
    f.update(k * kPeriodS, z);
    ASSERT_GE(f.adaptedR(0), r_min) << "frame " << k;
    ASSERT_LE(f.adaptedR(0), r_max) << "frame " << k;
    ASSERT_TRUE(std::isfinite(f.gaussian(0).x(0))) << "frame " << k;
    ASSERT_TRUE(f.gaussian(0).P.allFinite()) << "frame " << k;
  }
}

TEST(FakfClassic, RaisesRWhenTheNoiseIsLargerThanAssumed) {
  // GIVEN an assumed R = 1 px^2 and a real noise variance of 9 px^2
  FakfClassicPredictor<2> f(1, {{"r", 1.0}});
  // WHEN it filters 30 s of a noisy ramp
  runRamp(f, 3.0, 300, 11);
  // THEN R has grown well above its initial value (it wanders around the true 9 px^2; 3 is a
  // margin far outside what an unadapted R = 1 could show)
  EXPECT_GT(f.adaptedR(0), 3.0);
}

TEST(FakfClassic, LowersRWhenTheNoiseIsSmallerThanAssumed) {
  // GIVEN an assumed R = 1 px^2 and a real noise variance of 0.09 px^2
  FakfClassicPredictor<2> f(1, {{"r", 1.0}});
  // WHEN it filters 30 s of a noisy ramp
  runRamp(f, 0.3, 300, 12);
  // THEN R has come down by more than half (dR is bounded per frame, so it descends slowly)
  EXPECT_LT(f.adaptedR(0), 0.5);
}

TEST(FakfClassic, RStaysInsideItsClampUnderOutliers) {
  // GIVEN tight bounds on R and a sequence of wild measurements (1e6 px jumps)
  FakfClassicPredictor<2> f(1, {{"r", 1.0}, {"r_min", 0.5}, {"r_max", 2.0}, {"dr_max", 100.0}});
  // WHEN it filters 200 frames THEN R stays inside [r_min, r_max] and the state stays finite
  expectRClampedUnderOutliers(f, 200, 0.5, 2.0);
}

TEST(FakfClassic, ResetRestoresTheInitialR) {
  FakfClassicPredictor<2> f(1, {{"r", 1.0}});
  runRamp(f, 3.0, 100, 13);
  ASSERT_NE(f.adaptedR(0), 1.0);
  f.reset();
  EXPECT_EQ(f.adaptedR(0), 1.0);
  EXPECT_FALSE(f.initialized(0));
}

TEST(FakfClassic, RegisteredWithItsParameters) {
  EXPECT_TRUE(isPredictor("fakf-classic"));
  EXPECT_NO_THROW(makePredictor("fakf-classic", 2, {{"window", 20}, {"dr_max", 0.2}, {"r_max", 100}}));
  EXPECT_THROW(makePredictor("fakf-classic", 2, {{"beta_min", 0.9}}), std::invalid_argument);
  EXPECT_THROW(makePredictor("fakf-classic", 2, {{"r", 0.1}, {"r_min", 1.0}}), std::invalid_argument);
}


// ---------------------------------------------------------------------------------------------
// Improved FAKF (`fakf`)

TEST(Fakf, RaisesRWhenTheNoiseIsLargerThanAssumed) {
  // GIVEN an assumed R = 1 px^2 and a real noise variance of 9 px^2, three seeds
  double mean_r = 0.0;
  for (unsigned seed : {21u, 22u, 23u}) {
    FakfPredictor f(1, {{"r", 1.0}});
    // WHEN it filters 30 s of a noisy ramp
    runRamp(f, 3.0, 300, seed);
    mean_r += f.adaptedR(0) / 3.0;
  }
  // THEN R has grown (measured 4.2 .. 6.3: beta is bounded to ~±15% per frame and the wide dP'
  // universe of the paper, ±10 px^2, makes the pull towards the true 9 px^2 weak)
  EXPECT_GT(mean_r, 2.0);
}

TEST(Fakf, LowersRWhenTheNoiseIsSmallerThanAssumed) {
  // GIVEN an assumed R = 1 px^2 and a real noise variance of 0.09 px^2
  FakfPredictor f(1, {{"r", 1.0}});
  // WHEN it filters 30 s of a noisy ramp
  runRamp(f, 0.3, 300, 22);
  // THEN R has come down by more than half (measured 0.23)
  EXPECT_LT(f.adaptedR(0), 0.5);
}

TEST(Fakf, RStaysInsideItsClampUnderOutliers) {
  // GIVEN tight bounds on R and the same wild measurements
  FakfPredictor f(1, {{"r", 1.0}, {"r_min", 0.5}, {"r_max", 2.0}});
  // WHEN it filters 300 frames THEN R stays inside [r_min, r_max] and the state stays finite
  expectRClampedUnderOutliers(f, 300, 0.5, 2.0);
}

TEST(Fakf, InflatesPOnASuddenManoeuvreOnly) {
  // GIVEN a target moving at 50 px/s that reverses to -50 px/s at t = 10 s, 1 px noise
  for (unsigned seed : {31u, 32u, 33u}) {
    // (the paper's CS floor and ceiling: with the issue-11 floor of 1e5 the CS filter follows the
    // reversal by itself and the inflation is no longer needed there)
    FakfPredictor f(1, {{"sigma_min_sq", 10.0}, {"sigma_max_sq", 1000.0}});
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 1.0);
    Eigen::VectorXd z(1);
    int before = -1, after = -1;
    double gamma_max = 1.0;
    for (int k = 0; k <= 150; ++k) {
      const double t = k * kPeriodS;
      z(0) = (t < 10.0 ? 50.0 * t : 1000.0 - 50.0 * t) + noise(rng);
      f.update(t, z);
      gamma_max = std::max(gamma_max, f.lastGamma(0));
      if (k == 100) before = f.inflations(0);
      if (k == 120) after = f.inflations(0);
    }
    // THEN P is never inflated during the 10 s of straight motion, and is inflated within 2 s of
    // the reversal (the check runs every 10 frames; measured: at the first check, 1 s after) by a
    // gamma from the fuzzy map
    EXPECT_EQ(before, 0) << "seed " << seed;
    EXPECT_GE(after, 1) << "seed " << seed;
    EXPECT_GE(gamma_max, 175.0);
    EXPECT_LE(gamma_max, 925.0);
  }
}

TEST(Fakf, RegisteredWithItsParameters) {
  EXPECT_TRUE(isPredictor("fakf"));
  EXPECT_NO_THROW(makePredictor("fakf", 2,
                                {{"window", 20}, {"beta_min", 0.9}, {"beta_max", 1.1}, {"gamma_max", 500},
                                 {"inflation_period", 5}, {"sigma_min_sq", 0.5}}));
  EXPECT_THROW(makePredictor("fakf", 2, {{"beta_min", 1.5}}), std::invalid_argument);
  EXPECT_THROW(makePredictor("fakf", 2, {{"dom_range", 3}}), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Paper-000 simulations (docs/MODELS.md §10 E1-E4), generated here. One frame every kPeriodS, Gaussian
// noise of 1 px per axis, every predictor built from the registry with its defaults, prediction
// error = Euclidean distance between the prediction `horizon` frames ahead and the true position.

using Trajectory = std::function<Eigen::Vector2d(double)>;

struct ScenarioFigures {
  double max_lag_px = 0.0;    ///< largest mean error against the direction of the change
  double overshoot_px = 0.0;  ///< largest mean error along it
  double mean_after_px = 0.0; ///< mean |error| over the 3 s after the change
  double final_px = 0.0;      ///< mean |error| over the last 20 % of the run
};

/// The defaults before issue 11 (data/scenarios/e1-e4 pin them too): the figures quoted in this
/// file were measured with them.
Params paperEraParams(const std::string& name) {
  if (name == "kf-cv" || name == "fakf-classic")
    return {{"q", 100.0}, {"r", 1.0}, {"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}};
  if (name == "fakf" || name == "cs-akf-adaptive")
    return {{"sigma_min_sq", 10.0}, {"sigma_max_sq", 1000.0}, {"r", 1.0}, {"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}};
  return {};
}

/// Mean-over-seeds figures of predictor `name` on `traj` over [0, duration_s]; the change happens
/// at t_change_s (0: the start) in direction `dir` (signed errors are projected on it).
ScenarioFigures runScenario(const std::string& name, const Trajectory& traj, double duration_s, double t_change_s,
                            const Eigen::Vector2d& dir, int horizon, int seeds, const Params& params = {}) {
  const int K = static_cast<int>(std::lround(duration_s / kPeriodS));
  std::vector<double> signed_err(static_cast<size_t>(K + 1), 0.0), abs_err(static_cast<size_t>(K + 1), 0.0);
  for (int seed = 0; seed < seeds; ++seed) {
    std::mt19937 rng(5000u + static_cast<unsigned>(seed));
    std::normal_distribution<double> noise(0.0, 1.0);
    auto p = makePredictor(name, 2, params.values().empty() ? paperEraParams(name) : params);
    for (int k = 0; k + horizon <= K; ++k) {
      const double t = k * kPeriodS;
      Eigen::Vector2d z = traj(t);
      z(0) += noise(rng);
      z(1) += noise(rng);
      p->update(t, z);
      const double tp = (k + horizon) * kPeriodS;
      const Eigen::Vector2d e = p->predictPositions(tp) - traj(tp);
      signed_err[static_cast<size_t>(k + horizon)] += e.dot(dir) / seeds;
      abs_err[static_cast<size_t>(k + horizon)] += e.norm() / seeds;
    }
  }
  ScenarioFigures f;
  const int k0 = t_change_s > 0.0 ? static_cast<int>(std::lround(t_change_s / kPeriodS)) + 1 : 1 + horizon;
  for (int k = k0; k <= K; ++k) {
    f.max_lag_px = std::max(f.max_lag_px, -signed_err[static_cast<size_t>(k)]);
    f.overshoot_px = std::max(f.overshoot_px, signed_err[static_cast<size_t>(k)]);
  }
  const int k3 = std::min(K, k0 + 30);
  for (int k = k0; k <= k3; ++k) f.mean_after_px += abs_err[static_cast<size_t>(k)] / (k3 - k0 + 1);
  const int kf = static_cast<int>(0.8 * K);
  for (int k = kf; k <= K; ++k) f.final_px += abs_err[static_cast<size_t>(k)] / (K - kf + 1);
  return f;
}

void report(const std::string& scenario, const std::string& name, const ScenarioFigures& f) {
  std::printf("[ figures  ] %-28s %-13s max_lag %6.2f  overshoot %5.2f  mean_3s %5.2f  final %5.2f px\n",
              scenario.c_str(), name.c_str(), f.max_lag_px, f.overshoot_px, f.mean_after_px, f.final_px);
}

const std::vector<std::string> kCompared = {"kf-cv", "fakf-classic", "fakf"};

TEST(FakfScenarios, E1LineE2AccelJumpE3Zigzag) {
  // E1-E3 (docs/MODELS.md §10; data/scenarios/e1-line.yaml ...): E1 line v = (10, 10) px/s; E2 v0 = (20, 20), a = (1, 1) jumping to (30, 30) px/s^2
  // at 14 s; E3 vx = 1, vy = 10 switching to -10 px/s at 9 s. One frame ahead, 20 seeds.
  struct Case {
    std::string id;
    Trajectory traj;
    double duration_s, t_change_s;
    Eigen::Vector2d dir;
  };
  const std::vector<Case> cases = {
      {"E1 line", [](double t) { return Eigen::Vector2d(10.0 * t, 10.0 * t); }, 20.0, 0.0,
       Eigen::Vector2d(1.0, 1.0).normalized()},
      {"E2 accel-jump",
       [](double t) {
         const double d = t - 14.0;
         const double p = t < 14.0 ? 20.0 * t + 0.5 * t * t : 378.0 + 34.0 * d + 15.0 * d * d;
         return Eigen::Vector2d(p, p);
       },
       20.0, 14.0, Eigen::Vector2d(1.0, 1.0).normalized()},
      {"E3 zigzag", [](double t) { return Eigen::Vector2d(t, t < 9.0 ? 10.0 * t : 180.0 - 10.0 * t); }, 18.0, 9.0,
       Eigen::Vector2d(0.0, -1.0)},
  };
  for (const Case& c : cases) {
    std::map<std::string, ScenarioFigures> fig;
    for (const auto& name : kCompared) {
      fig[name] = runScenario(name, c.traj, c.duration_s, c.t_change_s, c.dir, 1, 20);
      report(c.id, name, fig[name]);
    }
    // THEN (measured, not the paper's claim): the CS-based fakf ends with the smallest error on
    // all three (E2: the CV models keep a constant lag under constant acceleration). Its reaction
    // right after a change is NOT the fastest: on E2/E3 its largest lag exceeds kf-cv's (reported
    // above, not asserted), because on smooth motion its CS variance sits on its floor.
    // Measured final errors kf-cv / fakf-classic / fakf: E1 1.13 / 1.14 / 0.93, E2 2.24 / 2.35 /
    // 1.02, E3 1.13 / 1.13 / 0.91 px.
    EXPECT_LT(fig["fakf"].final_px, 0.9 * fig["kf-cv"].final_px) << c.id;
    EXPECT_LT(fig["fakf"].final_px, 0.9 * fig["fakf-classic"].final_px) << c.id;
  }
}

/// Final error of the three predictors on a circle of radius_px at omega_rad_s, predicted
/// `horizon` frames ahead, over 1.5 revolutions, 5 seeds.
std::map<std::string, double> circleFinalErrors(double radius_px, double omega_rad_s, int horizon) {
  const Trajectory circle = [=](double t) {
    return Eigen::Vector2d(100.0 + radius_px * std::cos(omega_rad_s * t), 150.0 + radius_px * std::sin(omega_rad_s * t));
  };
  const double duration_s = 1.5 * 2.0 * M_PI / omega_rad_s;
  std::map<std::string, double> out;
  for (const auto& name : kCompared) {
    const ScenarioFigures f = runScenario(name, circle, duration_s, 0.0, Eigen::Vector2d(1.0, 0.0), horizon, 5);
    out[name] = f.final_px;
    report("E4 circle r" + std::to_string(static_cast<int>(radius_px)) + " h" + std::to_string(horizon), name, f);
  }
  return out;
}

TEST(FakfScenarios, E4CircleHeadline) {
  // GIVEN the paper's literal set-up: radius 20 px, omega 0.15 rad/s, one frame (0.1 s) ahead
  const auto literal = circleFinalErrors(20.0, 0.15, 1);
  // THEN every predictor is within about 1 px (docs/MODELS.md §11) and fakf is the best: measured
  // kf-cv 1.08, fakf-classic 1.10, fakf 0.91 px (paper: ~8 / ~4 / ~2 px, another set-up).
  // fakf inherits cs-akf-adaptive's defaults; its CS variance floor decides the smooth-motion
  // error (with sigma_min_sq = 1 instead of the default 10, fakf measures 0.70 px here).
  EXPECT_LT(literal.at("kf-cv"), 1.5);
  EXPECT_LT(literal.at("fakf"), 0.9 * literal.at("kf-cv"));
  EXPECT_LT(literal.at("fakf"), 0.9 * literal.at("fakf-classic"));

  // GIVEN the separating set-up: radius 200 px (a closer or larger target), same omega, predicted
  // 5 frames (0.5 s) ahead, as a servo loop with a 0.5 s delay needs
  const auto far = circleFinalErrors(200.0, 0.15, 5);
  // THEN fakf is clearly ahead (measured kf-cv 2.46, fakf-classic 2.51, fakf 1.89 px; 1.30 with
  // sigma_min_sq = 1), and the
  // classic FAKF does NOT beat the plain KF, unlike in the paper: its R adaptation only adds a
  // little noise to a CV filter whose error is dominated by the model
  EXPECT_LT(far.at("fakf"), 0.85 * far.at("kf-cv"));
  EXPECT_LT(far.at("fakf"), 0.85 * far.at("fakf-classic"));
  EXPECT_GT(far.at("fakf-classic"), 0.97 * far.at("kf-cv"));
  EXPECT_GT(far.at("kf-cv"), literal.at("kf-cv"));  // the set-up does separate more
}

}  // namespace
}  // namespace predvs
