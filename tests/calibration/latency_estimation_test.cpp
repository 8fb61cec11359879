// Latency estimation (calibration/latency_estimation.h) on logs of the simulated closed loop with
// known delays: several vision delays, noise levels and frame rates, recovered within one base
// period; and the logs that cannot carry a delay are rejected.
#include "predvs/calibration/latency_estimation.h"

#include "predvs/predictors/predictor.h"
#include "predvs/servo/servo_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

namespace predvs {
namespace {

/// The loop's trace as a latency log: every tick with its applied command, a frame at every tick
/// that delivers a new acquisition (t_acq_s changes).
LatencyLog logOf(const ServoResult& r, bool with_stamps) {
  LatencyLog log;
  double last_acq = std::nan("");
  for (const ServoSample& s : r.trace) {
    log.tick_t_s.push_back(s.t_s);
    log.command.emplace_back(s.command.data(), s.command.data() + s.command.size());
    if (std::isfinite(s.t_acq_s) && !(s.t_acq_s == last_acq)) {
      last_acq = s.t_acq_s;
      log.frame_delivery_s.push_back(s.t_s);
      if (with_stamps) log.frame_acquisition_s.push_back(s.t_acq_s);
      log.features.emplace_back(s.measured.data(), s.measured.data() + s.measured.size());
    }
  }
  return log;
}

struct Case {
  double base_period_s;
  int frame_period_n;
  double vision_latency_s;  ///< t_ac + t_p
  double sigma_px;
};

ServoResult simulate(const Case& c, double duration_s, std::uint64_t seed) {
  ServoConfig cfg;
  cfg.seed = seed;
  cfg.timing.base_period_s = c.base_period_s;
  cfg.timing.frame_period_n = c.frame_period_n;
  cfg.timing.acquisition_lag_s = cfg.timing.processing_lag_s = 0.5 * c.vision_latency_s;
  cfg.noise.sigma = c.sigma_px;
  cfg.duration_s = duration_s;
  auto p = makePredictor("hold", 8);
  return runServoLoop(cfg, *p);
}

/// The delay the loop really applies: the release tick of a frame acquired on a tick.
double deliveredDelay(const Case& c) {
  const TimingConfig t{c.base_period_s, c.frame_period_n, 0.5 * c.vision_latency_s, 0.5 * c.vision_latency_s};
  const TimingModel m(t);
  return m.releaseTime(0.0);
}

class LatencyRecovery : public ::testing::TestWithParam<Case> {};

TEST_P(LatencyRecovery, WithinOneBasePeriod) {
  const Case c = GetParam();
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
  SCOPED_TRACE("seed " + std::to_string(seed));
  // GIVEN a 4 s run of the default IBVS loop with that timing (the fit uses the first 1.3 s)
  const ServoResult r = simulate(c, 4.0, seed);
  const double truth = deliveredDelay(c);
  // WHEN the delay is estimated from delivery times only, and with acquisition stamps
  const LatencyResult d = estimateLatency(logOf(r, false));
  const LatencyResult s = estimateLatency(logOf(r, true));
  // THEN the delay is recovered within one base period (the loop delivers on ticks) with a finite
  // uncertainty, the stamps give the delivery delay exactly, and at moderate noise the stamped fit
  // sees no actuation lag (the log holds the command as applied)
  EXPECT_NEAR(d.vision_delay_s, truth, c.base_period_s) << "sigma " << d.vision_sigma_s;
  EXPECT_TRUE(std::isfinite(d.vision_sigma_s) && d.vision_sigma_s > 0.0);
  EXPECT_NEAR(s.stamped_delay_s, truth, 1e-9);
  if (c.sigma_px <= 0.5) {
    EXPECT_NEAR(s.actuation.delay_s, 0.0, c.base_period_s);
  }
  EXPECT_NEAR(d.base_period_s, c.base_period_s, 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Delays, LatencyRecovery,
                         ::testing::Values(Case{0.04, 1, 0.08, 0.5},   // the default scenario
                                           Case{0.04, 1, 0.0, 0.5},    // no delay
                                           Case{0.04, 1, 0.04, 2.0},   // one frame, noisy
                                           Case{0.02, 1, 0.04, 0.1},   // 50 Hz, 2 ticks
                                           Case{0.01, 4, 0.07, 0.5},   // dual rate, 100 Hz control, 25 Hz vision
                                           Case{0.02, 2, 0.05, 0.5},   // dual rate 25 Hz, between ticks
                                           Case{0.04, 1, 0.04, 1.0}));

}  // namespace
}  // namespace predvs

namespace predvs {
namespace {

void expectRejected(const LatencyLog& log, const std::string& fragment) {
  try {
    estimateLatency(log);
    ADD_FAILURE() << "expected an error containing '" << fragment << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

TEST(LatencyEstimation, RejectsLogsWithoutInformation) {
  // GIVEN an empty log, a constant command, features that never move and a short log
  expectRejected(LatencyLog{}, "fewer than 2 control ticks");
  LatencyLog flat;
  for (int k = 0; k < 100; ++k) {
    flat.tick_t_s.push_back(0.04 * k);
    flat.command.push_back({0.1, 0.0});
    flat.frame_delivery_s.push_back(0.04 * k);
    flat.features.push_back({1.0 * k, 2.0});
  }
  expectRejected(flat, "the command never changes");
  LatencyLog still = flat;
  for (int k = 0; k < 100; ++k) still.command[static_cast<size_t>(k)] = {k < 10 ? 0.0 : 0.1, 0.0};
  for (auto& f : still.features) f = {3.0, 4.0};
  expectRejected(still, "the features never change");
  LatencyLog shortLog;
  for (int k = 0; k < 6; ++k) {
    shortLog.tick_t_s.push_back(0.04 * k);
    shortLog.command.push_back({k < 2 ? 0.0 : 0.1, 0.0});
    shortLog.frame_delivery_s.push_back(0.04 * k);
    shortLog.features.push_back({k < 4 ? 0.0 : 1.0 * k, 0.0});
  }
  expectRejected(shortLog, "too few frames");
}

}  // namespace
}  // namespace predvs

namespace predvs {
namespace {

struct PointCase {
  const char* predictor;
  Case timing;
};

class PointModelRecovery : public ::testing::TestWithParam<PointCase> {};

TEST_P(PointModelRecovery, WithinOneBasePeriodOverTheWholeRun) {
  const PointCase pc = GetParam();
  const Case& c = pc.timing;
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    // GIVEN an 8 s run of the default IBVS loop (camera 800 px, principal point 320, 240)
    ServoConfig cfg;
    cfg.seed = seed;
    cfg.timing.base_period_s = c.base_period_s;
    cfg.timing.frame_period_n = c.frame_period_n;
    cfg.timing.acquisition_lag_s = cfg.timing.processing_lag_s = 0.5 * c.vision_latency_s;
    cfg.noise.sigma = c.sigma_px;
    cfg.duration_s = 8.0;
    auto p = makePredictor(pc.predictor, 8);
    const ServoResult r = runServoLoop(cfg, *p);
    // WHEN the point model is fitted with the camera's intrinsics
    LatencyOptions o;
    o.point_model = true;
    o.px = cfg.camera.px, o.py = cfg.camera.py, o.u0 = cfg.camera.u0, o.v0 = cfg.camera.v0;
    const LatencyResult d = estimateLatency(logOf(r, true), o);
    // THEN the delay is within one base period, and no actuation lag is seen
    EXPECT_NEAR(d.total.delay_s, deliveredDelay(c), c.base_period_s) << "sigma " << d.total.sigma_s;
    EXPECT_NEAR(d.actuation.delay_s, 0.0, c.base_period_s);
  }
}

INSTANTIATE_TEST_SUITE_P(Delays, PointModelRecovery,
                         ::testing::Values(PointCase{"hold", {0.04, 1, 0.08, 0.5}}, PointCase{"kf-cv", {0.04, 1, 0.08, 0.5}},
                                           PointCase{"hold", {0.04, 1, 0.0, 0.5}}, PointCase{"kf-cv", {0.04, 1, 0.04, 2.0}},
                                           PointCase{"hold", {0.02, 1, 0.04, 0.1}}, PointCase{"kf-cv", {0.02, 1, 0.04, 0.1}},
                                           PointCase{"hold", {0.01, 4, 0.07, 0.5}}, PointCase{"hold", {0.02, 2, 0.05, 1.0}},
                                           PointCase{"kf-cv", {0.02, 2, 0.05, 1.0}}, PointCase{"kf-cv", {0.04, 1, 0.04, 1.0}}));

}  // namespace
}  // namespace predvs
