// A gap just after the filter's velocity fell through zero (channel_predictor.h, "A turn or a stop
// through zero", `coast_crossing`, docs/MODELS.md §15): each channel learns whether its crossings
// turn or stop, and a gap that begins at one carries the acceleration times that share. The share
// of crossings that stopped or turned; a stop's gap that no longer drifts back; nothing changed on
// a track that never crosses zero.
#include "predvs/predictors/channel_predictor.h"
#include "predvs/predictors/registry.h"
#include "predictors/gap_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

namespace predvs {
namespace {

constexpr double kRateHz = 60.0;
constexpr double kDt = 1.0 / kRateHz;

/// Feeds `s` the filter velocity v(t) at 60 Hz from t0 for `seconds` (positions: its integral from 0).
template <class V>
void feed(CoastStop& s, const V& v, double t0, double seconds, double& z) {
  for (int k = 0; k < static_cast<int>(std::lround(seconds * kRateHz)); ++k) {
    const double t = t0 + k * kDt;
    z += v(t) * kDt;
    s.remember(t, z, v(t), std::exp(-kDt / 6.0), Innovation{});
    if (s.watching()) s.watchCrossing(1.0, 6.0);
  }
}

TEST(CoastCrossing, TheShareOfTurnsFollowsWhatTheCrossingsDid) {
  // GIVEN a velocity that swings +-200 px/s through zero and on to the other side (a zigzag), and
  // one that falls through zero to -30 px/s and settles at rest (a lagging filter at a hard stop),
  // four times each over 8 s
  CoastStop turns, stops;
  double z_turns = 0.0, z_stops = 0.0;
  feed(turns, [](double t) { return 200.0 * std::cos(2.0 * M_PI * t / 2.0); }, 0.0, 8.0, z_turns);
  feed(stops, [](double t) {
    const double u = std::fmod(t, 2.0);  // 1 s at 200 px/s, a 0.1 s fall to -30 px/s, back to 0 within 0.1 s
    if (u < 1.0) return 200.0;
    if (u < 1.1) return 200.0 - 2300.0 * (u - 1.0);
    if (u < 1.2) return -30.0 + 300.0 * (u - 1.1);
    return 0.0;
  }, 0.0, 8.0, z_stops);
  // THEN the turns keep most of the prior's share, the stops lose it
  EXPECT_GT(turns.turnShare(), 0.8);
  EXPECT_LT(stops.turnShare(), 0.3);
  // and before any crossing the share is the prior's 1 (a channel that never crossed keeps its acceleration)
  EXPECT_EQ(CoastStop{}.turnShare(), 1.0);
}

/// A target that moves in bursts at 60 Hz, noise-free: 250 px/s for 0.6 s, a stop in 80 ms, 0.6 s
/// at rest, again, three times; the last stop is followed by a 0.4 s gap 4 frames after it ended
/// (the filter's velocity has fallen through zero by then). Sum of squared forecast errors there.
double gapErrorAfterLastStop(const std::string& name, const Params& params) {
  const auto truth = [](double t) {
    const double period = 1.28, v = 250.0, a = v / 0.08;
    const int n = static_cast<int>(std::floor(t / period));
    const double u = t - n * period;
    const double leg = v * 0.6 + 0.5 * v * 0.08;  // the distance of one burst
    double p = n * leg;
    if (u < 0.6) return p + v * u;
    p += v * 0.6;
    const double s = std::min(u - 0.6, 0.08);
    return p + v * s - 0.5 * a * s * s;
  };
  return gapSquaredError(name, params, truth, kRateHz, 2 * 1.28 + 0.68 + 4 * kDt, 0.4);
}

TEST(CoastCrossing, AGapAfterAStopThroughZeroNoLongerDriftsBack) {
  // (imm with its raise on the combined innovation, q_raise_from_ca 0, as when the rule came in)
  const Params imm_then{{"q_raise_from_ca", 0.0}};
  for (const auto& [name, then] : {std::pair<const char*, Params>{"kf-ca", {}}, {"stkf", {}}, {"imm", imm_then}}) {
    Params without_rule = then;
    without_rule.set("coast_crossing", 0.0);
    const double with_rule = gapErrorAfterLastStop(name, then);
    const double without = gapErrorAfterLastStop(name, without_rule);
    // (when the rule came in: kf-ca 275 against 550 px^2, stkf 444 against 1,027, imm 26 against 87)
    EXPECT_LT(with_rule, 0.6 * without) << name << ": " << with_rule << " against " << without;
  }
  // AND imm with its defaults, its CA mode raised on its own innovation, does not drift back with the
  // rule or without it (0.03 and 0.02 px^2 summed over the gap's 24 forecasts)
  EXPECT_LT(gapErrorAfterLastStop("imm", {}), 1.0);
  EXPECT_LT(gapErrorAfterLastStop("imm", {{"coast_crossing", 0.0}}), 1.0);
}

TEST(CoastCrossing, ATrackThatNeverCrossesZeroIsTheSameBits) {
  // GIVEN a target accelerating away (v > 0 throughout) with a gap
  const auto truth = [](double t) { return 20.0 * t + 40.0 * t * t; };
  for (const char* name : {"kf-ca", "cs-akf", "stkf", "st-akf", "fakf", "imm"}) {
    EXPECT_EQ(gapSquaredError(name, {}, truth, kRateHz, 1.5, 0.3),
              gapSquaredError(name, {{"coast_crossing", 0.0}}, truth, kRateHz, 1.5, 0.3))
        << name;
  }
}

}  // namespace
}  // namespace predvs
