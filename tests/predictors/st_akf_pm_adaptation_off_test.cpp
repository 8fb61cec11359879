// st-akf-pm with `adaptation: off` (st_akf.h): the discontinuity monitor is off too, so the
// structure is the fixed Kalman filter of its model, as for st-akf and fakf-classic.
#include "predvs/predictors/registry.h"
#include "predvs/predictors/st_akf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

namespace predvs {
namespace {

TEST(StAkfPmAdaptationOff, MonitorIsSilentAndTheFilterIsTheFixedKalmanFilter) {
  for (const std::string model : {"cv", "ca"}) {
    SCOPED_TRACE(model);
    // GIVEN st-akf-pm with a monitor band so tight that it fires on noise (pm_band at its lower
    // bound, no floor), with adaptation on and off, and kf-cv / kf-ca with the same noise
    Params p;
    p.setText("model", model);
    p.set("q", model == "cv" ? 2e3 : 5e4);
    p.set("r", 1.5);
    p.set("shrink_sigmas", 0.0);
    p.set("pm_band", 1e-6);
    p.set("pm_floor", 0.0);
    Params off = p;
    off.setText("adaptation", "off");
    Params kf;
    kf.set("q", model == "cv" ? 2e3 : 5e4);
    kf.set("r", 1.5);
    kf.set("shrink_sigmas", 0.0);
    auto on = makePredictor("st-akf-pm", 2, p);
    auto pm_off = makePredictor("st-akf-pm", 2, off);
    auto fixed = makePredictor(model == "cv" ? "kf-cv" : "kf-ca", 2, kf);
    // WHEN they run along a noisy track with a jump
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 1.0);
    double worst = 0.0;
    for (int n = 0; n < 300; ++n) {
      const double t = n / 30.0;
      Eigen::VectorXd z(2);
      z << 50.0 * std::sin(t) + (n >= 150 ? 40.0 : 0.0) + noise(rng), 10.0 * t + noise(rng);
      on->update(t, z);
      pm_off->update(t, z);
      fixed->update(t, z);
      for (int c = 0; c < 2; ++c)
        worst = std::max(worst, std::abs(pm_off->predictPosition(c, t + 0.066) - fixed->predictPosition(c, t + 0.066)));
    }
    // THEN the monitor fires with adaptation on, never with it off, and off forecasts as the fixed KF
    EXPECT_GT(on->monitorAlarms(), 0);
    EXPECT_EQ(pm_off->monitorAlarms(), 0);
    constexpr double kRoundingPx = 1e-9;
    EXPECT_LT(worst, kRoundingPx);
  }
}

}  // namespace
}  // namespace predvs
