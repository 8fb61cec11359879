#include "predvs/predictors/stkf.h"

#include "predictors/paper_trajectories.h"

#include <Eigen/QR>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {
namespace {

/// `params` completed with paper 001's values (R_0 = 5, Q_0 = diag(5, 20), squared variance), the
/// stkf defaults before issue 11, for every key it does not give: the tests below are about the
/// paper's filter.
Params withPaperValues(const Params& params) {
  Params p = params;
  // coast_tau_s = 0: the paper's predict-only extrapolation through an occlusion (no coasting decay)
  const std::pair<const char*, double> paper[] = {
      {"r", 5.0}, {"q_pos", 5.0}, {"q_vel", 20.0}, {"squared", 1.0}, {"coast_tau_s", 0.0}};
  for (const auto& kv : paper)
    if (!p.has(kv.first)) p.set(kv.first, kv.second);
  if (!p.has("model")) p.setText("model", "cv");  // the paper's model (the registry's default is ca)
  return p;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Round-off on O(100) sums of O(100) numbers.
constexpr double kLinAlgTol = 1e-9;

Eigen::VectorXd vec1(double v) { return Eigen::VectorXd::Constant(1, v); }

TEST(Stkf, ResidualMakerEqualsLineFitResidualsByQr) {
  // GIVEN a window of k samples and the fixed residual maker T_st
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 30.0);
  for (int k : {3, 5, 10, 15, 20}) {
    const Eigen::MatrixXd T = StkfPredictor::makeResidualMaker(k);
    Eigen::VectorXd Y(k);
    for (int i = 0; i < k; ++i) Y(i) = 100.0 + 2.5 * i + noise(rng);
    // WHEN the line y = a n + b is fitted independently (Householder QR on the design matrix)
    Eigen::MatrixXd A(k, 2);
    for (int i = 0; i < k; ++i) A.row(i) << i + 1.0, 1.0;
    const Eigen::Vector2d theta = A.colPivHouseholderQr().solve(Y);
    const Eigen::VectorXd residual = Y - A * theta;
    // THEN T_st Y are exactly those residuals, and T_st is a symmetric projector
    EXPECT_LT((T * Y - residual).cwiseAbs().maxCoeff(), kLinAlgTol) << "k = " << k;
    EXPECT_LT((T - T.transpose()).cwiseAbs().maxCoeff(), kLinAlgTol);
    EXPECT_LT((T * T - T).cwiseAbs().maxCoeff(), kLinAlgTol);
  }
}

// Feeds a line plus uniform noise of half-width `half_width` to a 1-channel stkf, and returns it.
StkfPredictor feedLine(double half_width, const Params& params, int frames, unsigned seed) {
  StkfPredictor f(1, withPaperValues(params));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> w(-1.0, 1.0);
  for (int n = 0; n < frames; ++n) f.update(0.1 * n, vec1(50.0 + 3.0 * n + half_width * w(rng)));
  return f;
}

TEST(Stkf, RIsR0UntilTheWindowIsFullThenGrowsWithNoise) {
  const Params p{{"window", 10}};
  // GIVEN fewer than k samples, R is R_0
  EXPECT_EQ(feedLine(10.0, p, 9, 1).currentR(0), 5.0);
  // GIVEN a noise-free line, the residuals vanish and R stays R_0
  EXPECT_NEAR(feedLine(0.0, p, 30, 1).currentR(0), 5.0, 1e-6);
  // WHEN the noise grows, THEN the self-tuned R grows
  const double r_small = feedLine(2.0, p, 30, 1).currentR(0);
  const double r_large = feedLine(10.0, p, 30, 1).currentR(0);
  EXPECT_GT(r_small, 5.0);
  EXPECT_GT(r_large, r_small);
}

TEST(Stkf, SquaredAndPlainFormsUseTheWindowResidualVariance) {
  // GIVEN the same noisy line fed to the squared (paper) and plain forms
  const int k = 12, frames = 40;
  const StkfPredictor sq = feedLine(6.0, {{"window", k}, {"squared", 1}}, frames, 3);
  const StkfPredictor pl = feedLine(6.0, {{"window", k}, {"squared", 0}}, frames, 3);
  // WHEN the residual variance of the last k samples is computed independently
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> w(-1.0, 1.0);
  std::vector<double> y;
  for (int n = 0; n < frames; ++n) y.push_back(50.0 + 3.0 * n + 6.0 * w(rng));
  Eigen::VectorXd Y(k);
  Eigen::MatrixXd A(k, 2);
  for (int i = 0; i < k; ++i) {
    Y(i) = y[static_cast<size_t>(frames - k + i)];
    A.row(i) << i + 1.0, 1.0;
  }
  const Eigen::VectorXd res = Y - A * A.colPivHouseholderQr().solve(Y);
  const double var = res.squaredNorm() / (k - 1);
  // THEN R = R_0 + var^2 (squared) and R = R_0 + var (plain)
  EXPECT_NEAR(sq.currentR(0), 5.0 + var * var, 1e-9 * var * var);
  EXPECT_NEAR(pl.currentR(0), 5.0 + var, 1e-9 * var);
}

TEST(Stkf, OcclusionPredictsOnlyThenReinitialisesWhenPExceedsThreshold) {
  // GIVEN the paper's filter tracking a ramp of 20 px/s at T = 0.1 s
  const double T = 0.1;
  StkfPredictor f(1, withPaperValues({}));
  int n = 0;
  for (; n < 60; ++n) f.update(T * n, vec1(20.0 * T * n));
  const Gaussian<2> g0 = f.gaussian(0);
  // The expected covariance recursion during an occlusion, computed by hand (Q_0 = diag(5, 20)).
  Eigen::Matrix2d P = g0.P;
  int expected_frames = 0;
  while (P.diagonal().maxCoeff() <= 4800.0) {
    Eigen::Matrix2d F;
    F << 1.0, T, 0.0, 1.0;
    P = F * P * F.transpose();
    P(0, 0) += 5.0;
    P(1, 1) += 20.0;
    ++expected_frames;
  }
  // WHEN the target is hidden
  int frames = 0;
  while (!f.reinitPending(0) && frames < 1000) {
    f.update(T * n++);
    ++frames;
    // THEN the estimate is extrapolated at the learned velocity while predicting only
    if (!f.reinitPending(0)) {
      EXPECT_NEAR(f.gaussian(0).x(0), g0.x(0) + frames * T * g0.x(1), 1e-9);
      EXPECT_FALSE(f.innovation(0).valid);
    }
  }
  // THEN the channel is marked for re-initialisation exactly when a P diagonal passes 4800
  EXPECT_EQ(frames, expected_frames);
  EXPECT_EQ(f.reinitialisations(), 1);
  std::printf("[ stkf ] occlusion: reinit after %d frames = %.1f s (paper: about 3 s)\n", frames, frames * T);
  // AND the next measurement restarts it at x = [z, 0], P = P_0 = I
  f.update(T * n++, vec1(-7.0));
  EXPECT_FALSE(f.reinitPending(0));
  EXPECT_EQ(f.gaussian(0).x(0), -7.0);
  EXPECT_EQ(f.gaussian(0).x(1), 0.0);
  EXPECT_TRUE(f.gaussian(0).P.isApprox(Eigen::Matrix2d::Identity()));
}

TEST(Stkf, KnownImageVelocityShiftsTheNextPredictionOnly) {
  // GIVEN two identical filters
  const double T = 0.1;
  StkfPredictor a(2, {}), b(2, {});
  for (int n = 0; n < 20; ++n) {
    Eigen::VectorXd z(2);
    z << 10.0 + n, -3.0 * n;
    a.update(T * n, z);
    b.update(T * n, z);
  }
  // WHEN b is told the robot moves the image by v = (40, -10) px/s
  Eigen::VectorXd v(2);
  v << 40.0, -10.0;
  b.setKnownImageVelocity(v);
  // THEN the prediction query already includes T v, without changing the filter
  for (int c = 0; c < 2; ++c)
    EXPECT_NEAR(b.predict(c, 20 * T).position() - a.predict(c, 20 * T).position(), T * v(c), kLinAlgTol);
  // AND a predict-only update moves the state by T v more than without it
  a.update(20 * T);
  b.update(20 * T);
  for (int c = 0; c < 2; ++c) EXPECT_NEAR(b.gaussian(0 + c).x(0) - a.gaussian(c).x(0), T * v(c), kLinAlgTol);
  // AND the input applies once: the next step adds no further offset
  a.update(21 * T);
  b.update(21 * T);
  for (int c = 0; c < 2; ++c) EXPECT_NEAR(b.gaussian(c).x(0) - a.gaussian(c).x(0), T * v(c), kLinAlgTol);
}

// ---------------------------------------------------------------------------------------------
// The motion model (`model: cv | ca`, issue 11 item 3).

Params modelParams(const std::string& model, const Params& more = {}) {
  Params p = more;
  p.setText("model", model);
  return p;
}

/// Sum of the 2-frame predictions of both channels over a deterministic 300-frame, 15 Hz track
/// (a sine and a bending ramp plus deterministic ripple; frames 44..49 of every 50 missing).
double fingerprint(Predictor& f) {
  const double T = 1.0 / 15.0;
  double sum = 0.0;
  for (int n = 0; n < 300; ++n) {
    const double t = n * T;
    Eigen::VectorXd z(2);
    z << 100.0 + 80.0 * std::sin(1.3 * t) + 0.9 * std::sin(37.0 * n), 50.0 + 40.0 * t * t / (1.0 + t) + 0.7 * std::cos(23.0 * n);
    if (n % 50 >= 44)
      f.update(t);
    else
      f.update(t, z);
    for (int c = 0; c < 2; ++c) sum += f.predictPosition(c, t + 2 * T);
  }
  return sum;
}

TEST(StkfModels, CvGivesTheSameNumbersAsBeforeAndTheDefaultIsCa) {
  // GIVEN stkf with its defaults, with `model: cv` (its default before issue 11's weighted
  // forecast made ca the default), and with the paper's values
  // (the forecast's blend with hold, channel_predictor.h, is off in both: it came after b41f742)
  Params paper{{"r", 5.0}, {"q_pos", 5.0}, {"q_vel", 20.0}, {"squared", 1.0}, {"coast_tau_s", 0.0}, {"hold_blend_tau_s", 0.0}};
  paper.setText("model", "cv");
  auto by_default = makePredictor("stkf", 2, {{"glitch_sigmas", 0.0}});  // the filter itself, not behind the glitch gate
  Params cv_params = modelParams("cv");
  cv_params.set("hold_blend_tau_s", 0.0);
  auto cv = makePredictor("stkf", 2, cv_params);
  auto paper_filter = makePredictor("stkf", 2, paper);
  // THEN the default is the 3-state filter
  EXPECT_NE(dynamic_cast<StkfCaPredictor*>(by_default.get()), nullptr);
  EXPECT_EQ(by_default->predict(0, 0.0).x.size(), 3);
  // AND the cv filter's predictions are bit for bit those of the CV filter before `model` existed
  // (the sums were printed by the same loop linked against the stkf of commit b41f742)
  EXPECT_EQ(fingerprint(*cv), 0x1.30c2147f2c8cep+17);
  EXPECT_EQ(fingerprint(*paper_filter), 0x1.31350c4c1f62p+17);
}

TEST(StkfModels, ResidualMakerOfCaEqualsQuadraticFitResidualsByQr) {
  // GIVEN a window of k samples and the CA residual maker (built on centred, scaled columns)
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 10.0);
  for (int k : {4, 5, 15, 60}) {
    const Eigen::MatrixXd T = StkfCaPredictor::makeResidualMaker(k);
    Eigen::VectorXd Y(k);
    for (int i = 0; i < k; ++i) Y(i) = 100.0 + 2.5 * i - 0.3 * i * i + noise(rng);
    // WHEN y = a n^2 + b n + c is fitted on the raw design [n^2, n, 1] by Householder QR
    Eigen::MatrixXd A(k, 3);
    for (int i = 0; i < k; ++i) A.row(i) << (i + 1.0) * (i + 1.0), i + 1.0, 1.0;
    const Eigen::VectorXd residual = Y - A * A.colPivHouseholderQr().solve(Y);
    // THEN T_st Y are those residuals, and T_st is a symmetric projector
    EXPECT_LT((T * Y - residual).cwiseAbs().maxCoeff(), 1e-8) << "k = " << k;
    EXPECT_LT((T - T.transpose()).cwiseAbs().maxCoeff(), kLinAlgTol);
    EXPECT_LT((T * T - T).cwiseAbs().maxCoeff(), kLinAlgTol);
  }
  EXPECT_THROW(StkfCaPredictor::makeResidualMaker(3), std::invalid_argument);
}

TEST(StkfModels, CaSelfTunesROnTheScatterAboutAQuadratic) {
  // GIVEN a parabola (constant acceleration) sampled at 10 Hz
  auto parabola = [](int n, double ripple) { return 20.0 + 4.0 * n + 0.5 * n * n + ripple * std::sin(2.1 * n); };
  const int k = 8, frames = 30;
  const Params common{{"r", 2.0}, {"window", k}, {"q_raise_ratio", 0.0}};  // the self-tuning alone
  StkfCaPredictor ca(1, modelParams("ca", common));
  StkfPredictor cv(1, common);
  for (int n = 0; n < frames; ++n) {
    ca.update(0.1 * n, vec1(parabola(n, 0.0)));
    cv.update(0.1 * n, vec1(parabola(n, 0.0)));
  }
  // THEN without noise the CA filter keeps R = R_0, while the line fit of the CV filter reads the
  // curvature as scatter
  EXPECT_NEAR(ca.currentR(0), 2.0, 1e-6);
  EXPECT_GT(cv.currentR(0), 2.0 + 1.0);
  // AND with a ripple, R = R_0 + the residual variance of the quadratic fit of the last k samples
  StkfCaPredictor noisy(1, modelParams("ca", common));
  for (int n = 0; n < frames; ++n) noisy.update(0.1 * n, vec1(parabola(n, 1.5)));
  Eigen::VectorXd Y(k);
  Eigen::MatrixXd A(k, 3);
  for (int i = 0; i < k; ++i) {
    Y(i) = parabola(frames - k + i, 1.5);
    A.row(i) << (i + 1.0) * (i + 1.0), i + 1.0, 1.0;
  }
  const double var = (Y - A * A.colPivHouseholderQr().solve(Y)).squaredNorm() / (k - 1);
  EXPECT_GT(var, 0.1);
  EXPECT_NEAR(noisy.currentR(0), 2.0 + var, 1e-8);
}

TEST(StkfModels, CaWithoutSelfTuningIsKfCa) {
  // GIVEN stkf model=ca with the self-tuning off, and kf-ca with the same q, r, P_0 and forecast
  // weighting (shrink_sigmas 2)
  const double r = 2.0, q = 5e4;
  const Params kfca{{"r", r}, {"q", q}, {"p0_vel", 300.0}, {"p0_acc", 5e3}, {"shrink_sigmas", 2.0}};
  Params st = modelParams("ca", kfca);
  st.set("window", 0);
  st.set("p0_pos", r);  // kf-ca starts P(0,0) at R
  st.set("glitch_sigmas", 0.0);  // the filter itself (its reinitialisations()), not behind the glitch gate
  auto a = makePredictor("stkf", 2, st);
  auto b = makePredictor("kf-ca", 2, kfca);
  // WHEN both track a manoeuvring target at 30 Hz with noise, dropped entries and 3-frame gaps
  // (coasting included)
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.5);
  const double T = 1.0 / 30.0;
  double worst = 0.0;
  for (int n = 0; n < 600; ++n) {
    const double t = n * T;
    Eigen::VectorXd z(2);
    z << 200.0 * std::sin(0.8 * t) + noise(rng), (t < 8.0 ? 30.0 * t : 240.0) + noise(rng);
    if (n % 17 == 5) z(1) = kNaN;
    if (n % 97 >= 94) {
      a->update(t);
      b->update(t);
    } else {
      a->update(t, z);
      b->update(t, z);
    }
    for (int c = 0; c < 2; ++c) {
      const ChannelEstimate ea = a->predict(c, t + 2 * T), eb = b->predict(c, t + 2 * T);
      ASSERT_EQ(ea.x.size(), 3);
      worst = std::max(worst, (ea.x - eb.x).cwiseAbs().maxCoeff());
      worst = std::max(worst, (ea.P - eb.P).cwiseAbs().maxCoeff() / std::max(1.0, eb.P.cwiseAbs().maxCoeff()));
    }
  }
  // THEN state and covariance agree to round-off, and the 3-frame gaps never re-initialised it
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(dynamic_cast<StkfCaPredictor&>(*a).reinitialisations(), 0);
}

TEST(StkfModels, CaKeepsKnownImageVelocityAndPredictPositionBitForBit) {
  // GIVEN two identical CA filters on an accelerating target
  const double T = 0.1;
  StkfCaPredictor a(2, modelParams("ca")), b(2, modelParams("ca"));
  for (int n = 0; n < 20; ++n) {
    Eigen::VectorXd z(2);
    z << 10.0 + n + 0.2 * n * n, -3.0 * n;
    a.update(T * n, z);
    b.update(T * n, z);
  }
  Eigen::VectorXd v(2);
  v << 40.0, -10.0;
  b.setKnownImageVelocity(v);
  for (int c = 0; c < 2; ++c) {
    // THEN the query includes T v, and predictPosition() is predict().position() bit for bit
    EXPECT_NEAR(b.predict(c, 20 * T).position() - a.predict(c, 20 * T).position(), T * v(c), kLinAlgTol);
    EXPECT_EQ(b.predictPosition(c, 20.5 * T), b.predict(c, 20.5 * T).position());
    EXPECT_EQ(a.predictPosition(c, 21 * T), a.predict(c, 21 * T).position());
  }
  // AND a predict-only update moves the state by T v more, once
  a.update(20 * T);
  b.update(20 * T);
  a.update(21 * T);
  b.update(21 * T);
  for (int c = 0; c < 2; ++c) EXPECT_NEAR(b.gaussian(c).x(0) - a.gaussian(c).x(0), T * v(c), 1e-9);
}

TEST(StkfModels, CaReinitialisesOnItsPerDiagonalThresholds) {
  const double T = 0.1;
  auto track = [&](StkfCaPredictor& f, int& n) {
    for (; n < 40; ++n) f.update(T * n, vec1(5.0 * n + 0.1 * n * n));
  };
  // GIVEN the default thresholds (position 4800 px^2; velocity and acceleration not compared)
  StkfCaPredictor f(1, modelParams("ca", {{"r", 1.0}, {"coast_tau_s", 0.0}}));
  int n = 0;
  track(f, n);
  // THEN measured frames never re-initialise although P(2,2) is far above 4800
  EXPECT_EQ(f.reinitialisations(), 0);
  EXPECT_GT(f.gaussian(0).P(2, 2), 4800.0);
  // WHEN the target is hidden, THEN it re-initialises when P(0,0) passes 4800 and not before
  int frames = 0;
  while (!f.reinitPending(0) && frames < 1000) {
    const double p00 = f.gaussian(0).P(0, 0);
    EXPECT_LE(p00, 4800.0);
    f.update(T * n++);
    ++frames;
  }
  EXPECT_GT(f.gaussian(0).P(0, 0), 4800.0);
  EXPECT_EQ(f.reinitialisations(), 1);
  // AND the next measurement restarts it at [z, 0, 0], P = P_0 = diag(1, 1e4, 1e4)
  f.update(T * n++, vec1(-7.0));
  EXPECT_FALSE(f.reinitPending(0));
  EXPECT_EQ(f.gaussian(0).x, Eigen::Vector3d(-7.0, 0.0, 0.0));
  EXPECT_EQ(f.gaussian(0).P, Eigen::Vector3d(1.0, 1e4, 1e4).asDiagonal().toDenseMatrix());
  // GIVEN a velocity threshold, WHEN hidden, THEN it fires on P(1,1) first
  StkfCaPredictor g(1, modelParams("ca", {{"r", 1.0}, {"reinit_threshold_vel", 4800.0}}));
  n = 0;
  track(g, n);
  while (!g.reinitPending(0) && n < 1000) g.update(T * n++);
  EXPECT_GT(g.gaussian(0).P(1, 1), 4800.0);
  EXPECT_LE(g.gaussian(0).P(0, 0), 4800.0);
}

TEST(StkfModels, StructuralVariantsAreCvAndCaAndEachRuns) {
  for (const char* model : {"cv", "ca"}) {
    // GIVEN the variants of either model's instance
    const auto variants = makePredictor("stkf", 1, modelParams(model))->structuralVariants();
    ASSERT_EQ(variants.size(), 7u);
    EXPECT_EQ(variants[0].texts().at("model"), "cv");
    EXPECT_EQ(variants[1].texts().at("model"), "cv");
    EXPECT_EQ(variants[1].values().at("window"), 3.0);
    EXPECT_EQ(variants[2].texts().at("model"), "ca");
    EXPECT_TRUE(variants[0].values().empty());
    // each model with the self-tuning off (window 0)
    EXPECT_EQ(variants[3].texts().at("model"), "cv");
    EXPECT_EQ(variants[3].values().at("window"), 0.0);
    EXPECT_EQ(variants[4].texts().at("model"), "ca");
    EXPECT_EQ(variants[4].values().at("window"), 0.0);
    // the white-acceleration cv model (kf-cv's Q) with window 3 and 0 (stkf.h)
    for (size_t i : {5u, 6u}) {
      EXPECT_EQ(variants[i].texts().at("model"), "cv");
      EXPECT_EQ(variants[i].texts().at("process_noise"), "white-acceleration");
    }
    EXPECT_EQ(variants[5].values().at("window"), 3.0);
    EXPECT_EQ(variants[6].values().at("window"), 0.0);
  }
  const auto variants = makePredictor("stkf", 1)->structuralVariants();
  for (size_t i = 0; i < variants.size(); ++i) {
    // WHEN a predictor is built from the variant alone (plus r), THEN it runs with its defaults
    Params p = variants[i];
    p.set("r", 1.0);
    auto f = makePredictor("stkf", 2, p);
    const int n_state = variants[i].texts().at("model") == "cv" ? 2 : 3;
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 1.0);
    for (int n = 0; n < 300; ++n) {
      Eigen::VectorXd z(2);
      z << 100.0 * std::sin(0.05 * n) + noise(rng), 2.0 * n + noise(rng);
      f->update(n / 30.0, z);
    }
    for (int c = 0; c < 2; ++c) {
      const ChannelEstimate e = f->predict(c, 10.0 + 2.0 / 30.0);
      EXPECT_EQ(e.x.size(), n_state);
      EXPECT_TRUE(e.x.allFinite());
      EXPECT_LT(std::abs(e.position() - (c == 0 ? 100.0 * std::sin(0.05 * 302) : 2.0 * 302)), 5.0);
    }
    // AND its noise keys are the model's: cv r, q_pos, q_vel (white-acceleration: r and the
    // white-acceleration density q); ca r and the white-jerk density q
    std::vector<std::string> keys;
    for (const NoiseParameter& np : makePredictor("stkf", 1, variants[i])->noiseParameters()) keys.push_back(np.key);
    const bool diagonal = variants[i].texts().at("model") == "cv" && !variants[i].texts().count("process_noise");
    EXPECT_EQ(keys, diagonal ? std::vector<std::string>({"r", "q_pos", "q_vel"}) : std::vector<std::string>({"r", "q"}));
  }
  // AND the CA q is bounded as every white-jerk density, and defaults to kf-ca's
  for (const NoiseParameter& np : makePredictor("stkf", 1, modelParams("ca"))->noiseParameters())
    if (np.key == "q") {
      EXPECT_EQ(np.value, kDefaultQStkfCa);
      EXPECT_EQ(np.lo, jerkDensityParameter("q", 1.0).lo);
      EXPECT_EQ(np.hi, jerkDensityParameter("q", 1.0).hi);
    }
}

/// The message of the std::invalid_argument makePredictor throws for `params`.
std::string errorOf(const Params& params) {
  try {
    makePredictor("stkf", 1, params);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(StkfModels, ABadModelIsAOneLineErrorNamingModel) {
  const std::string bad_word = errorOf(modelParams("cx"));
  EXPECT_NE(bad_word.find("'model'"), std::string::npos) << bad_word;
  EXPECT_NE(bad_word.find("cv or ca"), std::string::npos) << bad_word;
  EXPECT_NE(bad_word.find("'cx'"), std::string::npos) << bad_word;
  EXPECT_EQ(bad_word.find('\n'), std::string::npos);
  const std::string number = errorOf({{"model", 2.0}});
  EXPECT_NE(number.find("'model'"), std::string::npos) << number;
  EXPECT_EQ(number.find('\n'), std::string::npos);
  // A key of the other model is unknown, and a CA window needs k >= 4
  EXPECT_NE(errorOf(modelParams("ca", {{"q_vel", 3.0}})).find("'q_vel'"), std::string::npos);
  EXPECT_NE(errorOf(modelParams("cv", {{"q", 3.0}})).find("'q'"), std::string::npos);
  EXPECT_NE(errorOf(modelParams("ca", {{"window", 3.0}})).find("'window'"), std::string::npos);
  EXPECT_EQ(errorOf(modelParams("cv", {{"window", 3.0}})), "");
  // The class of one model refuses the other's word
  EXPECT_THROW(StkfPredictor(1, modelParams("ca")), std::invalid_argument);
  EXPECT_THROW(StkfCaPredictor(1, modelParams("cv")), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// E6 (paper 001 Table 2): noise study on the eq. 44 trajectory.

struct E6Result {
  Eigen::Vector3d mse_pos = Eigen::Vector3d::Zero();
  Eigen::Vector3d mse_vel = Eigen::Vector3d::Zero();
};

// Mean over `seeds` runs of the per-run MSE of the filtered estimate X*(n|n) against the ideal
// X(n) and the ideal target image velocity, over every frame of the 20 s run.
E6Result runE6(const std::string& name, const Params& params, double sigma_n, int seeds) {
  const paper::E6Trajectory traj = paper::e6Trajectory();
  E6Result out;
  for (int s = 0; s < seeds; ++s) {
    std::mt19937 rng(1000u + static_cast<unsigned>(s));
    auto f = makePredictor(name, 3, name == "stkf" ? withPaperValues(params) : params);
    for (size_t n = 0; n < traj.t_s.size(); ++n) {
      f->update(traj.t_s[n], paper::e6Measure(traj.X_px[n], sigma_n, rng));
      for (int c = 0; c < 3; ++c) {
        const ChannelEstimate e = f->predict(c, traj.t_s[n]);
        out.mse_pos(c) += std::pow(e.position() - traj.X_px[n](c), 2);
        out.mse_vel(c) += std::pow(e.velocity() - traj.Xdot_px_s[n](c), 2);
      }
    }
  }
  const double count = static_cast<double>(seeds) * static_cast<double>(traj.t_s.size());
  out.mse_pos /= count;
  out.mse_vel /= count;
  return out;
}

void printE6(const char* label, double sigma_n, const E6Result& r) {
  std::printf("[ E6 ] %-34s sigma_n=%4.1f  MSE pos x,y,d = %7.3f %7.3f %7.3f   vel = %8.3f %8.3f %8.3f\n", label,
              sigma_n, r.mse_pos(0), r.mse_pos(1), r.mse_pos(2), r.mse_vel(0), r.mse_vel(1), r.mse_vel(2));
}

TEST(StkfE6, SelfTuningBeatsFixedRFiltersAtSigma10) {
  // GIVEN the E6 trajectory, 20 seeds, the paper's noise, T = 0.1 s
  constexpr int kSeeds = 20;
  // "paper KF": the paper's own KF, Q_0 and R_0 fixed (stkf with the self-tuning off).
  // kf-cv with the paper's R_0 = 5 and q = 200 px^2/s^3, whose velocity noise per 0.1 s equals
  // the paper's Q_0 velocity entry (20); its position noise is far smaller than Q_0's 5.
  // kf-cv with r = 33.4, the true measurement variance at sigma_n = 10 (100/3 + 1/12 for the
  // rounding), for reference: a fixed KF told the noise level in advance.
  const Params paper_kf{{"window", 0}};
  const Params kf{{"r", 5.0}, {"q", 200.0}};
  const Params kf_oracle{{"r", 100.0 / 3.0 + 1.0 / 12.0}, {"q", 200.0}};
  E6Result paper10, kf10, sq10, plain10;
  for (double sigma : {0.0, 10.0}) {
    const E6Result a = runE6("stkf", paper_kf, sigma, kSeeds);
    const E6Result b = runE6("kf-cv", kf, sigma, kSeeds);
    const E6Result c = runE6("stkf", {{"squared", 1}}, sigma, kSeeds);
    const E6Result d = runE6("stkf", {{"squared", 0}}, sigma, kSeeds);
    printE6("paper KF (stkf window=0)", sigma, a);
    printE6("kf-cv r=5 q=200", sigma, b);
    printE6("stkf squared (k=15)", sigma, c);
    printE6("stkf plain (k=15)", sigma, d);
    if (sigma > 0.0) paper10 = a, kf10 = b, sq10 = c, plain10 = d;
  }
  printE6("kf-cv r=33.4 q=200 (told the noise)", 10.0, runE6("kf-cv", kf_oracle, 10.0, kSeeds));
  for (int k : {5, 10, 20}) {
    char label[64];
    std::snprintf(label, sizeof label, "stkf squared (k=%d)", k);
    printE6(label, 10.0, runE6("stkf", {{"window", k}}, 10.0, kSeeds));
  }
  std::printf("[ E6 ] paper Table 2 at sigma_n=10: KF pos 16.77 16.62 16.54 vel 62.6 60.9 59.1; "
              "STKF pos 8.87 6.92 6.39 vel 29.9 8.04 6.68\n");
  for (int c = 0; c < 3; ++c) {
    // THEN both STKF forms beat the paper's fixed-R KF in position and velocity on every channel
    EXPECT_LT(sq10.mse_pos(c), paper10.mse_pos(c)) << "channel " << c;
    EXPECT_LT(sq10.mse_vel(c), paper10.mse_vel(c)) << "channel " << c;
    EXPECT_LT(plain10.mse_pos(c), paper10.mse_pos(c)) << "channel " << c;
    EXPECT_LT(plain10.mse_vel(c), paper10.mse_vel(c)) << "channel " << c;
    // AND the squared STKF estimates velocity far better than kf-cv (r = 5, q = 200)
    EXPECT_LT(sq10.mse_vel(c), 0.5 * kf10.mse_vel(c)) << "channel " << c;
  }
  // AND on the slowly moving y and d channels the squared form (paper) also beats kf-cv in
  // position; on x (the fastest channel) it only ties with it (measured 13.6 vs 13.5, not asserted).
  for (int c = 1; c < 3; ++c) EXPECT_LT(sq10.mse_pos(c), kf10.mse_pos(c)) << "channel " << c;
}

}  // namespace
}  // namespace predvs
