// The maneuvering-track generator (servo/maneuver_tracks.h), and the test-sized version of the
// "defaults that hold" grid of issue 11: every predictor with its default parameters predicts
// better than `hold` on every generated track (the full grid: `predvs track-study`,
// docs/PERFORMANCE.md).
#include "predvs/predictors/predictor.h"
#include "predvs/servo/maneuver_tracks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

namespace predvs {
namespace {

TEST(ManeuverTracks, SameSeedSameTrackOtherSeedOtherTrack) {
  ManeuverTrackConfig c;
  c.kind = ManeuverKind::Stops;
  const ManeuverTrack a = generateManeuverTrack(c), b = generateManeuverTrack(c);
  c.seed = 2;
  const ManeuverTrack d = generateManeuverTrack(c);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.u_true_px[i], b.u_true_px[i]);
    if (std::isfinite(a.u_px[i])) {
      EXPECT_EQ(a.u_px[i], b.u_px[i]);
    }
  }
  EXPECT_NE(a.u_true_px.back(), d.u_true_px.back());
}

TEST(ManeuverTracks, RateNoiseAndDropsAreAsConfigured) {
  for (ManeuverKind kind : maneuverKinds()) {
    ManeuverTrackConfig c;
    c.kind = kind;
    c.rate_hz = 60.0;
    c.noise_px = 2.0;
    c.duration_s = 30.0;
    c.drop_prob = 0.05;
    const ManeuverTrack t = generateManeuverTrack(c);
    ASSERT_EQ(t.size(), 1801u) << maneuverKindName(kind);
    EXPECT_NEAR(t.t_s[1] - t.t_s[0], 1.0 / 60.0, 1e-12);
    double s2 = 0.0;
    int n = 0, dropped = 0;
    double max_step = 0.0;
    for (size_t i = 0; i < t.size(); ++i) {
      if (i > 0)
        max_step = std::max(max_step, std::hypot(t.u_true_px[i] - t.u_true_px[i - 1], t.v_true_px[i] - t.v_true_px[i - 1]));
      if (!std::isfinite(t.u_px[i])) {
        ++dropped;
        continue;
      }
      s2 += std::pow(t.u_px[i] - t.u_true_px[i], 2) + std::pow(t.v_px[i] - t.v_true_px[i], 2);
      n += 2;
    }
    // 3,400 samples: the sample std is within ~3 % of 2 px (5 standard errors = 6 %).
    EXPECT_NEAR(std::sqrt(s2 / n), 2.0, 0.12) << maneuverKindName(kind);
    // drop_prob 5 % plus occlusions of 6..18 frames (0.1..0.3 s at 60 Hz) starting at 1 %:
    // about 5 % + 1 % x 12 = 17 % of the frames (sampling spread: 11..24 %).
    EXPECT_GT(dropped, 0.11 * 1801) << maneuverKindName(kind);
    EXPECT_LT(dropped, 0.24 * 1801) << maneuverKindName(kind);
    // Truth is a continuous motion: no frame-to-frame jump above 400 px/s / 60 Hz (+ margin).
    EXPECT_LT(max_step, 500.0 / 60.0) << maneuverKindName(kind);
    EXPECT_TRUE(std::isfinite(t.u_px[0]));
  }
}

TEST(ManeuverTracks, RejectsBadConfigAndUnknownKind) {
  ManeuverTrackConfig c;
  c.rate_hz = 0.5;
  EXPECT_THROW(generateManeuverTrack(c), std::invalid_argument);
  c = ManeuverTrackConfig{};
  c.drop_prob = 0.9;
  EXPECT_THROW(generateManeuverTrack(c), std::invalid_argument);
  EXPECT_THROW(parseManeuverKind("spiral"), std::invalid_argument);
  EXPECT_EQ(parseManeuverKind("zigzag"), ManeuverKind::Zigzag);
}

TEST(ManeuverTracks, HoldErrorIsTheMotionOverTheHorizon) {
  // GIVEN a noise-free turns track WHEN hold predicts 2 frames ahead THEN its error vs truth is
  // about speed * horizon (80..150 px/s * 2/30 s = 5..10 px): the score is measuring the right thing.
  ManeuverTrackConfig c;
  c.noise_px = 0.0;
  c.drop_prob = 0.0;
  const ManeuverTrack t = generateManeuverTrack(c);
  auto hold = makePredictor("hold", 2);
  const TrackScore s = scoreOnTrack(t, *hold, 2.0 / 30.0);
  EXPECT_GT(s.rmse_truth_px, 5.0);
  EXPECT_LT(s.rmse_truth_px, 10.5);
  EXPECT_NEAR(s.rmse_truth_px, s.rmse_meas_px, 1e-9);
}

/// Test-sized "defaults that hold" grid: 6 kinds x {10, 60} Hz x {0.5, 3} px, 20 s, one seed.
/// Measured at this commit (ratio = RMSE vs truth / hold's, 2 frames ahead), wins out of 24:
/// the bounds below are those figures with a margin, so that a change of defaults that loses to
/// hold more often fails here. Not every predictor beats hold everywhere yet (issue 11 item 3 is
/// met on this grid by kf-cv, cs-akf, fakf-classic, stkf and imm only): the losses are bursts, zigzag and
/// hand at 10 Hz with 3 px noise, the abrupt 5000 px/s^2 starts and stops of a burst
/// (docs/PERFORMANCE.md "Defaults that hold" has the full grid).
// Measured wins: kf-ca 23, cs-akf-adaptive 19, fakf 21, st-akf 22, st-akf-pm 22 (of 24);
// kf-cv, cs-akf, fakf-classic, stkf and imm 24. Geometric-mean ratios 0.44 (imm) .. 0.59 (fakf).
const std::map<std::string, int> kMinWins = {{"kf-ca", 22}, {"cs-akf-adaptive", 18},
                                             {"st-akf", 21}, {"st-akf-pm", 21}, {"fakf", 20}};

TEST(DefaultsThatHold, PredictorsBeatHoldOnGeneratedTracks) {
  std::map<std::string, int> wins;
  std::map<std::string, double> log_ratio;
  int tracks = 0;
  for (ManeuverKind kind : maneuverKinds())
    for (double rate : {10.0, 60.0})
      for (double noise : {0.5, 3.0}) {
        ManeuverTrackConfig c;
        c.kind = kind;
        c.rate_hz = rate;
        c.noise_px = noise;
        c.duration_s = 20.0;
        c.seed = 7;
        const ManeuverTrack t = generateManeuverTrack(c);
        const double horizon = 2.0 / rate;
        auto hold = makePredictor("hold", 2);
        const double hold_rmse = scoreOnTrack(t, *hold, horizon).rmse_truth_px;
        ++tracks;
        for (const auto& info : predictorRegistry()) {
          if (info.name == "hold") continue;
          auto p = makePredictor(info.name, 2);
          const double rmse = scoreOnTrack(t, *p, horizon).rmse_truth_px;
          wins[info.name] += rmse < hold_rmse ? 1 : 0;
          log_ratio[info.name] += std::log(rmse / hold_rmse);
        }
      }
  for (const auto& [name, w] : wins) {
    const double mean_ratio = std::exp(log_ratio[name] / tracks);
    std::printf("[ defaults ] %-16s beats hold on %2d/%d tracks, geometric-mean ratio %.3f\n", name.c_str(), w, tracks,
                mean_ratio);
    if (name == "kf-cv" || name == "cs-akf" || name == "fakf-classic" || name == "stkf" || name == "imm")
      EXPECT_EQ(w, tracks) << name;
    else
      EXPECT_GE(w, kMinWins.at(name)) << name;
    EXPECT_LT(mean_ratio, 0.8) << name;
  }
}

}  // namespace
}  // namespace predvs
