// Metrics on signals with known answers.
#include "predvs/servo/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kTol = 1e-9;  // sums of a few hundred exact terms

TEST(Metrics, ExponentialDecayToAConstant) {
  // GIVEN e(t) = 1 + 9 exp(-t) sampled every 10 ms over 20 s
  std::vector<double> t, e;
  for (int i = 0; i <= 2000; ++i) {
    t.push_back(0.01 * i);
    e.push_back(1.0 + 9.0 * std::exp(-t.back()));
  }
  MetricsOptions raw;
  raw.settling_smoothing_s = 0.0;
  const Metrics m = computeMetrics(t, e, raw);
  // THEN the steady figures see ~1, the peak is 10, and e enters the 5 % band when 9 e^-t = 0.45
  EXPECT_NEAR(m.final_error, 1.0, 1e-6);
  EXPECT_NEAR(m.rmse, 1.0, 1e-3);
  EXPECT_NEAR(m.peak_error, 10.0, kTol);
  EXPECT_NEAR(m.settling_time_s, std::log(9.0 / 0.45), 0.011);  // one sample of 10 ms
  // left rectangle rule: + step (e0 - e_end) / 2 = 0.045, plus the last sample's extra step (0.01)
  EXPECT_NEAR(m.iae, 20.0 + 9.0 * (1 - std::exp(-20.0)), 0.06);
  EXPECT_TRUE(std::isnan(m.control_effort));
  EXPECT_EQ(m.steady_samples, 1001);
}

TEST(Metrics, SettlingIgnoresNoiseAfterTheTransient) {
  // GIVEN a step response 5 exp(-2 t) + 1 with seeded uniform noise of +-0.5 on top, 10 ms steps
  std::vector<double> t, e;
  unsigned state = 12345u;
  for (int i = 0; i <= 3000; ++i) {
    state = state * 1664525u + 1013904223u;  // LCG: deterministic, platform independent
    const double w = (state >> 8) / double(1u << 24);
    t.push_back(0.01 * i);
    e.push_back(1.0 + 5.0 * std::exp(-2.0 * t.back()) + (w - 0.5));
  }
  const Metrics m = computeMetrics(t, e);
  // THEN the settling time is a transient time (the smoothed curve enters the band within ~2 s),
  // not a late noise spike
  ASSERT_FALSE(std::isnan(m.settling_time_s));
  EXPECT_LT(m.settling_time_s, 3.0);
  EXPECT_GT(m.settling_time_s, 0.5);
}

TEST(Metrics, ControlEffortAndNaNSkipping) {
  std::vector<double> t = {0, 1, 2, 3}, e = {NAN, 2, 2, 2};
  std::vector<Eigen::VectorXd> v(4, Eigen::VectorXd::Zero(6));
  for (auto& x : v) x(0) = 2.0;
  const Metrics m = computeMetrics(t, e, {}, &v);
  EXPECT_NEAR(m.control_effort, 16.0, kTol);
  EXPECT_NEAR(m.rmse, 2.0, kTol);
  EXPECT_NEAR(m.iae, 6.0, kTol);
  EXPECT_THROW(computeMetrics({0, 1}, {1}), std::invalid_argument);
  MetricsOptions bad;
  bad.steady_start_fraction = 1.5;
  EXPECT_THROW(computeMetrics(t, e, bad), std::invalid_argument);
}

/// A piecewise-constant signed error along the change direction, sampled every 10 ms: `before`
/// until t = 5 s (the change), then a lag of 2 for 1 s, an overshoot of 1 for 1 s, then 0.
void responseCurve(double before, std::vector<double>& t, std::vector<double>& e, std::vector<double>& s) {
  for (int i = 0; i <= 1000; ++i) {
    const double ti = 0.01 * i;
    const double si = ti < 5.0 ? before : ti < 6.0 ? -2.0 : ti < 7.0 ? 1.0 : 0.0;
    t.push_back(ti);
    s.push_back(si);
    e.push_back(std::abs(si));
  }
}

TEST(Response, LagOvershootMeanAndResponseTime) {
  // GIVEN a lag of 2 for 1 s after the change at 5 s, then an overshoot of 1 for 1 s, then 0
  std::vector<double> t, e, s;
  responseCurve(0.0, t, e, s);
  MetricsOptions raw;
  raw.settling_smoothing_s = 0.0;  // judge the raw curve: exact expected values
  // WHEN the response to the change at 5 s is computed
  const ResponseMetrics r = computeResponse(t, e, s, 5.0, raw);
  // THEN lag and overshoot are the plateaus, the mean over 3 s is (2 + 1 + 0) / 3 and the error
  // is back to 0 from t = 7 s, 2 s after the change
  EXPECT_NEAR(r.max_lag, 2.0, kTol);
  EXPECT_NEAR(r.overshoot, 1.0, kTol);
  EXPECT_NEAR(r.mean_after, 3.0 / 3.0, 0.01);  // one sample of quantisation over 301 samples
  EXPECT_NEAR(r.response_s, 2.0, 0.011);
  // AND with the default 0.5 s trailing mean the plateaus (longer than the window) are still
  // reached, and the response ends up to one window later
  const ResponseMetrics smooth = computeResponse(t, e, s, 5.0);
  EXPECT_NEAR(smooth.max_lag, 2.0, kTol);
  EXPECT_NEAR(smooth.overshoot, 1.0, kTol);
  EXPECT_GT(smooth.response_s, 2.0);
  EXPECT_LE(smooth.response_s, 2.51);
}

TEST(Response, LagAndOvershootOnlyWithinTheResponseWindow) {
  // GIVEN the response curve (lag 2 in [5, 6) s, overshoot 1 in [6, 7) s) with a noise spike of
  // +5 at t = 9 s and -7 at t = 9.5 s, 4-4.5 s after the change
  std::vector<double> t, e, s;
  responseCurve(0.0, t, e, s);
  for (size_t i = 0; i < t.size(); ++i)
    if (std::abs(t[i] - 9.0) < 1e-9) s[i] = 5.0, e[i] = 5.0;
    else if (std::abs(t[i] - 9.5) < 1e-9) s[i] = -7.0, e[i] = 7.0;
  MetricsOptions raw;
  raw.settling_smoothing_s = 0.0;
  // WHEN the response is taken over the default 3 s window
  const ResponseMetrics r = computeResponse(t, e, s, 5.0, raw);
  // THEN the spikes after the window do not count
  EXPECT_NEAR(r.max_lag, 2.0, kTol);
  EXPECT_NEAR(r.overshoot, 1.0, kTol);
  // AND over a 5 s window they do
  raw.response_window_s = 5.0;
  const ResponseMetrics wide = computeResponse(t, e, s, 5.0, raw);
  EXPECT_NEAR(wide.max_lag, 7.0, kTol);
  EXPECT_NEAR(wide.overshoot, 5.0, kTol);
  // AND a window <= 0 is rejected by name
  raw.response_window_s = 0.0;
  try {
    computeResponse(t, e, s, 5.0, raw);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& ex) {
    EXPECT_NE(std::string(ex.what()).find("response_window_s"), std::string::npos) << ex.what();
  }
}

TEST(Response, OnlyTheSamplesFromTheChangeOnCount) {
  // GIVEN a large error before the change
  std::vector<double> t, e, s;
  responseCurve(-50.0, t, e, s);
  MetricsOptions raw;
  raw.settling_smoothing_s = 0.0;
  // THEN it does not enter the response to the change at 5 s
  const ResponseMetrics r = computeResponse(t, e, s, 5.0, raw);
  EXPECT_NEAR(r.max_lag, 2.0, kTol);
  // AND a change after the last sample gives NaN figures; bad sizes throw
  EXPECT_TRUE(std::isnan(computeResponse(t, e, s, 20.0).max_lag));
  EXPECT_THROW(computeResponse({0, 1}, {1, 1}, {1}, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace predvs

namespace predvs {
namespace {

TEST(FeatureErrorValues, SteadyWindowMeanRmsAndMaxPerFeature) {
  // GIVEN two features with s* = (10, 0) over four samples; the steady window is the second half
  const std::vector<double> t = {0.0, 1.0, 2.0, 3.0};
  std::vector<Eigen::VectorXd> s(4, Eigen::VectorXd::Zero(2));
  s[0] << 100.0, 100.0;  // transient: ignored
  s[1] << 100.0, 100.0;  // t = 1 < 1.5: ignored
  s[2] << 12.0, -3.0;
  s[3] << 8.0, std::numeric_limits<double>::quiet_NaN();  // a lost sample is skipped
  const Eigen::Vector2d desired(10.0, 0.0);
  // WHEN computing the per-feature figures
  const NamedValues v = featureErrorValues(t, s, desired, {"u0", "v0"});
  // THEN they come as mean_e_*, rms_e_*, max_e_* per feature, in feature order
  ASSERT_EQ(v.size(), 6u);
  EXPECT_EQ(v[0].first, "mean_e_u0");
  EXPECT_DOUBLE_EQ(v[0].second, 0.0);           // (+2 - 2) / 2
  EXPECT_DOUBLE_EQ(v[1].second, -3.0);          // mean_e_v0: one finite sample
  EXPECT_EQ(v[2].first, "rms_e_u0");
  EXPECT_DOUBLE_EQ(v[2].second, 2.0);
  EXPECT_EQ(v[5].first, "max_e_v0");
  EXPECT_DOUBLE_EQ(v[5].second, 3.0);
  EXPECT_THROW(featureErrorValues(t, s, desired, {"u0"}), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
