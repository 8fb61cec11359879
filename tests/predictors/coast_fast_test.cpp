// A gap that begins at an unusual speed coasts shorter, and any other gap coasts with a hazard that
// grows with the time since the last measurement (channel_predictor.h, `coast_fast_ratio`,
// `coast_shape`, docs/MODELS.md §15): the speed ratio a channel keeps, a burst that stops as its gap
// begins, a single dropped frame on a ramp, and nothing changed where the blend with hold is off.
#include "predvs/predictors/channel_predictor.h"
#include "predvs/predictors/registry.h"
#include "predictors/gap_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace predvs {
namespace {

constexpr double kRateHz = 60.0;
constexpr double kDt = 1.0 / kRateHz;
// A ratio of two exact velocities through a time-weighted mean: rounding only.
constexpr double kRatioTol = 1e-9;

TEST(CoastFast, TheSpeedRatioIsTheLastSpeedOverTheRecentRms) {
  // GIVEN 2 s at 20 px/s then one frame at 300 px/s, remembered with no forgetting (keep = 1)
  CoastStop s;
  int k = 0;
  for (; k <= 120; ++k) s.remember(k * kDt, 0.0, 20.0, 1.0, Innovation{});
  const double before = s.speedRatio();
  s.remember(k * kDt, 0.0, 300.0, 1.0, Innovation{});
  // THEN the ratio is 1 on the steady speed and |v| / sqrt(mean v^2) after the jump
  EXPECT_NEAR(before, 1.0, kRatioTol);
  const double rms = std::sqrt((120 * 20.0 * 20.0 + 300.0 * 300.0) / 121.0);
  EXPECT_NEAR(s.speedRatio(), 300.0 / rms, kRatioTol);
}

TEST(CoastFast, NoRatioBeforeASecondOfMemory) {
  // GIVEN half a second of frames
  CoastStop s;
  for (int k = 0; k <= 30; ++k) s.remember(k * kDt, 0.0, k < 30 ? 10.0 : 300.0, 1.0, Innovation{});
  // THEN no ratio yet (0): the gap coasts as before
  EXPECT_EQ(s.speedRatio(), 0.0);
}

/// Sum of squared forecast errors (px^2) of `name`, 2 frames ahead, through a 0.3 s gap on a
/// noise-free 1-channel track: 3 s of drift at 15 px/s, a burst at 300 px/s for 0.5 s, and the gap
/// beginning exactly when the burst ends (the target at rest, as the generated bursts at 60 Hz whose
/// stop no test can see before the gap).
double gapErrorBurstEnd(const std::string& name, const Params& params) {
  const double t_burst = 3.0, t_end = 3.5;
  const auto truth = [&](double t) {
    if (t < t_burst) return 15.0 * t;
    return 15.0 * t_burst + 300.0 * (std::min(t, t_end) - t_burst);
  };
  return gapSquaredError(name, params, truth, kRateHz, t_end, 0.3);
}

TEST(CoastFast, AGapAtAnUnusualSpeedCoastsLess) {
  for (const char* name : {"kf-cv", "kf-ca", "imm"}) {
    // GIVEN the defaults and the same without the speed rule
    const double with_rule = gapErrorBurstEnd(name, {});
    const double without = gapErrorBurstEnd(name, {{"coast_fast_ratio", 0.0}});
    // THEN the forecasts through the gap run on less past the stop (rho is about 2.6 here: the RMS
    // of 3 s at 15 px/s and 0.5 s at 300 px/s is ~114 px/s)
    EXPECT_LT(with_rule, 0.6 * without) << name;
  }
}

/// Squared error (px^2) of the 2-frame forecast made on a single dropped frame of an exact
/// 200 px/s ramp at 60 Hz (the dropped frame at 2 s).
double droppedFrameError(const std::string& name, const Params& params) {
  auto p = makePredictor(name, 1, params);
  const int dropped = static_cast<int>(2.0 * kRateHz);
  Eigen::VectorXd z(1);
  double err = 0.0;
  for (int k = 0; k <= dropped; ++k) {
    const double t = k * kDt;
    z(0) = k < dropped ? 200.0 * t : std::nan("");
    p->update(t, z);
    if (k == dropped) err = std::pow(p->predictPosition(0, t + 2 * kDt) - 200.0 * (t + 2 * kDt), 2);
  }
  return err;
}

TEST(CoastFast, TheShapeKeepsMoreVelocityOverASingleDroppedFrame) {
  for (const char* name : {"kf-cv", "imm"}) {
    // GIVEN the default shape (1.5) and the exponential decay (1), the blend on
    const double shaped = droppedFrameError(name, {});
    const double exponential = droppedFrameError(name, {{"coast_shape", 1.0}});
    // THEN the forecast over one dropped frame of a steady ramp is closer with the shape:
    // S(1/60 s) = exp(-(u / tau)^1.5) = 0.976 instead of exp(-u / tau) = 0.920
    EXPECT_GT(exponential, 0.0) << name;
    EXPECT_LT(shaped, 0.2 * exponential) << name;
  }
}

TEST(CoastFast, OffWithTheBlend) {
  for (const char* name : {"kf-cv", "kf-ca", "imm"}) {
    // GIVEN the blend off (hold_blend_tau_s 0), the two keys given or not
    const double plain = gapErrorBurstEnd(name, {{"hold_blend_tau_s", 0.0}});
    const double given = gapErrorBurstEnd(name, {{"hold_blend_tau_s", 0.0}, {"coast_fast_ratio", 1.1}, {"coast_shape", 3.0}});
    // THEN the same forecasts, bit for bit
    EXPECT_EQ(plain, given) << name;
  }
}

}  // namespace
}  // namespace predvs
