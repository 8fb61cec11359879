// `adaptation: off` (kalman_math.h adaptationParam): an adaptive filter with its adaptive layer
// off is the fixed Kalman filter it is built on, and the structure the noise fit tries for it.
#include "predvs/predictors/cs_akf.h"
#include "predvs/predictors/fakf.h"
#include "predvs/predictors/registry.h"
#include "predvs/predictors/st_akf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

/// A manoeuvring 2-channel track at 30 Hz with 1 px noise and a jump: something every adaptive
/// layer reacts to.
template <typename F>
void runManoeuvre(F&& step) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int n = 0; n < 400; ++n) {
    const double t = n / 30.0;
    const double jump = n >= 200 ? 60.0 : 0.0;
    Eigen::VectorXd z(2);
    z << 80.0 * std::sin(0.8 * t) + jump + noise(rng), 20.0 * t + 3.0 * t * t + noise(rng);
    if (n % 37 == 5) z(0) = std::nan("");  // a dropped measurement on one channel
    step(t, z);
  }
}

/// Largest |difference| between the two predictors' forecasts 2 frames ahead along the track.
double maxForecastDifference(Predictor& a, Predictor& b) {
  double worst = 0.0;
  runManoeuvre([&](double t, const Eigen::VectorXd& z) {
    a.update(t, z);
    b.update(t, z);
    for (int c = 0; c < 2; ++c)
      worst = std::max(worst, std::abs(a.predictPosition(c, t + 2.0 / 30.0) - b.predictPosition(c, t + 2.0 / 30.0)));
  });
  return worst;
}

Params fixedNoise(const std::string& model) {
  Params p;
  p.setText("model", model);
  p.set("q", model == "cv" ? 2e3 : 5e4);
  p.set("r", 1.5);
  p.set("p0_vel", 1e4);
  p.set("shrink_sigmas", 0.0);
  p.set("hold_blend_tau_s", 0.0);
  return p;
}

TEST(AdaptationOff, StAkfAndFakfClassicOffAreTheFixedKalmanFilterOfTheirModel) {
  for (const char* name : {"st-akf", "st-akf-pm", "fakf-classic"}) {
    for (const std::string model : {"cv", "ca"}) {
      SCOPED_TRACE(std::string(name) + " " + model);
      // GIVEN the adaptive filter with adaptation off and kf-cv / kf-ca with the same noise
      Params off = fixedNoise(model);
      off.setText("adaptation", "off");
      if (std::string(name) == "st-akf-pm") off.set("pm_band", 1e6);  // the monitor never fires here
      Params kf;
      kf.set("q", model == "cv" ? 2e3 : 5e4);
      kf.set("r", 1.5);
      kf.set("p0_vel", 1e4);
      kf.set("shrink_sigmas", 0.0);
      kf.set("hold_blend_tau_s", 0.0);
      auto a = makePredictor(name, 2, off);
      auto b = makePredictor(model == "cv" ? "kf-cv" : "kf-ca", 2, kf);
      // WHEN both run along a manoeuvring track THEN their forecasts agree to rounding
      EXPECT_LT(maxForecastDifference(*a, *b), 1e-9);
      // and with adaptation on they do not (the adaptive layer acts on this track)
      auto on = makePredictor(name, 2, fixedNoise(model));
      auto b2 = makePredictor(model == "cv" ? "kf-cv" : "kf-ca", 2, kf);
      EXPECT_GT(maxForecastDifference(*on, *b2), 1e-3);
    }
  }
}

TEST(AdaptationOff, CsAdaptiveFiltersKeepSigmaOnItsFloorAndFakfKeepsR) {
  Params p;
  p.set("r", 2.0);
  p.set("sigma_min_sq", 500.0);
  p.setText("adaptation", "off");
  // GIVEN cs-akf-adaptive and fakf with adaptation off
  CsAkfAdaptivePredictor cs(2, p);
  FakfPredictor fakf(2, p);
  double worst_sigma = 0.0, worst_r = 0.0;
  // WHEN they run through a manoeuvre and a jump
  runManoeuvre([&](double t, const Eigen::VectorXd& z) {
    cs.update(t, z);
    fakf.update(t, z);
    for (int c = 0; c < 2; ++c) {
      worst_sigma = std::max({worst_sigma, std::abs(cs.accelerationVariance(c) - 500.0),
                              std::abs(fakf.accelerationVariance(c) - 500.0)});
      worst_r = std::max(worst_r, std::abs(fakf.adaptedR(c) - 2.0));
    }
  });
  // THEN sigma^2 stays at sigma_min_sq and fakf's R at r, and both forecast the same
  EXPECT_EQ(worst_sigma, 0.0);
  EXPECT_EQ(worst_r, 0.0);
  CsAkfAdaptivePredictor cs2(2, p);
  FakfPredictor fakf2(2, p);
  EXPECT_LT(maxForecastDifference(cs2, fakf2), 1e-9);
  // and sigma_max_sq, which no longer acts, is not a noise parameter to fit
  for (const auto& k : cs.noiseParameters()) EXPECT_NE(k.key, "sigma_max_sq");
}

TEST(AdaptationOff, EveryAdaptiveFilterOffersItsStructuresWithAdaptationOffAndRejectsABadWord) {
  for (const char* name : {"st-akf", "st-akf-pm", "fakf-classic", "cs-akf-adaptive", "fakf"}) {
    SCOPED_TRACE(name);
    // GIVEN its structural variants
    const auto variants = makePredictor(name, 1)->structuralVariants();
    // THEN the second half repeats the first with adaptation: off
    ASSERT_EQ(variants.size() % 2, 0u);
    const size_t half = variants.size() / 2;
    for (size_t i = 0; i < half; ++i) {
      EXPECT_EQ(variants[i].text("adaptation", "on"), "on");
      EXPECT_EQ(variants[half + i].text("adaptation", ""), "off");
      EXPECT_EQ(variants[half + i].text("model", "-"), variants[i].text("model", "-"));
      EXPECT_EQ(variants[half + i].text("mean", "-"), variants[i].text("mean", "-"));
    }
    // and a word other than on / off is a one-line error naming the key
    Params bad;
    bad.setText("adaptation", "maybe");
    try {
      makePredictor(name, 1, bad);
      ADD_FAILURE() << "accepted adaptation: maybe";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'adaptation'"), std::string::npos) << e.what();
    }
  }
  // stkf turns its self-tuning off with window 0, a structure of each model and of the
  // white-acceleration cv model (stkf.h)
  const auto stkf = makePredictor("stkf", 1)->structuralVariants();
  int fixed = 0;
  for (const auto& v : stkf) fixed += v.values().count("window") && v.values().at("window") == 0.0 ? 1 : 0;
  EXPECT_EQ(fixed, 3);
}

}  // namespace
}  // namespace predvs
