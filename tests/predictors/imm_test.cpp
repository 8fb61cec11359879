// imm (predictors/imm.h): mode probabilities, and the two limits of the mixture.
#include "predvs/predictors/imm.h"
#include "predvs/predictors/noise_estimate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <random>

namespace predvs {
namespace {

TEST(Imm, ModeProbabilitiesFollowTheMotion) {
  // GIVEN a target moving at constant velocity for 4 s, then accelerating at 400 px/s^2 for 1 s,
  // 30 Hz, 0.5 px noise; THEN the CA probability is low on the straight part and rises during the
  // acceleration, and the probabilities of each channel sum to one.
  ImmPredictor imm(1, Params{{"r", 0.25}});
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 0.5);
  double mu_ca_straight = 0.0, mu_ca_accel = 0.0;
  int n_straight = 0, n_accel = 0;
  for (int k = 0; k <= 150; ++k) {
    const double t = k / 30.0;
    const double p = t <= 4.0 ? 50.0 * t : 200.0 + 50.0 * (t - 4.0) + 200.0 * (t - 4.0) * (t - 4.0);
    Eigen::VectorXd z(1);
    z << p + n(rng);
    imm.update(t, z);
    EXPECT_NEAR(imm.modeProbability(0, 0) + imm.modeProbability(0, 1), 1.0, 1e-12);
    if (t > 2.0 && t <= 4.0) {
      mu_ca_straight += imm.modeProbability(0, 1);
      ++n_straight;
    }
    if (t > 4.3) {
      mu_ca_accel += imm.modeProbability(0, 1);
      ++n_accel;
    }
  }
  mu_ca_straight /= n_straight;
  mu_ca_accel /= n_accel;
  EXPECT_LT(mu_ca_straight, 0.35);
  EXPECT_GT(mu_ca_accel, 0.6);
  EXPECT_GT(mu_ca_accel, 2.0 * mu_ca_straight);
  const NamedValues d = imm.diagnostics();
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].first, "mu_ca_0");
  EXPECT_EQ(d[0].second, imm.modeProbability(0, 1));
}

TEST(Imm, PredictionIsConstAndBetweenItsModes) {
  ImmPredictor imm(2, Params{});
  Eigen::Vector2d z;
  for (int k = 0; k < 40; ++k) {
    z << 3.0 * k + 0.1 * k * k, -2.0 * k;
    imm.update(k * 0.05, z);
  }
  const ChannelEstimate a = imm.predict(0, imm.time() + 0.1);
  const ChannelEstimate b = imm.predict(0, imm.time() + 0.1);
  EXPECT_EQ(a.x(0), b.x(0));
  EXPECT_EQ(a.x.size(), 3);
  EXPECT_GT(a.P(0, 0), 0.0);
  EXPECT_TRUE(imm.innovation(0).valid);
  EXPECT_GT(imm.innovation(0).S, 0.0);
}

TEST(StartupNoiseEstimator, RecoversNoiseOnAcceleratingMotionAndIgnoresAJump) {
  // GIVEN a constant-acceleration motion with a jump of the acceleration (a jerk spike) and 2 px
  // noise at 30 Hz; THEN the frozen estimate (50 differences) is within a factor 0.4..1.6 of
  // 4 px^2 on every seed (its spread over seeds is about +-30 %: 53 frames of noise hold little
  // information), and unbiased: the median over 10 seeds is within 15 %.
  std::vector<double> ratios;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n(0.0, 2.0);
    StartupNoiseEstimator e;
    for (int k = 0; k < 60; ++k) {
      const double t = k / 30.0;
      // position and velocity continuous at 0.4 s, acceleration 100 -> -800 px/s^2
      const double p = t < 0.4 ? 10.0 + 40.0 * t + 50.0 * t * t
                               : 10.0 + 40.0 * 0.4 + 50.0 * 0.16 + 80.0 * (t - 0.4) - 400.0 * (t - 0.4) * (t - 0.4);
      e.push(t, p + n(rng));
    }
    EXPECT_TRUE(e.done());
    EXPECT_NEAR(e.variance() / 4.0, 1.0, 0.6) << "seed " << seed;
    ratios.push_back(e.variance() / 4.0);
  }
  std::sort(ratios.begin(), ratios.end());
  EXPECT_NEAR(0.5 * (ratios[4] + ratios[5]), 1.0, 0.15);
}

TEST(StartupNoiseEstimator, UsesThePriorUntilEnoughDifferencesAndSkipsGaps) {
  StartupNoiseEstimator e(1.0, 20, 5);  // count 20 here: the test only needs a few
  for (int k = 0; k < 7; ++k) e.push(k * 0.1, k % 2 == 0 ? 3.0 : -3.0);
  EXPECT_EQ(e.variance(), 1.0);  // 4 differences so far
  e.push(0.7, 3.0);
  EXPECT_GT(e.variance(), 1.0);
  e.push(0.8, std::numeric_limits<double>::quiet_NaN());  // gap: next three samples start a new run
  const double before = e.variance();
  e.push(0.9, 100.0);
  e.push(1.0, -100.0);
  e.push(1.1, 100.0);
  EXPECT_EQ(e.variance(), before);
  Params p;
  EXPECT_TRUE(isAutoMeasurementNoise(p));
  p.set("r", 2.0);
  EXPECT_FALSE(isAutoMeasurementNoise(p));
  Params w;
  w.setText("r", "often");
  EXPECT_THROW(isAutoMeasurementNoise(w), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
