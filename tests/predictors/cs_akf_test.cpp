#include "predvs/predictors/cs_akf.h"
#include "predictors/accelerating_feed.h"
#include "predictors/eigen_test_utils.h"

#include <unsupported/Eigen/MatrixFunctions>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

namespace predvs {
namespace {

// The reference computations below run in dimensionless time tau = t / dt with the scaled state
// y = [p, v dt, a dt^2], so every reference entry is O(1) and the matrix exponential's absolute
// error (~1e-16 of the block norm) is also a relative one.
constexpr double kRefTol = 1e-11;      // Pade exponential + our closed form / series, O(1) entries
constexpr double kQuadTol = 1e-11;     // composite Simpson with 4000 intervals on a smooth integrand
constexpr double kContinuityTol = 1e-12;  // both branches are near machine precision at the switch

/// Continuous Singer model in scaled time for x = alpha dt: A = [[0,1,0],[0,0,1],[0,0,-x]].
Mat<3> scaledA(double x) {
  Mat<3> A = Mat<3>::Zero();
  A(0, 1) = 1.0;
  A(1, 2) = 1.0;
  A(2, 2) = -x;
  return A;
}

/// D = diag(1, dt, dt^2) maps the state to its scaled form y = D x.
Mat<3> scaling(double dt) { return Vec<3>(1.0, dt, dt * dt).asDiagonal(); }

/// Van Loan: exp([[-A, G G'], [0, A']]) = [[., F^-1 Qd], [0, F']] with unit noise density on a.
void vanLoan(double x, Mat<3>& F_scaled, Mat<3>& Qunit_scaled) {
  Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
  const Mat<3> A = scaledA(x);
  M.block<3, 3>(0, 0) = -A;
  M(2, 5) = 1.0;  // G G' with G = e3
  M.block<3, 3>(3, 3) = A.transpose();
  const Eigen::Matrix<double, 6, 6> E = M.exp();
  F_scaled = E.block<3, 3>(3, 3).transpose();
  Qunit_scaled = F_scaled * E.block<3, 3>(0, 3);
}

/// U in scaled form: integral over [0, 1] of exp(A s) B ds with B = [0, 0, x] (Simpson).
Vec<3> quadratureU(double x) {
  const int n = 4000;
  const Mat<3> A = scaledA(x);
  Vec<3> B(0.0, 0.0, x);
  Vec<3> sum = Vec<3>::Zero();
  for (int i = 0; i <= n; ++i) {
    const double s = static_cast<double>(i) / n;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * ((A * s).exp() * B);
  }
  return sum / (3.0 * n);
}

struct Case {
  double alpha, dt;
};
// x = alpha dt from 5e-5 to 5: both sides of kSingerSeriesThreshold. (Van Loan itself degrades for
// large x: its exponential holds e^x entries that cancel, 4e-10 relative error at x = 20.)
const std::vector<Case> kCases = {{0.05, 0.001}, {0.05, 0.04}, {1.0, 1.0 / 30}, {1.0, 0.1}, {2.0, 0.2},
                                  {1.0, 0.6},    {3.0, 0.5},   {10.0, 0.1},     {10.0, 0.5}};

TEST(Singer, TransitionAndNoiseMatchVanLoan) {
  for (const Case& k : kCases) {
    // GIVEN the continuous Singer model with x = alpha dt
    const double x = k.alpha * k.dt, sigma2 = 3.0;
    Mat<3> Fs, Qs;
    vanLoan(x, Fs, Qs);
    // WHEN F and Q come from the closed form / series
    const Mat<3> D = scaling(k.dt), Dinv = D.inverse();
    const Mat<3> F_ref = Dinv * Fs * D;
    // Noise of density q on a in time t is noise of density q dt^5 on a dt^2 in scaled time, so
    // Q = q dt^5 D^-1 Qs D^-1 with q = 2 alpha sigma2, i.e. D Q D / (q dt^5) = Qs.
    // THEN they agree entry by entry in the scaled frame
    SCOPED_TRACE("alpha=" + std::to_string(k.alpha) + " dt=" + std::to_string(k.dt));
    EXPECT_TRUE(matricesNear(Mat<3>(D * singerTransition(k.alpha, k.dt) * Dinv), Fs, kRefTol));
    const Mat<3> Q = singerProcessNoise(k.alpha, sigma2, k.dt);
    const double qscale = 2.0 * k.alpha * sigma2 * std::pow(k.dt, 5);
    EXPECT_TRUE(matricesNear(Mat<3>(D * Q * D / qscale), Qs, kRefTol));
    EXPECT_TRUE(matricesNear(F_ref, singerTransition(k.alpha, k.dt), kRefTol));
  }
}

TEST(Singer, InputMatchesQuadrature) {
  for (const Case& k : kCases) {
    const double x = k.alpha * k.dt;
    // U scaled: y = D x and the input abar enters as abar dt^2 in scaled units
    const Vec<3> U_ref = quadratureU(x);
    const Vec<3> U_scaled = scaling(k.dt) * singerInput(k.alpha, k.dt) / (k.dt * k.dt);
    SCOPED_TRACE("alpha=" + std::to_string(k.alpha) + " dt=" + std::to_string(k.dt));
    EXPECT_TRUE(matricesNear(U_scaled, U_ref, kQuadTol));
  }
}

TEST(Singer, SeriesAndClosedFormAreContinuousAtTheSwitch) {
  // GIVEN alpha dt just below and just above the series threshold
  const double dt = 0.1, a_lo = kSingerSeriesThreshold * (1.0 - 1e-13) / dt,
               a_hi = kSingerSeriesThreshold * (1.0 + 1e-13) / dt;
  // THEN F, U and Q agree to near machine precision (relative, entry by entry)
  const Mat<3> D = scaling(dt), Dinv = D.inverse();
  const double s = std::pow(dt, 5);
  EXPECT_TRUE(matricesNear(Mat<3>(D * singerTransition(a_lo, dt) * Dinv),
                           Mat<3>(D * singerTransition(a_hi, dt) * Dinv), kContinuityTol));
  EXPECT_TRUE(matricesNear(Vec<3>(D * singerInput(a_lo, dt)), Vec<3>(D * singerInput(a_hi, dt)), kContinuityTol));
  EXPECT_TRUE(matricesNear(Mat<3>(D * singerProcessNoise(a_lo, 1.0 / (2 * a_lo * s), dt) * D),
                           Mat<3>(D * singerProcessNoise(a_hi, 1.0 / (2 * a_hi * s), dt) * D), kContinuityTol));
}

TEST(Singer, SmallAlphaTendsToConstantAccelerationModel) {
  // GIVEN alpha dt = 1e-9 (closed forms would be pure rounding noise here) and 2 alpha sigma2 = q
  const double dt = 0.04, alpha = 1e-9 / dt, q = 5.0;
  // THEN F -> F_CA, Q -> white-jerk Q of density q, U -> 0 (to O(alpha dt))
  constexpr double kLimitTol = 1e-8;  // first neglected term is O(alpha dt) = 1e-9 relative
  const Mat<3> D = scaling(dt), Dinv = D.inverse();
  EXPECT_TRUE(matricesNear(Mat<3>(D * singerTransition(alpha, dt) * Dinv), Mat<3>(D * caTransition(dt) * Dinv),
                           kLimitTol));
  EXPECT_TRUE(matricesNear(Mat<3>(D * singerProcessNoise(alpha, q / (2 * alpha), dt) * D / std::pow(dt, 5)),
                           Mat<3>(D * caProcessNoise(q, dt) * D / std::pow(dt, 5)), kLimitTol));
  EXPECT_LT(singerInput(alpha, dt).norm(), 1e-8);
}

TEST(CsModel, MeanPredictionWithCurrentAccelerationIsConstantAcceleration) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  for (const Case& k : kCases) {
    // GIVEN a random state and abar = a(k|k-1) = a(k-1|k-1)
    const Vec<3> x(u(rng), u(rng), u(rng));
    // WHEN the CS mean prediction F x + U abar is formed
    const Vec<3> cs = singerTransition(k.alpha, k.dt) * x + singerInput(k.alpha, k.dt) * x(2);
    // THEN it equals F_CA x
    EXPECT_TRUE(matricesNear(cs, Vec<3>(caTransition(k.dt) * x), 1e-11 * (1.0 + x.norm())));
  }
}

TEST(CsModel, FilterQueryUsesCaMeanAndSingerNoise) {
  // GIVEN a cs-akf (paper 000's model: no significance weighting) that has seen a few measurements
  CsAkfPredictor f(1, {{"alpha", 0.7}, {"a_max", 50.0}, {"a_neg_max", 50.0}, {"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}});
  Eigen::VectorXd z(1);
  for (int k = 0; k < 10; ++k) {
    z << 3.0 * k * 0.05 + 0.5 * 4.0 * std::pow(k * 0.05, 2);
    f.update(k * 0.05, z);
  }
  const Gaussian<3> g = f.gaussian(0);
  // WHEN the state is queried 0.1 s ahead
  const double h = 0.1;
  const ChannelEstimate e = f.predict(0, f.time() + h);
  // THEN x = F_CA x and P = F_CA P F_CA' + Q_singer(alpha, rayleigh(a), h)
  const Mat<3> F = caTransition(h);
  const Mat<3> P = F * g.P * F.transpose() + singerProcessNoise(0.7, f.accelerationVariance(0), h);
  EXPECT_TRUE(matricesNear(Vec<3>(e.x), Vec<3>(F * g.x), 1e-12));
  EXPECT_TRUE(matricesNear(Mat<3>(e.P), P, 1e-12));
  EXPECT_NEAR(f.accelerationVariance(0), rayleighVariance(g.x(2), 50.0, 50.0, 1.0), 1e-12);
}

TEST(Significance, WeightIsHalfAtNSigmasAndOneWhenOff) {
  // w = m^2 / (m^2 + n^2 var): 1/2 at |m| = n sigma, -> 1 far out, 0 at zero, 1 when n = 0
  EXPECT_DOUBLE_EQ(significanceWeight(6.0, 9.0, 2.0), 0.5);
  EXPECT_DOUBLE_EQ(significanceWeight(-6.0, 9.0, 2.0), 0.5);
  EXPECT_DOUBLE_EQ(significanceWeight(0.0, 9.0, 2.0), 0.0);
  EXPECT_DOUBLE_EQ(significanceWeight(0.0, 0.0, 2.0), 0.0);
  EXPECT_DOUBLE_EQ(significanceWeight(5.0, 9.0, 0.0), 1.0);
  EXPECT_GT(significanceWeight(60.0, 9.0, 2.0), 0.99);
  EXPECT_LT(significanceWeight(0.6, 9.0, 2.0), 0.01);
}

TEST(CsModel, ForecastExtrapolatesTheSignificantPartOfVelocityAndAcceleration) {
  // GIVEN cs-akf-adaptive with its defaults (shrink_sigmas = 2) after 1 s of a noisy accelerating
  // target at 10 Hz (accelerating_feed.h), but for the blend's start-up prior (hold_blend_prior 0:
  // after 1 s its factor is still 0.98, blend_start_test.cpp)
  CsAkfAdaptivePredictor f(1, {{"hold_blend_prior", 0.0}});
  feedAcceleratingTarget(f, 3);
  // WHEN the position is queried 0.2 s ahead
  const double h = 0.2;
  const Gaussian<3> g = f.gaussian(0);
  const double w_a = significanceWeight(g.x(2), g.P(2, 2), kDefaultShrinkSigmasAdaptive);
  const double w_v = significanceWeight(g.x(1), g.P(1, 1), kDefaultShrinkSigmasAdaptive);
  const double expected = g.x(0) + w_v * g.x(1) * h + 0.5 * w_v * w_a * g.x(2) * h * h;
  // THEN the forecast is the CA extrapolation of the weighted velocity and acceleration (both
  // query paths), the filter's state is untouched, and the weights are really below 1 here
  EXPECT_NEAR(f.predict(0, f.time() + h).x(0), expected, 1e-9);
  EXPECT_NEAR(f.predictPosition(0, f.time() + h), expected, 1e-9);
  EXPECT_TRUE(matricesNear(Vec<3>(f.gaussian(0).x), g.x, 0.0));
  EXPECT_LT(w_a * w_v, 0.999);
  // and cs-akf weighs the acceleration only (shrink_v_sigmas defaults to 0 there)
  CsAkfPredictor cs(1, {{"hold_blend_prior", 0.0}});
  feedAcceleratingTarget(cs, 3, 0.0);  // without noise
  const Gaussian<3> gc = cs.gaussian(0);
  const double w_c = significanceWeight(gc.x(2), gc.P(2, 2), kDefaultShrinkSigmasCsAkf);
  EXPECT_NEAR(cs.predictPosition(0, cs.time() + h), gc.x(0) + gc.x(1) * h + 0.5 * w_c * gc.x(2) * h * h, 1e-9);
  // and with shrink_sigmas = 0 (and no blend with hold) it is paper 000's CA mean
  CsAkfAdaptivePredictor paper(1, {{"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}});
  Eigen::VectorXd z(1);
  for (int k = 0; k <= 10; ++k) {
    z << 20.0 * 0.1 * k;
    paper.update(0.1 * k, z);
  }
  const Gaussian<3> gp = paper.gaussian(0);
  EXPECT_NEAR(paper.predictPosition(0, paper.time() + h), (caTransition(h) * gp.x)(0), 1e-9);
}

TEST(CsModel, RayleighVariance) {
  const double k = (4.0 - M_PI) / M_PI;
  EXPECT_NEAR(rayleighVariance(10.0, 50.0, 40.0, 2.0), k * 40.0 * 40.0, 1e-12);
  EXPECT_NEAR(rayleighVariance(-10.0, 50.0, 40.0, 2.0), k * 30.0 * 30.0, 1e-12);
  EXPECT_NEAR(rayleighVariance(-10.0, 50.0, -40.0, 2.0), k * 30.0 * 30.0, 1e-12);  // magnitude
  EXPECT_EQ(rayleighVariance(0.0, 50.0, 40.0, 2.0), 2.0);
}

TEST(CsAdaptive, VarianceFollowsAccelerationChangeWithinClamp) {
  // GIVEN an adaptive filter with a narrow clamp
  CsAkfAdaptivePredictor f(1, {{"sigma_min_sq", 2.0}, {"sigma_max_sq", 50.0}});
  EXPECT_EQ(f.accelerationVariance(0), 50.0);  // starts at the ceiling
  Eigen::VectorXd z(1);
  double a_prev = 0.0;
  for (int k = 0; k < 40; ++k) {
    z << (k < 20 ? 0.0 : 5.0);  // a step: large corrections, then quiet
    f.update(k * 0.05, z);
    if (k == 0) continue;
    const double d = f.gaussian(0).x(2) - a_prev;
    // THEN sigma^2 = clamp((4-pi)/pi d^2, min, max)
    EXPECT_NEAR(f.accelerationVariance(0), std::clamp((4.0 - M_PI) / M_PI * d * d, 2.0, 50.0), 1e-9);
    a_prev = f.gaussian(0).x(2);
  }
}

// ---------------------------------------------------------------------------------------------
// Scenario helpers: 30 Hz, 1 px Gaussian noise, error of the 2-frame-ahead prediction.

constexpr double kFramePeriod_s = 1.0 / 30.0;
constexpr int kHorizonFrames = 2;

template <class Truth>
double predictionRmse(Predictor& p, Truth truth, double t_end_s, double t0_s, double t1_s, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  double se = 0.0;
  int n = 0;
  for (int k = 0; k * kFramePeriod_s <= t_end_s; ++k) {
    const double t = k * kFramePeriod_s;
    Eigen::Vector2d z = truth(t);
    z(0) += noise(rng);
    z(1) += noise(rng);
    p.update(t, z);
    const double th = t + kHorizonFrames * kFramePeriod_s;
    if (th < t0_s || th > t1_s) continue;
    se += (p.predictPositions(th) - truth(th)).squaredNorm();
    ++n;
  }
  return std::sqrt(se / n);
}

/// E2 (docs/MODELS.md §10; data/scenarios/e2-accel-jump.yaml): v0 = (20, 20) px/s, a = (1, 1) px/s^2 jumping to (30, 30) at t = 14 s.
Eigen::Vector2d accelJump(double t) {
  const double v0 = 20.0, a0 = 1.0, a1 = 30.0, tj = 14.0;
  double p;
  if (t < tj) {
    p = v0 * t + 0.5 * a0 * t * t;
  } else {
    const double s = t - tj;
    p = v0 * tj + 0.5 * a0 * tj * tj + (v0 + a0 * tj) * s + 0.5 * a1 * s * s;
  }
  return {p, p};
}

Eigen::Vector2d circle200(double t) {
  const double r = 200.0, w = 0.15;
  return {320.0 + r * std::cos(w * t), 240.0 + r * std::sin(w * t)};
}

TEST(CsAdaptive, BeatsTheWorstAmaxButNotTheBestOnAccelerationJump) {
  // (The spec asked for a test that the adaptive variance removes the a_max sensitivity; measured, it
  // does not: it lands between the best and the worst fixed a_max. The name says what is asserted.)
  // GIVEN the E2 trajectory, error measured over the 3 s after the jump (t in [14, 17] s), averaged
  // (RMS) over 4 noise seeds, for the fixed filter with a_max from 5 to 500 px/s^2
  const std::vector<unsigned> seeds = {14, 15, 16, 17};
  auto meanRmse = [&](auto make) {
    double s2 = 0.0;
    for (unsigned seed : seeds) {
      auto p = make();
      const double r = predictionRmse(*p, accelJump, 17.0, 14.0, 17.0, seed);
      s2 += r * r;
    }
    return std::sqrt(s2 / seeds.size());
  };
  std::vector<double> fixed;
  for (double a_max : {5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0}) {
    fixed.push_back(meanRmse([&] { return std::make_unique<CsAkfPredictor>(2, Params{{"a_max", a_max}, {"a_neg_max", a_max}}); }));
    std::printf("  cs-akf a_max=%6.0f  rmse[14,17]=%.3f px\n", a_max, fixed.back());
  }
  // WHEN the adaptive filter (which has no a_max at all) runs with its defaults
  const double ad = meanRmse([] { return std::make_unique<CsAkfAdaptivePredictor>(2, Params{}); });
  std::printf("  cs-akf-adaptive (defaults) rmse[14,17]=%.3f px\n", ad);
  const double best = *std::min_element(fixed.begin(), fixed.end());
  const double worst = *std::max_element(fixed.begin(), fixed.end());
  // THEN the fixed filter's error depends strongly on a_max (measured x2.2 between a_max = 50 and 5)
  EXPECT_GT(worst / best, 1.8);
  // and the adaptive one is better than the worst a_max choices but NOT as good as the best tuned
  // a_max: measured ~1.7x the best error with the floor of 1e4, 2.2x with the issue-11 floor of
  // 1e5 (a wider filter: noisier on this 1 px, 30 Hz jump, better on the generated manoeuvres,
  // docs/MODELS.md §15). Asserted as measured, with margin.
  EXPECT_LT(ad, worst);
  EXPECT_LT(ad, 2.5 * best);
  EXPECT_THROW(makePredictor("cs-akf-adaptive", 2, {{"a_max", 50.0}}), std::invalid_argument);
}

TEST(CsAdaptive, FloorDecidesSmoothMotionError) {
  // GIVEN the 200 px circle at 0.15 rad/s, error over [10, 60] s, for floors 1e-3 .. 100
  std::vector<double> rmse;
  for (double floor : {1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0}) {
    CsAkfAdaptivePredictor f(2, {{"sigma_min_sq", floor}, {"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}});
    rmse.push_back(predictionRmse(f, circle200, 60.0, 10.0, 60.0, 3));
    std::printf("  circle r=200: sigma_min_sq=%-6g rmse=%.3f px\n", floor, rmse.back());
  }
  // THEN a too-low floor over-smooths (lags) badly, and 0.1 .. 1 is several times better
  EXPECT_GT(rmse[0], 4.0 * rmse[2]);
  EXPECT_GT(rmse[0], 4.0 * rmse[3]);
  EXPECT_LT(rmse[3], 1.0);
}

TEST(CsAdaptive, LowPassedReferenceSoftensATooLowFloor) {
  // GIVEN the 200 px circle and the lowest floor of the sweep (1e-3, which over-smooths)
  auto rmse = [](double tau_s) {
    CsAkfAdaptivePredictor f(2, {{"sigma_min_sq", 1e-3}, {"adapt_tau_s", tau_s}, {"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}});
    return predictionRmse(f, circle200, 60.0, 10.0, 60.0, 3);
  };
  const double one_step = rmse(0.0), low_passed = rmse(3.0);
  std::printf("  circle r=200, floor 1e-3: adapt_tau_s=0 rmse=%.3f px, adapt_tau_s=3 rmse=%.3f px\n", one_step,
              low_passed);
  // THEN measuring the acceleration change over ~3 s instead of one frame keeps sigma^2 off the
  // floor on the turning target (measured 3.0 -> 0.6 px)
  EXPECT_LT(low_passed, 0.5 * one_step);
}

}  // namespace
}  // namespace predvs

namespace predvs {
namespace {

/// cs-akf-adaptive fed 40 frames of a parabola at 30 Hz (no noise), with `mean` and alpha given and
/// the significance weighting and the blend with hold off, so the forecast extrapolates x(k|k) itself.
std::unique_ptr<Predictor> csOnParabola(const std::string& mean, double alpha) {
  Params p;
  p.setText("mean", mean);
  p.set("alpha", alpha);
  p.set("shrink_sigmas", 0.0);
  p.set("hold_blend_tau_s", 0.0);
  p.set("r", 1.0);
  auto f = makePredictor("cs-akf-adaptive", 1, p);
  for (int k = 0; k < 40; ++k) {
    const double t = k / 30.0;
    Eigen::VectorXd z(1);
    z << 100.0 + 20.0 * t + 0.5 * 80.0 * t * t;
    f->update(t, z);
  }
  return f;
}

TEST(CsModel, ZeroMeanIsSingersModelTheAccelerationDecaysOverTheHorizon) {
  // GIVEN the same filter with the CS mean and with Singer's zero mean, alpha = 2/s
  for (const char* mean : {"current", "zero"}) {
    const auto f = csOnParabola(mean, 2.0);
    const double t = f->time();
    const ChannelEstimate now = f->predict(0, t);
    const ChannelEstimate ahead = f->predict(0, t + 0.5);
    // WHEN it forecasts 0.5 s ahead THEN the CS mean keeps the acceleration (F_CA), Singer's decays
    // it by exp(-alpha h) = exp(-1), and the position moves with the matching transition
    ASSERT_GT(std::abs(now.x(2)), 10.0) << mean;
    if (std::string(mean) == "current") {
      EXPECT_NEAR(ahead.x(2), now.x(2), 1e-9);
      EXPECT_NEAR(ahead.x(0), (caTransition(0.5) * now.x)(0), 1e-9);
    } else {
      EXPECT_NEAR(ahead.x(2), std::exp(-1.0) * now.x(2), 1e-9);
      EXPECT_NEAR(ahead.x(0), (singerTransition(2.0, 0.5) * now.x)(0), 1e-9);
    }
  }
}

TEST(CsModel, AdaptiveFiltersOfferTheCsAndSingerMeansAsStructuresAndRejectABadWord) {
  for (const char* name : {"cs-akf-adaptive", "fakf"}) {
    // GIVEN the structural variants of the adaptive CS filters
    const auto variants = makePredictor(name, 1)->structuralVariants();
    ASSERT_EQ(variants.size(), 6u) << name;  // the three below, then each with adaptation: off
    EXPECT_EQ(variants[0].texts().at("mean"), "current");
    EXPECT_EQ(variants[1].texts().at("mean"), "current");
    EXPECT_EQ(variants[1].values().at("shrink_sigmas"), 0.0);
    EXPECT_FALSE(variants[1].has("hold_blend_tau_s"));  // the blend with hold stays at its default
    EXPECT_EQ(variants[2].texts().at("mean"), "zero");
    // WHEN each is built and run THEN it predicts a finite position
    for (const auto& v : variants) {
      auto f = makePredictor(name, 1, v);
      for (int k = 0; k < 20; ++k) {
        Eigen::VectorXd z(1);
        z << 10.0 * k;
        f->update(k / 30.0, z);
      }
      EXPECT_TRUE(std::isfinite(f->predictPosition(0, 1.0))) << name;
    }
  }
  Params bad;
  bad.setText("mean", "singer");
  try {
    makePredictor("cs-akf-adaptive", 1, bad);
    FAIL() << "a bad mean word must throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'mean'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace predvs
