// The cap on extrapolations the track has not shown (channel_predictor.h, `extrapolation_cap`,
// default 4; docs/MODELS.md §15, docs/PERFORMANCE.md "A recorded track at other frame rates"): a
// slow target whose image steps once by 15 px in one frame (a camera bumped, a frame the recording
// skipped; mire-2 has such steps), seen at 10 Hz and scored 2 frames ahead. Without the cap the
// filters with an acceleration state extrapolate the step over the horizon and lose to hold on the
// whole track; with it they do not. (imm is not in the first test: its constant-position and
// constant-velocity modes take such a step without the cap, x0.98 of hold either way; its cap
// pays on the second generator's dashes, docs/PERFORMANCE.md.)
#include "predvs/predictors/glitch_gate.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/maneuver_tracks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace predvs {
namespace {

constexpr double kRateHz = 10.0;
constexpr double kHorizonS = 0.2;  // 2 frames
constexpr double kStepS = 15.0;    // the image steps between the frames at 14.9 and 15 s

/// 30 s at 10 Hz of a slow sway (at most about 6 px/s) with 0.2 px of noise, and a step of
/// (12, -9) px at kStepS that stays.
ManeuverTrack steppedSway(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.2);
  ManeuverTrack tr;
  for (int k = 0; k < static_cast<int>(30.0 * kRateHz); ++k) {
    const double t = k / kRateHz;
    const bool after = t >= kStepS - 1e-9;
    const double u = 320.0 + 20.0 * std::sin(2.0 * M_PI * 0.05 * t) + (after ? 12.0 : 0.0);
    const double v = 240.0 + 15.0 * std::cos(2.0 * M_PI * 0.04 * t) - (after ? 9.0 : 0.0);
    tr.t_s.push_back(t);
    tr.u_true_px.push_back(u);
    tr.v_true_px.push_back(v);
    tr.u_px.push_back(u + noise(rng));
    tr.v_px.push_back(v + noise(rng));
  }
  return tr;
}

/// The distance (px) of the forecast made on the step's frame from the truth kHorizonS later.
double errorOfTheForecastAtTheStep(const ManeuverTrack& tr, Predictor& p) {
  p.reset();
  for (size_t k = 0; k < tr.t_s.size(); ++k) {
    p.update(tr.t_s[k], Eigen::Vector2d(tr.u_px[k], tr.v_px[k]));
    if (tr.t_s[k] >= kStepS - 1e-9) {
      const size_t later = k + static_cast<size_t>(std::lround(kHorizonS * kRateHz));
      return std::hypot(p.predictPosition(0, tr.t_s[later]) - tr.u_true_px[later],
                        p.predictPosition(1, tr.t_s[later]) - tr.v_true_px[later]);
    }
  }
  return NAN;
}

TEST(ExtrapolationCap, AOneFrameStepOfASlowTargetIsNotExtrapolatedOverTheHorizon) {
  int free_losses = 0, pairs = 0;
  for (const unsigned seed : {1u, 2u, 3u}) {
    // GIVEN a slow sway at 10 Hz that steps by 15 px in one frame
    const ManeuverTrack tr = steppedSway(seed);
    auto hold = makePredictor("hold", 2);
    const double hold_px = scoreOnTrack(tr, *hold, kHorizonS).rmse_truth_px;
    for (const char* name : {"kf-ca", "cs-akf-adaptive", "fakf", "st-akf"}) {
      // WHEN the filter runs with its defaults and without the cap (extrapolation_cap 0), and with
      // the glitch gate of `predvs track` (glitch_gate.h: it doubts the step, below)
      auto capped = makePredictor(name, 2);
      auto free = makePredictor(name, 2, {{"extrapolation_cap", 0.0}});
      auto gated = makePredictor(name, 2, {{"glitch_sigmas", kTrackerGlitchSigmas}});
      const double capped_px = scoreOnTrack(tr, *capped, kHorizonS).rmse_truth_px;
      const double free_px = scoreOnTrack(tr, *free, kHorizonS).rmse_truth_px;
      const double capped_step = errorOfTheForecastAtTheStep(tr, *capped);
      const double free_step = errorOfTheForecastAtTheStep(tr, *free);
      const double gated_px = scoreOnTrack(tr, *gated, kHorizonS).rmse_truth_px;
      std::printf("[ step #%u ] %s / hold: %.3f without the cap %.3f (with the glitch gate %.3f); forecast at the step %.1f px off, without %.1f\n",
                  seed, name, capped_px / hold_px, free_px / hold_px, gated_px / hold_px, capped_step, free_step);
      // THEN with the cap the forecast made on the step's frame stays within a few noise levels of
      // the target (measured 0.6-1.8 px; without the cap 1.8-57 px) and the filter beats hold on
      // the track
      EXPECT_LT(capped_step, 2.5) << name << " #" << seed;
      EXPECT_LE(capped_step, free_step + 1e-9) << name << " #" << seed;
      EXPECT_LT(capped_px, hold_px) << name << " #" << seed;
      // AND with the glitch gate the forecast made on the step's frame is
      // halfway to the line the track was on (a glitch is as likely as a step until the track has
      // shown either): the one forecast costs the track up to 2 % against hold (measured x0.990-1.018),
      // docs/PERFORMANCE.md "Tracker glitches"
      EXPECT_GT(errorOfTheForecastAtTheStep(tr, *gated), 4.0) << name << " #" << seed;
      EXPECT_LT(gated_px, 1.02 * hold_px) << name << " #" << seed;
      free_losses += free_px > hold_px;
      ++pairs;
    }
  }
  // and without it (nearly) every filter loses to hold (measured: 11 of the 12, x0.98-2.30)
  EXPECT_GE(free_losses, pairs - 2);
}

TEST(ExtrapolationCap, ASteadyMotionIsNotCapped) {
  // GIVEN a noise-free sway at 10 Hz without a step, whose extrapolations keep to the rates the
  // track has shown
  ManeuverTrack tr = steppedSway(1);
  for (size_t k = 0; k < tr.t_s.size(); ++k) {
    const double t = tr.t_s[k];
    tr.u_px[k] = tr.u_true_px[k] = 320.0 + 20.0 * std::sin(2.0 * M_PI * 0.05 * t);
    tr.v_px[k] = tr.v_true_px[k] = 240.0 + 15.0 * std::cos(2.0 * M_PI * 0.04 * t);
  }
  for (const char* name : {"kf-cv", "kf-ca", "cs-akf-adaptive", "stkf", "imm"}) {
    // WHEN the filter runs with its defaults and without the cap
    auto capped = makePredictor(name, 2);
    auto free = makePredictor(name, 2, {{"extrapolation_cap", 0.0}});
    // THEN every forecast is the same bits
    for (size_t k = 0; k + 2 < tr.t_s.size(); ++k) {
      const Eigen::Vector2d z(tr.u_px[k], tr.v_px[k]);
      capped->update(tr.t_s[k], z);
      free->update(tr.t_s[k], z);
      for (int c = 0; c < 2; ++c)
        ASSERT_EQ(capped->predictPosition(c, tr.t_s[k + 2]), free->predictPosition(c, tr.t_s[k + 2]))
            << name << " at t = " << tr.t_s[k] << ", channel " << c;
    }
  }
}

}  // namespace
}  // namespace predvs
