// Metrics on signals with known answers.
#include "predvs/servo/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
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
  const Metrics m = computeMetrics(t, e);
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

TEST(Metrics, ControlEffortAndNaNSkipping) {
  std::vector<double> t = {0, 1, 2, 3}, e = {NAN, 2, 2, 2};
  std::vector<Eigen::Matrix<double, 6, 1>> v(4, Eigen::Matrix<double, 6, 1>::Zero());
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

}  // namespace
}  // namespace predvs
