#include "predvs/predictors/kalman_baselines.h"

#include <gtest/gtest.h>

namespace predvs {
namespace {

// Tolerance for closed-form arithmetic on O(1) numbers.
constexpr double kTol = 1e-12;

TEST(KfCv, OneStepMatchesClosedForm) {
  // GIVEN a CV filter initialised at z0 = 2 with P0 = diag(r, p0v)
  const double r = 0.5, q = 3.0, p0v = 10.0, T = 0.1;
  KfCvPredictor kf(1, {{"r", r}, {"q", q}, {"p0_vel", p0v}});
  Eigen::VectorXd z(1);
  z << 2.0;
  kf.update(0.0, z);
  // WHEN a second measurement arrives after T
  z << 2.5;
  kf.update(T, z);
  // THEN the state equals the hand-derived KF step
  const double P00 = r + T * T * p0v + q * T * T * T / 3.0;
  const double P01 = T * p0v + q * T * T / 2.0;
  const double P11 = p0v + q * T;
  const double S = P00 + r;
  const double eps = 2.5 - 2.0;
  const auto& g = kf.gaussian(0);
  EXPECT_NEAR(g.x(0), 2.0 + P00 / S * eps, kTol);
  EXPECT_NEAR(g.x(1), 0.0 + P01 / S * eps, kTol);
  EXPECT_NEAR(g.P(0, 0), P00 - P00 * P00 / S, kTol);
  EXPECT_NEAR(g.P(0, 1), P01 - P00 * P01 / S, kTol);
  EXPECT_NEAR(g.P(1, 1), P11 - P01 * P01 / S, kTol);
  EXPECT_NEAR(kf.innovation(0).eps, eps, kTol);
  EXPECT_NEAR(kf.innovation(0).S, S, kTol);
}

TEST(Hold, ReturnsLastMeasurement) {
  HoldPredictor hold(2, {});
  Eigen::VectorXd z(2);
  z << 1.0, 2.0;
  hold.update(0.0, z);
  z << 3.0, std::numeric_limits<double>::quiet_NaN();
  hold.update(0.1, z);
  EXPECT_EQ(hold.predict(0, 5.0).position(), 3.0);
  EXPECT_EQ(hold.predict(1, 5.0).position(), 2.0);
}

}  // namespace
}  // namespace predvs
