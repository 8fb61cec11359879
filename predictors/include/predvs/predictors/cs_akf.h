// predvs — the current statistical (CS) motion model and its Kalman filters (docs/MODELS.md §2, paper 000 §3).
//
// Model, per channel, state x = [p, v, a]. The acceleration is a mean abar plus a first-order Markov
// deviation with correlation rate alpha (1/s), driven by white noise of density 2 alpha sigma^2:
//
//   p' = v,   v' = a,   a' = -alpha a + alpha abar + w,   E[w(t) w(s)] = 2 alpha sigma^2 delta(t - s).
//
// Exactly discretised over a step dt (x = alpha dt, e = exp(-x)):
//
//   x(k+1) = F x(k) + U abar + w(k),   Cov w(k) = Q,
//   F = [[1, dt, (e - 1 + x)/alpha^2], [0, 1, (1 - e)/alpha], [0, 0, e]]            (singerTransition)
//   U = [(1 - x + x^2/2 - e)/alpha^2, dt - (1 - e)/alpha, 1 - e]'                    (singerInput)
//   Q = 2 alpha sigma^2 [q_ij] with the q_ij of docs/MODELS.md §2                           (singerProcessNoise)
//
// CS filter (the "current" statistical model): the mean abar is the filter's own predicted
// acceleration, abar = a(k|k-1). Since a(k|k-1) = e a(k-1|k-1) + (1 - e) abar, that choice makes
// a(k|k-1) = a(k-1|k-1), and the mean prediction F x + U abar = (F + U [0 0 1]) x is exactly the
// constant-acceleration prediction F_CA x. alpha and sigma^2 then act only through Q.
//
// Covariance propagation (our choice, docs/MODELS.md §11): P(k|k-1) = F_CA P F_CA' + Q_singer. The map the
// mean actually applies is F_CA (abar is a function of the state, not an exogenous input), so F_CA is
// its exact Jacobian. Propagating with the Singer F instead would shrink the acceleration variance by
// e^2 every step while the mean keeps the full acceleration: P would understate the actual error,
// the gain would fall, and the filter would become overconfident and lag (the fragility docs/MODELS.md §11
// reports). The same F_CA / Q_singer pair is used by update() and by the const prediction query,
// so a horizon prediction is consistent with the filter's own time update.
#pragma once

#include "predvs/predictors/channel_predictor.h"

#include <vector>

namespace predvs {

/// alpha*dt below which the Singer quantities are evaluated by their Taylor series in x = alpha*dt
/// instead of the closed forms. The closed forms cancel O(1) terms down to O(x^5) (q11), so their
/// relative rounding error grows like 1e-16 / x^5: ~1e-13 at x = 0.5 but 10% at x = 1e-3. The series
/// (20 terms, coefficients computed once from the exponential series) is accurate to < 1e-15
/// relative for x <= 0.5, so switching at 0.5 keeps both branches near machine precision on either
/// side (tested for continuity).
constexpr double kSingerSeriesThreshold = 0.5;

/// Singer transition F over dt for correlation rate alpha (1/s), alpha >= 0 (alpha = 0 gives F_CA).
Mat<3> singerTransition(double alpha, double dt);
/// Singer input vector U over dt: the response of [p, v, a] to a constant mean acceleration abar.
Vec<3> singerInput(double alpha, double dt);
/// Singer process noise Q = 2 alpha sigma2 [q_ij] over dt (sigma2: acceleration variance, (px/s^2)^2).
/// As alpha -> 0 with 2 alpha sigma2 = q fixed, Q tends to the white-jerk caProcessNoise(q, dt).
Mat<3> singerProcessNoise(double alpha, double sigma2, double dt);

/// Modified-Rayleigh acceleration variance of the CS model (paper 000 §3.1):
///   sigma^2 = (4 - pi)/pi (a_max - abar)^2        if abar > 0,
///   sigma^2 = (4 - pi)/pi (a_neg_max + abar)^2    if abar < 0   (a_neg_max: magnitude of the lower limit),
///   sigma^2 = sigma0_sq                           if abar == 0.
/// a_neg_max is used by magnitude, so -50 and 50 mean the same limit. The model assumes
/// -a_neg_max < abar < a_max; outside, the formula is applied as written (the variance grows again).
double rayleighVariance(double abar, double a_max, double a_neg_max, double sigma0_sq);

/// significanceWeight() (the weight of shrink_sigmas below) is in kalman_math.h, shared with the
/// per-channel filters (channel_predictor.h).

/// Default `shrink_sigmas` of cs-akf (3: an acceleration 3 standard deviations from zero counts
/// half; its velocity is not weighted) and of cs-akf-adaptive and fakf (2, velocity too). See
/// CsKalmanPredictor, docs/MODELS.md §15 and docs/PERFORMANCE.md "Defaults that hold" for the grids
/// that chose them; 0 turns the weighting off (paper 000's CS filter).
inline constexpr double kDefaultShrinkSigmasCsAkf = 3.0;
inline constexpr double kDefaultShrinkSigmasAdaptive = 2.0;

/// Common part of the CS filters: F_CA mean prediction, F_CA / Singer-Q covariance propagation,
/// Joseph-form scalar position update, and the hooks an adaptive variant overrides. Derived classes
/// only say which acceleration variance sigma^2 drives Q (accelerationVariance()).
///
/// One cycle (step) on channel c, in this order:
///   predictStep(c, dt)        x <- F_CA x, P <- F_CA P F_CA' + Q_singer(alpha, sigma^2(c), dt)
///   inflatePrior(c, dt)       hook on P(k|k-1) before the update (default: nothing; a fuzzy filter
///                             scales P here, e.g. P <- gamma P)
///   correctStep(c, z)         only if z is measured: Joseph update with R = measurementNoise(c),
///                             stores the innovation
///   afterStep(c, dt, z)       hook after the update (adaptive variance, windows; default: nothing)
///
/// Parameters common to both CS filters:
///   alpha   (1/s, default 1.0, range [1e-6, 1e3]): acceleration correlation rate; 1/alpha = 1 s is
///           the time over which an image-feature acceleration (a target turning or speeding up
///           by hand or on a conveyor) stays correlated. Q scales with 2 alpha sigma^2, so alpha
///           must stay > 0 (alpha = 0 would mean no process noise at all).
///   r       (px^2, default `auto`: estimated from the first frames, predictors/noise_estimate.h;
///           a number fixes it): measurement noise variance.
///   p0_vel  ((px/s)^2, default 1e4): initial velocity variance (100 px/s std covers 10..100 px/s).
///   p0_acc  ((px/s^2)^2, default 1e4): initial acceleration variance (as kf-ca).
///   coast_tau_s (s, default 0.2): velocity decay on frames without a measurement (channel_predictor.h).
///   mean    (word, default `current`): the acceleration's mean. `current` is the CS model (paper 000:
///           abar = the current estimate a(k-1|k-1), so the mean moves with F_CA); `zero` is Singer's
///           model it grew from (abar = 0: the acceleration decays as e^(-alpha dt) and the mean and
///           the covariance both move with the Singer F, the exact discretisation of that model).
///           With a large alpha the Singer filter tends to a constant-velocity one (the acceleration
///           forgets itself within a frame, Q ~ white acceleration of density 2 sigma^2 / alpha), with
///           a small one to constant acceleration: one structure spans both, with alpha fitted. This is
///           the structural variant the noise fit tries for the adaptive CS filters (cs-akf-adaptive,
///           fakf: structuralVariants()); the adaptation of sigma^2 is the same under either mean.
///   shrink_sigmas (dimensionless n, default 3 for cs-akf, 2 for cs-akf-adaptive and fakf; 0 = off,
///           paper 000's CS filter): significance weighting (issue 11, docs/MODELS.md §15). With
///           w(m, var) = m^2 / (m^2 + n^2 var) (significanceWeight):
///             forecast   the horizon query extrapolates x' = [p, w_v v, w_v w_a a] instead of
///                        x(k|k), w_a = w(a, P_aa) with n = shrink_sigmas, w_v = w(v, P_vv) with
///                        n = shrink_v_sigmas: a velocity or acceleration the filter cannot tell
///                        from zero (n standard deviations: weight 1/2) is not extrapolated over the
///                        horizon; a well-determined one is, in full;
///             time update  the CS mean abar is the significant part of the acceleration,
///                        a(k|k-1) = w_a a(k-1|k-1) (mean F_CA x with that a; P as before).
///           Stated in px and s through the filter's own P: the same n means "n standard deviations"
///           at any frame rate and noise; the weighting fades out where v and a are well determined
///           (high rate, low noise) and moves the forecast towards `hold` where they are not (10 Hz,
///           3 px). Why: at 10-15 Hz and 3 px noise the CA extrapolation of a noisy acceleration
///           (and, on the slow `hand` sway, of a noisy velocity) over a 0.2 s horizon cost more than
///           hold's lag, and an acceleration left in the state after a burst overshot.
///           Measured (`predvs track-study`, 216 tracks, docs/PERFORMANCE.md "Defaults that hold"):
///           beats hold on cs-akf 214 -> 216 (geometric-mean ratio 0.607 -> 0.581), cs-akf-adaptive
///           211 -> 216 (0.552 -> 0.535), fakf 203 -> 216 (0.581 -> 0.539, with r_band, fakf.h), and
///           on all tracks of both held-out grids. cs-akf with n = 2 leaves hand 10 Hz 3 px #1 at
///           x1.007, hence 3; the forecast alone (shrink_update_sigmas 0) leaves 1-2 bursts at 30 Hz
///           3 px for cs-akf-adaptive.
///   shrink_v_sigmas (default: shrink_sigmas for cs-akf-adaptive and fakf, 0 for cs-akf): n of the
///           velocity weight w_v. cs-akf-adaptive and fakf need it on one held-out track (hand 10 Hz
///           3 px #101, where kf-cv only ties hold: x1.155 / x1.166 without it); cs-akf beats hold on
///           every grid without it, and it costs the closed loop of ibvs-moving-target (slow image
///           motion, a high-bandwidth filter: v is "not significant"): cs-akf's rmse there 3.63 px
///           with 0, 8.96 with 2, 13.9 with 3 (2.37 px without any weighting; hold 36.5).
///   shrink_update_sigmas (default: shrink_sigmas): n of the time-update weighting alone (0: only
///           the forecast is weighted). Known cost: with a low process noise (a floor sigma_min_sq of
///           10 as in the papers' scenarios, or a small a_max) the gain on a is too small to rebuild an
///           acceleration the weighting removed, and a slow constant acceleration is followed like a
///           CV filter (fakf on E2, floor 10: final error 20 px instead of 1 px); use 0 there. The
///           papers' scenarios (data/scenarios, data/params) pin shrink_sigmas: 0, which also turns
///           the other two off unless they are given, and hold_blend_tau_s: 0 (no blend with hold,
///           channel_predictor.h; shrink_sigmas does not turn the blend off).
class CsKalmanPredictor : public ChannelPredictor<3> {
 public:
  /// Acceleration correlation rate (1/s).
  double alpha() const { return alpha_; }
  /// sigma^2 ((px/s^2)^2) that drives Q for the next time update of channel c.
  virtual double accelerationVariance(int c) const = 0;

 protected:
  /// The `alpha` entry of noiseParameters() (1/s, bounds 1e-3..1e2).
  NoiseParameter alphaParameter() const { return {"alpha", 1e-3, 1e2, alpha_}; }

  /// Reads alpha, r, p0_vel, p0_acc from params (derived classes read their own keys).
  /// auto_r: whether an absent `r` means `auto` (noise_estimate.h) or the number 1 px^2.
  /// default_shrink_sigmas: the default of `shrink_sigmas` for this filter; weigh_velocity: whether
  /// `shrink_v_sigmas` defaults to shrink_sigmas (true) or to 0.
  CsKalmanPredictor(int channels, const Params& params, bool auto_r, double default_shrink_sigmas, bool weigh_velocity);

  /// The mean's transition: F_CA for the CS mean (abar = a(k-1|k-1)), the Singer F for `mean: zero`.
  Mat<3> transition(int, double dt) const override { return zero_mean_ ? singerTransition(alpha_, dt) : caTransition(dt); }
  Mat<3> processNoise(int c, double dt) const override;
  /// Whether the acceleration has the zero mean of Singer's model (`mean: zero`) instead of the CS mean.
  bool zeroMean() const { return zero_mean_; }

  /// predictStep; inflatePrior; correctStep if z is measured; afterStep. Not meant to be overridden
  /// (override the hooks instead), but left virtual for filters that restructure the cycle.
  void step(int c, double dt, double z) override;
  /// Time update of channel c: x(k|k-1) = F_CA x(k-1|k-1), P(k|k-1) = F_CA P F_CA' + Q_singer.
  virtual void predictStep(int c, double dt);
  /// Hook on the prior P(k|k-1) (and x(k|k-1)) before the measurement update. Default: nothing.
  virtual void inflatePrior(int /*c*/, double /*dt*/) {}
  /// Measurement update of channel c with z (finite), R = measurementNoise(c), Joseph form;
  /// records the innovation returned by innovation(c).
  virtual void correctStep(int c, double z);
  /// Hook after the (possible) measurement update; z is NaN when the channel was not measured.
  virtual void afterStep(int /*c*/, double /*dt*/, double /*z*/) {}

  /// Mutable Gaussian of channel c (x(k|k) after a step, x(k|k-1) inside inflatePrior).
  Gaussian<3>& channelGaussian(int c) { return state_[static_cast<size_t>(c)].g; }

 private:
  double alpha_;
  bool zero_mean_ = false;
  double shrink_update_sigmas_;  ///< the time-update weighting (the forecast's: ChannelPredictor)
};

/// `cs-akf`: CS Kalman filter with the modified-Rayleigh variance and fixed limits:
/// sigma^2(k) = rayleighVariance(a(k-1|k-1), a_max, a_neg_max, sigma0_sq) (abar = a(k|k-1) = a(k-1|k-1)).
/// Parameters (besides alpha, r, p0_vel, p0_acc):
///   a_max      (px/s^2, default 200; 50 before issue 11): largest expected positive acceleration.
///              Targets moving at 50..400 px/s that turn within ~0.5 s accelerate by ~200 px/s^2
///              (the generated tracks of servo/maneuver_tracks.h); the slow circle of E4 has
///              4.5 px/s^2, E2 jumps to 30.
///   a_neg_max  (px/s^2, default 200): magnitude of the largest negative acceleration.
///   r          unlike the other Kalman predictors, cs-akf keeps the number 1 px^2 as its default
///              (`auto` on request): measured with `predvs track-study` (216 generated tracks),
///              a_max 200 with r = 1 beats hold on 210, with the estimated r on 174 (its Rayleigh
///              Q already follows the manoeuvres; a larger R at 3 px noise only slows it).
///   sigma0_sq  ((px/s^2)^2, default 1.0): variance used when abar == 0 (in practice only at start).
/// Known weakness (the reason for the adaptive variant): small a_max gives smooth estimates but a
/// slow response to manoeuvres, large a_max the opposite.
class CsAkfPredictor : public CsKalmanPredictor {
 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<CsAkfPredictor>(*this); }
  CsAkfPredictor(int channels, const Params& params);
  std::string name() const override { return "cs-akf"; }
  double accelerationVariance(int c) const override;
  std::vector<NoiseParameter> noiseParameters() const override {
    return {alphaParameter(), {"a_max", 1e-1, 1e5, a_max_}, {"a_neg_max", 1e-1, 1e5, a_neg_max_},
            measurementNoiseParameter()};
  }

 private:
  double a_max_;
  double a_neg_max_;
  double sigma0_sq_;
};

/// `cs-akf-adaptive`: CS Kalman filter whose acceleration variance adapts from the filter's own
/// acceleration estimates instead of a fixed a_max (paper 000 §3.2; its eq. 10 is lost, this is the
/// variant docs/MODELS.md §2 suggests):
///
///   sigma^2(k) = clamp((4 - pi)/pi (a(k|k) - a(k-1|k-1))^2, sigma_min_sq, sigma_max_sq),
///
/// computed after the measurement update of frame k and used in Q for the prediction to k+1.
/// Since a(k|k-1) = a(k-1|k-1) under the CS mean, the difference is the acceleration correction
/// K_a eps of the last update: a large innovation (a manoeuvre) raises Q at once, which raises the
/// gain; on smooth motion the correction is small and sigma^2 sits on its floor.
/// Choices:
///   * the raw one-step difference, no averaging: fastest reaction to a jump (averaging would delay
///     it by the window length), with the floor and ceiling bounding the feedback loop;
///   * a frame without a measurement on that channel leaves sigma^2 and a(k-1|k-1) unchanged
///     (a predict-only step has no correction, so it carries no information about manoeuvres);
///   * sigma^2 starts at sigma_max_sq, so the filter converges quickly from its first measurements.
/// Measured (tests/predictors/cs_akf_test.cpp, 30 Hz, 1 px noise, 2 frames ahead): on the E2 jump
/// the fixed cs-akf error varies x2.2 with a_max in [5, 500] px/s^2; this filter with its default
/// floor is better than the worst a_max choices but ~1.6x the error of the best-tuned a_max. Its
/// acceleration correction K_a eps is small when sigma^2 is small (low gain), so a low floor
/// reacts to a jump slowly: the floor, not a_max, is now the parameter that matters.
/// Parameters (besides alpha, r, p0_vel, p0_acc):
///   sigma_min_sq ((px/s^2)^2, default 1e5 since issue 11, 10 before; sigma_max_sq when only a lower
///                ceiling is given): the floor. On smooth motion sigma^2 stays on it and it
///                alone sets the smoothing / lag trade-off (docs/MODELS.md §11); its effect is measured in
///                tests/predictors/cs_akf_test.cpp (see kDefaultSigmaMinSq in cs_akf.cpp).
///   sigma_max_sq ((px/s^2)^2, default 1e6 ~ (4-pi)/pi * 3600^2; 1000 before issue 11): the ceiling.
///   adaptation   (word, on | off, default on): off fixes sigma^2 at sigma_min_sq (a fixed CS /
///                Singer filter; fakf: also R at r and no P inflation), kalman_math.h adaptationParam.
///   q_raise_ratio (default 2; 0 = off): when neither bound is given and the blend with hold is on,
///                the Singer density is multiplied by a factor >= 1 that rises while the innovations
///                are more than this many times their predicted variance (process_noise_adapt.h,
///                docs/MODELS.md §15); cs-akf (fixed r = 1 px^2 by default) does not read it.
///   adapt_tau_s  (s, default 0): time constant of the reference acceleration. 0 is the variant
///                above (reference = a(k-1|k-1)); tau > 0 replaces a(k-1|k-1) by a low-passed
///                a_ref += (1 - exp(-dt/tau)) (a(k|k) - a_ref), which measures the change over ~tau
///                and makes a small floor less harmful on smooth motion (measured, not the default).
///
/// Extension points for subclasses (e.g. the improved fuzzy AKF, docs/MODELS.md §3): override
/// measurementNoise(c) for a per-channel adapted R, inflatePrior() to scale P(k|k-1), afterStep()
/// to update windows (call CsAkfAdaptivePredictor::afterStep to keep the variance adaptation), and
/// resetAdaptation() (call the base version too). channelGaussian(c), innovation(c) and state_
/// give access to the per-channel estimate.
class CsAkfAdaptivePredictor : public CsKalmanPredictor {
 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<CsAkfAdaptivePredictor>(*this); }
  CsAkfAdaptivePredictor(int channels, const Params& params);
  std::string name() const override { return "cs-akf-adaptive"; }
  double accelerationVariance(int c) const override { return sigma2_[static_cast<size_t>(c)]; }
  double sigmaMinSq() const { return sigma_min_sq_; }
  double sigmaMaxSq() const { return sigma_max_sq_; }
  /// With `adaptation: off` sigma^2 is fixed at sigma_min_sq and sigma_max_sq is not fitted.
  std::vector<NoiseParameter> noiseParameters() const override {
    if (!adapt_) return {alphaParameter(), sigmaMinSqParameter(), measurementNoiseParameter()};
    return {alphaParameter(), sigmaMinSqParameter(), {"sigma_max_sq", 1e-1, 1e10, sigma_max_sq_},
            measurementNoiseParameter()};
  }
  /// {mean: current} (the CS model), the same unweighted (shrink_sigmas 0, still blended with hold) and {mean: zero}
  /// (Singer's; see CsKalmanPredictor), each also with `adaptation: off` (kalman_math.h: sigma^2
  /// fixed at sigma_min_sq; for fakf also no fuzzy R or P): a fit keeps whichever predicts the
  /// track better (fakf inherits them).
  std::vector<Params> structuralVariants() const override;
  /// Two warm starts (FitSeed::start), every structure. 0, from cs-akf's fit (the fixed CS filter):
  /// alpha, and sigma_min_sq = (4 - pi)/pi a_max^2, cs-akf's Rayleigh variance at zero acceleration
  /// (the floor this filter sits on in smooth motion, and its fixed variance with `adaptation:
  /// off`). 1, from kf-ca's fit: sigma_min_sq = q / (2 alpha) at this structure's alpha (the Singer
  /// density 2 alpha sigma^2 equal to kf-ca's white-jerk q), and with the adaptation on
  /// sigma_max_sq the same (sigma^2 pinned: the structure nearest to kf-ca). fakf inherits it.
  std::vector<FitSeed> fitSeeds() const override;

 protected:
  /// The `sigma_min_sq` entry of noiseParameters() ((px/s^2)^2, bounds 1e-3..1e10; 1e8 before FIT4).
  /// Why 1e10, the ceiling's own upper bound: on smooth motion the floor sets the Singer density
  /// 2 alpha sigma^2, which has to reach the white-jerk densities kf-ca is fitted to (bounded at
  /// 1e11 px^2/s^5, kalman_math.h) while alpha stays CA-like (alpha dt << 1). A fixed KF at equal
  /// per-frame gains has q ~ r / dt^5, so the densities grow fast with the rate: kf-ca fitted on
  /// bursts 60 Hz 0.5 px has q = 9.1e8 px^2/s^5, i.e. sigma^2 = 4.6e8 at alpha = 1/s, above the old
  /// bound (an acceleration std of 1e4 px/s^2 sounds like a lot for a target, but the floor here is a
  /// bandwidth, not a physical acceleration: at 60 Hz it is 2 alpha sigma^2 dt = (1800 px/s^2)^2 of
  /// acceleration change per frame at 1e8).
  NoiseParameter sigmaMinSqParameter() const { return {"sigma_min_sq", 1e-3, 1e10, sigma_min_sq_}; }
  /// Adapts sigma^2(c) from a(k|k) - a(k-1|k-1) when z was measured.
  void afterStep(int c, double dt, double z) override;
  /// sigma^2 back to sigma_max_sq and the acceleration memory cleared, on every channel.
  void resetAdaptation() override;
  /// Records a(0|0) as the first acceleration memory.
  void initialize(int c, double z) override;

 private:
  double sigma_max_sq_;  // before sigma_min_sq_: its default depends on the ceiling
  double sigma_min_sq_;
  double adapt_tau_s_;

 protected:
  bool adapt_;  ///< `adaptation` on (default) / off (kalman_math.h adaptationParam)
  /// sigma^2 of a channel at its start: the ceiling (adapting down from it), or with adaptation off
  /// the floor it stays at.
  double startVariance() const { return adapt_ ? sigma_max_sq_ : sigma_min_sq_; }

 private:
  std::vector<double> sigma2_;  ///< per channel, (px/s^2)^2
  std::vector<double> a_prev_;  ///< a(k-1|k-1) per channel, px/s^2
};

}  // namespace predvs
