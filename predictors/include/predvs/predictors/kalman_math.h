// predvs — small fixed-size Kalman building blocks shared by every predictor (Eigen only).
//
// Motion models are continuous-time, discretised over an arbitrary step dt, so one model serves
// the frame period T, a horizon h*T, or an irregular gap between two measurements.
#pragma once

#include "predvs/predictors/predictor.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace predvs {

/// The 2-state Kalman updates below (and predictedMean<2>) are inlined into every caller. GCC
/// stopped inlining them once ChannelPredictor::predict() and step() grew (the blend with hold, the
/// coasting): each call then passed the Gaussian through memory and read it back at once, which
/// cost the plain kf-cv a third of its time per frame (docs/PERFORMANCE.md, "Predictor cost per
/// frame"). Inlining changes no bit (no FMA contraction without -march). The generic (3-state)
/// ones are left to the compiler: forced inline, kf-ca, the CS filters and stkf ran 10-20 % slower.
#if defined(__GNUC__) || defined(__clang__)
#define PREDVS_KALMAN_INLINE __attribute__((always_inline)) inline
#else
#define PREDVS_KALMAN_INLINE inline
#endif

template <int N>
using Vec = Eigen::Matrix<double, N, 1>;
template <int N>
using Mat = Eigen::Matrix<double, N, N>;

/// Gaussian state of one channel.
template <int N>
struct Gaussian {
  Vec<N> x = Vec<N>::Zero();
  Mat<N> P = Mat<N>::Identity();
};

/// P <- (P + P') / 2, pair by pair (no temporary).
template <int N>
inline void symmetrize(Mat<N>& P) {
  for (int i = 0; i < N; ++i)
    for (int j = i + 1; j < N; ++j) P(i, j) = P(j, i) = 0.5 * (P(i, j) + P(j, i));
}

/// Significance weight of an estimate m with variance var (issue 11, "Defaults that hold"):
///   w = m^2 / (m^2 + n^2 var),   n = n_sigmas;   w = 1 when n_sigmas = 0 (no weighting).
/// w -> 1 for an estimate many standard deviations away from zero, w = 1/2 at exactly n standard
/// deviations, w -> 0 for an estimate buried in its own uncertainty (a velocity or an acceleration
/// that the filter cannot tell from zero). Units: m and sqrt(var) in the same unit (px/s, px/s^2).
inline double significanceWeight(double m, double var, double n_sigmas) {
  if (!(n_sigmas > 0.0)) return 1.0;
  const double m2 = m * m;
  const double d = m2 + n_sigmas * n_sigmas * std::max(var, 0.0);
  return d > 0.0 ? m2 / d : 0.0;
}

/// The mean of a time update, F x: the arithmetic timeUpdate() uses for it (the same bits), for a
/// forecast without its covariance.
template <int N>
inline Vec<N> predictedMean(const Vec<N>& x, const Mat<N>& F) {
  return (F * x).eval();
}
/// The 2-state one written out, as timeUpdate<2> below computes it.
template <>
PREDVS_KALMAN_INLINE Vec<2> predictedMean<2>(const Vec<2>& x, const Mat<2>& F) {
  return Vec<2>(F(0, 0) * x(0) + F(0, 1) * x(1), F(1, 0) * x(0) + F(1, 1) * x(1));
}

/// Time update: x <- F x, P <- F P F' + Q (kept symmetric).
template <int N>
inline void timeUpdate(Gaussian<N>& g, const Mat<N>& F, const Mat<N>& Q) {
  g.x = predictedMean(g.x, F);
  const Mat<N> FP = F * g.P;
  g.P.noalias() = FP * F.transpose();
  g.P += Q;
  symmetrize(g.P);
}

/// (F x)(0) of a state x: row 0 of F times x summed left to right, which is the order of Eigen's
/// product in timeUpdate (its columns accumulated in turn, exact zeros included), so the same bits
/// as the position timeUpdate would give, without building the other rows.
template <int N>
inline double predictedPosition(const Vec<N>& x, const Mat<N>& F) {
  double p = F(0, 0) * x(0);
  for (int k = 1; k < N; ++k) p += F(0, k) * x(k);
  return p;
}
/// The same for a Gaussian's mean, without touching P.
template <int N>
inline double predictedPosition(const Gaussian<N>& g, const Mat<N>& F) {
  return predictedPosition(g.x, F);
}

/// Measurement update of a scalar position measurement (H = [1 0 ..]) in Joseph form:
///   K = P H' / S,  x <- x + K eps,  P <- (I - K H) P (I - K H)' + K R K'.
/// The Joseph form keeps P symmetric PSD even when the gain is sub-optimal (adapted R, inflated
/// or faded P), which is the case for every adaptive predictor here.
template <int N>
inline Innovation measurementUpdate(Gaussian<N>& g, double z, double R) {
  Innovation in;
  in.eps = z - g.x(0);
  in.S = g.P(0, 0) + R;
  in.valid = true;
  const Vec<N> K = g.P.col(0) / in.S;
  g.x += K * in.eps;
  Mat<N> IKH = Mat<N>::Identity();
  IKH.col(0) -= K;
  const Mat<N> AP = IKH * g.P;
  g.P.noalias() = AP * IKH.transpose();
  g.P.noalias() += (R * K) * K.transpose();
  symmetrize(g.P);
  return in;
}

/// 2-state specialisations: the same arithmetic as the generic products above (the Joseph form
/// stays a product, so P stays PSD for any gain), written out on the three distinct entries of the
/// symmetric P. Eigen's 2x2 products spend most of their time shuffling lanes; these run about
/// twice as fast, and the 2-state filters (kf-cv, fakf-classic, stkf) are the per-frame hot path.
template <>
PREDVS_KALMAN_INLINE void timeUpdate<2>(Gaussian<2>& g, const Mat<2>& F, const Mat<2>& Q) {
  const double a = F(0, 0), b = F(0, 1), c = F(1, 0), d = F(1, 1);
  const double p00 = g.P(0, 0), p01 = 0.5 * (g.P(0, 1) + g.P(1, 0)), p11 = g.P(1, 1);
  g.x = predictedMean(g.x, F);
  const double fp00 = a * p00 + b * p01, fp01 = a * p01 + b * p11;  // row 0 of F P
  const double fp10 = c * p00 + d * p01, fp11 = c * p01 + d * p11;  // row 1 of F P
  const double q01 = 0.5 * (Q(0, 1) + Q(1, 0));
  g.P(0, 0) = fp00 * a + fp01 * b + Q(0, 0);
  g.P(0, 1) = g.P(1, 0) = fp00 * c + fp01 * d + q01;
  g.P(1, 1) = fp10 * c + fp11 * d + Q(1, 1);
}

template <>
PREDVS_KALMAN_INLINE Innovation measurementUpdate<2>(Gaussian<2>& g, double z, double R) {
  Innovation in;
  const double p00 = g.P(0, 0), p01 = 0.5 * (g.P(0, 1) + g.P(1, 0)), p11 = g.P(1, 1);
  in.eps = z - g.x(0);
  in.S = p00 + R;
  in.valid = true;
  const double k0 = p00 / in.S, k1 = p01 / in.S;
  g.x(0) += k0 * in.eps;
  g.x(1) += k1 * in.eps;
  // A = I - K H = [[1 - k0, 0], [-k1, 1]];  P <- A P A' + R K K'
  const double a00 = 1.0 - k0;
  // (A P A') is symmetric: its (0, 1) entry is taken as (1, 0) = row 1 of A P times column 0 of A'.
  const double ap00 = a00 * p00;                              // (0, 0) of A P
  const double ap10 = p01 - k1 * p00, ap11 = p11 - k1 * p01;  // row 1 of A P
  g.P(0, 0) = ap00 * a00 + R * k0 * k0;
  g.P(0, 1) = g.P(1, 0) = ap10 * a00 + R * k0 * k1;
  g.P(1, 1) = -ap10 * k1 + ap11 + R * k1 * k1;
  return in;
}

/// Constant velocity: x = [p, v], F = [[1, dt], [0, 1]].
inline Mat<2> cvTransition(double dt) {
  Mat<2> F;
  F << 1.0, dt, 0.0, 1.0;
  return F;
}

/// White-noise acceleration of spectral density q (units^2/s^3):
///   Q = q [[dt^3/3, dt^2/2], [dt^2/2, dt]].
inline Mat<2> cvProcessNoise(double q, double dt) {
  Mat<2> Q;
  const double dt2 = dt * dt, dt3 = dt2 * dt;
  Q << dt3 / 3.0, dt2 / 2.0, dt2 / 2.0, dt;
  return q * Q;
}

/// Constant acceleration: x = [p, v, a], F = [[1, dt, dt^2/2], [0, 1, dt], [0, 0, 1]].
inline Mat<3> caTransition(double dt) {
  Mat<3> F;
  F << 1.0, dt, 0.5 * dt * dt, 0.0, 1.0, dt, 0.0, 0.0, 1.0;
  return F;
}

/// White-noise jerk of spectral density q (units^2/s^5):
///   Q = q [[dt^5/20, dt^4/8, dt^3/6], [dt^4/8, dt^3/3, dt^2/2], [dt^3/6, dt^2/2, dt]].
inline Mat<3> caProcessNoise(double q, double dt) {
  const double dt2 = dt * dt, dt3 = dt2 * dt, dt4 = dt3 * dt, dt5 = dt4 * dt;
  Mat<3> Q;
  Q << dt5 / 20.0, dt4 / 8.0, dt3 / 6.0,  //
      dt4 / 8.0, dt3 / 3.0, dt2 / 2.0,    //
      dt3 / 6.0, dt2 / 2.0, dt;
  return q * Q;
}

/// The polynomial motion model of a filter on N states: constant velocity (N = 2, cvTransition /
/// cvProcessNoise, q a white-acceleration density, px^2/s^3) or constant acceleration (N = 3,
/// caTransition / caProcessNoise, q a white-jerk density, px^2/s^5).
template <int N>
inline Mat<N> motionTransition(double dt) {
  if constexpr (N == 2)
    return cvTransition(dt);
  else
    return caTransition(dt);
}
template <int N>
inline Mat<N> motionProcessNoise(double q, double dt) {
  if constexpr (N == 2)
    return cvProcessNoise(q, dt);
  else
    return caProcessNoise(q, dt);
}
/// The noiseParameters() entry of that q (accelerationDensityParameter / jerkDensityParameter).
template <int N>
inline NoiseParameter motionDensityParameter(const std::string& key, double q);
/// The two structures of a filter that runs on either model, for structuralVariants():
/// {model: cv} and {model: ca}.
inline std::vector<Params> motionModelVariants() {
  Params cv, ca;
  cv.setText("model", "cv");
  ca.setText("model", "ca");
  return {cv, ca};
}

/// The fit seed of a structure on the model of N states whose `key` is the model's noise density
/// (cvProcessNoise's q for N = 2, caProcessNoise's q for N = 3): kf-cv's fitted q, or kf-ca's
/// (Predictor::fitSeeds(); the same quantity under the same name in the same units).
template <int N>
inline FitSeed motionDensitySeed(const std::string& key) {
  return {key, N == 2 ? "kf-cv" : "kf-ca", "q", 1.0, 1.0};
}

/// `adaptation` (word: on | off, default on), read by the adaptive filters (st-akf, st-akf-pm,
/// fakf-classic, cs-akf-adaptive, fakf): off keeps the filter's model, noise and forecast and turns
/// its adaptive layer off (no fading factor; R fixed at r; sigma^2 fixed at its floor; no fuzzy
/// R or P), leaving the fixed Kalman filter it is built on. It is a structure the noise fit
/// tries (withAdaptationOff): where the adaptation does not pay on a track, the fit says so.
/// Throws std::invalid_argument naming `who` for another word.
inline bool adaptationParam(const Params& params, const std::string& who) {
  const std::string word = params.text("adaptation", "on");
  if (word == "on") return true;
  if (word == "off") return false;
  throw std::invalid_argument("predictor '" + who + "': parameter 'adaptation' must be on or off, got '" + word + "'");
}
/// The structures `variants` (each as given, with the adaptive layer on) followed by each of them
/// with `adaptation: off`, for the structuralVariants() of an adaptive filter.
inline std::vector<Params> withAdaptationOff(const std::vector<Params>& variants) {
  std::vector<Params> out = variants;
  for (Params v : variants) {
    v.setText("adaptation", "off");
    out.push_back(v);
  }
  return out;
}

/// noiseParameters() entries shared by several filters (bounds: see Predictor::noiseParameters).
/// Measurement variance `r` (px^2): 1e-3..1e3, i.e. 0.03..30 px standard deviation.
inline NoiseParameter measurementVarianceParameter(double r_px2) { return {"r", 1e-3, 1e3, r_px2}; }
/// White-acceleration density (cvProcessNoise's q, px^2/s^3): 1e-2..1e8.
inline NoiseParameter accelerationDensityParameter(const std::string& key, double q) { return {key, 1e-2, 1e8, q}; }
/// White-jerk density (caProcessNoise's q, px^2/s^5; also the Singer density 2 alpha sigma^2): 1e-1..1e11.
inline NoiseParameter jerkDensityParameter(const std::string& key, double q) { return {key, 1e-1, 1e11, q}; }
template <int N>
inline NoiseParameter motionDensityParameter(const std::string& key, double q) {
  if constexpr (N == 2)
    return accelerationDensityParameter(key, q);
  else
    return jerkDensityParameter(key, q);
}

/// Estimate of a fixed-size Gaussian as the interface's ChannelEstimate.
/// Copied element by element: for these runtime-sized (at most 3x3) types Eigen's assignment
/// goes through an out-of-line memmove, which was a measurable share of a whole kf-cv step.
template <int N>
inline ChannelEstimate toEstimate(const Gaussian<N>& g) {
  ChannelEstimate e;
  e.x.resize(N);
  e.P.resize(N, N);
  for (int i = 0; i < N; ++i) {
    e.x(i) = g.x(i);
    for (int j = 0; j < N; ++j) e.P(i, j) = g.P(i, j);
  }
  return e;
}

inline bool isMeasured(double z) { return std::isfinite(z); }

}  // namespace predvs
