// The feed-forward's velocity (Predictor::feedforwardVelocity(); channel_predictor.h, "The
// feed-forward's velocity"; docs/MODELS.md §15): the velocity the servo loop feeds a law forward,
// judged on low-passed steps instead of the blend's one- and two-frame forecasts. A slow ramp under
// noise, where the blend hands out a velocity of about 0, keeps its velocity here, and the velocity
// is not weighted by its significance; without the blend and the weighting it is predictVelocity()'s
// number; the glitch gate and imm hand out their own.
#include "predvs/predictors/params.h"
#include "predvs/predictors/predictor.h"

#include <Eigen/Core>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace predvs {
namespace {

// A 5 px/s ramp at 25 Hz under 1 px of Gaussian noise, 40 s: 0.2 px a frame, a fifth of the noise
// (e5-line's leader seen by its follower, docs/MODELS.md §10 E5).
constexpr double kRateHz = 25.0;
constexpr double kSpeedPxS = 5.0;
constexpr double kNoisePx = 1.0;
constexpr double kDurationS = 40.0;
constexpr double kWarmUpS = 10.0;  // the means below are over the rest of the track
constexpr int kHorizonFrames = 3;  // e5's 120 ms from acquisition to motion

/// The mean over the track after kWarmUpS of the velocity `p` hands out 3 frames ahead of every
/// frame: feedforwardVelocity() with `feedforward`, predictVelocity() without.
struct MeanVelocities {
  double blended = 0.0, feedforward = 0.0;
};

MeanVelocities onTheRamp(const std::string& name, const Params& params, unsigned seed) {
  std::unique_ptr<Predictor> p = makePredictor(name, 1, params);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, kNoisePx);
  const double dt = 1.0 / kRateHz;
  MeanVelocities m;
  int n = 0;
  Eigen::VectorXd z(1);
  for (int k = 0; k * dt < kDurationS; ++k) {
    const double t = k * dt;
    z(0) = kSpeedPxS * t + noise(rng);
    p->update(t, z);
    if (t < kWarmUpS) continue;
    m.blended += p->predictVelocity(0, t + kHorizonFrames * dt);
    m.feedforward += p->feedforwardVelocity(0, t + kHorizonFrames * dt);
    ++n;
  }
  m.blended /= n;
  m.feedforward /= n;
  return m;
}

TEST(FeedforwardVelocity, KeepsTheVelocityOfASlowRampThatTheBlendScalesToNothing) {
  for (unsigned seed : {1u, 2u, 3u}) {
    // GIVEN kf-cv and cs-akf with their defaults on a 5 px/s ramp under 1 px of noise at 25 Hz
    for (const char* name : {"kf-cv", "cs-akf"}) {
      // WHEN they are asked for velocities 3 frames ahead
      const MeanVelocities m = onTheRamp(name, {}, seed);
      // THEN the forecast's velocity is scaled towards hold's 0 (measured 0.00 for both), while the
      // feed-forward's keeps the ramp's 5 px/s on average (measured 4.93 and 4.96 at seed 1)
      EXPECT_LT(m.blended, 0.2 * kSpeedPxS) << name << " seed " << seed;
      EXPECT_NEAR(m.feedforward, kSpeedPxS, 0.15 * kSpeedPxS) << name << " seed " << seed;
    }
  }
}

TEST(FeedforwardVelocity, IsThePredictedVelocityWhenTheBlendAndTheWeightingAreOff) {
  // GIVEN predictors with the blend and the forecast weighting off (the papers' scenarios pin them
  // so) on a noisy ramp with a gap
  Params off;
  off.set("hold_blend_tau_s", 0.0);
  off.set("shrink_sigmas", 0.0);
  for (const char* name : {"kf-cv", "kf-ca", "cs-akf", "cs-akf-adaptive", "stkf", "st-akf", "st-akf-pm", "fakf-classic", "fakf"}) {
    std::unique_ptr<Predictor> p = makePredictor(name, 2, off);
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, kNoisePx);
    Eigen::VectorXd z(2);
    for (int k = 0; k < 300; ++k) {
      const double t = k / kRateHz;
      z(0) = kSpeedPxS * t + noise(rng);
      z(1) = k >= 100 && k < 110 ? std::nan("") : 3.0 * std::sin(t) + noise(rng);
      p->update(t, z);
      // THEN the feed-forward's velocity is predictVelocity()'s, bit for bit, now and ahead
      for (int c = 0; c < 2; ++c)
        for (double ahead : {0.0, 1.0 / kRateHz, 0.12}) {
          const double v = p->predictVelocity(c, t + ahead), f = p->feedforwardVelocity(c, t + ahead);
          ASSERT_TRUE(v == f || (std::isnan(v) && std::isnan(f))) << name << " channel " << c << " frame " << k << " +" << ahead;
        }
    }
  }
}

TEST(FeedforwardVelocity, TheVelocityIsNotWeightedByItsSignificance) {
  // GIVEN the CA-model filters with the blend off and their forecast weighting at its defaults, on
  // the slow ramp: a velocity of 5 px/s is small against its own standard deviation there, so the
  // weighting shrinks the forecast's velocity towards 0
  Params no_blend;
  no_blend.set("hold_blend_tau_s", 0.0);
  for (const char* name : {"kf-ca", "st-akf"}) {
    const MeanVelocities m = onTheRamp(name, no_blend, 1);
    // THEN the feed-forward's velocity keeps the ramp's 5 px/s (the law averages the noise out, the
    // shrink's bias would stay), the forecast's is shrunk (measured: kf-ca 4.99 and 1.37, st-akf 5.01 and 1.98)
    EXPECT_NEAR(m.feedforward, kSpeedPxS, 0.1 * kSpeedPxS) << name;
    EXPECT_LT(m.blended, 0.6 * kSpeedPxS) << name;
  }
}

TEST(FeedforwardVelocity, TheGlitchGateAndImmHandOutTheirOwn) {
  // GIVEN kf-cv behind a glitch gate, and imm, with their defaults, on the slow ramp
  Params gated;
  gated.set("glitch_sigmas", 4.0);
  // WHEN asked for the feed-forward's velocity THEN the gate passes on its filter's (not the
  // blended one; measured 4.93 px/s), and imm's mode-weighted velocity without the modes' blends
  // keeps the ramp's 5 px/s (measured 5.3) where its forecast's velocity is 0.00
  const MeanVelocities g = onTheRamp("kf-cv", gated, 1);
  EXPECT_LT(g.blended, 0.2 * kSpeedPxS);
  EXPECT_NEAR(g.feedforward, kSpeedPxS, 0.15 * kSpeedPxS);
  const MeanVelocities imm = onTheRamp("imm", {}, 1);
  EXPECT_LT(imm.blended, 0.2 * kSpeedPxS);
  EXPECT_GT(imm.feedforward, 0.5 * kSpeedPxS);
}

}  // namespace
}  // namespace predvs
