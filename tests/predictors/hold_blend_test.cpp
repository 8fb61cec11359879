// The forecast's blend with hold (channel_predictor.h, `hold_blend_tau_s`, docs/MODELS.md §15):
// the least-squares weight of the model's one-frame forecast against hold's, with forgetting; an
// exact ramp keeps the model forecast (w = 1), noise around a still target moves it towards hold,
// and the filter itself is untouched.
#include "predvs/predictors/kalman_baselines.h"
#include "predvs/predictors/registry.h"
#include "predictors/blend_alone.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {
namespace {

constexpr double kRateHz = 10.0;
constexpr double kH = 2.0 / kRateHz;  // s, the 2-frame horizon
// Two double evaluations of the same blend differ by rounding only (px).
constexpr double kRoundingPx = 1e-9;

// Two configurations of one predictor, and hold, each on one channel, fed the same measurements.
struct TwinsAndHold {
  std::unique_ptr<Predictor> a, b, hold;
  TwinsAndHold(const char* name, const Params& pa, const Params& pb)
      : a(makePredictor(name, 1, pa)), b(makePredictor(name, 1, pb)), hold(makePredictor("hold", 1)) {}
  void update(double t_s, double z) {
    Eigen::VectorXd v(1);
    v(0) = z;
    a->update(t_s, v);
    b->update(t_s, v);
    hold->update(t_s, v);
  }
};

TEST(HoldBlend, ForecastIsHoldPlusTheLeastSquaresWeightTimesTheModelStep) {
  // GIVEN kf-cv with the blend (tau 2 s) and a twin without it, fed the same noisy sway with a
  // dropped frame every 7th (the shorter coasting of a gap after a stop, which comes with the blend,
  // off: it changes the coasted filter; coast_stop_test.cpp; so do the speed rule and the shape of
  // the coast, coast_fast_test.cpp)
  const double tau_s = 2.0;
  // (the one-frame regression alone, hold_blend_frames 1: the two-frame one is the next test's)
  // (and with the weight shrunk by its own uncertainty, hold_blend_sigmas 1, so that the whole rule
  // is checked)
  KfCvPredictor on(1, blendAlone(tau_s, {{"hold_blend_frames", 1.0}, {"hold_blend_sigmas", 1.0},
                                         {"hold_blend_split", 0.0}}));  // the one weight: the split's is its own test
  KfCvPredictor off(1, {{"hold_blend_tau_s", 0.0}});
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 2.0);
  double s_dd = 0.0, s_dy = 0.0, s_yy = 0.0, s_n = 0.0, w = 1.0, z_hold = 0.0;
  double shrink_min = 1.0;
  bool last_measured = false;
  Eigen::VectorXd z(1);
  for (int k = 0; k < 120; ++k) {
    const double t = k / kRateHz;
    const bool measured = k == 0 || k % 7 != 0;
    z(0) = measured ? 30.0 * std::sin(0.8 * t) + noise(rng) : std::nan("");
    // the twin's one-frame forecast, made before z(k) is seen (the blend does not change the filter)
    const double f = k > 0 ? off.predictPosition(0, t) : 0.0;
    if (measured && last_measured) {  // the regression of y = z - z_hold on d = f - z_hold
      const double lambda = std::exp(-(1.0 / kRateHz) / tau_s), d = f - z_hold, y = z(0) - z_hold;
      s_dd = lambda * s_dd + d * d;
      s_dy = lambda * s_dy + d * y;
      s_yy = lambda * s_yy + y * y;
      s_n = lambda * s_n + 1.0;
      w = s_dd > 0.0 ? std::clamp(s_dy / s_dd, 0.0, 1.0) : 1.0;  // no forecast step yet: the model's
      // times its significance (hold_blend_sigmas 1): ls^2 / (ls^2 + var(ls)), var(ls)
      // the residual variance over (count - 1) over S_dd
      if (s_dd > 0.0 && s_n > 2.0) {
        const double ls = s_dy / s_dd, var = (s_yy - s_dy * s_dy / s_dd) / (s_n - 1.0) / s_dd;
        const double shrink = ls * ls / (ls * ls + var);
        w *= shrink;
        shrink_min = std::min(shrink_min, shrink);
      }
    }
    if (measured) z_hold = z(0);
    last_measured = measured;
    on.update(t, z);
    off.update(t, z);
    // THEN the filter is the same, and the forecast is hold + w (model forecast - hold)
    const double t_f = t + kH;
    ASSERT_EQ(on.gaussian(0).x, off.gaussian(0).x) << k;
    const double expected = z_hold + w * (off.predictPosition(0, t_f) - z_hold);
    ASSERT_NEAR(on.predictPosition(0, t_f), expected, kRoundingPx) << k;
    ASSERT_EQ(on.predictPosition(0, t_f), on.predict(0, t_f).position()) << k;
    ASSERT_NEAR(on.predict(0, t_f).velocity(), w * off.predict(0, t_f).velocity(), kRoundingPx) << k;
  }
  // (the weight moved: the data are noisy enough for the regression to pull it below 1, and for
  // its own uncertainty to count)
  EXPECT_LT(w, 0.99);
  EXPECT_LT(shrink_min, 0.9);
}

TEST(HoldBlend, TheWeightIsTheSmallerOfTheOneAndTheTwoFrameRegressions) {
  // GIVEN kf-cv with the blend on two horizons (hold_blend_frames 2, the default) and a twin without
  // the blend, fed 20 s of short dashes at 10 Hz (moves of 3 frames at 200 px/s between rests of 5)
  // under 1 px noise, with a dropped frame every 11th; the coasting rules that come with the blend
  // off, as in the test above
  const double tau_s = 3.0;
  KfCvPredictor on(1, blendAlone(tau_s, {{"hold_blend_split", 0.0}}));
  KfCvPredictor off(1, {{"hold_blend_tau_s", 0.0}});
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  // The regressions of y = z_k - z_hold(k-h) on d = f(k | k-h) - z_hold(k-h), h = 1, 2
  std::array<double, 3> s_dd{}, s_dy{}, w{1.0, 1.0, 1.0};
  std::vector<double> z_at, t_at, forecast_2;  // per frame: z (NaN: dropped), t, the twin's forecast for frame k + 2
  double x = 0.0, w_min_seen = 1.0;
  int two_frame_samples = 0;
  Eigen::VectorXd z(1);
  for (int k = 0; k < 200; ++k) {
    const double t = k / kRateHz;
    if (k % 8 < 3) x += 200.0 / kRateHz;  // the dash
    const bool measured = k == 0 || k % 11 != 0;
    z(0) = measured ? x + noise(rng) : std::nan("");
    const double f1 = k > 0 ? off.predictPosition(0, t) : 0.0;
    const auto ku = static_cast<size_t>(k);
    const auto was = [&](int j) { return j >= 0 && std::isfinite(z_at[static_cast<size_t>(j)]); };
    if (measured && was(k - 1)) {
      const double lambda = std::exp(-(1.0 / kRateHz) / tau_s);
      const double zh1 = z_at[ku - 1];
      s_dd[1] = lambda * s_dd[1] + (f1 - zh1) * (f1 - zh1);
      s_dy[1] = lambda * s_dy[1] + (f1 - zh1) * (z(0) - zh1);
      w[1] = s_dd[1] > 0.0 ? std::clamp(s_dy[1] / s_dd[1], 0.0, 1.0) : 1.0;
      if (was(k - 2)) {
        const double zh2 = z_at[ku - 2], f2 = forecast_2[ku - 2];
        s_dd[2] = lambda * s_dd[2] + (f2 - zh2) * (f2 - zh2);
        s_dy[2] = lambda * s_dy[2] + (f2 - zh2) * (z(0) - zh2);
        w[2] = s_dd[2] > 0.0 ? std::clamp(s_dy[2] / s_dd[2], 0.0, 1.0) : 1.0;
        ++two_frame_samples;
      }
      w[0] = std::min(w[1], w[2]);
    }
    z_at.push_back(z(0));
    t_at.push_back(t);
    on.update(t, z);
    off.update(t, z);
    forecast_2.push_back(off.predictPosition(0, t + 2.0 / kRateHz));
    double z_hold = 0.0;  // the last measurement
    for (size_t j = z_at.size(); j-- > 0;)
      if (std::isfinite(z_at[j])) {
        z_hold = z_at[j];
        break;
      }
    // THEN the forecast is hold + min(w1, w2) (model forecast - hold), at any horizon
    for (const double h : {0.1, kH, 0.35}) {
      const double expected = z_hold + w[0] * (off.predictPosition(0, t + h) - z_hold);
      ASSERT_NEAR(on.predictPosition(0, t + h), expected, kRoundingPx) << k << " " << h;
    }
    w_min_seen = std::min(w_min_seen, w[0]);
  }
  // (both regressions ran, and on these dashes the two-frame one is the smaller, as the blend is for)
  EXPECT_GT(two_frame_samples, 100);
  EXPECT_LT(w[2], w[1]);
  EXPECT_LT(w_min_seen, 0.95);
}

TEST(HoldBlend, TwoWeightsAreTheLeastSquaresOfTheSmoothingStepAndTheExtrapolatedStep) {
  // GIVEN kf-cv with the blend split in two weights (the default) on the one-frame regression
  // (tau 2 s, hold_blend_frames 1) and a twin without the blend, fed a noisy sway with a dropped
  // frame every 7th; the coasting rules that come with the blend off, as in the first test
  const double tau_s = 2.0;
  KfCvPredictor on(1, blendAlone(tau_s, {{"hold_blend_frames", 1.0}}));
  KfCvPredictor off(1, {{"hold_blend_tau_s", 0.0}});
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 2.0);
  // y ~ w_s d_s + w_x d_x (d_s = p0 - z_hold, d_x = f - p0), and the one weight of y ~ w (d_s + d_x)
  double s_ss = 0.0, s_sx = 0.0, s_xx = 0.0, s_sy = 0.0, s_xy = 0.0, s_dd = 0.0, s_dy = 0.0;
  double w = 1.0, w_s = 1.0, w_x = 1.0, z_hold = 0.0;
  bool last_measured = false;
  int clamped = 0, free = 0;
  Eigen::VectorXd z(1);
  for (int k = 0; k < 150; ++k) {
    const double t = k / kRateHz;
    const bool measured = k == 0 || k % 7 != 0;
    z(0) = measured ? 30.0 * std::sin(0.8 * t) + noise(rng) : std::nan("");
    const double f = k > 0 ? off.predictPosition(0, t) : 0.0, p0 = off.gaussian(0).x(0);
    if (measured && last_measured) {
      const double lambda = std::exp(-(1.0 / kRateHz) / tau_s);
      const double d_s = p0 - z_hold, d_x = (f - z_hold) - d_s, d = f - z_hold, y = z(0) - z_hold;
      s_dd = lambda * s_dd + d * d;
      s_dy = lambda * s_dy + d * y;
      w = s_dd > 0.0 ? std::clamp(s_dy / s_dd, 0.0, 1.0) : 1.0;  // no forecast step yet: the model's
      s_ss = lambda * s_ss + d_s * d_s;
      s_sx = lambda * s_sx + d_s * d_x;
      s_xx = lambda * s_xx + d_x * d_x;
      s_sy = lambda * s_sy + d_s * y;
      s_xy = lambda * s_xy + d_x * y;
      // the normal equations [S_ss S_sx; S_sx S_xx] (a, b) = (S_sy, S_xy); the weight outside
      // [0, 1] clamped and the other one solved given it
      // (one direction, as the first sample always is: w for both)
      const double det = s_ss * s_xx - s_sx * s_sx;
      const double a = (s_xx * s_sy - s_sx * s_xy) / det, b = (s_ss * s_xy - s_sx * s_sy) / det;
      if (!(det > 1e-12 * s_ss * s_xx)) {
        w_s = w_x = w;
      } else if (a < 0.0 || a > 1.0) {
        w_s = std::clamp(a, 0.0, 1.0);
        w_x = std::clamp((s_xy - w_s * s_sx) / s_xx, 0.0, 1.0);
        ++clamped;
      } else if (b < 0.0 || b > 1.0) {
        w_x = std::clamp(b, 0.0, 1.0);
        w_s = std::clamp((s_sy - w_x * s_sx) / s_ss, 0.0, 1.0);
        ++clamped;
      } else {
        w_s = a;
        w_x = b;
        ++free;
      }
    }
    if (measured) z_hold = z(0);
    last_measured = measured;
    on.update(t, z);
    off.update(t, z);
    // THEN the filter is the same; a forecast made on a measured frame is
    // z_hold + w_s (p0 - z_hold) + w_x (model forecast - p0), its velocity scaled by w_x, and one
    // made in a gap is z_hold + w (model forecast - z_hold)
    const double t_f = t + kH, model = off.predictPosition(0, t_f), start = off.gaussian(0).x(0);
    ASSERT_EQ(on.gaussian(0).x, off.gaussian(0).x) << k;
    const double expected = measured ? z_hold + w_s * (start - z_hold) + w_x * (model - start) : z_hold + w * (model - z_hold);
    ASSERT_NEAR(on.predictPosition(0, t_f), expected, kRoundingPx) << k;
    ASSERT_NEAR(on.predict(0, t_f).position(), expected, kRoundingPx) << k;
    ASSERT_NEAR(on.predict(0, t_f).velocity(), (measured ? w_x : w) * off.predict(0, t_f).velocity(), kRoundingPx) << k;
  }
  // (both branches of the rule ran, and the two weights are not the one)
  EXPECT_GT(clamped, 0);
  EXPECT_GT(free, 0);
  EXPECT_GT(std::abs(w_s - w_x), 0.05);
}

TEST(HoldBlend, TwoWeightsKeepTheSmoothingOfAStillTargetThatOneWeightGivesUp) {
  // GIVEN kf-cv and kf-ca with the two weights (the default) and with one (hold_blend_split 0), and
  // hold, on 20 s of a still target under 3 px noise at 10 Hz: the filtered position is closer to
  // the target than the last measurement, and every velocity the filter sees is noise
  for (const char* name : {"kf-cv", "kf-ca"}) {
    SCOPED_TRACE(name);
    TwinsAndHold p(name, {}, {{"hold_blend_split", 0.0}});
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 3.0);
    double se_two = 0.0, se_one = 0.0, se_hold = 0.0;
    int n = 0;
    for (int k = 0; k < 200; ++k) {
      const double t = k / kRateHz;
      p.update(t, 100.0 + noise(rng));
      if (k < 30) continue;
      se_two += std::pow(p.a->predictPosition(0, t + kH) - 100.0, 2);
      se_one += std::pow(p.b->predictPosition(0, t + kH) - 100.0, 2);
      se_hold += std::pow(p.hold->predictPosition(0, t + kH) - 100.0, 2);
      ++n;
    }
    const double two = std::sqrt(se_two / n), one = std::sqrt(se_one / n), hold = std::sqrt(se_hold / n);
    // THEN the two weights keep part of the smoothing while one weight, which has to take the noisy
    // step with it, sits at hold (measured: 2.51 px against 3.08 and hold's 3.08, both filters)
    EXPECT_LT(two, 0.9 * one) << two << " " << one << " " << hold;
    EXPECT_LT(two, 0.9 * hold) << two << " " << one << " " << hold;
  }
}

TEST(HoldBlend, AnExactRampKeepsTheModelForecast) {
  // GIVEN kf-cv, kf-ca and imm with their defaults (blend on) but the start-up prior off (its
  // first forecasts are hold's: blend_start_test.cpp), with the one weight shrunk by its own
  // uncertainty (hold_blend_sigmas 1, hold_blend_split 0), and without the blend, on a noise-free
  // ramp at 80 px/s
  for (const char* name : {"kf-cv", "kf-ca", "imm"}) {
    auto on = makePredictor(name, 1, {{"hold_blend_prior", 0.0}});
    auto shrunk = makePredictor(name, 1, {{"hold_blend_sigmas", 1.0}, {"hold_blend_split", 0.0}, {"hold_blend_prior", 0.0}});
    auto off = makePredictor(name, 1, {{"hold_blend_tau_s", 0.0}});
    for (int k = 0; k < 60; ++k) {
      feedRamp(k, kRateHz, {on.get(), shrunk.get(), off.get()});
      const double t = k / kRateHz;
      // THEN the weights stay near 1: the model's forecast, within 0.05 px of the 16 px step, and
      // 0.002 px over the last second. They are a hair under 1 because the filters converge from
      // rest (the velocity starts at 0 with a large variance): their two-frame forecasts overshoot
      // the ramp by a little, and while they converge the filtered position is not the measurement
      // (d_s != 0), so the two weights (channel_predictor.h, "Two weights") fit those residuals
      // too; measured: kf-cv 0.046 px short on frame 3, 0.0011 px on the last; kf-ca 0.013 and 0
      const double tol = k < 50 ? 0.05 : 0.002;
      const double model = off->predictPosition(0, t + kH);
      EXPECT_NEAR(on->predictPosition(0, t + kH), model, tol) << name << " " << k;
      // and the shrunk one tends to 1 as the start's misfits are forgotten: the start-up costs up
      // to a fifth of the step in the first frames (the filters converging from rest leave residuals
      // the weight's variance counts), 0.06 px over the last second
      EXPECT_NEAR(shrunk->predictPosition(0, t + kH), model, k < 50 ? 3.5 : 0.06) << name << " " << k;
    }
  }
}

TEST(HoldBlend, NoiseAroundAStillTargetMovesTheForecastTowardsHold) {
  // GIVEN kf-cv (and imm, which blends its combined forecast the same way) with its defaults and
  // without the blend, 10 s of a still target under 3 px noise at 10 Hz (every velocity the filter
  // sees is noise)
  for (const char* name : {"kf-cv", "imm"}) {
  SCOPED_TRACE(name);
  TwinsAndHold p(name, {}, {{"hold_blend_tau_s", 0.0}});
  const auto &on = p.a, &off = p.b, &hold = p.hold;
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 3.0);
  double se_on = 0.0, se_off = 0.0, se_hold = 0.0;
  int n = 0;
  for (int k = 0; k < 100; ++k) {
    const double t = k / kRateHz;
    p.update(t, 100.0 + noise(rng));
    if (k < 30) continue;  // after the first 3 s
    const double truth = 100.0;
    se_on += std::pow(on->predictPosition(0, t + kH) - truth, 2);
    se_off += std::pow(off->predictPosition(0, t + kH) - truth, 2);
    se_hold += std::pow(hold->predictPosition(0, t + kH) - truth, 2);
    ++n;
  }
  const double rmse_on = std::sqrt(se_on / n), rmse_off = std::sqrt(se_off / n), rmse_hold = std::sqrt(se_hold / n);
  // THEN the blended forecast beats the plain one there, and is not worse than hold (measured: the
  // weight sits at 0 and the forecast is hold's)
  EXPECT_LE(rmse_on, rmse_hold);
  if (std::string(name) == "kf-cv") {
    EXPECT_LT(rmse_on, 0.9 * rmse_off);
  } else {
    // imm's CP mode already forecasts a still target well (0.73 px here against hold's ~3); the
    // blend's weight, learnt from 60 noisy samples and clamped at 1, sits a little below 1 and
    // costs it about 11 % (0.81 px): the known price of the blend where the model is right.
    EXPECT_LT(rmse_on, 1.2 * rmse_off);
  }
  }
}

TEST(HoldBlend, TheWeightsOwnUncertaintyShrinksANoisyWeightAndLeavesAClearOne) {
  // GIVEN the regression fed model steps d that explain half of the measured steps under noise 1.5
  // times their size (a weight of about 0.5 with a standard error of about 0.2 from ~60 samples), and
  // steps that match exactly
  std::mt19937 rng(5);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double lambda = std::exp(-0.1 / 6.0);  // 10 Hz, tau 6 s
  BlendWeight raw, shrunk, exact, exact_shrunk;
  double s_dd = 0.0, s_dy = 0.0, s_yy = 0.0, s_n = 0.0;
  for (int k = 0; k < 200; ++k) {
    const double d = unit(rng), y = 0.5 * d + 1.5 * unit(rng);
    raw.learn(d, 0.0, y, lambda, 0.0, false, 0.0);
    shrunk.learn(d, 0.0, y, lambda, 1.0, false, 0.0);
    exact.learn(d, 0.0, d, lambda, 0.0, false, 0.0);
    exact_shrunk.learn(d, 0.0, d, lambda, 1.0, false, 0.0);
    s_dd = lambda * s_dd + d * d;
    s_dy = lambda * s_dy + d * y;
    s_yy = lambda * s_yy + y * y;
    s_n = lambda * s_n + 1.0;
  }
  // THEN with hold_blend_sigmas 0 the weight is the clamped least-squares one, as before
  EXPECT_DOUBLE_EQ(raw.w, std::clamp(s_dy / s_dd, 0.0, 1.0));
  // and with 1 it is that weight times its significance weight: w^2 / (w^2 + var(w)), var(w) the
  // regression's residual variance over (count - 1) over S_dd
  const double w = raw.w, var_w = (s_yy - s_dy * s_dy / s_dd) / (s_n - 1.0) / s_dd;
  ASSERT_GT(w, 0.0);
  EXPECT_NEAR(shrunk.w, w * w * w / (w * w + var_w), 1e-12);
  EXPECT_LT(shrunk.w, 0.95 * w);  // a weight a few standard errors from 0 is shrunk a little
  // and a model step that matches the measured one exactly leaves no residual: the weight stays 1
  EXPECT_EQ(exact.w, 1.0);
  EXPECT_EQ(exact_shrunk.w, 1.0);
}

TEST(HoldBlend, TheWeightsOwnUncertaintyMovesANoisyForecastTowardsHold) {
  for (const char* name : {"kf-cv", "kf-ca", "cs-akf-adaptive", "st-akf"}) {
    SCOPED_TRACE(name);
    // GIVEN a per-channel filter with its defaults (hold_blend_sigmas 0) and with hold_blend_sigmas 1,
    // on 30 s of a slow sway (6 px, 0.25 Hz) under 3 px noise at 10 Hz: a model step a little better
    // than hold's, by an amount 60 noisy samples hardly resolve
    // (both with the one weight, hold_blend_split 0: hold_blend_sigmas applies to that weight only;
    // and without the start-up prior, blend_start_test.cpp, which moves both towards hold at first)
    TwinsAndHold p(name, {{"hold_blend_split", 0.0}, {"hold_blend_prior", 0.0}},
                   {{"hold_blend_sigmas", 1.0}, {"hold_blend_split", 0.0}, {"hold_blend_prior", 0.0}});
    const auto &plain = p.a, &shrunk = p.b, &hold = p.hold;
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 3.0);
    double gap_plain = 0.0, gap_shrunk = 0.0;
    for (int k = 0; k < 300; ++k) {
      const double t = k / kRateHz;
      p.update(t, 100.0 + 6.0 * std::sin(2.0 * M_PI * 0.25 * t) + noise(rng));
      // THEN the filter is the same (hold_blend_sigmas changes the forecast only), and each
      // forecast is at most as far from hold's as the plain one
      ASSERT_EQ(plain->innovation(0).eps, shrunk->innovation(0).eps) << k;
      const double h = hold->predictPosition(0, t + kH);
      const double g_plain = std::abs(plain->predictPosition(0, t + kH) - h);
      const double g_shrunk = std::abs(shrunk->predictPosition(0, t + kH) - h);
      ASSERT_LE(g_shrunk, g_plain + kRoundingPx) << k;
      gap_plain += g_plain;
      gap_shrunk += g_shrunk;
    }
    // and, in sum, clearly closer to it: the weight was mostly within its own scatter of 0
    EXPECT_GT(gap_plain, 10.0);
    EXPECT_LT(gap_shrunk, 0.8 * gap_plain);
  }
}

TEST(HoldBlend, OnlyHoldBlendTauZeroTurnsTheBlendOffNotShrinkSigmasZero) {
  for (const char* name : {"kf-ca", "cs-akf-adaptive", "imm"}) {
    SCOPED_TRACE(name);
    // GIVEN the filter with shrink_sigmas 0 alone, the same with the blend given at its default,
    // and with it off (the papers' plain filter: shrink_sigmas 0 and hold_blend_tau_s 0)
    auto alone = makePredictor(name, 1, {{"shrink_sigmas", 0.0}});
    auto given = makePredictor(name, 1, {{"shrink_sigmas", 0.0}, {"hold_blend_tau_s", kDefaultHoldBlendTauS}});
    auto off = makePredictor(name, 1, {{"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}});
    // and kf-cv with its defaults and with its default shrink_sigmas (0) spelt out
    auto cv_default = makePredictor("kf-cv", 1);
    auto cv_spelt = makePredictor("kf-cv", 1, {{"shrink_sigmas", kDefaultShrinkSigmasKfCv}});
    std::mt19937 rng(2);
    std::normal_distribution<double> noise(0.0, 3.0);
    Eigen::VectorXd z(1);
    bool differs = false;
    for (int k = 0; k < 50; ++k) {
      const double t = k / kRateHz;
      z(0) = 10.0 * t + noise(rng);
      for (Predictor* f : {alone.get(), given.get(), off.get(), cv_default.get(), cv_spelt.get()}) f->update(t, z);
      // THEN shrink_sigmas 0 alone keeps the blend at its default, bit for bit, and that blends
      // (its forecast is not the unblended one); kf-cv's default spelt out is its default
      ASSERT_EQ(alone->predictPosition(0, t + kH), given->predictPosition(0, t + kH)) << k;
      ASSERT_EQ(cv_default->predictPosition(0, t + kH), cv_spelt->predictPosition(0, t + kH)) << k;
      differs = differs || alone->predictPosition(0, t + kH) != off->predictPosition(0, t + kH);
    }
    EXPECT_TRUE(differs);
  }
}

TEST(HoldBlend, TheHorizonAskedForSetsTheBlendHorizonsUnlessTheyAreGiven) {
  // GIVEN every predictor: each takes horizon_frames, the caller's key (predictor.h), and refuses a
  // negative or infinite one naming it
  for (const auto& info : predictorRegistry()) {
    EXPECT_NO_THROW(makePredictor(info.name, 1, {{"horizon_frames", 5.0}})) << info.name;
    for (double bad : {-1.0, std::numeric_limits<double>::infinity()}) {
      try {
        makePredictor(info.name, 1, {{"horizon_frames", bad}});
        ADD_FAILURE() << info.name << ": horizon_frames " << bad << " was taken";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("horizon_frames"), std::string::npos) << e.what();
      }
    }
  }
  // AND, for a per-channel filter and imm, configurations that must forecast alike: a horizon of h
  // frames asked for and the blend on ceil(h) horizons (2 at the least, 8 at the most); an explicit
  // hold_blend_frames wins over the horizon
  struct Same {
    Params told, given;
  };
  const std::vector<Same> same = {
      {{{"horizon_frames", 5.0}}, {{"hold_blend_frames", 5.0}}},
      {{{"horizon_frames", 4.2}}, {{"hold_blend_frames", 5.0}}},
      {{{"horizon_frames", 4.0 + 1e-9}}, {{"hold_blend_frames", 4.0}}},  // a rounding above 4 is 4
      {{{"horizon_frames", 20.0}}, {{"hold_blend_frames", 8.0}}},
      {{{"horizon_frames", 1e12}}, {{"hold_blend_frames", 8.0}}},  // any horizon a command takes
      {{{"horizon_frames", 2.0}}, {}},
      {{{"horizon_frames", 1.0}}, {}},
      {{{"horizon_frames", 0.0}}, {}},
      {{{"horizon_frames", 6.0}, {"hold_blend_frames", 1.0}}, {{"hold_blend_frames", 1.0}}},
  };
  for (const char* name : {"kf-cv", "imm"}) {
    for (size_t i = 0; i < same.size(); ++i) {
      SCOPED_TRACE(std::string(name) + " pair " + std::to_string(i));
      TwinsAndHold f(name, same[i].told, same[i].given);
      // and a twin on the default two horizons, which the five-frame horizon must not forecast like
      TwinsAndHold g(name, {{"horizon_frames", 5.0}}, {});
      std::mt19937 rng(3);
      std::normal_distribution<double> noise(0.0, 1.0);
      bool differs = false;
      for (int k = 0; k < 200; ++k) {
        const double t = k / kRateHz;
        const double z = 40.0 * std::sin(0.7 * t) + 15.0 * std::sin(2.3 * t) + noise(rng);
        f.update(t, z);
        g.update(t, z);
        const double h = 5.0 / kRateHz;
        // THEN each pair forecasts the same bits 5 frames ahead
        ASSERT_EQ(f.a->predictPosition(0, t + h), f.b->predictPosition(0, t + h)) << k;
        differs = differs || g.a->predictPosition(0, t + h) != g.b->predictPosition(0, t + h);
      }
      // AND the horizon asked for changes the forecast
      EXPECT_TRUE(differs);
    }
  }
}

}  // namespace
}  // namespace predvs
