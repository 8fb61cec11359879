// The significance-weighted forecast of the per-channel filters (channel_predictor.h, issue 11
// item 3): off at shrink_sigmas = shrink_v_sigmas = 0 bit for bit, half of a (or v) at exactly n
// standard deviations, the filter's own state untouched, predictPosition() = predict().position().
#include "predvs/predictors/fakf.h"
#include "predvs/predictors/kalman_baselines.h"
#include "predvs/predictors/st_akf.h"
#include "predvs/predictors/stkf.h"
#include "predictors/accelerating_feed.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace predvs {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// 1 s of a noisy accelerating target at 10 Hz, 3 px noise (accelerating_feed.h).
template <class F>
void feed(F& f) {
  feedAcceleratingTarget(f, 5);
}

constexpr double kH = 0.2;  // s, the 2-frame horizon at 10 Hz

TEST(ForecastWeighting, ZeroIsTheUnweightedFilterBitForBit) {
  // GIVEN kf-ca with shrink_sigmas 0 (and no blend with hold) after 1 s of data
  KfCaPredictor f(1, {{"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}, {"q", kDefaultQCa}, {"r", 9.0}});
  feed(f);
  // WHEN it forecasts kH ahead
  const Gaussian<3> g = f.gaussian(0);
  const double t = f.time() + kH, h = t - f.time();  // the dt predict() computes
  Gaussian<3> model = g;
  timeUpdate(model, caTransition(h), caProcessNoise(kDefaultQCa, h));
  const ChannelEstimate e = f.predict(0, t);
  // THEN it is the model's own time update of x(k|k), P(k|k), to the bit, on both query paths
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(sameBits(e.x(i), model.x(i))) << i;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_TRUE(sameBits(e.P(i, j), model.P(i, j))) << i << j;
  EXPECT_TRUE(sameBits(f.predictPosition(0, t), predictedPosition(g, caTransition(h))));
}

TEST(ForecastWeighting, HalvesAccelerationAndVelocityAtNSigmas) {
  // GIVEN the same data in an unweighted kf-ca, which gives x(k|k) and P(k|k) (the weighting does
  // not touch the filter, so every filter below holds the same Gaussian)
  // (the blend with hold off: this test is about the significance weights alone)
  const Params base{{"q", kDefaultQCa}, {"r", 9.0}, {"hold_blend_tau_s", 0.0}};
  Params off = base;
  off.set("shrink_sigmas", 0.0);
  KfCaPredictor ref(1, off);
  feed(ref);
  const Gaussian<3> g = ref.gaussian(0);
  const double n_a = std::abs(g.x(2)) / std::sqrt(g.P(2, 2));
  const double n_v = std::abs(g.x(1)) / std::sqrt(g.P(1, 1));
  ASSERT_GT(n_a, 0.05);  // measured 0.099: a weighting on (n > 0) that matters
  ASSERT_GT(n_v, 0.05);
  const double p = g.x(0), v = g.x(1), a = g.x(2);
  // WHEN shrink_sigmas is |a| / sigma_a (velocity not weighted)
  Params pa = base;
  pa.set("shrink_sigmas", n_a);
  pa.set("shrink_v_sigmas", 0.0);
  KfCaPredictor fa(1, pa);
  feed(fa);
  // THEN the forecast extrapolates a / 2, and the filter's state is unchanged
  EXPECT_NEAR(fa.predictPosition(0, fa.time() + kH), p + v * kH + 0.5 * (a / 2.0) * kH * kH, 1e-9);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(sameBits(fa.gaussian(0).x(i), g.x(i))) << i;
  // WHEN shrink_v_sigmas is |v| / sigma_v (acceleration weight off): v and a both count half
  Params pv = base;
  pv.set("shrink_sigmas", 0.0);
  pv.set("shrink_v_sigmas", n_v);
  KfCaPredictor fv(1, pv);
  feed(fv);
  EXPECT_NEAR(fv.predictPosition(0, fv.time() + kH), p + (v / 2.0) * kH + 0.5 * (a / 2.0) * kH * kH, 1e-9);
  // and shrink_v_sigmas defaults to shrink_sigmas: both weights at n = n_v
  Params pb = base;
  pb.set("shrink_sigmas", n_v);
  KfCaPredictor fb(1, pb);
  feed(fb);
  const double w_a = significanceWeight(a, g.P(2, 2), n_v);
  EXPECT_NEAR(fb.predictPosition(0, fb.time() + kH), p + (v / 2.0) * kH + 0.5 * (w_a * a / 2.0) * kH * kH, 1e-9);
}

TEST(ForecastWeighting, DefaultsWeighAndBothQueryPathsAgree) {
  // GIVEN each weighted filter with its defaults, and the same filter with shrink_sigmas 0 and
  // hold_blend_tau_s 0 (the plain forecast: neither weighted nor blended with hold)
  auto check = [](Predictor& on, Predictor& off, const char* what, bool weighted = true) {
    feed(on);
    feed(off);
    const double t = on.time() + kH;
    // THEN predictPosition() is predict().position() to the bit, and the weighting moved the
    // forecast (10 Hz, 3 px: v and a are not many sigmas from zero after 1 s)
    EXPECT_TRUE(sameBits(on.predictPosition(0, t), on.predict(0, t).position())) << what;
    if (weighted)
      EXPECT_NE(on.predictPosition(0, t), off.predictPosition(0, t)) << what;
    else  // a default of 0: the unweighted forecast, bit for bit
      EXPECT_TRUE(sameBits(on.predictPosition(0, t), off.predictPosition(0, t))) << what;
    EXPECT_TRUE(sameBits(off.predictPosition(0, t), off.predict(0, t).position())) << what;
  };
  const Params off{{"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}};
  const auto withModel = [](Params p, const char* model) {
    p.setText("model", model);
    return p;
  };
  const Params ca = withModel({}, "ca"), ca_off = withModel(off, "ca");
  const Params cv = withModel({}, "cv"), cv_off = withModel(off, "cv");
  {
    KfCaPredictor a(1, {}), b(1, off);
    check(a, b, "kf-ca");
  }
  {
    KfCvPredictor a(1, {}), b(1, off);
    check(a, b, "kf-cv");  // weighted by the blend with hold (hold_blend_tau_s 0 given: off)
  }
  {
    StAkfPredictor<3> a(1, {}), b(1, off);
    check(a, b, "st-akf");
  }
  {
    StAkfPredictor<2> a(1, cv), b(1, cv_off);
    check(a, b, "st-akf model cv");
  }
  {
    StAkfPmPredictor<3> a(1, {}), b(1, off);
    check(a, b, "st-akf-pm");
  }
  {
    StkfCaPredictor a(1, ca), b(1, ca_off);
    check(a, b, "stkf model ca");
  }
  {
    StkfPredictor a(1, {}), b(1, off);
    check(a, b, "stkf");  // the blend with hold
  }
  {
    FakfClassicPredictor<2> a(1, {}), b(1, off);
    check(a, b, "fakf-classic");
  }
  {
    FakfClassicPredictor<3> a(1, ca), b(1, ca_off);
    check(a, b, "fakf-classic model ca");
  }
}

}  // namespace
}  // namespace predvs
