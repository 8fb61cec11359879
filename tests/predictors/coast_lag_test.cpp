// A gap that begins while the last measurements fell behind the filter's motion coasts shorter
// (channel_predictor.h, `coast_lag_sigmas`, docs/MODELS.md §15): the lag score a channel keeps, a
// burst that stopped three frames before its gap, and a steady ramp into a gap, which it leaves alone.
#include "predvs/predictors/channel_predictor.h"
#include "predvs/predictors/registry.h"
#include "predictors/gap_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <utility>

namespace predvs {
namespace {

constexpr double kRateHz = 60.0;
constexpr double kDt = 1.0 / kRateHz;

TEST(CoastLag, TheLagScoreSumsTheLastFiveNormalisedInnovations) {
  // GIVEN a channel's frames with normalised innovations 9, then 1, -2, 0.5, 3, -1 (newest last;
  // each eps = 2 r with S = 4)
  CoastStop s;
  const double r[] = {9.0, 1.0, -2.0, 0.5, 3.0, -1.0};
  for (int k = 0; k < 6; ++k) s.remember(k * kDt, 0.0, 10.0, 1.0, Innovation{2.0 * r[k], 4.0, true});
  // THEN the score is the last five summed over sqrt(5): the oldest one is out
  EXPECT_NEAR(s.lagScore(), (1.0 - 2.0 + 0.5 + 3.0 - 1.0) / std::sqrt(5.0), 1e-15);
  // ... and with two frames only, the missing three count as 0
  CoastStop two;
  two.remember(0.0, 0.0, 10.0, 1.0, Innovation{2.0, 1.0, true});
  two.remember(kDt, 0.0, 10.0, 1.0, Innovation{3.0, 1.0, true});
  EXPECT_NEAR(two.lagScore(), 5.0 / std::sqrt(5.0), 1e-15);
  EXPECT_EQ(CoastStop{}.lagScore(), 0.0);
  // ... and a frame without an innovation (not valid) counts as 0
  two.remember(2 * kDt, 0.0, 10.0, 1.0, Innovation{});
  EXPECT_NEAR(two.lagScore(), 5.0 / std::sqrt(5.0), 1e-15);
}

/// The other two rules that shorten a gap's coast off, so that only the lag rule differs.
Params onlyTheLagRule(double lag_sigmas) {
  return {{"coast_fast_ratio", 0.0}, {"coast_stop_fraction", 0.0}, {"coast_lag_sigmas", lag_sigmas}};
}

/// Sum of squared 2-frame forecast errors (px^2) through a 0.3 s gap on a noise-free track: 3 s at
/// 15 px/s, a burst at 300 px/s for 0.5 s, at rest after it; the gap begins after `frames_after_stop`
/// measured frames at rest (on make-track's bursts 60 Hz 3 px #525 a burst stops three noisy frames
/// before a 23-frame gap; here, without noise, the filters take one or two frames to see it).
double gapAfterStop(const std::string& name, const Params& params, int frames_after_stop) {
  const double t_burst = 3.0, t_end = 3.5;
  const auto truth = [&](double t) {
    if (t < t_burst) return 15.0 * t;
    return 15.0 * t_burst + 300.0 * (std::min(t, t_end) - t_burst);
  };
  return gapSquaredError(name, params, truth, kRateHz, t_end + frames_after_stop * kDt, 0.3);
}

TEST(CoastLag, AGapAFrameOrTwoAfterAStopCoastsLess) {
  // (A gap on the stop's own frame has no lagging measurement to go by; once a filter's velocity
  // has turned, as kf-ca's three frames after this noise-free stop, the rule has nothing to shorten.)
  const std::pair<const char*, int> cases[] = {{"kf-cv", 1}, {"kf-ca", 1}, {"kf-ca", 2}, {"cs-akf", 2}, {"imm", 1}, {"imm", 3}};
  for (const auto& [name, frames] : cases) {
    // GIVEN the lag rule at its default and off (the other two rules off in both)
    const double with_rule = gapAfterStop(name, onlyTheLagRule(kDefaultCoastLagSigmas), frames);
    const double without = gapAfterStop(name, onlyTheLagRule(0.0), frames);
    // THEN the measurements behind the filter's forecasts shorten the coast: the forecasts through
    // the gap run on less past the stop
    EXPECT_LT(with_rule, 0.5 * without) << name << " " << frames << ": " << with_rule << " vs " << without;
  }
}

TEST(CoastLag, ASteadyRampIntoAGapIsLeftAlone) {
  for (const char* name : {"kf-cv", "kf-ca", "cs-akf", "imm"}) {
    // GIVEN an exact 200 px/s ramp at 60 Hz with a 0.3 s gap at 2 s: the filter's innovations are
    // rounding only
    const auto ramp = [](double t) { return 200.0 * t; };
    const double with_rule = gapSquaredError(name, {}, ramp, kRateHz, 2.0, 0.3);
    const double without = gapSquaredError(name, {{"coast_lag_sigmas", 0.0}}, ramp, kRateHz, 2.0, 0.3);
    // THEN the rule does not fire: the same forecasts, bit for bit
    EXPECT_EQ(std::memcmp(&with_rule, &without, sizeof with_rule), 0) << name << ": " << with_rule << " vs " << without;
  }
}

TEST(CoastLag, TheShareIsTheSmallestMeanStepMadeOverTheNewestFrames) {
  // GIVEN a channel at 10 px/s, 60 Hz (a one-frame step of 1/6 px), with its newest innovations
  const double step = 10.0 * kDt;
  const auto share = [&](std::initializer_list<double> eps_in_steps) {
    CoastStop s;
    int k = 0;
    for (double e : eps_in_steps) s.remember(k++ * kDt, 0.0, 10.0, 1.0, Innovation{e * step, 1.0, true});
    return s.lagVelocityShare();
  };
  // THEN measurements where the filter forecast them keep the whole step
  EXPECT_DOUBLE_EQ(share({0.0, 0.0, 0.0, 0.0, 0.0, 0.0}), 1.0);
  // ... each a quarter step short keeps three quarters
  EXPECT_NEAR(share({-0.25, -0.25, -0.25, -0.25, -0.25, -0.25}), 0.75, 1e-12);
  // ... a dead stop on the newest frame (a whole step short) keeps none, whatever came before
  EXPECT_DOUBLE_EQ(share({0.0, 0.0, 0.0, 0.0, 0.0, -1.0}), 0.0);
  // ... the smallest over the newest 1..5 frames: a half-step lag two frames back, none since
  EXPECT_NEAR(share({0.0, 0.0, 0.0, -1.0, 0.0, 0.0}), 1.0 - 1.0 / 3.0, 1e-12);
  // ... measurements ahead of the forecast keep the whole step (the share is at most 1)
  EXPECT_DOUBLE_EQ(share({0.5, 0.5, 0.5, 0.5, 0.5, 0.5}), 1.0);
  // ... and so does a channel with one frame, or at rest
  EXPECT_DOUBLE_EQ(share({-1.0}), 1.0);
  CoastStop rest;
  for (int k = 0; k < 6; ++k) rest.remember(k * kDt, 0.0, 0.0, 1.0, Innovation{-1.0, 1.0, true});
  EXPECT_DOUBLE_EQ(rest.lagVelocityShare(), 1.0);
}

TEST(CoastLag, TheCutGoesNoFurtherThanTheShare) {
  // GIVEN a channel at 200 px/s, 60 Hz (a step of 3.33 px), whose last five measurements each fell
  // 0.8 px short of the forecast, with S = 0.04 px^2 (a converged filter at 0.5 px): z_l = -4 sqrt 5,
  // far beyond n_l = 2, while the target kept 76 % of its step
  const double step = 200.0 * kDt;
  HoldBlend b;
  for (int k = 0; k < 6; ++k) b.recent.remember(k * kDt, 0.0, 200.0, 1.0, Innovation{-0.8, 0.04, true});
  ASSERT_NEAR(b.recent.lagScore(), -20.0 / std::sqrt(5.0), 1e-12);
  // WHEN a gap begins (the stop and speed rules off)
  const double tau = kDefaultCoastTauS;
  b.startGap(tau, 0.0, 0.0, kDefaultCoastLagSigmas, false, 1.0, 0.25);
  const double by_significance = b.gap_tau_s;
  b.startGap(tau, 0.0, 0.0, kDefaultCoastLagSigmas, true, 1.0, 0.25);
  // THEN the significance alone cuts the coast to tau (2 / |z_l|)^2 = 0.05 tau; with the share, to
  // 0.76 tau
  EXPECT_NEAR(by_significance, tau * 4.0 / (400.0 / 5.0), 1e-12);
  EXPECT_NEAR(b.gap_tau_s, tau * (1.0 - 0.8 / step), 1e-12);
  // ... and a dead stop on the newest frame (a whole step short) is cut as before
  b.recent.remember(6 * kDt, 0.0, 200.0, 1.0, Innovation{-step, 0.04, true});
  b.startGap(tau, 0.0, 0.0, kDefaultCoastLagSigmas, true, 1.0, 0.25);
  const double z_l = b.recent.lagScore();
  EXPECT_NEAR(b.gap_tau_s, tau * std::pow(kDefaultCoastLagSigmas / z_l, 2.0), 1e-12);
}

}  // namespace
}  // namespace predvs
