// predvs — strong-tracking adaptive Kalman filter (ST-AKF, docs/MODELS.md §5, paper 004 §3) and its
// variant supervised by the predictive monitor (docs/MODELS.md §6, paper 004 §4), each on the CA
// model of the paper (default) or the CV model (`model: cv`). Units: px, s; q in px^2/s^5 (CA) or
// px^2/s^3 (CV), r in px^2.
#pragma once

#include "predvs/predictors/channel_predictor.h"
#include "predvs/predictors/monitor.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace predvs {

/// Default white-jerk density of st-akf and st-akf-pm with `model: ca` (the default), px^2/s^5:
/// 1e5, i.e. a jerk of ~300 px/s^3 per sqrt(s), the order of the turns and starts of targets
/// moving at 50..400 px/s. Chosen on the generated maneuvering tracks (`predvs track-study`,
/// docs/PERFORMANCE.md "Defaults that hold"): with 1000 (the value before issue 11) the filter
/// relied on its fading factor to follow every manoeuvre and lagged on the `hand` sway at 3 px
/// noise, where the fading (beta = 5) rarely triggers.
inline constexpr double kDefaultQStAkf = 1e5;
/// Default white-acceleration density of st-akf and st-akf-pm with `model: cv`, px^2/s^3: kf-cv's
/// (kDefaultQCv), an acceleration change of ~100 px/s^2 per sqrt(s). With the other defaults of
/// the CA filter (beta 5, rho 0.95) st-akf on cv beats hold on 216/216 generated tracks, geometric
/// mean ratio 0.512 (q 3e3: 0.515, 3e4: 0.535, 1e3 and 1e5 lose 4-5 tracks); docs/PERFORMANCE.md
/// "Defaults that hold", subsection "st-akf, st-akf-pm and fakf-classic on either motion model".
inline constexpr double kDefaultQStAkfCv = 1e4;
/// Default `shrink_sigmas` of st-akf and st-akf-pm (ca, cv), and whether shrink_v_sigmas defaults to
/// it (channel_predictor.h, significance-weighted forecast; docs/MODELS.md §15). CA: 1.5, the
/// smallest n (0.25 steps near it) that beats hold on the 216 tracks of `predvs track-study` and
/// both held-out grids (1.25 loses zigzag 10 Hz 3 px #101 by x1.02; mean ratio 0.533 -> 0.509);
/// CV: 0.5 (0 loses hand 10 Hz 3 px #101 by x1.016).
inline constexpr double kDefaultShrinkSigmasStAkf = 1.5;
inline constexpr double kDefaultShrinkSigmasStAkfCv = 0.5;
inline constexpr bool kDefaultShrinkVelocityStAkf = true;

/// `st-akf`: Kalman filter with fading factors (strong tracking), on either motion model.
///
/// Motion model (`model`, a word): `ca` (default, paper 004's) x = [p, v, a] per channel,
/// F = CA transition over dt, Q = white-jerk noise of density q (px^2/s^5), as kf-ca; or `cv`:
/// x = [p, v], F = CV transition, Q = white-acceleration noise of density q (px^2/s^3), as kf-cv.
/// H = [1, 0(, 0)]. The class is a template on the state size N (2 = cv, 3 = ca);
/// makeStAkfPredictor() reads `model` and builds the instantiation. When the innovations grow
/// larger than the filter expects, the predicted covariance is inflated so that the gain rises
/// and old data are forgotten faster:
///   gamma = z - H F x(k|k),
///   V0 = gamma^2 on the first step, then V0 <- (rho V0 + gamma^2) / (1 + rho)   (rho = 0.95),
///   N = V0 - H Q H' - beta R          (beta >= 1 softens the factor),
///   M = a_1 (F P F')_11               (paper 004 eq. 22: tr(diag(a) F P F' H'H) for H = [1 0 0]),
///   c = N / M,  lambda_i = max(1, a_i c),  i = 1..N (p, v(, a)),
///   P(k+1|k) = L^1/2 F P F' L^1/2 + Q,  L = diag(lambda_i).
/// With all a_i = 1 this is the single-factor filter, lambda = max(1, tr N / tr M). Nothing in the
/// fading depends on the motion model: only F, Q and the number of factors change.
/// While R is a start-up estimate that is not yet frozen (`r: auto`, noise_estimate.h) lambda = 1:
/// the innovations then measure the R mismatch, not a manoeuvre (issue 11: at 60 Hz and 3 px the
/// fading on the prior R = 1 px^2 drove the start-up acceleration to the noise, and an occlusion
/// in the first second extrapolated it, x1.7 hold's error over the track; docs/MODELS.md §15).
/// The paper writes L F P F'; with unequal factors that product is not symmetric, so the factors
/// are applied symmetrically here (identical when the factors are equal). The measurement update
/// is in Joseph form, since a faded gain is not the optimal one.
///
/// Parameters: model (cv | ca, default ca), q (ca: px^2/s^5, default kDefaultQStAkf = 1e5, 1000
/// before issue 11; cv: px^2/s^3, default kDefaultQStAkfCv = 1e4; raised as kf-cv's when not given,
/// q_raise_ratio (default 2; 0 = no raise); `auto`: adapted both ways; in a closed loop whitened
/// towards q_white_rho, default kDefaultQWhiteRhoAcceleration on ca, kDefaultQWhiteRho on cv;
/// process_noise_adapt.h),
/// r (px^2, default `auto`: predictors/noise_estimate.h),
/// p0_vel ((px/s)^2, 1e4), p0_acc ((px/s^2)^2, 1e4), rho (0.95), beta (default 5 since issue 11,
/// 1 before), a1, a2, a3 (1: preset ratios of the fading factors of p, v, a; each >= 1),
/// coast_tau_s (s, 0.2, channel_predictor.h), adaptation (on | off, default on; off: no fading,
/// kalman_math.h adaptationParam), adapt_after_gap (0 | 1, default 0: while coasting, the first
/// measured frame after a gap neither fades nor enters V0, its innovation being the coast's own
/// departure from the model; 1 = fade there too, as before; without coasting every measured frame
/// fades; channel_predictor.h, docs/MODELS.md §5), shrink_sigmas (significance weight of the forecast
/// acceleration, default 1.5 on ca, 0.5 on cv; 0 = the unweighted filter) and shrink_v_sigmas
/// (velocity, default shrink_sigmas): channel_predictor.h.
/// Choice: with `model: cv` the keys of the acceleration state, p0_acc and a3, are accepted (range
/// checked) and unused, so that one configuration runs on either model (a noise fit's structural
/// variants change `model` alone); every other key means the same on both models.
/// beta: with beta = 1 any innovation power above R fades P, so at 60 Hz and 3 px noise the noise
/// alone kept the gain near 1 and st-akf lost to hold by x2.3 (`predvs track-study`); beta = 5
/// fades only on innovations well above the noise (133/144 generated tracks beat hold, was 118).
template <int N>
class StAkfPredictor : public ChannelPredictor<N> {
  using Base = ChannelPredictor<N>;

 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<StAkfPredictor>(*this); }
  StAkfPredictor(int channels, const Params& params);
  std::string name() const override { return "st-akf"; }
  /// q (the white-acceleration density for cv, the white-jerk density for ca) and r (also those of
  /// st-akf-pm: the monitor adds no noise parameter).
  std::vector<NoiseParameter> noiseParameters() const override {
    return {motionDensityParameter<N>("q", q_), this->measurementNoiseParameter()};
  }
  /// {model: cv} and {model: ca}, each also with `adaptation: off` (no fading: the KF of the model).
  std::vector<Params> structuralVariants() const override;
  /// q from kf-cv's fitted q (cv) or kf-ca's (ca): the same density (kalman_math.h motionDensitySeed).
  std::vector<FitSeed> fitSeeds() const override { return {motionDensitySeed<N>("q")}; }

  /// Fading factors lambda_i of channel c at its last measured update (1 when no fading).
  Vec<N> fadingFactors(int c) const { return ext_.at(static_cast<size_t>(c)).lambda; }
  /// Innovation variance predicted before fading, H (F P F' + Q) H' + R, at the last update.
  double unfadedS(int c) const { return ext_.at(static_cast<size_t>(c)).s_unfaded; }

 protected:
  Mat<N> transition(int, double dt) const override { return motionTransition<N>(dt); }
  Mat<N> processNoise(int c, double dt) const override {
    return motionProcessNoise<N>(q_ * this->processNoiseScale(c), dt);
  }
  void resetAdaptation() override;
  void step(int c, double dt, double z) override;
  /// Starts channel c again at z (x = [z, 0(, 0)], P = P_0) and clears its fading memory.
  void restartChannel(int c, double z);

 private:
  struct Extra {
    double V0 = 0.0;
    bool has_V0 = false;
    Vec<N> lambda = Vec<N>::Ones();
    double s_unfaded = 0.0;
  };
  double q_, rho_, beta_;
  bool adapt_;  ///< `adaptation` on (default) / off: no fading (kalman_math.h adaptationParam)

 protected:
  double q() const { return q_; }

 private:
  Vec<N> a_;
  std::vector<Extra> ext_;
};

/// Steady-state Kalman filter of the CV (N = 2: white-acceleration density q, px^2/s^3) or CA
/// (N = 3: white-jerk density q, px^2/s^5) model, measurement variance r, step dt: the fixed
/// point of the Riccati recursion, found by iterating it from P = 0 until it stops changing.
/// K is the fixed gain, P_post the filtered covariance it leaves.
template <int N>
struct SteadyStateKf {
  Vec<N> K = Vec<N>::Zero();
  Mat<N> P_post = Mat<N>::Zero();
  int iterations = 0;
};
template <int N>
SteadyStateKf<N> steadyStateKf(double q, double r, double dt);
using SteadyStateCa = SteadyStateKf<3>;
inline SteadyStateCa steadyStateCa(double q, double r, double dt) { return steadyStateKf<3>(q, r, dt); }

/// `st-akf-pm`: st-akf supervised by a DiscontinuityMonitor per channel, on either motion model
/// (`model`, as st-akf; the monitor does not depend on it).
///
/// Before each measured update the two-step prediction error dxp = z(k) - H x(k|k-2) is formed
/// by propagating the estimate kept from two updates earlier over t(k) - t(k-2) (so it stays
/// correct with irregular periods or after a predict-only frame). The band monitor watches dxp;
/// the chi-square monitor watches the one-step innovation against its unfaded variance. On an
/// alarm the channel is re-initialised at the measurement, x = [z, 0(, 0)], P = P_0, its fading
/// memory and monitor history are cleared, as paper 004 does.
/// With pm_on_alarm = 1 the channel instead restarts at [z, 0(, 0)] and runs the steady-state
/// filter of its model (fixed gain of steadyStateKf<N>(q, r, dt), no fading) for the next
/// pm_ss_frames measured frames, then hands back to the strong-tracking filter with P = P_post of
/// that steady state. The paper switches to "an appropriate steady-state KF" on a discontinuity
/// without saying when it switches back; the fixed duration is our choice. The monitor is silent
/// during the steady-state phase and restarts after it.
///
/// Parameters: those of st-akf, plus monitor (0 = band, 1 = chi-square; default 0),
/// pm_window (n, default 20), pm_band (lambda_b, default 6; see MonitorConfig), pm_floor (band floor, signal units,
/// default 1e-6), pm_chi2 (threshold, default 15.13, false-alarm prob. 1e-4 per sample),
/// pm_on_alarm (0 = re-initialise, default; 1 = steady-state KF), pm_ss_frames (default 25).
/// `adaptation: off` turns the monitor off too (no alarm, no re-initialisation): the monitor is
/// part of the adaptive layer, and off leaves the fixed Kalman filter underneath (kalman_math.h),
/// the structure the noise fit compares with the adaptive ones (docs/PERFORMANCE.md "--fit on the
/// whole track": with the monitor left on, that structure lost to kf-cv on bursts and stops).
template <int N>
class StAkfPmPredictor : public StAkfPredictor<N> {
  using Base = StAkfPredictor<N>;

 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<StAkfPmPredictor>(*this); }
  StAkfPmPredictor(int channels, const Params& params);
  std::string name() const override { return "st-akf-pm"; }

  int monitorAlarms() const override;
  /// The monitor of channel c (counters, last alarm time, last ratio).
  const DiscontinuityMonitor& monitor(int c) const { return monitors_.at(static_cast<size_t>(c)); }

 protected:
  void resetAdaptation() override;
  void initialize(int c, double z) override;
  void step(int c, double dt, double z) override;

 private:
  struct Past {
    Gaussian<N> g;
    double t_s = 0.0;
  };
  struct History {
    std::array<Past, 2> past;  // [0] = k-2, [1] = k-1
    int count = 0;
    void push(const Gaussian<N>& g, double t_s) {
      past[0] = past[1];
      past[1] = Past{g, t_s};
      if (count < 2) ++count;
    }
  };
  const SteadyStateKf<N>& steadyState(double dt);

  bool monitor_on_;  ///< false with `adaptation: off`
  bool on_alarm_steady_;
  int ss_frames_;
  std::vector<DiscontinuityMonitor> monitors_;
  std::vector<History> history_;
  std::vector<int> ss_left_;  // measured frames left in the steady-state phase, per channel
  SteadyStateKf<N> ss_;       // cached for ss_dt_
  double ss_dt_ = -1.0;
};

extern template class StAkfPredictor<2>;
extern template class StAkfPredictor<3>;
extern template class StAkfPmPredictor<2>;
extern template class StAkfPmPredictor<3>;

/// The registry's factories: read `model` (cv | ca, default ca) and build StAkfPredictor<2> / <3>
/// (resp. StAkfPmPredictor). Another word is a std::invalid_argument naming `model`.
std::unique_ptr<Predictor> makeStAkfPredictor(int channels, const Params& params);
std::unique_ptr<Predictor> makeStAkfPmPredictor(int channels, const Params& params);

}  // namespace predvs
