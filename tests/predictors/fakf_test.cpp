// Tests of the fuzzy adaptive Kalman filters (METHODS §3): R adaptation follows the real noise,
// R stays inside [r_min, r_max], P inflation fires on a manoeuvre, and the E4 circle ranking.
#include "predvs/predictors/fakf.h"
#include "predvs/predictors/predictor.h"

#include <gtest/gtest.h>

#include <cmath>
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

TEST(FakfClassic, RaisesRWhenTheNoiseIsLargerThanAssumed) {
  // GIVEN an assumed R = 1 px^2 and a real noise variance of 9 px^2
  FakfClassicPredictor f(1, {{"r", 1.0}});
  // WHEN it filters 30 s of a noisy ramp
  runRamp(f, 3.0, 300, 11);
  // THEN R has grown well above its initial value (it wanders around the true 9 px^2; 3 is a
  // margin far outside what an unadapted R = 1 could show)
  EXPECT_GT(f.adaptedR(0), 3.0);
}

TEST(FakfClassic, LowersRWhenTheNoiseIsSmallerThanAssumed) {
  // GIVEN an assumed R = 1 px^2 and a real noise variance of 0.09 px^2
  FakfClassicPredictor f(1, {{"r", 1.0}});
  // WHEN it filters 30 s of a noisy ramp
  runRamp(f, 0.3, 300, 12);
  // THEN R has come down by more than half (dR is bounded per frame, so it descends slowly)
  EXPECT_LT(f.adaptedR(0), 0.5);
}

TEST(FakfClassic, RStaysInsideItsClampUnderOutliers) {
  // GIVEN tight bounds on R and a sequence of wild measurements (1e6 px jumps)
  FakfClassicPredictor f(1, {{"r", 1.0}, {"r_min", 0.5}, {"r_max", 2.0}, {"dr_max", 100.0}});
  Eigen::VectorXd z(1);
  for (int k = 0; k < 200; ++k) {
    z(0) = (k % 7 == 0) ? 1e6 * ((k % 2) ? 1.0 : -1.0) : 0.0;
    f.update(k * kPeriodS, z);
    // THEN R stays finite and inside [r_min, r_max], and so does the state
    ASSERT_GE(f.adaptedR(0), 0.5);
    ASSERT_LE(f.adaptedR(0), 2.0);
    ASSERT_TRUE(std::isfinite(f.gaussian(0).x(0)));
  }
}

TEST(FakfClassic, ResetRestoresTheInitialR) {
  FakfClassicPredictor f(1, {{"r", 1.0}});
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

}  // namespace
}  // namespace predvs
