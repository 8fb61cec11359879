// predvs — the plumbing shared by every per-channel Kalman predictor.
//
// Channels are independent, each with a fixed-size Gaussian state of N entries. A derived filter
// provides the motion model (transition and process noise over any dt), its measurement noise,
// and may override step() to adapt R, Q or P (fuzzy, strong-tracking, self-tuning filters).
//
// Coasting (issue 11, docs/MODELS.md §15): on a frame where channel c is not measured (dropped
// frame, occlusion), its velocity and acceleration estimates decay before the time update,
//   v <- v exp(-dt / tau),   a <- a exp(-2 dt / tau),   tau = coast_tau_s (s),
// i.e. without measurements the target's velocity is a first-order Markov process that returns to
// rest with time constant tau, and the coasted position tends to p + v tau instead of growing
// without bound. A measured frame is not affected (the prediction horizon of a measured frame is
// extrapolated with the full model). The covariance is left as the model propagates it (the decay
// claims no extra certainty). tau = 0 switches coasting off (the model's own extrapolation, as
// before). Every predictor with a motion state reads the key `coast_tau_s` (s, default
// kDefaultCoastTauS) through readCoastParam(); `hold` has no velocity to decay.
//
// Significance-weighted forecast (issue 11 item 3, docs/MODELS.md §15): a derived filter that calls
// readShrinkParams() extrapolates the prediction horizon from
//   [p, w_v v(, w_v w_a a)],   w_a = w(a, P_aa; shrink_sigmas),  w_v = w(v, P_vv; shrink_v_sigmas),
// with w(m, var; n) = m^2 / (m^2 + n^2 var) (significanceWeight(), kalman_math.h) and P = P(k|k), the
// filter's own covariance: a velocity or an acceleration the filter cannot tell from zero (10 Hz,
// 3 px) is damped towards hold, a well determined one (60 Hz, 0.5 px) is left as it is. Only the
// forecast is weighted: the filter's own time update (step()) is unchanged, and the covariance of the
// forecast is the model's propagation of P(k|k). n = 0 switches a weight off, and with both 0
// predict() and predictPosition() are the unweighted ones bit for bit. The CS filters (cs_akf.h) use this
// forecast weighting and also weigh the acceleration of their own time update.
#pragma once

#include "predvs/predictors/kalman_math.h"
#include "predvs/predictors/noise_estimate.h"
#include "predvs/predictors/predictor.h"
#include "predvs/predictors/process_noise_adapt.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {

/// Default coasting time constant (s): the velocity of an unmeasured target decays with it.
/// Chosen with `predvs track-study` on the main and held-out grids (docs/PERFORMANCE.md "Defaults
/// that hold"): a hard stop (the generated `stops` and `bursts` tracks) inside an occlusion of
/// 0.1..0.3 s otherwise costs an extrapolation error far above hold's. 0.2 s is the longest
/// 2-frame horizon of the 10..60 Hz envelope, so a single dropped frame at 10 Hz keeps 60 % of v.
inline constexpr double kDefaultCoastTauS = 0.2;

/// The `coast_tau_s` parameter (s, >= 0, default kDefaultCoastTauS; 0 = no coasting).
inline double coastTauParam(const Params& params) { return params.get("coast_tau_s", kDefaultCoastTauS, 0.0, 1e6); }

/// The coasting decay of an unmeasured frame (above) on a state [p, v(, a)]:
/// v <- v e, a <- a e^2, e = exp(-dt / tau_s); tau_s > 0.
template <int N>
inline void coast(Vec<N>& x, double dt, double tau_s) {
  const double e = std::exp(-dt / tau_s);
  x(1) *= e;
  if constexpr (N == 3) x(2) *= e * e;
}

template <int N>
class ChannelPredictor : public Predictor {
 public:
  static_assert(N == 2 || N == 3, "a channel state is [p, v] or [p, v, a]");

  void reset() override {
    resetClock();
    for (auto& c : state_) c = ChannelState{};
    for (auto& e : r_est_) e.reset();
    for (auto& m : q_auto_) m.reset();
    resetAdaptation();
  }

  void update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) override {
    if (z.size() != channels())
      throw std::invalid_argument(name() + ": measurement has " + std::to_string(z.size()) +
                                  " entries, expected " + std::to_string(channels()));
    const double dt = advanceClock(t_s);
    for (int c = 0; c < channels(); ++c) {
      ChannelState& s = state_[c];
      s.innovation = Innovation{};
      if (!r_est_.empty()) r_est_[static_cast<size_t>(c)].push(t_s, z(c));
      if (!s.initialized) {
        if (isMeasured(z(c))) {
          initialize(c, z(c));
          s.initialized = true;
        }
        continue;
      }
      if (coast_tau_s_ > 0.0 && !isMeasured(z(c))) coast(s.g.x, dt, coast_tau_s_);
      step(c, dt, z(c));
      if (!q_auto_.empty() && s.innovation.valid) q_auto_[static_cast<size_t>(c)].observe(s.innovation.eps, s.innovation.S, dt);
    }
  }
  using Predictor::update;

  ChannelEstimate predict(int channel, double t_s) const override {
    const ChannelState& s = state_.at(channel);
    if (!s.initialized) {
      ChannelEstimate e;
      e.x = ChannelVector::Constant(N, std::numeric_limits<double>::quiet_NaN());
      e.P = ChannelMatrix::Constant(N, N, std::numeric_limits<double>::quiet_NaN());
      return e;
    }
    const double dt = t_s - time();
    if (!(dt > 0.0)) return toEstimate(s.g);
    Gaussian<N> g = forecastWeightingOn() ? weightedForecastStart(channel) : s.g;
    timeUpdate(g, transition(channel, dt), processNoise(channel, dt));
    return toEstimate(g);
  }

  /// predict(channel, t_s).position() without the covariance: x(0) of the same F x product.
  double predictPosition(int channel, double t_s) const override {
    const ChannelState& s = state_.at(channel);
    if (!s.initialized) return std::numeric_limits<double>::quiet_NaN();
    const double dt = t_s - time();
    if (!(dt > 0.0)) return s.g.x(0);
    if (forecastWeightingOn()) return predictedPosition(weightedForecastStart(channel), transition(channel, dt));
    return predictedPosition(s.g, transition(channel, dt));
  }

  Innovation innovation(int channel) const override { return state_.at(channel).innovation; }

  /// The filtered Gaussian of a channel at the last update time (tests, monitors).
  const Gaussian<N>& gaussian(int channel) const { return state_.at(channel).g; }
  bool initialized(int channel) const { return state_.at(channel).initialized; }

 protected:
  struct ChannelState {
    Gaussian<N> g;
    bool initialized = false;
    Innovation innovation;
  };

  ChannelPredictor(int channels, double r_px2, double p0_vel, double p0_acc)
      : Predictor(channels), state_(static_cast<size_t>(channels)), r0_(r_px2), p0_vel_(p0_vel), p0_acc_(p0_acc) {}

  /// Transition matrix of channel c over dt.
  virtual Mat<N> transition(int c, double dt) const = 0;
  /// Process noise of channel c over dt.
  virtual Mat<N> processNoise(int c, double dt) const = 0;
  /// Measurement noise variance of channel c (may be adapted).
  virtual double measurementNoise(int c) const { return nominalNoise(c); }
  /// The nominal R of channel c: r0_, or the start-up estimate when enableAutoNoise() was called.
  double nominalNoise(int c) const { return r_est_.empty() ? r0_ : r_est_[static_cast<size_t>(c)].variance(); }
  /// Makes R a start-up estimate per channel (noise_estimate.h); called by a derived constructor
  /// when its `r` parameter is absent or `auto`. The estimate's prior is
  /// r0_.
  void enableAutoNoise() { r_est_.assign(state_.size(), StartupNoiseEstimator(r0_)); }
  /// Reads `coast_tau_s` (s, >= 0, default kDefaultCoastTauS); called by every derived constructor
  /// whose state has a velocity.
  void readCoastParam(const Params& params) { coast_tau_s_ = coastTauParam(params); }
  double coastTauS() const { return coast_tau_s_; }
  /// Reads `shrink_sigmas` (n of the acceleration weight w_a, dimensionless >= 0, default
  /// default_sigmas; with N = 2 there is no acceleration and it only sets the default of the next
  /// key) and `shrink_v_sigmas` (n of the velocity weight w_v, default: shrink_sigmas when
  /// weigh_velocity, else 0); see the file comment. Called by the derived constructors whose
  /// forecast is weighted; without the call the forecast is unweighted.
  void readShrinkParams(const Params& params, double default_sigmas, bool weigh_velocity) {
    shrink_a_sigmas_ = params.get("shrink_sigmas", default_sigmas, 0.0, 1e3);
    shrink_v_sigmas_ = params.get("shrink_v_sigmas", weigh_velocity ? shrink_a_sigmas_ : 0.0, 0.0, 1e3);
    if constexpr (N == 2) shrink_a_sigmas_ = 0.0;
  }
  /// True when the forecast is weighted (a shrink key > 0).
  bool forecastWeightingOn() const { return shrink_a_sigmas_ > 0.0 || shrink_v_sigmas_ > 0.0; }
  /// The Gaussian the forecast of channel c extrapolates: x(k|k) with a weighted by w_a w_v and v by
  /// w_v (file comment), P(k|k) unchanged.
  Gaussian<N> weightedForecastStart(int c) const {
    Gaussian<N> g = state_[static_cast<size_t>(c)].g;
    const double w_v = significanceWeight(g.x(1), g.P(1, 1), shrink_v_sigmas_);
    g.x(1) *= w_v;
    if constexpr (N == 3) {
      g.x(2) *= significanceWeight(g.x(2), g.P(2, 2), shrink_a_sigmas_);
      g.x(2) *= w_v;
    }
    return g;
  }
  /// Makes the process noise of every channel adapted by covariance matching (`q: auto`,
  /// process_noise_adapt.h); called by a derived constructor when its `q` is absent or `auto`.
  void enableAutoProcessNoise() { q_auto_.assign(state_.size(), ProcessNoiseMatcher()); }
  /// q / q0 of channel c: 1 unless enableAutoProcessNoise() was called. A derived processNoise()
  /// multiplies its nominal density by it.
  double processNoiseScale(int c) const { return q_auto_.empty() ? 1.0 : q_auto_[static_cast<size_t>(c)].scale(); }
  bool autoNoise() const { return !r_est_.empty(); }
  /// The `r` entry of noiseParameters(): r0_, i.e. the number given for `r`, or, when `r` is
  /// `auto`, the prior the start-up estimate begins from (not the running estimate, which depends
  /// on the data seen so far and differs per channel). For the fuzzy filters it is the initial R.
  NoiseParameter measurementNoiseParameter() const { return measurementVarianceParameter(r0_); }
  /// True when channel c's nominal R no longer changes (fixed r, or the estimate is frozen).
  bool nominalNoiseFinal(int c) const { return r_est_.empty() || r_est_[static_cast<size_t>(c)].done(); }
  /// Clears adaptive terms (windows, adapted R, fading memories) on reset().
  virtual void resetAdaptation() {}

  /// First measurement: x = [z, 0(, 0)], P = diag(R, p0_vel(, p0_acc)).
  virtual void initialize(int c, double z) {
    Gaussian<N>& g = state_[c].g;
    g.x.setZero();
    g.x(0) = z;
    g.P.setZero();
    g.P(0, 0) = measurementNoise(c);
    g.P(1, 1) = p0_vel_;
    if constexpr (N == 3) g.P(2, 2) = p0_acc_;
  }

  /// One filter cycle on channel c: predict over dt, then fuse z unless it is NaN. Adaptive
  /// filters override this and reuse timeUpdate()/measurementUpdate().
  virtual void step(int c, double dt, double z) {
    ChannelState& s = state_[c];
    timeUpdate(s.g, transition(c, dt), processNoise(c, dt));
    if (isMeasured(z)) s.innovation = measurementUpdate(s.g, z, measurementNoise(c));
  }

  std::vector<ChannelState> state_;
  std::vector<StartupNoiseEstimator> r_est_;  ///< empty unless enableAutoNoise()
  std::vector<ProcessNoiseMatcher> q_auto_;   ///< empty unless enableAutoProcessNoise()
  double r0_;
  double p0_vel_;
  double p0_acc_;
  double coast_tau_s_ = 0.0;  ///< 0 until readCoastParam(): hold never coasts
  double shrink_a_sigmas_ = 0.0;  ///< 0 until readShrinkParams(): unweighted forecast
  double shrink_v_sigmas_ = 0.0;
};

}  // namespace predvs
