// The lost-feature policy (servo/lost_feature_policy.h, issue 9 item 2): the per-channel timeout,
// hold and drop in the closed loop, re-acquisition (and the predictor restart after a whole-target
// loss), `drop` on the point laws (ibvs on the remaining points equals ibvs built without them),
// and an E7-like open-loop run where the policy keeps kf-cv and st-akf from ending worse than hold.
#include "predvs/predictors/predictor.h"
#include "predvs/servo/channel_experiment.h"
#include "predvs/servo/lost_feature_policy.h"
#include "predvs/servo/paper_trajectories.h"
#include "predvs/servo/run_metrics.h"
#include "predvs/servo/servo_loop.h"
#include "predvs/tasks/ibvs_task.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTimeTol = 1e-9;  // times are sums of periods

TEST(LostFeatureTracker, EngagesAtTheTimeoutNotBeforePerChannel) {
  // GIVEN two channels at 10 Hz, timeout 1 s: channel 0 lost after t = 1.0, channel 1 measured throughout
  LostFeatureTracker tr(LostFeatureConfig{1.0, LostAction::Hold}, 2);
  for (int k = 0; k <= 10; ++k) EXPECT_FALSE(tr.observe(0.1 * k, Eigen::Vector2d(k, -k)));
  for (int k = 11; k <= 19; ++k) {
    // WHEN channel 0 has been lost for 0.1 .. 0.9 s THEN it is not expired yet
    EXPECT_FALSE(tr.observe(0.1 * k, Eigen::Vector2d(kNaN, -k)));
    EXPECT_FALSE(tr.expired(0)) << "t = " << 0.1 * k;
  }
  // WHEN 1.0 s has passed since its last measurement THEN it is expired, the other channel is not
  EXPECT_FALSE(tr.observe(2.0, Eigen::Vector2d(kNaN, -20)));
  EXPECT_TRUE(tr.expired(0));
  EXPECT_FALSE(tr.expired(1));
  EXPECT_EQ(tr.lastValue(0), 10.0);
  EXPECT_NEAR(tr.lastSeen(0), 1.0, kTimeTol);
  // AND a measurement clears it without asking for a predictor reset (not every channel had expired)
  EXPECT_FALSE(tr.observe(2.1, Eigen::Vector2d(7.0, -21)));
  EXPECT_FALSE(tr.anyExpired());
  EXPECT_EQ(tr.lastValue(0), 7.0);
}

TEST(LostFeatureTracker, WholeTargetBackAfterTheTimeoutAsksForAReset) {
  LostFeatureTracker tr(LostFeatureConfig{0.5, LostAction::Hold}, 2);
  tr.observe(0.0, Eigen::Vector2d(1, 2));
  tr.observe(0.4, Eigen::Vector2d(kNaN, kNaN));
  // a gap shorter than the timeout: no reset
  EXPECT_FALSE(tr.observe(0.45, Eigen::Vector2d(1, kNaN)));
  tr.observe(1.0, Eigen::Vector2d(kNaN, kNaN));
  EXPECT_TRUE(tr.expired(0) && tr.expired(1));
  // a frame with nothing measured: still no reset
  EXPECT_FALSE(tr.observe(1.1, Eigen::Vector2d(kNaN, kNaN)));
  // the first frame measuring one channel: reset
  EXPECT_TRUE(tr.observe(1.2, Eigen::Vector2d(kNaN, 3)));
  EXPECT_TRUE(tr.expired(0));
  EXPECT_FALSE(tr.expired(1));
}

TEST(LostFeatureTracker, ExtrapolateNeverExpiresAndTimeoutIsValidated) {
  LostFeatureTracker tr(LostFeatureConfig{0.1, LostAction::Extrapolate}, 1);
  tr.observe(0.0, Eigen::VectorXd::Constant(1, 1.0));
  EXPECT_FALSE(tr.observe(5.0, Eigen::VectorXd::Constant(1, kNaN)));
  EXPECT_FALSE(tr.expired(0));
  EXPECT_FALSE(tr.observe(6.0, Eigen::VectorXd::Constant(1, 2.0)));  // no reset either
  for (double bad : {0.0, -1.0, kNaN})
    EXPECT_THROW(LostFeatureTracker(LostFeatureConfig{bad, LostAction::Hold}, 1), std::invalid_argument);
  EXPECT_EQ(parseLostAction("drop"), LostAction::Drop);
  try {
    parseLostAction("freeze");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lost.action"), std::string::npos);
  }
}

// ---------------------------------------------------------------------------------------------
// Closed loop: the default scenario (4 points, 40 ms frames, 80 ms latency) cut to 9 s, the target
// hidden from 3 s to 6 s, kf-cv fed the raw features (compensation off, forecast feature), so the
// task acts on the predictor's forecast and a held channel shows as pred == meas.
ServoConfig occludedLoop(LostAction action) {
  ServoConfig c;
  c.duration_s = 9.0;
  c.occlusions = {{3.0, 6.0}};
  c.compensation = Compensation::Off;
  c.forecast = ForecastMode::Feature;
  c.lost = LostFeatureConfig{1.0, action};
  return c;
}

// Last frame seen at 2.96 s; frames acquired from 3.96 s on are past the timeout, delivered 80 ms
// later; the first frame after the occlusion (6.00 s) is delivered at 6.08 s.
constexpr double kExpiresAtS = 3.96 + 0.08;
constexpr double kReacquiredAtS = 6.00 + 0.08;

TEST(LostFeaturePolicy, ClosedLoopHoldEngagesAfterTheTimeoutAndReleasesAtReacquisition) {
  for (LostAction action : {LostAction::Hold, LostAction::Extrapolate}) {
    auto kf = makePredictor("kf-cv", 8);
    const ServoResult r = runServoLoop(occludedLoop(action), *kf);
    int held = 0, extrapolated = 0;
    for (const auto& s : r.trace) {
      const bool occluded = s.frame_lost;
      const bool past = s.t_s >= kExpiresAtS - kTimeTol && s.t_s < kReacquiredAtS - kTimeTol;
      // THEN the policy engages exactly from the timeout to re-acquisition (never with extrapolate)
      EXPECT_EQ(s.lost_expired, action == LostAction::Hold && past) << "t = " << s.t_s;
      if (!occluded) continue;
      // AND while engaged the task acts on the last measurement; before it, on the extrapolation
      if (s.lost_expired) {
        EXPECT_EQ(s.predicted, s.measured) << "t = " << s.t_s;
        ++held;
      } else if ((s.predicted - s.measured).norm() > 1e-6) {
        ++extrapolated;
      }
    }
    if (action == LostAction::Hold) {
      EXPECT_EQ(held, 51);  // 6.08 - 4.04 s at 40 ms
      EXPECT_EQ(extrapolated, 24);  // 3.08 .. 4.00 s: predict-only within the timeout
    } else {
      EXPECT_EQ(held, 0);
      EXPECT_EQ(extrapolated, 75);
    }
  }
}

TEST(LostFeaturePolicy, WholeTargetReacquiredRestartsThePredictor) {
  // GIVEN kf-cv through the 3 s occlusion, with and without the policy
  auto first_after = [](const ServoResult& r) {
    for (const auto& s : r.trace)
      if (s.t_s >= kReacquiredAtS - kTimeTol) return s;
    return ServoSample{};
  };
  auto kf = makePredictor("kf-cv", 8);
  const ServoSample held = first_after(runServoLoop(occludedLoop(LostAction::Hold), *kf));
  const ServoSample extrapolated = first_after(runServoLoop(occludedLoop(LostAction::Extrapolate), *kf));
  ASSERT_FALSE(held.frame_lost);
  // THEN with the policy the filter restarts from the first frame back: a fresh CV filter's
  // forecast is that measurement (velocity 0), the predictor's output is used again
  EXPECT_FALSE(held.lost_expired);
  EXPECT_NEAR((held.predicted - held.measured).norm(), 0.0, 1e-9);
  // AND without it the filter blends the frame into its 3 s extrapolation and forecasts with the old velocity
  EXPECT_GT((extrapolated.predicted - extrapolated.measured).norm(), 0.1);
}

TEST(LostFeaturePolicy, ClosedLoopDropStopsIbvsWhenEveryPointIsDropped) {
  // GIVEN the default compensated feed-forward loop with drop
  ServoConfig c = occludedLoop(LostAction::Drop);
  c.compensation = Compensation::Auto;
  c.forecast = ForecastMode::Feedforward;
  // (coast_tau_s = 0: with the default coasting the velocity is re-learnt after the gap and the
  // error of the last frame is 10.8 px with drop, 12.0 px with hold, just above the bound below)
  // (hold_blend_tau_s = 0: the plain kf-cv forecast; with the default blend with hold the last
  // frame's error is 13.4 px with drop, 16.5 px with hold)
  auto kf = makePredictor("kf-cv", 8, {{"coast_tau_s", 0.0}, {"hold_blend_tau_s", 0.0}});
  const ServoResult r = runServoLoop(c, *kf);
  int dropped = 0;
  for (const auto& s : r.trace) {
    if (!s.lost_expired) continue;
    ++dropped;
    // THEN the task gets no feature (NaN), and ibvs without points commands nothing
    EXPECT_TRUE(s.predicted.array().isNaN().all()) << "t = " << s.t_s;
    EXPECT_EQ(s.command.norm(), 0.0) << "t = " << s.t_s;
  }
  EXPECT_EQ(dropped, 51);
  // AND with hold the robot keeps acting on the held features
  c.lost.action = LostAction::Hold;
  const ServoResult h = runServoLoop(c, *kf);
  double effort_held = 0.0;
  for (const auto& s : h.trace)
    if (s.lost_expired) effort_held += s.command.norm();
  EXPECT_GT(effort_held, 0.0);
  // AND after re-acquisition both loops track again (the error of the last second is small)
  EXPECT_LT(r.trace.back().error, 10.0);
  EXPECT_LT(h.trace.back().error, 10.0);
}

// ---------------------------------------------------------------------------------------------
TEST(LostFeaturePolicy, IbvsOnTheRemainingPointsEqualsIbvsWithoutThem) {
  // GIVEN a square slightly off its goal (pixels = normalised coordinates) and point 2 dropped
  const Eigen::VectorXd sd = (Eigen::VectorXd(8) << -0.1, -0.1, 0.1, -0.1, 0.1, 0.1, -0.1, 0.1).finished();
  const Eigen::VectorXd s = (Eigen::VectorXd(8) << -0.08, -0.12, 0.12, -0.09, 0.11, 0.1, -0.09, 0.12).finished();
  const Eigen::VectorXd rate = (Eigen::VectorXd(8) << 0.01, 0.02, -0.01, 0.0, 0.5, 0.5, 0.03, -0.02).finished();
  auto context = [](const Eigen::VectorXd& desired) {
    TaskContext c;
    c.camera = CameraIntrinsics{1.0, 1.0, 0.0, 0.0};
    c.desired_points.uv_px = desired;
    c.desired_points.Z_m = Eigen::VectorXd::Constant(desired.size() / 2, 0.5);
    c.desired_points.seen.assign(static_cast<size_t>(desired.size() / 2), true);
    c.command_space = {"camera-twist", {"vx", "vy", "vz", "wx", "wy", "wz"}};
    return c;
  };
  auto without2 = [](const Eigen::VectorXd& x) {
    Eigen::VectorXd y(6);
    y << x.head<4>(), x.tail<2>();
    return y;
  };
  const Eigen::MatrixXd Jc = Eigen::MatrixXd::Identity(6, 6), none;
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  for (const char* interaction : {"current", "desired", "mean"}) {
    Params p{{"lambda", 0.7}};
    p.setText("interaction", interaction);
    IbvsTask four(p, context(sd));
    IbvsTask three(p, context(without2(sd)));
    ASSERT_TRUE(four.canDropFeatures());
    Eigen::VectorXd s_drop = s, rate_drop = rate;
    s_drop.segment<2>(4).setConstant(kNaN);
    rate_drop.segment<2>(4).setZero();
    const Eigen::VectorXd Z4 = Eigen::VectorXd::Constant(4, 0.55), Z3 = Eigen::VectorXd::Constant(3, 0.55);
    const Eigen::VectorXd s3 = without2(s), rate3 = without2(rate);
    // WHEN the 4-point law gets point 2 as NaN and the 3-point law never had it
    const Eigen::VectorXd u4 = four.computeCommand(TaskInput{0.0, 0.0, s_drop, s_drop, rate_drop, Z4, Jc, q, none});
    const Eigen::VectorXd u3 = three.computeCommand(TaskInput{0.0, 0.0, s3, s3, rate3, Z3, Jc, q, none});
    // THEN the commands agree (Eigen's pseudo-inverse against vpServo's: same law, two codes)
    EXPECT_NEAR((u4 - u3).norm(), 0.0, 1e-9) << interaction;
    EXPECT_TRUE(u4.allFinite());
    // AND no point at all gives no command
    const Eigen::VectorXd all_nan = Eigen::VectorXd::Constant(8, kNaN);
    EXPECT_EQ(four.computeCommand(TaskInput{0.0, 0.0, all_nan, all_nan, rate_drop, Z4, Jc, q, none}).norm(), 0.0);
  }
}

// ---------------------------------------------------------------------------------------------
// E7 cut short: e7-occlusion's set-up (the E6 target x_i, y_i, d_x; sigma_n = 4 uniform rounded
// noise; T = 0.1 s, no latency; hidden from 8 s to 11 s) run to 12 s instead of 20 s, 5 seeds.
TEST(LostFeaturePolicy, E7LikeOcclusionPolicyEndsNoWorseThanHold) {
  PredictionExperimentConfig cfg;
  cfg.duration_s = 12.0;
  cfg.timing.base_period_s = 0.1;
  cfg.timing.frame_period_n = 1;
  cfg.timing.acquisition_lag_s = cfg.timing.processing_lag_s = 0.0;
  cfg.noise = {NoiseKind::Uniform, 4.0, true};
  cfg.occlusions = {{8.0, 11.0}};
  const auto e6 = makeChannelTrajectory("e6-target");
  auto end_error = [&](const std::string& name, const Params& params, LostAction action) {
    cfg.lost = LostFeatureConfig{1.0, action};
    double sum = 0.0;
    for (std::uint64_t seed = 700; seed < 705; ++seed) {
      cfg.seed = seed;
      auto p = makePredictor(name, 3, params);
      std::map<std::string, double> v;
      for (const auto& kv : openLoopRunValues(runChannelExperiment(cfg, *e6, *p), cfg, *e6)) v[kv.first] = kv.second;
      sum += v.at("occl_end_error");
    }
    return sum / 5.0;
  };
  // E7's kf-cv tuning; st-akf with its q before issue 11; both without coasting (coast_tau_s = 0,
  // as e7-occlusion pins): the pure extrapolation E7 studies
  const Params kf_e7{{"r", 5}, {"q", 200}, {"coast_tau_s", 0}};
  const Params st_e7{{"q", 1000}, {"coast_tau_s", 0}};
  const double hold = end_error("hold", {}, LostAction::Extrapolate);
  const double kf_off = end_error("kf-cv", kf_e7, LostAction::Extrapolate);
  const double st_off = end_error("st-akf", st_e7, LostAction::Extrapolate);
  // (with the default coasting, tau = 0.2 s, the coasted estimate stops near where the target was
  // lost and ends the 3 s gap below hold: kf-cv measured 6.8 px against hold's 9.4)
  EXPECT_LT(end_error("kf-cv", {{"r", 5}, {"q", 200}}, LostAction::Extrapolate), kf_off);
  // GIVEN the policy off, the extrapolation over 3 s ends worse than holding (the E7 finding)
  EXPECT_GT(kf_off, hold);
  EXPECT_GT(st_off, 2.0 * hold);
  // WHEN the policy holds after 1 s THEN both end no worse than hold (equal: the same last frame)
  constexpr double kSameFrameTol = 1e-9;
  EXPECT_LE(end_error("kf-cv", kf_e7, LostAction::Hold), hold + kSameFrameTol);
  EXPECT_LE(end_error("st-akf", st_e7, LostAction::Hold), hold + kSameFrameTol);
  // AND the open loop refuses drop (no task to drop a feature from)
  cfg.lost.action = LostAction::Drop;
  auto p = makePredictor("kf-cv", 3);
  EXPECT_THROW(runChannelExperiment(cfg, *e6, *p), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
