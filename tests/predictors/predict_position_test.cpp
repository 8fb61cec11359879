// Predictor::predictPosition (and predictPositions into a buffer) is predict(c, t).position()
// bit for bit, and predictVelocity (and predictVelocities) predict(c, t).velocity(), for every
// registered predictor (issue 11 item 8: the per-channel filters skip the covariance there; the
// servo loop asks for velocities every tick). The suite is instantiated over predictorRegistry(),
// so a new predictor, or a new override of predict() without one of predictPosition() or
// predictVelocity(), is caught here.
#include "predvs/predictors/predictor.h"
#include "predvs/predictors/stkf.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Same bits (every NaN equal to every NaN): the same arithmetic must give the same doubles.
bool sameBits(double a, double b) {
  if (std::isnan(a) && std::isnan(b)) return true;
  return std::memcmp(&a, &b, sizeof a) == 0;
}

class PredictPosition : public ::testing::TestWithParam<std::string> {};

TEST_P(PredictPosition, EqualsThePositionOfPredictBitForBit) {
  // GIVEN a 4-channel predictor fed 600 noisy frames at a jittered 30 Hz, 5 % entries missing and
  // one whole frame missing in 50
  auto p = makePredictor(GetParam(), 4);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.5);
  Eigen::VectorXd z(4), x(4);
  double t = 0.0;
  for (int k = 0; k < 600; ++k) {
    // WHEN it is asked, after every update, for the positions at several horizons (0, fractional,
    // the frame period, 2 frames, 1 s) and before its first update
    for (double h : {0.0, 0.01, 1.0 / 30.0, 2.0 / 30.0, 1.0}) {
      p->predictPositions(t + h, x);
      const Eigen::VectorXd y = p->predictPositions(t + h);
      const Eigen::VectorXd v = p->predictVelocities(t + h);
      for (int c = 0; c < 4; ++c) {
        const ChannelEstimate e = p->predict(c, t + h);
        const double expected = e.position();
        // THEN every form gives the bits of predict().position(), and of its velocity()
        ASSERT_TRUE(sameBits(p->predictPosition(c, t + h), expected)) << GetParam() << " frame " << k << " h " << h;
        ASSERT_TRUE(sameBits(x(c), expected)) << GetParam() << " frame " << k;
        ASSERT_TRUE(sameBits(y(c), expected)) << GetParam() << " frame " << k;
        ASSERT_TRUE(sameBits(p->predictVelocity(c, t + h), e.velocity())) << GetParam() << " frame " << k << " h " << h;
        ASSERT_TRUE(sameBits(v(c), e.velocity())) << GetParam() << " frame " << k;
      }
    }
    t += (1.0 + 0.2 * (2.0 * uni(rng) - 1.0)) / 30.0;
    for (int c = 0; c < 4; ++c) {
      const double truth = 200.0 + 100.0 * std::sin(0.5 * t + c) + 40.0 * std::sin(2.3 * t);
      z(c) = uni(rng) < 0.05 ? kNaN : truth + noise(rng);
    }
    if (k % 50 == 49)
      p->update(t);
    else
      p->update(t, z);
  }
}

INSTANTIATE_TEST_SUITE_P(AllPredictors, PredictPosition, ::testing::ValuesIn([] {
                           std::vector<std::string> names;
                           for (const auto& info : predictorRegistry()) names.push_back(info.name);
                           return names;
                         }()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string s;
                           for (char ch : info.param) s += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                           return s;
                         });

TEST(PredictPosition, StkfKnownImageVelocityIsIncluded) {
  // GIVEN two stkf fed the same frames, one with a known image velocity set for its next update
  StkfPredictor p(2, Params{}), twin(2, Params{});
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector2d z(100.0 + k, 50.0 - k);
    p.update(k / 30.0, z);
    twin.update(k / 30.0, z);
  }
  const Eigen::Vector2d v(30.0, -60.0);
  p.setKnownImageVelocity(v);
  // WHEN they predict 0.1 s ahead THEN the position includes dt * v, as predict() does
  const double t = 19 / 30.0 + 0.1, dt = t - p.time();
  for (int c = 0; c < 2; ++c) {
    EXPECT_TRUE(sameBits(p.predictPosition(c, t), p.predict(c, t).position()));
    EXPECT_TRUE(sameBits(p.predictPosition(c, t), twin.predictPosition(c, t) + dt * v(c)));
    // and the velocity is the filter's own, as predict()'s is (the known velocity moves the position only)
    EXPECT_TRUE(sameBits(p.predictVelocity(c, t), p.predict(c, t).velocity()));
    EXPECT_TRUE(sameBits(p.predictVelocity(c, t), twin.predictVelocity(c, t)));
  }
}

TEST(PredictPosition, BufferOfTheWrongSizeIsRejected) {
  auto p = makePredictor("kf-cv", 2);
  Eigen::VectorXd x(3);
  EXPECT_THROW(p->predictPositions(0.0, x), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
