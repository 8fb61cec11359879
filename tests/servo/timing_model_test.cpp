// Timing model: release ticks, effect times and horizons (docs/MODELS.md §0).
#include "predvs/servo/timing_model.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace predvs {
namespace {

// Times are sums of a few decimal periods: only binary rounding separates them from the exact value.
constexpr double kTimeTol = 1e-12;

TEST(TimingModel, DefaultIsTwoFrameLatencyParallel) {
  // GIVEN the default configuration (delta = T = 40 ms, t_ac = t_p = 40 ms, parallel)
  const TimingModel tm;
  // THEN a frame acquired at 0 is delivered two ticks later, and the horizon is two frames
  EXPECT_EQ(tm.framePeriodTicks(), 1);
  EXPECT_NEAR(tm.visionLatency(), 0.08, kTimeTol);
  EXPECT_EQ(tm.releaseTick(0.0), 2);
  EXPECT_NEAR(tm.releaseTime(0.4), 0.48, kTimeTol);
  EXPECT_NEAR(tm.horizon(tm.releaseTime(0.4), 0.4), 0.08, kTimeTol);
  EXPECT_NEAR(tm.nominalHorizonFrames(), 2.0, kTimeTol);
  // AND one frame a tick, the freshest frame is never older than at its release
  EXPECT_NEAR(tm.longestHorizonFrames(), 2.0, kTimeTol);
}

TEST(TimingModel, SerialPipelineNeedsLongerFramePeriod) {
  // GIVEN a serial pipeline with t_ac + t_p = 80 ms
  TimingConfig c;
  c.pipeline = Pipeline::Serial;
  // WHEN T = 40 ms THEN it is rejected, naming the key
  try {
    TimingModel tm(c);
    FAIL() << "infeasible serial pipeline accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("timing.frame_period_n"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("serial"), std::string::npos) << e.what();
  }
  // WHEN T = 80 ms (N = 2) THEN accepted: latency 80 ms = one frame, delivered at the next frame
  c.frame_period_n = 2;
  const TimingModel tm(c);
  EXPECT_NEAR(tm.minimumFramePeriod(), 0.08, kTimeTol);
  EXPECT_EQ(tm.releaseTick(0.0), 2);
  EXPECT_NEAR(tm.nominalHorizonFrames(), 1.0, kTimeTol);
  // AND at the tick before the next release it is one tick older: 1 + 1/2 frames
  EXPECT_NEAR(tm.longestHorizonFrames(), 1.5, kTimeTol);
  EXPECT_NEAR(tm.longestHorizonFrames(), tm.horizonFrames(tm.releaseTime(0.0) + tm.basePeriod(), 0.0), kTimeTol);
  // and the parallel pipeline with the same lags needs only max(t_ac, t_p)
  c.pipeline = Pipeline::Parallel;
  EXPECT_NEAR(TimingModel(c).minimumFramePeriod(), 0.04, kTimeTol);
}

TEST(TimingModel, DualRateReleaseRoundsUpToControlTick) {
  // GIVEN paper 003's dual rate: delta = 10 ms, N = 8, latency 25 ms (not a multiple of delta)
  TimingConfig c;
  c.base_period_s = 0.01;
  c.frame_period_n = 8;
  c.acquisition_lag_s = 0.01;
  c.processing_lag_s = 0.015;
  const TimingModel tm(c);
  // THEN frames are taken every 8 ticks and delivered at the first tick at or after +25 ms
  EXPECT_NEAR(tm.framePeriod(), 0.08, kTimeTol);
  EXPECT_TRUE(tm.isAcquisitionTick(16));
  EXPECT_FALSE(tm.isAcquisitionTick(17));
  EXPECT_EQ(tm.releaseTick(0.16), 19);
  EXPECT_NEAR(tm.releaseTime(0.16), 0.19, kTimeTol);
  // and a command computed 5 ticks after the release must reach 8 ticks past the acquisition
  EXPECT_NEAR(tm.horizon(0.24, 0.16), 0.08, kTimeTol);
  EXPECT_NEAR(tm.horizonFrames(0.24, 0.16), 1.0, kTimeTol);
}

TEST(TimingModel, CommandAndMotionLagsExtendTheHorizon) {
  // GIVEN t_c1 = 10 ms, t_c2 = 30 ms, t_m = 20 ms (modelled)
  TimingConfig c;
  c.controller_lag_s = 0.01;
  c.servo_lag_s = 0.03;
  c.motion_lag_s = 0.02;
  c.model_motion_lag = true;
  const TimingModel tm(c);
  // THEN horizon = (t_now - t_acq) + t_c1 + t_c2 + t_m / 2, the command acts one tick later
  EXPECT_NEAR(tm.horizon(1.0, 0.92), 0.08 + 0.04 + 0.01, kTimeTol);
  EXPECT_NEAR(tm.effectTime(1.0), 1.05, kTimeTol);
  EXPECT_EQ(tm.commandApplyTick(25), 26);
  // WHEN the motion lag is not modelled THEN it does not enter the horizon
  c.model_motion_lag = false;
  EXPECT_NEAR(TimingModel(c).horizon(1.0, 0.92), 0.12, kTimeTol);
  EXPECT_THROW(tm.horizon(0.9, 0.92), std::invalid_argument);
}

TEST(TimingModel, RejectsBadValuesNamingTheKey) {
  TimingConfig c;
  c.frame_period_n = 0;
  try {
    TimingModel tm(c);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "timing.frame_period_n must be >= 1, got 0");
  }
  c = TimingConfig{};
  c.base_period_s = 0.0;
  EXPECT_THROW(TimingModel{c}, std::invalid_argument);
  c = TimingConfig{};
  c.servo_lag_s = -0.01;
  try {
    TimingModel tm(c);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("timing.servo_lag_s"), std::string::npos);
  }
  EXPECT_EQ(parsePipeline("serial"), Pipeline::Serial);
  EXPECT_THROW(parsePipeline("pipelined"), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
