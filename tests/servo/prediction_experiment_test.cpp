// Open-loop prediction experiment: timing of deliveries, the hold baseline's known error, and the
// Kalman predictors' behaviour on E1-like motion (docs/MODELS.md §10).
#include "predvs/predictors/predictor.h"
#include "predvs/servo/prediction_experiment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kTimeTol = 1e-12;

PredictionExperimentConfig noiseless() {
  PredictionExperimentConfig c;
  c.noise.kind = NoiseKind::None;
  c.duration_s = 10.0;
  return c;
}

TEST(PredictionExperiment, HoldLagsByTheHorizon) {
  // GIVEN the E1 line (|v| = 10 sqrt 2 per s), no noise, two-frame latency, hold
  const auto line = makeTrajectory("line");
  auto hold = makePredictor("hold", 2);
  const PredictionResult r = runPredictionExperiment(noiseless(), *line, *hold);
  // THEN the first row is at the first delivery (t = 0.08 s) and every row predicts 0.08 s ahead
  ASSERT_FALSE(r.trace.empty());
  EXPECT_NEAR(r.trace.front().t_s, 0.08, kTimeTol);
  EXPECT_NEAR(r.trace.front().t_acq_s, 0.0, kTimeTol);
  EXPECT_EQ(r.trace.size(), 249u);  // ticks 2 .. 250
  for (const auto& s : r.trace) EXPECT_NEAR(s.horizon_s, 0.08, 1e-9);
  // and the hold error is exactly |v| * horizon
  EXPECT_NEAR(r.metrics.rmse, std::sqrt(200.0) * 0.08, 1e-9);
  EXPECT_NEAR(r.metrics.final_error, std::sqrt(200.0) * 0.08, 1e-9);
}

TEST(PredictionExperiment, ConstantVelocityFilterRemovesTheLagOnALine) {
  // GIVEN the same line without noise
  const auto line = makeTrajectory("line");
  auto kf = makePredictor("kf-cv", 2);
  const PredictionResult r = runPredictionExperiment(noiseless(), *line, *kf);
  // THEN after the transient the CV model predicts a line exactly (sub-millipixel)
  EXPECT_LT(r.metrics.final_error, 1e-3);
  EXPECT_LT(r.metrics.rmse, 1e-3);
}

TEST(PredictionExperiment, PredictorsBeatHoldOnNoisyCircle) {
  // GIVEN E4's circle scaled to 200 px radius, 1 px Gaussian noise, seed 3
  PredictionExperimentConfig c;
  c.seed = 3;
  const auto circle = makeTrajectory("circle", Params{{"radius", 200}});
  auto hold = makePredictor("hold", 2);
  auto kf = makePredictor("kf-cv", 2);
  const double e_hold = runPredictionExperiment(c, *circle, *hold).metrics.rmse;
  const double e_kf = runPredictionExperiment(c, *circle, *kf).metrics.rmse;
  // THEN hold's error combines the travel over 80 ms (200 * 0.15 * 0.08 = 2.4 px) with the noise
  // of both axes (sigma^2 = 1 px^2 each); 0.1 px covers the sample spread over 250 frames
  EXPECT_NEAR(e_hold, std::sqrt(2.4 * 2.4 + 2.0), 0.1);
  EXPECT_LT(e_kf, e_hold);
}

TEST(PredictionExperiment, OcclusionIsPredictOnly) {
  // GIVEN the line hidden between 3 and 5 s
  PredictionExperimentConfig c = noiseless();
  c.occlusions.push_back({3.0, 5.0});
  c.lost.action = LostAction::Extrapolate;  // the lost-feature policy off: predict-only throughout
  const auto line = makeTrajectory("line");
  // (coast_tau_s = 0: no coasting decay, so the gap is a pure constant-velocity extrapolation)
  auto kf = makePredictor("kf-cv", 2, {{"coast_tau_s", 0.0}});
  const PredictionResult r = runPredictionExperiment(c, *line, *kf);
  // THEN rows during the occlusion flag the measurement as lost but the prediction continues
  int lost = 0;
  for (const auto& s : r.trace) {
    if (!s.measured_valid) {
      ++lost;
      EXPECT_TRUE(std::isnan(s.measured.x()));
      EXPECT_LT(s.error, 1e-3) << "at t = " << s.t_s;  // a CV model extrapolates a line exactly
    }
  }
  EXPECT_EQ(lost, 50);  // frames at 3.00 .. 4.96 s
}

TEST(PredictionExperiment, SeededAndValidated) {
  PredictionExperimentConfig c;
  c.seed = 11;
  const auto circle = makeTrajectory("circle");
  auto a = makePredictor("kf-ca", 2);
  const double e1 = runPredictionExperiment(c, *circle, *a).metrics.rmse;
  const double e2 = runPredictionExperiment(c, *circle, *a).metrics.rmse;  // reset() inside
  EXPECT_EQ(e1, e2);
  auto eight = makePredictor("kf-cv", 8);
  EXPECT_THROW(runPredictionExperiment(c, *circle, *eight), std::invalid_argument);
  c.occlusions.push_back({2.0, 1.0});
  EXPECT_THROW(runPredictionExperiment(c, *circle, *a), std::invalid_argument);
  EXPECT_EQ(predictionTraceColumns().size(), predictionTraceRow(PredictionSample{}).size());
}

}  // namespace
}  // namespace predvs
