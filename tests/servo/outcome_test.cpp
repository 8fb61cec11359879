// The outcome of a positioning run (servo/metrics.h, Outcome; metrics.outcome): convergence and
// failure on synthetic error traces, then through ServoLoop runs that converge, fail by a point
// going behind the camera or out of the image, or start against a joint limit of the arm.
#include "predvs/predictors/predictor.h"
#include "predvs/servo/metrics.h"
#include "predvs/servo/servo_loop.h"
#include "predvs/servo/viper850_robot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTimeTol = 1e-9;  // times are sums of exact steps of 10 ms

/// e(t) = 50 exp(-t) sampled every 10 ms over [0, duration_s].
void decay(double duration_s, std::vector<double>& t, std::vector<double>& e) {
  t.clear(), e.clear();
  for (int i = 0; 0.01 * i <= duration_s + 1e-12; ++i) {
    t.push_back(0.01 * i);
    e.push_back(50.0 * std::exp(-t.back()));
  }
}

std::map<std::string, double> valueMap(const NamedValues& values) {
  std::map<std::string, double> m;
  for (const auto& kv : values) m[kv.first] = kv.second;
  return m;
}

TEST(Outcome, ConvergesWhenTheErrorStaysUnderTheThresholdToTheEnd) {
  // GIVEN e = 50 exp(-t) over 10 s and the default threshold of 1 px
  std::vector<double> t, e;
  decay(10.0, t, e);
  const MetricsOptions o;
  const Outcome r = computeOutcome(t, e, FailureKind::None, kNaN, o);
  // THEN the run converges at the first sample at or below 1 px: t = ln 50 = 3.91 s, rounded up to
  // the 10 ms grid
  EXPECT_TRUE(r.converged);
  EXPECT_FALSE(r.failed());
  EXPECT_NEAR(r.convergence_time_s, std::ceil(std::log(50.0) / 0.01) * 0.01, kTimeTol);
  // AND a larger threshold is reached sooner (50 exp(-t) = 5 at t = ln 10)
  MetricsOptions loose;
  loose.converge_px = 5.0;
  EXPECT_NEAR(computeOutcome(t, e, FailureKind::None, kNaN, loose).convergence_time_s,
              std::ceil(std::log(10.0) / 0.01) * 0.01, kTimeTol);
}

TEST(Outcome, ALaterExcursionOrAShortStayIsNotConvergence) {
  // GIVEN a trace that goes under 1 px and comes back above it at t = 8 s
  std::vector<double> t, e;
  decay(10.0, t, e);
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] >= 8.0) e[i] = 3.0;
  const MetricsOptions o;
  // THEN it has not converged: the error must stay at or below the threshold to the end
  Outcome r = computeOutcome(t, e, FailureKind::None, kNaN, o);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(std::isnan(r.convergence_time_s));
  // GIVEN it comes back under 1 px only for the last 0.5 s (from t = 9.5 s)
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] >= 9.5 - 1e-9) e[i] = 0.5;
  // THEN it has not converged with the default hold of 1 s, but has with a hold of 0.4 s, at 9.5 s
  EXPECT_FALSE(computeOutcome(t, e, FailureKind::None, kNaN, o).converged);
  MetricsOptions short_hold;
  short_hold.converge_hold_s = 0.4;
  r = computeOutcome(t, e, FailureKind::None, kNaN, short_hold);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.convergence_time_s, 9.5, kTimeTol);
  // AND a NaN sample in the final stretch breaks it (it counts as above the threshold)
  e[e.size() - 3] = kNaN;
  EXPECT_FALSE(computeOutcome(t, e, FailureKind::None, kNaN, short_hold).converged);
}

TEST(Outcome, AFailedRunHasNotConvergedAndNamesItsFailure) {
  // GIVEN a trace that converged before the loop reported a failure at 6 s
  std::vector<double> t, e;
  decay(6.0, t, e);
  const Outcome r = computeOutcome(t, e, FailureKind::Behind, 6.0, MetricsOptions{});
  // THEN the failure wins: not converged, failed behind the camera at 6 s
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.failed());
  EXPECT_EQ(r.failure, FailureKind::Behind);
  const auto v = valueMap(outcomeValues(r));
  EXPECT_EQ(v.at("converged"), 0.0);
  EXPECT_TRUE(std::isnan(v.at("convergence_time_s")));
  EXPECT_EQ(v.at("failed"), 1.0);
  EXPECT_EQ(v.at("failure_time_s"), 6.0);
  EXPECT_EQ(v.at("fail_behind"), 1.0);
  EXPECT_EQ(v.at("fail_image"), 0.0);
  EXPECT_EQ(v.at("fail_robot"), 0.0);
  // AND the names come in the documented order
  const NamedValues names = outcomeValues(Outcome{});
  ASSERT_EQ(names.size(), 7u);
  EXPECT_EQ(names.front().first, "converged");
  EXPECT_EQ(names.back().first, "fail_robot");
  // AND a failed run's steady figures are NaN while peak, iae and effort stay
  const Metrics m = withoutSteadyState(computeMetrics(t, e));
  EXPECT_TRUE(std::isnan(m.rmse) && std::isnan(m.final_error) && std::isnan(m.max_error) &&
              std::isnan(m.settling_time_s));
  EXPECT_NEAR(m.peak_error, 50.0, kTimeTol);
  EXPECT_GT(m.iae, 0.0);
}

TEST(Outcome, RejectsBadOptionsNamingTheKey) {
  MetricsOptions o;
  o.converge_px = 0.0;
  EXPECT_THROW(
      {
        try {
          computeOutcome({}, {}, FailureKind::None, kNaN, o);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("metrics.converge_px"), std::string::npos) << e.what();
          throw;
        }
      },
      std::invalid_argument);
  o = MetricsOptions{};
  o.converge_hold_s = -1.0;
  EXPECT_THROW(computeOutcome({}, {}, FailureKind::None, kNaN, o), std::invalid_argument);
  EXPECT_THROW(computeOutcome({0.0}, {}, FailureKind::None, kNaN, MetricsOptions{}), std::invalid_argument);
}

// ---- through the loop -------------------------------------------------------------------------

ServoResult runLoop(const ServoConfig& c, const std::string& predictor = "hold") {
  auto p = makePredictor(predictor, servoChannels(c));
  return runServoLoop(c, *p);
}

/// The default scenario with the target at rest and the outcome on.
ServoConfig staticTarget() {
  ServoConfig c;
  c.scene.trajectory = "static";
  c.scene.trajectory_params = Params{};
  c.duration_s = 10.0;
  c.metrics.outcome = true;
  return c;
}

/// docs/MODELS.md §11 E10's failing regime as a stand-in: 150 degrees about the optical axis, no velocity
/// saturation, delta = 10 ms, N = 16 (T = 0.16 s) with one frame of latency, lambda = 2. The
/// current-matrix IBVS backs away and then comes through the object plane on stale commands.
ServoConfig rotation150() {
  ServoConfig c = staticTarget();
  c.initial_pose << 0.0, 0.0, 0.0, 0.0, 0.0, 2.618;
  c.timing.base_period_s = 0.01;
  c.timing.frame_period_n = 16;
  c.timing.acquisition_lag_s = c.timing.processing_lag_s = 0.08;  // t_ac + t_p = T
  c.robot.params.set("saturation", 0.0);
  c.task.params.set("lambda", 2.0);
  return c;
}

TEST(OutcomeLoop, AConvergingRunKeepsItsFiguresAndAddsTheOutcome) {
  // GIVEN the default loop on a static target, with and without metrics.outcome
  ServoConfig plain = staticTarget();
  plain.metrics.outcome = false;
  const ServoResult a = runLoop(plain, "kf-cv");
  const ServoResult b = runLoop(staticTarget(), "kf-cv");
  // THEN it converges (57 px to well under 1 px within the 10 s) and never fails
  EXPECT_TRUE(b.outcome.converged);
  EXPECT_FALSE(b.outcome.failed());
  EXPECT_GT(b.outcome.convergence_time_s, 0.5);
  EXPECT_LT(b.outcome.convergence_time_s, 9.0);
  // AND the error is under the threshold from then on
  for (const auto& s : b.trace)
    if (s.t_s >= b.outcome.convergence_time_s - kTimeTol) {
      EXPECT_LE(s.error, 1.0) << s.t_s;
    }
  // AND the outcome changes nothing else: same trace, same figures, outcome names added after the
  // metricValues() ones
  ASSERT_EQ(a.trace.size(), b.trace.size());
  for (size_t i = 0; i < a.trace.size(); ++i) ASSERT_EQ(a.trace[i].error, b.trace[i].error) << i;
  const auto va = valueMap(a.values), vb = valueMap(b.values);
  for (const auto& kv : va) EXPECT_EQ(vb.at(kv.first), kv.second) << kv.first;
  EXPECT_EQ(vb.size(), va.size() + 7);
  EXPECT_EQ(b.values[7].first, "converged");
  EXPECT_EQ(vb.at("converged"), 1.0);
  EXPECT_EQ(vb.at("failed"), 0.0);
  auto p = makePredictor("kf-cv", 8);
  EXPECT_EQ(ServoLoop(staticTarget(), *p).valueNames().size(), b.values.size());
}

TEST(OutcomeLoop, APointBehindTheCameraStopsTheRun) {
  // GIVEN the 150-degree rotation at high gain and latency, the image-border check off
  ServoConfig c = rotation150();
  c.metrics.fail_outside_image = false;
  const ServoResult r = runLoop(c);
  // THEN the run fails with a point behind the camera, before the end
  ASSERT_TRUE(r.outcome.failed());
  EXPECT_EQ(r.outcome.failure, FailureKind::Behind);
  EXPECT_FALSE(r.outcome.converged);
  EXPECT_GT(r.outcome.failure_time_s, 0.0);
  EXPECT_LT(r.outcome.failure_time_s, c.duration_s);
  // AND the run stopped there: the trace ends one tick before the failing state, every point of
  // the last row still in front of the camera
  ASSERT_FALSE(r.trace.empty());
  EXPECT_NEAR(r.trace.back().t_s, r.outcome.failure_time_s - c.timing.base_period_s, kTimeTol);
  EXPECT_LT(r.trace.size(), static_cast<size_t>(std::lround(c.duration_s / c.timing.base_period_s)));
  EXPECT_TRUE(std::isfinite(r.trace.back().error));
  // AND its steady figures are NaN, the others finite
  const auto v = valueMap(r.values);
  EXPECT_TRUE(std::isnan(v.at("rmse")));
  EXPECT_TRUE(std::isnan(v.at("final")));
  EXPECT_TRUE(std::isfinite(v.at("peak")));
  EXPECT_TRUE(std::isfinite(v.at("effort")));
  EXPECT_EQ(v.at("fail_behind"), 1.0);
  EXPECT_EQ(v.at("failure_time_s"), r.outcome.failure_time_s);
}

TEST(OutcomeLoop, APointOutsideTheImageFailsFirst) {
  // GIVEN the same run with the image-border check (on by default), 640 x 480
  const ServoConfig c = rotation150();
  ServoConfig behind = c;
  behind.metrics.fail_outside_image = false;
  const ServoResult r = runLoop(c);
  // THEN it fails by a point leaving the image, earlier than the point goes behind the camera
  ASSERT_TRUE(r.outcome.failed());
  EXPECT_EQ(r.outcome.failure, FailureKind::OutsideImage);
  EXPECT_LT(r.outcome.failure_time_s, runLoop(behind).outcome.failure_time_s);
  // AND every row of the trace has all four points inside the image
  for (const auto& s : r.trace)
    for (int i = 0; i < 4; ++i) {
      EXPECT_GE(s.truth(2 * i), 0.0);
      EXPECT_LT(s.truth(2 * i), c.image_width_px);
      EXPECT_GE(s.truth(2 * i + 1), 0.0);
      EXPECT_LT(s.truth(2 * i + 1), c.image_height_px);
    }
  // GIVEN an image too small for the initial view (the square spans u = 240..400 px)
  ServoConfig small = staticTarget();
  small.image_width_px = 300.0;
  const ServoResult r0 = runLoop(small);
  // THEN the run fails at t = 0 with no row; its figures are all there, NaN
  EXPECT_EQ(r0.outcome.failure, FailureKind::OutsideImage);
  EXPECT_EQ(r0.outcome.failure_time_s, 0.0);
  EXPECT_TRUE(r0.trace.empty());
  EXPECT_EQ(r0.values.size(), runLoop(staticTarget()).values.size());
  EXPECT_TRUE(std::isnan(valueMap(r0.values).at("rmse")));
  // AND a bad image size is a configuration error naming the key
  small.image_width_px = 0.0;
  auto p = makePredictor("hold", 8);
  try {
    ServoLoop loop(small, *p);
    ADD_FAILURE() << "accepted camera.width 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("camera.width"), std::string::npos) << e.what();
  }
}

TEST(OutcomeLoop, AnArmJointAtItsLimitIsAFailureWhenAsked) {
  // GIVEN the arm starting with joint 1 on its upper limit
  ServoConfig c = staticTarget();
  c.duration_s = 2.0;
  c.robot.name = "viper850";
  c.robot.params.set("q0_1", Viper850Robot().jointMax()(0));
  // THEN the run fails at t = 0 at the robot's limit
  const ServoResult r = runLoop(c);
  EXPECT_EQ(r.outcome.failure, FailureKind::RobotLimit);
  EXPECT_EQ(r.outcome.failure_time_s, 0.0);
  EXPECT_EQ(valueMap(r.values).at("fail_robot"), 1.0);
  // AND with metrics.fail_robot_limit off it runs to the end
  c.metrics.fail_robot_limit = false;
  const ServoResult full = runLoop(c);
  EXPECT_FALSE(full.outcome.failed());
  EXPECT_NEAR(full.trace.back().t_s, c.duration_s, kTimeTol);
}

}  // namespace
}  // namespace predvs
