// The blend with hold on two horizons (channel_predictor.h, `hold_blend_frames`, default 2;
// imm.h the same): on a target that moves in short dashes seen at 10 Hz, the one-frame weight
// alone keeps the extrapolation that overshoots every dash's end two frames ahead, and the filters
// lose to hold; the smaller of the one- and the two-frame weights does not (docs/MODELS.md §15,
// docs/PERFORMANCE.md "The blend on two horizons").
#include "predvs/predictors/predictor.h"
#include "predvs/servo/maneuver_tracks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace predvs {
namespace {

/// 20 s at 10 Hz of minimum-jerk dashes (30-150 px in 0.2-0.6 s, in any direction) between rests of
/// 0.2-1.2 s, integrated at 1 kHz, with 1 px of noise: the second generator's `dash`
/// (scripts/foreign-tracks.py), written again here.
ManeuverTrack dashes(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto uniform = [&](double a, double b) { return a + (b - a) * unit(rng); };
  struct Dash {
    double t0, length, dist, angle;
  };
  std::vector<Dash> moves;
  const double duration = 20.0, rate = 10.0, sub = 1000.0;
  for (double t = 0.0; t < duration + 1.0;) {
    t += uniform(0.2, 1.2);  // rest
    const Dash d{t, uniform(0.2, 0.6), uniform(30.0, 150.0), uniform(0.0, 2.0 * M_PI)};
    moves.push_back(d);
    t += d.length;
  }
  std::normal_distribution<double> noise(0.0, 1.0);
  ManeuverTrack tr;
  double x = 320.0, y = 240.0;
  size_t m = 0;
  const int steps = static_cast<int>(duration * sub);
  for (int i = 0; i <= steps; ++i) {
    const double t = i / sub;
    if (i % static_cast<int>(sub / rate) == 0) {
      tr.t_s.push_back(t);
      tr.u_true_px.push_back(x);
      tr.v_true_px.push_back(y);
      tr.u_px.push_back(x + noise(rng));
      tr.v_px.push_back(y + noise(rng));
    }
    while (m < moves.size() && t >= moves[m].t0 + moves[m].length) ++m;
    if (m < moves.size() && t >= moves[m].t0) {
      const double s = (t - moves[m].t0) / moves[m].length;
      const double speed = moves[m].dist / moves[m].length * 30.0 * s * s * (1.0 - s) * (1.0 - s);
      x += speed * std::cos(moves[m].angle) / sub;
      y += speed * std::sin(moves[m].angle) / sub;
    }
  }
  return tr;
}

TEST(BlendHorizons, TheTwoFrameWeightKeepsTheFiltersBelowHoldOnShortDashes) {
  // GIVEN dashes at 10 Hz (three seeds), scored 2 frames ahead as track-study scores
  const double horizon = 0.2;
  int h1_losses = 0, h2_losses = 0;
  for (const unsigned seed : {7u, 8u, 9u}) {
    const ManeuverTrack tr = dashes(seed);
    auto hold = makePredictor("hold", 2);
    const double hold_px = scoreOnTrack(tr, *hold, horizon).rmse_truth_px;
    for (const char* name : {"kf-cv", "kf-ca", "imm"}) {
      // WHEN the filter runs with its defaults (the blend on 1 and 2 frames) and with the blend
      // learnt on one-frame forecasts only (hold_blend_frames 1, the default before), both without
      // the extrapolation cap (extrapolation_cap 0: it came after, and holds back the dashes'
      // overshoot too, so that with it the one-frame blend lost 4 of the 9)
      auto two = makePredictor(name, 2, {{"extrapolation_cap", 0.0}});
      auto one = makePredictor(name, 2, {{"hold_blend_frames", 1.0}, {"extrapolation_cap", 0.0}});
      const double two_px = scoreOnTrack(tr, *two, horizon).rmse_truth_px;
      const double one_px = scoreOnTrack(tr, *one, horizon).rmse_truth_px;
      std::printf("[ dashes #%u ] %s / hold: %.3f (one-frame blend %.3f)\n", seed, name, two_px / hold_px, one_px / hold_px);
      // THEN with both horizons it does better than its one-frame self
      EXPECT_LT(two_px, one_px) << name << " #" << seed;
      h1_losses += one_px > hold_px;
      h2_losses += two_px > hold_px;
    }
  }
  // and where the one-frame blend loses to hold on (nearly) every track, the two horizons lose on
  // at most one of the three seeds (measured: #7, by x1.005-1.03; the one-frame blend lost all 9)
  EXPECT_GE(h1_losses, 8);
  EXPECT_LE(h2_losses, 3);
}

}  // namespace
}  // namespace predvs
