// stkf's `process_noise: white-acceleration` (stkf.h): with the self-tuning off (window 0) the cv
// filter is kf-cv's, so stkf's structural variants contain kf-cv's filter; its fit seeds.
#include "predvs/predictors/registry.h"
#include "predvs/predictors/stkf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

/// Largest |stkf - kf-cv| of the 2-frame forecast along a noisy track with a turn and 5 % drops.
double worstDifferencePx(const Params& stkf_params, const Params& kf_params) {
  auto stkf = makePredictor("stkf", 2, stkf_params);
  auto kf = makePredictor("kf-cv", 2, kf_params);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.5);
  std::uniform_real_distribution<double> drop(0.0, 1.0);
  double worst = 0.0;
  for (int n = 0; n < 600; ++n) {
    const double t = n / 30.0;
    Eigen::VectorXd z(2);
    z << 80.0 * std::sin(0.7 * t) + noise(rng), 12.0 * t + (t > 10.0 ? 3.0 * (t - 10.0) * (t - 10.0) : 0.0) + noise(rng);
    if (n > 20 && drop(rng) < 0.05) z(0) = z(1) = std::nan("");
    stkf->update(t, z);
    kf->update(t, z);
    for (int c = 0; c < 2; ++c)
      worst = std::max(worst, std::abs(stkf->predictPosition(c, t + 2.0 / 30.0) - kf->predictPosition(c, t + 2.0 / 30.0)));
  }
  return worst;
}

TEST(StkfWhiteAcceleration, WithoutSelfTuningItIsKfCvToRounding) {
  // GIVEN stkf on cv with the white-acceleration process noise and window 0, and kf-cv, with the
  // same q and r (and with r and q left at their defaults: auto r, kf-cv's q)
  Params s;
  s.setText("model", "cv");
  s.setText("process_noise", "white-acceleration");
  s.set("window", 0);
  Params k;
  EXPECT_LT(worstDifferencePx(s, k), 1e-9);  // defaults: q 1e4, r auto, P_0 = diag(R, 1e4)
  s.set("q", 2.5e3);
  s.set("r", 2.0);
  k.set("q", 2.5e3);
  k.set("r", 2.0);
  // WHEN both run along the same track THEN the forecasts agree to rounding
  EXPECT_LT(worstDifferencePx(s, k), 1e-9);
  // AND with the paper's diagonal process noise of the same velocity increment per 0.1 s they
  // do not (the structure is what differs)
  Params d;
  d.setText("model", "cv");
  d.set("window", 0);
  d.set("r", 2.0);
  d.set("q_vel", 2.5e3 * 0.1);
  EXPECT_GT(worstDifferencePx(d, k), 0.01);
}

TEST(StkfWhiteAcceleration, IsAStructuralVariantAndSeedsFromKfCv) {
  auto stkf = makePredictor("stkf", 1, {});
  bool found = false;
  for (const Params& v : stkf->structuralVariants())
    found = found || (v.text("process_noise", "") == "white-acceleration" && v.get("window", -1.0) == 0.0 &&
                      v.text("model", "") == "cv");
  EXPECT_TRUE(found);
  Params wa;
  wa.setText("model", "cv");
  wa.setText("process_noise", "white-acceleration");
  const auto seeds = makePredictor("stkf", 1, wa)->fitSeeds();
  ASSERT_EQ(seeds.size(), 1u);
  EXPECT_EQ(seeds[0].key, "q");
  EXPECT_EQ(seeds[0].from_predictor, "kf-cv");
  EXPECT_EQ(seeds[0].from_key, "q");
  // the diagonal cv model maps kf-cv's q onto the diagonal of its Q over q_period_s
  Params diag;
  diag.setText("model", "cv");
  diag.set("q_period_s", 0.2);
  const auto dseeds = makePredictor("stkf", 1, diag)->fitSeeds();
  ASSERT_EQ(dseeds.size(), 2u);
  EXPECT_DOUBLE_EQ(dseeds[0].factor, 0.2 * 0.2 * 0.2 / 3.0);  // q_pos
  EXPECT_DOUBLE_EQ(dseeds[1].factor, 0.2);                    // q_vel
}

TEST(StkfWhiteAcceleration, OtherWordIsAnErrorNamingTheKey) {
  Params p;
  p.setText("model", "cv");
  p.setText("process_noise", "white");
  try {
    makePredictor("stkf", 1, p);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("process_noise"), std::string::npos);
  }
}

}  // namespace
}  // namespace predvs
