#include "predvs/predictors/cs_akf.h"
#include "predvs/predictors/recent_values.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kPi = 3.14159265358979323846;
/// (4 - pi)/pi: variance of a Rayleigh variable per squared distance of its mean to the limit.
constexpr double kRayleigh = (4.0 - kPi) / kPi;

/// b^n for a small non-negative n (std::pow is several times slower on the hot path).
inline double ipow(double b, int n) {
  double r = 1.0;
  for (int i = 0; i < n; ++i) r *= b;
  return r;
}

/// Every Singer quantity has the form  N(x) / alpha^p  with x = alpha dt and
///   N(x) = A e^{-2x} + (B + C x) e^{-x} + (a polynomial of degree < k0),
/// where the polynomial cancels the exponential series below x^k0, so that
///   N(x) / alpha^p = dt^p x^(k0 - p) sum_{j >= 0} n_{k0+j} x^j,
///   n_k = A (-2)^k / k! + B (-1)^k / k! + C (-1)^(k-1) / (k-1)!.
/// The coefficients are computed once; the series is summed by Horner's rule for small x.
class SingerSeries {
 public:
  static constexpr int kTerms = 18;  // x <= 0.5: first neglected term ~ 1/(k0+18)! < 1e-17 relative

  SingerSeries(double A, double B, double C, int p, int k0) : p_(p), k0_(k0) {
    for (int j = 0; j < kTerms; ++j) {
      const int k = k0 + j;
      double fk = 1.0, fk1 = 1.0;  // k!, (k-1)!
      for (int i = 2; i <= k; ++i) fk *= i;
      for (int i = 2; i <= k - 1; ++i) fk1 *= i;
      const double sk = (k % 2 == 0) ? 1.0 : -1.0;
      coef_[static_cast<size_t>(j)] = A * std::pow(-2.0, k) / fk + B * sk / fk + C * (-sk) / fk1;
    }
  }

  /// N(alpha dt) / alpha^p evaluated by the series.
  double operator()(double x, double dt) const {
    double s = 0.0;
    for (int j = kTerms - 1; j >= 0; --j) s = s * x + coef_[static_cast<size_t>(j)];
    return ipow(dt, p_) * ipow(x, k0_ - p_) * s;
  }
  double coef(int j) const { return coef_[static_cast<size_t>(j)]; }

 private:
  int p_, k0_;
  std::array<double, kTerms> coef_{};
};

struct SingerSeriesTable {
  //                A     B     C   p  k0
  SingerSeries f02{0.0, 1.0, 0.0, 2, 2};     // (e - 1 + x) / alpha^2
  SingerSeries f12{0.0, -1.0, 0.0, 1, 1};    // (1 - e) / alpha
  SingerSeries u0{0.0, -1.0, 0.0, 2, 3};     // (1 - x + x^2/2 - e) / alpha^2
  SingerSeries u1{0.0, 1.0, 0.0, 1, 2};      // (x - 1 + e) / alpha
  SingerSeries u2{0.0, -1.0, 0.0, 0, 1};     // 1 - e
  SingerSeries q11{-1.0, 0.0, -4.0, 5, 5};   // 1 - e^2 + 2x + 2x^3/3 - 2x^2 - 4x e
  SingerSeries q12{1.0, -2.0, 2.0, 4, 4};    // e^2 + 1 - 2e + 2x e - 2x + x^2
  SingerSeries q13{-1.0, 0.0, -2.0, 3, 3};   // 1 - e^2 - 2x e
  SingerSeries q22{-1.0, 4.0, 0.0, 3, 3};    // 4e - 3 - e^2 + 2x
  SingerSeries q23{1.0, -2.0, 0.0, 2, 2};    // e^2 + 1 - 2e
  SingerSeries q33{-1.0, 0.0, 0.0, 1, 1};    // 1 - e^2
};

const SingerSeriesTable& series() {
  static const SingerSeriesTable table;
  return table;
}

/// The six q_ij series summed together (hot path: every time update and every horizon query).
/// Coefficients interleaved as [term][entry] so the six Horner chains run in parallel; each q_ij
/// has k0 = p, so q_ij = 0.5 dt^p_ij sum_j n_j x^j.
struct SingerQSeries {
  std::array<std::array<double, 6>, SingerSeries::kTerms> coef{};
  SingerQSeries() {
    const auto& s = series();
    const SingerSeries* q[6] = {&s.q11, &s.q12, &s.q13, &s.q22, &s.q23, &s.q33};
    for (int j = 0; j < SingerSeries::kTerms; ++j)
      for (int i = 0; i < 6; ++i) coef[static_cast<size_t>(j)][static_cast<size_t>(i)] = q[i]->coef(j);
  }
};

/// q11, q12, q13, q22, q23, q33 by their series (x = alpha dt < kSingerSeriesThreshold).
void singerQSeries(double x, double dt, double out[6]) {
  static const SingerQSeries table;
  double acc[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int j = SingerSeries::kTerms - 1; j >= 0; --j) {
    const auto& c = table.coef[static_cast<size_t>(j)];
    for (int i = 0; i < 6; ++i) acc[i] = acc[i] * x + c[static_cast<size_t>(i)];
  }
  const double dt2 = dt * dt, dt3 = dt2 * dt;
  out[0] = 0.5 * dt3 * dt2 * acc[0];  // p = 5
  out[1] = 0.5 * dt2 * dt2 * acc[1];  // p = 4
  out[2] = 0.5 * dt3 * acc[2];        // p = 3
  out[3] = 0.5 * dt3 * acc[3];        // p = 3
  out[4] = 0.5 * dt2 * acc[4];        // p = 2
  out[5] = 0.5 * dt * acc[5];         // p = 1
}

}  // namespace

namespace {

/// F(alpha, dt) of the Singer model (singerTransition computes it once per (alpha, dt) and thread).
Mat<3> computeSingerTransition(double alpha, double dt) {
  const double x = alpha * dt;
  Mat<3> F = Mat<3>::Identity();
  F(0, 1) = dt;
  if (x < kSingerSeriesThreshold) {
    const auto& s = series();
    F(0, 2) = s.f02(x, dt);
    F(1, 2) = s.f12(x, dt);
  } else {
    const double e = std::exp(-x);
    F(0, 2) = (e - 1.0 + x) / (alpha * alpha);
    F(1, 2) = (1.0 - e) / alpha;
  }
  F(2, 2) = std::exp(-x);
  return F;
}

}  // namespace

Mat<3> singerTransition(double alpha, double dt) {
  thread_local RecentValues<Mat<3>, 8, 2> cache;  // recent_values.h: the same bits, no exp per frame
  return cache.get({alpha, dt}, [&] { return computeSingerTransition(alpha, dt); });
}

Vec<3> singerInput(double alpha, double dt) {
  const double x = alpha * dt;
  Vec<3> U;
  if (x < kSingerSeriesThreshold) {
    const auto& s = series();
    U << s.u0(x, dt), s.u1(x, dt), s.u2(x, dt);
  } else {
    const double e = std::exp(-x);
    U << (-dt + alpha * dt * dt / 2.0 + (1.0 - e) / alpha) / alpha, dt - (1.0 - e) / alpha, 1.0 - e;
  }
  return U;
}

namespace {

/// [q_ij](alpha, dt) of the Singer model, Q / (2 alpha sigma^2) (singerProcessNoise computes it once
/// per (alpha, dt) and thread).
Mat<3> computeSingerQ(double alpha, double dt) {
  const double x = alpha * dt;
  double q11, q12, q13, q22, q23, q33;
  if (x < kSingerSeriesThreshold) {
    double q[6];
    singerQSeries(x, dt, q);
    q11 = q[0];
    q12 = q[1];
    q13 = q[2];
    q22 = q[3];
    q23 = q[4];
    q33 = q[5];
  } else {
    const double e = std::exp(-x), e2 = e * e;
    const double a2 = alpha * alpha, a3 = a2 * alpha, a4 = a3 * alpha, a5 = a4 * alpha;
    q11 = (1.0 - e2 + 2.0 * x + 2.0 * x * x * x / 3.0 - 2.0 * x * x - 4.0 * x * e) / (2.0 * a5);
    q12 = (e2 + 1.0 - 2.0 * e + 2.0 * x * e - 2.0 * x + x * x) / (2.0 * a4);
    q13 = (1.0 - e2 - 2.0 * x * e) / (2.0 * a3);
    q22 = (4.0 * e - 3.0 - e2 + 2.0 * x) / (2.0 * a3);
    q23 = (e2 + 1.0 - 2.0 * e) / (2.0 * a2);
    q33 = (1.0 - e2) / (2.0 * alpha);
  }
  Mat<3> Q;
  Q << q11, q12, q13, q12, q22, q23, q13, q23, q33;
  return Q;
}

}  // namespace

Mat<3> singerProcessNoise(double alpha, double sigma2, double dt) {
  // [q_ij] depends on (alpha, dt) only (recent_values.h: kept for the last few per thread).
  thread_local RecentValues<Mat<3>, 8, 2> cache;
  return (2.0 * alpha * sigma2) * cache.get({alpha, dt}, [&] { return computeSingerQ(alpha, dt); });
}

double rayleighVariance(double abar, double a_max, double a_neg_max, double sigma0_sq) {
  if (abar > 0.0) return kRayleigh * (a_max - abar) * (a_max - abar);
  if (abar < 0.0) {
    const double d = std::abs(a_neg_max) + abar;
    return kRayleigh * d * d;
  }
  return sigma0_sq;
}

// ---------------------------------------------------------------------------------------------

CsKalmanPredictor::CsKalmanPredictor(int channels, const Params& params, bool auto_r, double default_shrink_sigmas,
                                     bool weigh_velocity)
    : ChannelPredictor<3>(channels,
                          auto_r || params.texts().count("r") ? measurementNoiseParam(params, 1.0)
                                                              : params.get("r", 1.0, 1e-12, 1e12),
                          params.get("p0_vel", 1e4, 0.0, 1e12),
                          params.get("p0_acc", 1e4, 0.0, 1e12)),
      alpha_(params.get("alpha", 1.0, 1e-6, 1e3)) {
  readCoastParam(params);
  const std::string mean = params.text("mean", "current");
  if (mean != "current" && mean != "zero")
    throw std::invalid_argument("predictor parameter 'mean' must be current or zero, got '" + mean + "'");
  zero_mean_ = mean == "zero";
  // The forecast weighting is ChannelPredictor's (the same w_v, w_a); the CS filters also weigh
  // the acceleration of their time update (shrink_update_sigmas, defaulting to shrink_sigmas).
  readShrinkParams(params, default_shrink_sigmas, weigh_velocity);
  shrink_update_sigmas_ = params.get("shrink_update_sigmas", params.get("shrink_sigmas", default_shrink_sigmas), 0.0, 1e3);
  if ((auto_r || params.texts().count("r")) && isAutoMeasurementNoise(params)) enableAutoNoise();
}

Mat<3> CsKalmanPredictor::processNoise(int c, double dt) const {
  // processNoiseScale(c): the raise of cs-akf-adaptive and fakf (1 for cs-akf, which does not read it)
  return singerProcessNoise(alpha_, accelerationVariance(c) * processNoiseScale(c), dt);
}

void CsKalmanPredictor::step(int c, double dt, double z) {
  predictStep(c, dt);
  inflatePrior(c, dt);
  if (isMeasured(z)) correctStep(c, z);
  afterStep(c, dt, z);
}

void CsKalmanPredictor::predictStep(int c, double dt) {
  // Q first: it depends on the acceleration before the prediction (abar = a(k-1|k-1)).
  const Mat<3> Q = processNoise(c, dt);
  // The CS mean abar = the significant part of the acceleration estimate (shrink_sigmas).
  Gaussian<3>& g = channelGaussian(c);
  g.x(2) *= significanceWeight(g.x(2), g.P(2, 2), shrink_update_sigmas_);
  timeUpdate(channelGaussian(c), transition(c, dt), Q);
}

void CsKalmanPredictor::correctStep(int c, double z) {
  ChannelState& s = state_[static_cast<size_t>(c)];
  s.innovation = measurementUpdate(s.g, z, measurementNoise(c));
}

// ---------------------------------------------------------------------------------------------

CsAkfPredictor::CsAkfPredictor(int channels, const Params& params)
    : CsKalmanPredictor(channels, params, /*auto_r=*/false, kDefaultShrinkSigmasCsAkf, /*weigh_velocity=*/false),
      a_max_(params.get("a_max", 200.0, 1e-9, 1e9)),
      a_neg_max_(params.get("a_neg_max", 200.0, 1e-9, 1e9)),
      sigma0_sq_(params.get("sigma0_sq", 1.0, 0.0, 1e12)) {}

double CsAkfPredictor::accelerationVariance(int c) const {
  return rayleighVariance(gaussian(c).x(2), a_max_, a_neg_max_, sigma0_sq_);
}

// ---------------------------------------------------------------------------------------------

/// Default floor of the adaptive variance ((px/s^2)^2). On smooth motion sigma^2 sits on it
/// (docs/MODELS.md §11), so it sets the smoothing / lag trade-off. Measured (tests/predictors/cs_akf_test.cpp,
/// 30 Hz, 1 px noise, 2 frames ahead): on the 200 px circle 1e-3 -> 3.0 px, 0.1..1 -> 0.52 px,
/// 10 -> 0.63 px; on the E2 acceleration jump (3 s after it) 1 -> 2.9 px, 10 -> 1.3 px. 10 is the
/// compromise: a small loss on smooth motion for a much faster reaction to a manoeuvre.
/// Issue 11: 10 and 1000 (tuned at 10 Hz on E2) lost to hold on most generated maneuvering tracks
/// (29/144, `predvs track-study`); 1e4 and 1e6 ((100 px/s^2)^2 and (1000 px/s^2)^2) beat it on 116/144.
/// With coasting (channel_predictor.h) the floor became the limit: 1e5 ((316 px/s^2)^2, a white-jerk
/// density 2 alpha sigma^2 = 2e5 px^2/s^5 at alpha = 1/s, the order of kf-ca's 3e5) is the default
/// (docs/MODELS.md §15 and docs/PERFORMANCE.md "Defaults that hold" give the grid that chose it).
constexpr double kDefaultSigmaMinSq = 1e5;
constexpr double kDefaultSigmaMaxSq = 1e6;

CsAkfAdaptivePredictor::CsAkfAdaptivePredictor(int channels, const Params& params)
    : CsKalmanPredictor(channels, params, /*auto_r=*/true, kDefaultShrinkSigmasAdaptive, /*weigh_velocity=*/true),
      sigma_max_sq_(params.get("sigma_max_sq", kDefaultSigmaMaxSq, 0.0, 1e12)),
      // a ceiling given below the default floor lowers the default floor with it
      sigma_min_sq_(params.get("sigma_min_sq", std::min(kDefaultSigmaMinSq, sigma_max_sq_), 0.0, 1e12)),
      adapt_tau_s_(params.get("adapt_tau_s", 0.0, 0.0, 1e3)),
      adapt_(adaptationParam(params, "cs-akf-adaptive / fakf")),
      sigma2_(static_cast<size_t>(channels), startVariance()),
      a_prev_(static_cast<size_t>(channels), 0.0) {
  // With the adaptation off sigma^2 stays at sigma_min_sq and the ceiling is not used (nor fitted).
  if (adapt_ && !(sigma_min_sq_ <= sigma_max_sq_))
    throw std::invalid_argument("predictor parameter 'sigma_min_sq' must not exceed 'sigma_max_sq'");
  readProcessNoiseRaise(params, {"sigma_min_sq", "sigma_max_sq"});
}

void CsAkfAdaptivePredictor::afterStep(int c, double dt, double z) {
  if (!adapt_ || !isMeasured(z)) return;
  const auto i = static_cast<size_t>(c);
  const double a = gaussian(c).x(2);
  const double d = a - a_prev_[i];
  sigma2_[i] = std::clamp(kRayleigh * d * d, sigma_min_sq_, sigma_max_sq_);
  const double w = adapt_tau_s_ > 0.0 ? -std::expm1(-dt / adapt_tau_s_) : 1.0;
  a_prev_[i] += w * d;
}

std::vector<Params> CsAkfAdaptivePredictor::structuralVariants() const {
  Params current, current_unweighted, zero;
  current.setText("mean", "current");
  current_unweighted.setText("mean", "current");
  current_unweighted.set("shrink_sigmas", 0.0);  // the blend with hold stays on (channel_predictor.h)
  zero.setText("mean", "zero");
  return withAdaptationOff({current, current_unweighted, zero});
}

std::vector<FitSeed> CsAkfAdaptivePredictor::fitSeeds() const {
  // Start 0, cs-akf: alpha, and its Rayleigh variance at zero acceleration as the floor.
  // Start 1, kf-ca: at alpha dt << 1 the Singer Q is white jerk of density 2 alpha sigma^2
  // (px^2/s^5), so the floor sigma^2 = q / (2 alpha) at this structure's alpha; with the adaptation
  // on the ceiling too (sigma^2 pinned there: the CS filter closest to kf-ca, the adaptation inert
  // until the fit moves the ceiling up).
  const double per_density = 1.0 / (2.0 * alpha());
  std::vector<FitSeed> seeds = {{"alpha", "cs-akf", "alpha", 1.0, 1.0, 0},
                                {"sigma_min_sq", "cs-akf", "a_max", kRayleigh, 2.0, 0},
                                {"sigma_min_sq", "kf-ca", "q", per_density, 1.0, 1}};
  if (adapt_) {
    // Start 0 with the ceiling lifted to that floor where the floor is above the ceiling's start
    // value (cs-akf's a_max above ~1900 px/s^2 against 1e6): the start was infeasible and skipped.
    seeds.push_back({"sigma_max_sq", "cs-akf", "a_max", kRayleigh, 2.0, 0, /*raise_only=*/true});
    seeds.push_back({"sigma_max_sq", "kf-ca", "q", per_density, 1.0, 1});
  }
  return seeds;
}

void CsAkfAdaptivePredictor::resetAdaptation() {
  std::fill(sigma2_.begin(), sigma2_.end(), startVariance());
  std::fill(a_prev_.begin(), a_prev_.end(), 0.0);
}

void CsAkfAdaptivePredictor::initialize(int c, double z) {
  CsKalmanPredictor::initialize(c, z);
  a_prev_[static_cast<size_t>(c)] = gaussian(c).x(2);
  sigma2_[static_cast<size_t>(c)] = startVariance();
}

}  // namespace predvs
