// Noise models: statistics per model, seeding, rounding.
#include "predvs/servo/noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace predvs {
namespace {

constexpr int kSamples = 200000;
// Sample mean of n draws has std sigma / sqrt(n) ~ 0.0045 sigma: 5 standard errors.
constexpr double kMeanTol = 0.025;
// Relative error of the sample standard deviation ~ 1/sqrt(2n) ~ 0.0016: a 1 % band.
constexpr double kStdRelTol = 0.01;

struct Stats {
  double mean, std, min, max;
};

Stats draw(NoiseModel& m) {
  double s = 0, s2 = 0, lo = 1e300, hi = -1e300;
  for (int i = 0; i < kSamples; ++i) {
    const double x = m.apply(0.0);
    s += x;
    s2 += x * x;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  const double mean = s / kSamples;
  return {mean, std::sqrt(s2 / kSamples - mean * mean), lo, hi};
}

TEST(Noise, GaussianHasRequestedSigma) {
  NoiseModel m({NoiseKind::Gaussian, 2.0, false}, 7);
  const Stats st = draw(m);
  EXPECT_NEAR(st.mean, 0.0, kMeanTol * 2.0);
  EXPECT_NEAR(st.std / 2.0, 1.0, kStdRelTol);
  EXPECT_DOUBLE_EQ(m.standardDeviation(), 2.0);
}

TEST(Noise, UniformIsSigmaTimesTwoWMinusOne) {
  // GIVEN paper 001's n = sigma (2 w - 1)
  NoiseModel m({NoiseKind::Uniform, 10.0, false}, 7);
  const Stats st = draw(m);
  // THEN n is bounded by sigma with standard deviation sigma / sqrt(3)
  EXPECT_GE(st.min, -10.0);
  EXPECT_LE(st.max, 10.0);
  EXPECT_GT(st.max, 9.9);
  EXPECT_NEAR(st.mean, 0.0, kMeanTol * 10.0);
  EXPECT_NEAR(st.std / (10.0 / std::sqrt(3.0)), 1.0, kStdRelTol);
  EXPECT_NEAR(m.standardDeviation(), 10.0 / std::sqrt(3.0), 1e-12);
}

TEST(Noise, NoneAndRounding) {
  NoiseModel none({NoiseKind::None, 3.0, false}, 1);
  EXPECT_EQ(none.apply(1.25), 1.25);
  NoiseModel rounded({NoiseKind::Gaussian, 3.0, true}, 1);
  for (int i = 0; i < 100; ++i) {
    const double x = rounded.apply(100.3);
    EXPECT_EQ(x, std::round(x));
  }
}

TEST(Noise, SameSeedSameSequenceDifferentSeedDifferent) {
  NoiseModel a({NoiseKind::Gaussian, 1.0, false}, 42), b({NoiseKind::Gaussian, 1.0, false}, 42),
      c({NoiseKind::Gaussian, 1.0, false}, 43);
  bool differs = false;
  for (int i = 0; i < 50; ++i) {
    const double x = a.sample();
    EXPECT_EQ(x, b.sample());
    differs |= x != c.sample();
  }
  EXPECT_TRUE(differs);
}

TEST(Noise, ConfigByNameAndErrors) {
  const NoiseConfig c = makeNoiseConfig("uniform", Params{{"sigma", 4}, {"round", 1}});
  EXPECT_EQ(c.kind, NoiseKind::Uniform);
  EXPECT_EQ(c.sigma, 4.0);
  EXPECT_TRUE(c.round_to_integer);
  EXPECT_THROW(makeNoiseConfig("laplace"), std::invalid_argument);
  EXPECT_THROW(makeNoiseConfig("gaussian", Params{{"sigmaa", 1}}), std::invalid_argument);
  EXPECT_THROW(NoiseModel({NoiseKind::Gaussian, -1.0, false}, 1), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
