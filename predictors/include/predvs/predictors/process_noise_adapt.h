// predvs — process noise adapted online by covariance matching of the innovations (`q: auto`,
// issue 11 "defaults that hold", docs/MODELS.md §15).
//
// A Kalman filter whose process-noise density q is right produces innovations eps whose variance
// is the one it predicts, S = H P(k|k-1) H' + R, i.e. E[eps^2 / S] = 1. Too large a q (a filter
// that follows the noise) gives eps^2 / S below 1 on average, too small a q (a filter that lags a
// manoeuvre) above 1. `q: auto` runs q = q0 exp(l) and moves l by a stochastic-approximation step
// towards that balance after every measured frame:
//
//   l <- clamp(l + (dt / tau_s) (min(eps^2 / S, ratio_max) - 1), ln(scale_min), ln(scale_max)),
//
// dt the time since the previous update (s). The step is per second of data, not per frame, so
// the same tau_s adapts at the same speed at 10 and at 60 Hz; q0 is the predictor's nominal
// density in its own units (px^2/s^3 for a CV model, px^2/s^5 for a CA model) and stays the
// starting point. eps^2 / S is clipped at ratio_max = 9 (a 3-sigma innovation) so that one outlier
// or the first frames of a manoeuvre raise q by at most exp(8 dt / tau_s) per frame; the decrease
// is at most exp(-dt / tau_s) per frame. Choices (measured with `predvs track-study`,
// docs/PERFORMANCE.md "Defaults that hold"): tau_s = kDefaultQAutoTauS, scale bounds
// [kQAutoScaleMin, kQAutoScaleMax] around q0. A frame without a measurement leaves l unchanged.
//
// The raise (the default of kf-cv, kf-ca, stkf, st-akf, st-akf-pm, fakf-classic, cs-akf-adaptive,
// fakf and imm when the density is not given and the blend with hold is on; key `q_raise_ratio`,
// docs/MODELS.md §15 "q rises when the innovations say so"): the same recursion with the target
// ratio c = q_raise_ratio instead of 1 and the bounds [1, kQAutoScaleMax]:
//
//   l <- clamp(l + (dt / tau_s) (min(eps^2 / S, ratio_max) - c), 0, ln(scale_max)).
//
// The default q is the floor; q rises only while the innovations are, over about tau_s, more than
// c times the variance the filter predicts, i.e. while the target moves well outside what the
// default q was sized for (a fixed q cannot serve a 50 px/s drift and a 700 px/s oscillation at
// once), and falls back to the default once they are not. The symmetric `q: auto` lowers q too: on
// the generated tracks that costs more at two frames ahead than it gains (docs/MODELS.md §15).
//
// The whitening (the closed loop's, `closed_loop: 1`, docs/MODELS.md §15 "In a closed loop"): the
// step is the product of the last two normalised innovations instead of the spread,
//
//   l <- clamp(l + (dt / tau_w) clamp(e(k) e(k-1), -c_w, c_w), ln(scale_min), ln(scale_max)),
//   e = eps / sqrt(S),
//
// i.e. the density moves until the innovations are white (Mehra 1970, docs/MODELS.md §13: a Kalman filter's
// innovations are white exactly when its gain is the optimal one). A filter that follows the noise
// has innovations that alternate in sign (the product is negative on average: q falls), one that
// lags a motion has runs of one sign (positive: q rises). Why not the spread: E[eps^2 / S] = 1 ties
// q to R, and R is an estimate (noise_estimate.h: +-30 % over a track's first 50 differences). With
// R 20 % low, the spread balances kf-cv at q ~ 1e3 px^2/s^3 on a 5 px/s line at 25 Hz under 1 px of
// noise (its velocity noise 5.7 px/s); 43 % low (a draw of e5-line's first second), at q ~ 2e4
// (19 px/s); with R right, it drifts down. The sign of the innovations' correlation does not depend
// on R: a wrong R moves the density the whitening settles at in proportion, so the gain, and the
// velocity's noise, stay what they would be with R right (tests/predictors/q_whitening_test.cpp).
// The step's clip and time constant (measured on the closed-loop scenarios, 10 seeds, and 30 on
// five of them: docs/PERFORMANCE.md "Innovations made white"): c_w = 9 (the spread's clip) with
// tau_w = 1 s let cs-akf-adaptive and fakf run away on one seed of e8-vtc (95,946 px); c_w = 3 with
// 1 s and c_w = 1 with 0.5 s did 7 and 2 % worse than the kept tau_w = kDefaultQWhitenTauS,
// c_w = kQWhitenStepMax. The first measured frame (no product yet) moves nothing, and a gap keeps
// the last normalised innovation for the next measured frame.
//
// The whitening's target (`q_white_rho` rho*, a correlation in [-0.9, 0.9]; docs/MODELS.md §15):
// the step is e(k) e(k-1) - rho*, so the density settles where the lag-one correlation of the
// normalised innovations is rho* instead of 0. The filters with a white-jerk acceleration state
// whose density the whitening moves (kf-ca, st-akf and st-akf-pm on their CA model, imm's shared
// scale) default to rho* = kDefaultQWhiteRhoAcceleration = 0.2, the others to 0. Why: white
// innovations make the best one-frame forecast of the features, but a closed loop acts on the
// velocity, which it feeds forward and integrates. The CA model's one-frame optimum follows the
// jerk, and its velocity carries that noise to the robot; through the loop's compensation, whose
// model is not exact, the commanded motion comes back into the features the filter sees, and the
// whitening raises q further. A CA filter that lags a little keeps its acceleration state, so it
// still follows a turning target without a velocity lag. A constant-velocity model has no such
// state: it lags in velocity as soon as q is lower. Measured (docs/PERFORMANCE.md "A lagging
// acceleration model in the closed loop", 10 seeds): rho* = 0.2 lowers kf-ca's rmse on the 24
// closed-loop cells by 32 % (geometric mean; none worse) and on 12 held-out variants of the
// default loop (60, 25 and 10 Hz; 0.5 and 2 px; two target speeds) by 58 %; imm and st-akf by
// 24 / 23 % and 54 / 41 %. kf-cv, fakf-classic, cs-akf-adaptive and fakf lose on 14 of the 24
// cells with it, hence 0 for them. With rho* = 0.3 kf-ca does a little better still, st-akf a little
// worse (a run away at e9-broyden's gains 6 and 7). The open loop (the raise, `q: auto`) has no target.
#pragma once

#include "predvs/predictors/params.h"

#include <initializer_list>
#include <optional>
#include <string>

namespace predvs {

/// Time constant of the adaptation (s).
inline constexpr double kDefaultQAutoTauS = 1.0;
/// Bounds of q / q0.
inline constexpr double kQAutoScaleMin = 1e-3;
inline constexpr double kQAutoScaleMax = 1e2;
/// Largest eps^2 / S one frame contributes.
inline constexpr double kQAutoRatioMax = 9.0;
/// Default target ratio c of the raise (`q_raise_ratio`; 0 = no raise).
inline constexpr double kDefaultQRaiseRatio = 2.0;
/// Time constant of the whitening (s): 1 / 1.5 (file comment).
inline constexpr double kDefaultQWhitenTauS = 1.0 / 1.5;
/// Largest |e(k) e(k-1)| one frame contributes to the whitening.
inline constexpr double kQWhitenStepMax = 2.0;
/// Default `q_white_rho` rho* (file comment, "The whitening's target"): the lag-one correlation of the
/// normalised innovations the closed loop's whitening aims at. 0 (white) for the constant-velocity
/// models and the filters whose acceleration variance adapts on its own (cs-akf-adaptive, fakf).
inline constexpr double kDefaultQWhiteRho = 0.0;
/// The same for the filters with a white-jerk acceleration state whose density the whitening moves
/// (kf-ca, st-akf and st-akf-pm on their CA model, imm): a filter that lags a little.
inline constexpr double kDefaultQWhiteRhoAcceleration = 0.2;
/// Bound of |q_white_rho|: a correlation, short of 1.
inline constexpr double kQWhiteRhoMax = 0.9;

/// What the adaptation balances (file comment): the innovations' spread E[eps^2 / S] against a
/// target (`q: auto`, the raise), or their lag-one correlation against 0 (the whitening).
enum class InnovationStatistic { Spread, Whiteness };

/// True when the process-noise key `key` (e.g. "q") holds the word `auto`: q is then adapted
/// (ProcessNoiseMatcher) from the predictor's default. False when it is absent (the default q,
/// fixed: `auto` is opt-in, see docs/PERFORMANCE.md for why) or holds a number, which fixes q.
/// Throws std::invalid_argument naming the key for another word.
bool isAutoProcessNoise(const Params& params, const std::string& key);
/// The number given for `key` (checked against [lo, hi]), or `fallback` when absent or `auto`.
/// Marks the key as read.
double processNoiseParam(const Params& params, const std::string& key, double fallback, double lo, double hi);

/// The `q_raise_ratio` parameter: c of the raise (file comment), 0 (no raise) or in [1, kQAutoRatioMax];
/// default kDefaultQRaiseRatio. Throws std::invalid_argument naming the key for another value.
double processNoiseRaiseRatio(const Params& params);
/// The `q_white_rho` parameter: rho* of the whitening (file comment, "The whitening's target"), in
/// [-kQWhiteRhoMax, kQWhiteRhoMax]; default `fallback`, the filter's. Throws std::invalid_argument
/// naming the key outside.
double processNoiseWhiteRho(const Params& params, double fallback);
/// The per-channel state of the adaptation: the log scale l of q.
class ProcessNoiseMatcher {
 public:
  /// `target`: the mean eps^2 / S the recursion settles at (1: covariance matching, `q: auto`).
  explicit ProcessNoiseMatcher(double tau_s = kDefaultQAutoTauS, double scale_min = kQAutoScaleMin,
                               double scale_max = kQAutoScaleMax, double target = 1.0);
  /// The raise (file comment): floor 1, target ratio `ratio`.
  static ProcessNoiseMatcher raise(double ratio) {
    return ProcessNoiseMatcher(kDefaultQAutoTauS, 1.0, kQAutoScaleMax, ratio);
  }
  /// The whitening (file comment): bounds [kQAutoScaleMin, kQAutoScaleMax] around q0, aiming the
  /// lag-one correlation of the normalised innovations at `rho` ("The whitening's target").
  static ProcessNoiseMatcher whitening(double rho = kDefaultQWhiteRho);
  void reset() {
    log_scale_ = 0.0;
    scale_ = 1.0;
    last_e_ = 0.0;
    have_last_e_ = false;
  }
  InnovationStatistic statistic() const { return statistic_; }
  /// One measured frame: innovation eps (px) with predicted variance S (px^2), dt (s) since the
  /// previous update. Ignored when S <= 0 or dt <= 0.
  void observe(double eps, double S, double dt_s);
  /// q / q0 now (exp(l), kept with l: read on every time update).
  double scale() const { return scale_; }

 private:
  double tau_s_, log_min_, log_max_;
  double target_;  ///< the spread's target ratio, or the whitening's target correlation rho*
  InnovationStatistic statistic_ = InnovationStatistic::Spread;
  double log_scale_ = 0.0;
  double scale_ = 1.0;
  double last_e_ = 0.0;      ///< the whitening's last normalised innovation eps / sqrt(S)
  bool have_last_e_ = false;
};

/// The raise of a predictor (file comment), when it is on: none of `fixing_keys` (the keys that set
/// its density) given, the blend with hold on and `q_raise_ratio` > 0; otherwise none. In a closed
/// loop (`closed_loop: 1`, predictor.h closedLoopParam) with none of `fixing_keys` given, the
/// adaptation `in_closed_loop` says instead: the whitening (ProcessNoiseMatcher::whitening(), the
/// default), or covariance matching (Spread: ProcessNoiseMatcher(), as `q: auto`; stkf's, whose R
/// moves every frame). Either lets the density fall as far as the innovations allow
/// (docs/MODELS.md §15, "In a closed loop"). The whitening aims at the correlation `q_white_rho`,
/// default `white_rho` (the filter's: kDefaultQWhiteRho or kDefaultQWhiteRhoAcceleration). Reads
/// (and checks) `q_raise_ratio`, `q_white_rho` and `closed_loop` in every case.
std::optional<ProcessNoiseMatcher> processNoiseRaise(const Params& params, std::initializer_list<const char*> fixing_keys,
                                                     bool blend_on,
                                                     InnovationStatistic in_closed_loop = InnovationStatistic::Whiteness,
                                                     double white_rho = kDefaultQWhiteRho);

}  // namespace predvs
