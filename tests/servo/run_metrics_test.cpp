// The figures of an open-loop run by name (run_metrics.h): known answers on hand-made traces for
// the occlusion and monitor figures, and names that depend on the configuration only.
#include "predvs/predictors/predictor.h"
#include "predvs/servo/run_metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace predvs {
namespace {

constexpr double kExact = 1e-12;  // a few additions and one square root of small integers

std::map<std::string, double> asMap(const NamedValues& v) { return {v.begin(), v.end()}; }

std::vector<std::string> namesOf(const NamedValues& v) {
  std::vector<std::string> n;
  for (const auto& kv : v) n.push_back(kv.first);
  return n;
}

/// A 1-channel result with one row per (t, error, frame lost?); the prediction is the truth plus
/// the error, so the signed error along +x is the error.
ChannelExperimentResult handMade(const std::vector<double>& t, const std::vector<double>& e, const std::vector<bool>& lost) {
  ChannelExperimentResult r;
  r.channel_names = {"x"};
  for (size_t k = 0; k < t.size(); ++k) {
    ChannelSample s;
    s.t_s = s.t_acq_s = s.t_pred_s = t[k];
    s.measured_valid = !lost[k];
    s.truth = Eigen::VectorXd::Zero(1);
    s.predicted = Eigen::VectorXd::Constant(1, e[k]);
    s.measured = s.predicted_velocity = s.true_velocity = Eigen::VectorXd::Zero(1);
    s.error = e[k];
    r.trace.push_back(s);
  }
  r.position_mse = r.velocity_mse = Eigen::VectorXd::Zero(1);
  return r;
}

TEST(RunMetrics, OcclusionFiguresOfAKnownTrace) {
  // GIVEN 10 ticks of 0.1 s with the frames of ticks 3 and 4 lost (errors 3 and 4), errors k otherwise
  std::vector<double> t, e;
  std::vector<bool> lost;
  for (int k = 0; k < 10; ++k) t.push_back(0.1 * k), e.push_back(k), lost.push_back(k == 3 || k == 4);
  PredictionExperimentConfig cfg;
  cfg.duration_s = 1.0;
  cfg.occlusions = {{0.3, 0.5}};
  const auto static_target = makeChannelTrajectory("static");
  // WHEN the figures are computed
  auto v = asMap(openLoopRunValues(handMade(t, e, lost), cfg, *static_target));
  // THEN the occlusion ticks give RMS sqrt((9 + 16) / 2) and max 4, the extrapolation ends at 4,
  // the first tick after is 5, and the next 1 s holds ticks 5..9
  EXPECT_NEAR(v.at("occl_rmse"), std::sqrt(12.5), kExact);
  EXPECT_NEAR(v.at("occl_max"), 4.0, kExact);
  EXPECT_NEAR(v.at("occl_end_error"), 4.0, kExact);
  EXPECT_NEAR(v.at("reacq_error"), 5.0, kExact);
  EXPECT_NEAR(v.at("reacq_1s_rmse"), std::sqrt((25.0 + 36 + 49 + 64 + 81) / 5), kExact);
  // and no alarm in a run without a monitor, no detection figures without an onset
  EXPECT_EQ(v.at("alarms"), 0.0);
  EXPECT_EQ(v.at("false_alarms_per_min"), 0.0);
  EXPECT_EQ(v.count("detected"), 0u);
  EXPECT_EQ(v.count("effort"), 0u);  // no command in open loop
}

TEST(RunMetrics, DetectionCountsTheFirstAlarmInTheWindowAfterTheOnset) {
  // GIVEN an onset at 1.02 s, frames every 40 ms (first frame after it: 1.04 s), a 10 s run
  PredictionExperimentConfig cfg;
  cfg.duration_s = 10.0;
  const auto onset = makeChannelTrajectory("onset-sinusoid", Params{{"t_start", 1.02}});
  std::vector<double> t, e;
  std::vector<bool> lost;
  for (int k = 0; k < 250; ++k) t.push_back(0.04 * k), e.push_back(1.0), lost.push_back(false);
  ChannelExperimentResult r = handMade(t, e, lost);
  // WHEN alarms come from the frames of 1.12 s (2 frames late) and 5 s
  r.alarm_t_acq_s = {1.12, 5.0};
  auto v = asMap(openLoopRunValues(r, cfg, *onset));
  // THEN the onset is detected with a 2-frame delay and the other alarm is false: 1 per 1/6 min
  EXPECT_EQ(v.at("detected"), 1.0);
  EXPECT_NEAR(v.at("detect_delay_frames"), 2.0, kExact);
  EXPECT_EQ(v.at("alarms"), 2.0);
  EXPECT_NEAR(v.at("false_alarms_per_min"), 6.0, kExact);
  // WHEN the only alarm comes after the detection window (onset + 0.5 s)
  r.alarm_t_acq_s = {1.6};
  v = asMap(openLoopRunValues(r, cfg, *onset));
  // THEN nothing is detected and that alarm is a false one
  EXPECT_EQ(v.at("detected"), 0.0);
  EXPECT_TRUE(std::isnan(v.at("detect_delay_frames")));
  EXPECT_NEAR(v.at("false_alarms_per_min"), 6.0, kExact);
  // and the onset is a manoeuvre: the response figures are there
  EXPECT_EQ(v.count("resp_time_s"), 1u);
}

TEST(RunMetrics, NamesDependOnTheConfigurationOnlyAndAreDefined) {
  // GIVEN a short E7-like run: the 3-channel E6 target with an occlusion
  PredictionExperimentConfig cfg;
  cfg.duration_s = 3.0;
  cfg.timing.base_period_s = 0.1;
  cfg.occlusions = {{1.0, 1.5}};
  const auto e6 = makeChannelTrajectory("e6-target");
  std::vector<std::string> first;
  for (const char* name : {"hold", "kf-cv", "st-akf-pm"})
    for (std::uint64_t seed : {1u, 2u}) {
      cfg.seed = seed;
      auto p = makePredictor(name, 3);
      // WHEN each predictor runs on each seed
      const NamedValues v = openLoopRunValues(runChannelExperiment(cfg, *e6, *p), cfg, *e6);
      // THEN every run has the same names in the same order
      if (first.empty()) first = namesOf(v);
      EXPECT_EQ(namesOf(v), first) << name << " seed " << seed;
    }
  const std::vector<std::string> head = {"rmse", "final", "max", "peak", "iae", "settling_s",
                                         "pos_mse_x_i", "pos_mse_y_i", "pos_mse_d_x"};
  ASSERT_GE(first.size(), head.size());
  EXPECT_EQ(std::vector<std::string>(first.begin(), first.begin() + static_cast<long>(head.size())), head);
  EXPECT_NE(std::find(first.begin(), first.end(), "reacq_1s_rmse"), first.end());
  EXPECT_EQ(std::find(first.begin(), first.end(), "resp_max_lag"), first.end());  // e6-target: no manoeuvre
  // and every name, and every name of metricValues(), has a definition
  for (const auto& kv : metricValues(Metrics{})) first.push_back(kv.first);
  for (const auto& n : first) EXPECT_FALSE(runMetricDefinition(n).empty()) << n;
  EXPECT_TRUE(runMetricDefinition("sliding_rms_final").empty());  // a task's own figure
}

}  // namespace
}  // namespace predvs
