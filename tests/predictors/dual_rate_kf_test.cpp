#include "predvs/predictors/dual_rate_kf.h"
#include "predictors/eigen_test_utils.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace predvs {
namespace {

// N products of 2x2 matrices with entries up to ~1e2: round-off only.
constexpr double kModelTol = 1e-12;
// A noise-free constant-velocity channel: after 40 frames the estimate's error has decayed to
// far below this (the filter's error dynamics contract by ~0.5 per frame here).
constexpr double kTrackTol = 1e-6;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

DualRateKfConfig config(int channels, double delta = 0.01, int N = 8) {
  DualRateKfConfig c;
  c.base_period_s = delta;
  c.frame_ticks = N;
  c.accel_std = Eigen::VectorXd::LinSpaced(channels, 1.0, 3.0);
  c.measurement_std = Eigen::VectorXd::Constant(channels, 1e-3);
  c.initial_velocity_std = Eigen::VectorXd::Constant(channels, 10.0);
  return c;
}

TEST(DualRateKf, OneLiftedPredictionIsNBasePeriodsOfTheModel) {
  // GIVEN a filter initialised on one frame and then updated once (a non-trivial P)
  const double delta = 0.01;
  const int N = 8;
  DualRateKf kf(config(2, delta, N));
  kf.update(Eigen::Vector2d(0.1, -0.2));
  kf.predict();
  kf.update(Eigen::Vector2d(0.15, -0.1));
  const Gaussian<2> before = kf.channel(1);
  // WHEN the filter predicts one frame, and separately the base-period model (paper eq. 4) is
  // run N times with Q = sigma_a^2 B B', B = [delta^2 / 2; delta]
  kf.predict();
  Gaussian<2> brute = before;
  const Eigen::Vector2d B(delta * delta / 2, delta);
  const double sa = kf.config().accel_std(1);
  for (int i = 0; i < N; ++i) timeUpdate(brute, cvTransition(delta), Mat<2>(sa * sa * B * B.transpose()));
  // THEN the lifted step (Algorithm 2 lines 4-5) equals them
  EXPECT_TRUE(matricesNear(kf.channel(1).x, brute.x, kModelTol));
  EXPECT_TRUE(matricesNear(kf.channel(1).P, brute.P, kModelTol));
  EXPECT_TRUE(isSymmetricPsd(kf.channel(1).P, kModelTol));
}

TEST(DualRateKf, PredictsAConstantVelocityFeatureAtEveryBasePeriod) {
  // GIVEN a feature moving at 0.3 units/s, measured without noise once per frame (N = 8)
  const double delta = 0.01, v = 0.3, p0 = -0.2;
  const int N = 8;
  DualRateKf kf(config(1, delta, N));
  // WHEN 40 frames are fused
  for (int k = 0; k < 40; ++k) {
    if (k > 0) kf.predict();
    kf.update(Eigen::VectorXd::Constant(1, p0 + v * k * N * delta));
  }
  // THEN the predictions s(t+i|t) = s + i delta s_dot (Algorithm 2 line 10) are on the trajectory
  // at every base period of the coming frame and beyond it
  const double t = 39 * N * delta;
  for (int i = 0; i <= 2 * N; ++i) EXPECT_NEAR(kf.predictTicks(i)(0), p0 + v * (t + i * delta), kTrackTol) << i;
  EXPECT_NEAR(kf.velocities()(0), v, kTrackTol);
}

TEST(DualRateKf, InitialisesOnTheFirstMeasurementAndSkipsUnmeasuredChannels) {
  // GIVEN two channels, only the first measured on the first frame
  DualRateKf kf(config(2));
  kf.update(Eigen::Vector2d(1.0, kNaN));
  // THEN the first starts at its measurement with zero velocity, the second is unknown
  EXPECT_FALSE(kf.initialised());
  EXPECT_DOUBLE_EQ(kf.predictTicks(5)(0), 1.0);
  EXPECT_TRUE(std::isnan(kf.predictTicks(5)(1)));
  EXPECT_DOUBLE_EQ(kf.channel(0).P(0, 0), 1e-6);
  // WHEN a frame passes without a measurement, then the second channel is seen
  kf.predict();
  kf.update(Eigen::Vector2d(kNaN, 2.0));
  // THEN both are initialised, and predicting never changes the filter
  EXPECT_TRUE(kf.initialised());
  const Gaussian<2> g = kf.channel(0);
  (void)kf.predictTicks(100);
  EXPECT_TRUE(matricesNear(kf.channel(0).x, g.x, 0.0));
  EXPECT_TRUE(matricesNear(kf.channel(0).P, g.P, 0.0));
  EXPECT_DOUBLE_EQ(kf.predictTicks(0)(1), 2.0);
}

TEST(DualRateKf, RejectsBadConfiguration) {
  DualRateKfConfig c = config(2);
  c.frame_ticks = 0;
  EXPECT_THROW(DualRateKf{c}, std::invalid_argument);
  c = config(2);
  c.measurement_std(1) = 0.0;
  EXPECT_THROW(DualRateKf{c}, std::invalid_argument);
  c = config(2);
  c.accel_std.resize(3);
  EXPECT_THROW(DualRateKf{c}, std::invalid_argument);
  DualRateKf kf(config(2));
  EXPECT_THROW(kf.update(Eigen::VectorXd::Zero(3)), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
