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
// A stop before the gap (issue 11 item 3, docs/MODELS.md §15): when the blend with hold (below) is on,
// a gap that begins while the target is decelerating coasts with a shorter time constant,
//   tau_gap = min(tau, c t_stop),   c = coast_stop_fraction (default kDefaultCoastStopFraction),
// t_stop the time the target would take to come to rest at the deceleration seen when the
// measurements ended (CoastStop::stopTime(): the filter's own velocity fall over the last
// kCoastStopWindowS, when larger than kCoastStopVelocitySigmas sqrt(P_vv); or the deceleration of a
// quadratic fitted to the last kCoastStopFitFrames measurements, when larger than kCoastStopFitSigmas
// of its standard error; the shorter). A filter's velocity lags a hard stop by a few frames, and a
// gap that begins there otherwise coasts on v tau (50 px at 250 px/s) while the target stands still.
// tau_gap is chosen on the gap's first frame and holds to its end; no significant deceleration, or
// c = 0, leaves tau. Off with the blend (hold_blend_tau_s = 0, the papers' scenarios).
//
// The track's own speeds, and the shape of the coast (issue 11 item 3, docs/MODELS.md §15, with the
// blend only): a channel speed far above the speeds the channel has shown lately is a short
// excursion (a push, a burst) that ends soon. Each channel keeps the mean square of its filtered
// velocity over the measured frames of the last ~hold_blend_tau_s (a time-weighted forgetting mean,
// v_rms^2 = sum l v^2 dt / sum l dt); a gap that begins at rho = |v| / v_rms > rho_0 =
// coast_fast_ratio (once >= kCoastFastMinMemoryS of memory) coasts with
//   tau_gap = min(tau_gap, tau (rho_0 / rho)^kCoastFastPower).
// Measurements falling behind before the gap (issue 11 item 3, docs/MODELS.md §15, with the blend
// only): each channel keeps the normalised innovations r = eps / sqrt(S) of its measured frames;
// their sum over the last kCoastLagFrames, z_l = sum r / sqrt(kCoastLagFrames), is a standard normal
// while the model fits. A gap that begins while z_l opposes the filter's velocity (the measurements
// behind its forecasts: the target slows down more than the model thinks) by more than n_l =
// coast_lag_sigmas coasts with
//   tau_gap = min(tau_gap, tau max((n_l / |z_l|)^kCoastLagPower, s)),
// s the share of its one-frame step the filter's newest measurements still made
// (CoastStop::lagVelocityShare(): 1 + mean(eps) / (v dt) over the newest j frames, the smallest of
// j = 1..kCoastLagFrames, in [0, 1]; with `coast_lag_share` 1, the default, else s = 0). It sees a
// stop earlier than the stop rule's fits at 3 px: a burst that stops two or three noisy frames before
// its gap (docs/PERFORMANCE.md "Measurements falling behind before a gap"). The share bounds the cut
// by what the lag says of the velocity: a significance alone is large wherever S is small (60 Hz,
// 0.5 px), so a target that slows down gently, its measurements 0.9 px short of a 3.4 px step, had its
// coast cut to a third as if it had stopped (a Lissajous at 200 px/s, make-track smooth 60 Hz 0.5 px
// #804: kf-ca's coast 4 px through a 0.28 s gap, the target 50 px on); s = 0.65 there, and a dead
// stop still gives s = 0 (docs/PERFORMANCE.md "The lag rule cuts no more than the lag shows").
// A turn or a stop through zero (`coast_crossing`, default 1; 0 = off; issue 11 item 3,
// docs/MODELS.md §15, with the blend only): a filter with an acceleration state lags a hard stop,
// its velocity falls through zero a frame or two after the target came to rest, and a gap that
// begins there coasts the deceleration into a drift the other way (kf-ca 45 px back over a 0.53 s
// gap after a burst at 60 Hz, 1.46 times hold's error over the track). A turn falls through zero
// too, and there the acceleration is the new direction. Each channel learns which of the two its
// crossings are: on a measured frame where the filter's velocity changed sign, and fell through
// zero within kCoastStopWindowS by more than kCoastStopVelocitySigmas sqrt(P_vv) (CoastStop::
// crossedZero()), it notes the velocity v_0 at the window's start, and kCoastStopWindowS later
// scores the outcome o = clamp(-v / v_0, 0, 1) (1: the other way as fast, 0: at rest or back the
// same way); the share of turns is the forgetting mean of o (events forgotten with exp(-elapsed /
// hold_blend_tau_s); one turn counted as a prior, so a channel that has not crossed yet keeps its
// acceleration). A gap that begins within kCoastStopWindowS of such a crossing coasts with its
// acceleration multiplied by that share (the velocity is left to the rules above). A tremor or a
// zigzag keeps its acceleration, a track that bursts and stops loses it.
// A gap no rule shortened coasts with a hazard that grows with the time u since the last
// measurement: v(u) = v0 S(u), S(u) = exp(-(u / tau)^k), k = coast_shape (the per-frame factor
// S(u + dt) / S(u) on v, its square on a); k = 1 is the exponential decay above, k > 1 keeps more
// of the velocity over a dropped frame or two and less at the end of a long occlusion (its total
// displacement v tau Gamma(1 + 1/k) is 0.90 v tau at k = 1.5 instead of v tau). A shortened gap
// (tau_gap < tau) coasts exponentially with tau_gap.
//
// The first measurement after a gap (issue 11 item 3, docs/MODELS.md §3 and §5): while a channel
// coasts, the innovation of its first measured frame after unmeasured ones holds the coast's own
// departure from the model over the gap (the velocity decayed on purpose), not a one-step misfit of
// the model. A filter that adapts on its innovations (st-akf's and st-akf-pm's fading factors,
// fakf-classic's R, fakf's R and P inflation) and calls readAdaptAfterGapParam() does not adapt on
// that frame, nor let it into its statistics: adaptationPausedAfterGap(c). `adapt_after_gap: 1`
// adapts there too (as before); without coasting (coast_tau_s = 0, the papers' occlusion scenarios
// E7 and E8) every measured frame adapts, as in the papers.
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
//
// Blend with hold (issue 11 item 3, "defaults not worse than doing nothing"; docs/MODELS.md §15): the
// forecast handed out is
//   x_f = x_h + w (x_m - x_h),   x_h = [z_hold, 0(, 0)],
// x_m the (significance-weighted) model forecast above, z_hold the channel's last measurement (what
// `hold` predicts), w in [0, 1] the least-squares weight of the model's forecast step against hold's,
// learnt on the track: on every measured frame k whose previous frame was measured,
//   d = x_m(t_k | k-1)(0) - z_hold,  y = z_k - z_hold,  S_dd <- l S_dd + d^2,  S_dy <- l S_dy + d y,
//   w = clamp(S_dy / S_dd, 0, 1),  l = exp(-dt / tau),  tau = hold_blend_tau_s (s),
// i.e. the weight that would have made the one-frame forecasts of the last ~tau seconds closest to
// the measurements (measurement noise adds the same variance to every candidate, so it does not bias
// the choice). An exact ramp gives d = y once the filter has converged (and d < y while it catches
// up), so w = 1 and the model forecast is handed out unchanged; where the model's steps are mostly
// noise (a slow target under 3 px noise at 10 Hz) w falls towards 0 and the forecast towards hold.
// The velocity (and acceleration) of predict() are scaled by w too, so the blended estimate is one
// state. Only the forecast is blended: the filter (step(), gaussian()) is unchanged (but for the
// coasting time of a gap after a stop, above, which comes with the blend). Frames after a
// gap are not learnt from (their forecast spans the gap, not one frame). The same regression is
// also kept on the forecasts of 2, ..., H frames (x_m(t_k | k-h) against z_k, from the hold of
// frame k-h, on frames whose h previous frames were measured), H = hold_blend_frames (default 2),
// and the weight handed out is the smallest of the H weights: the model's step has to beat hold's
// at one frame and at H frames. A target that moves in short dashes of a few frames (a one-frame
// step that pays, a two-frame one that overshoots the dash's end) then gets the weight of the
// horizon where extrapolating pays least (docs/MODELS.md §15, "The blend on more than one
// horizon"). H = 1 is the one-frame weight alone (the default until 2026-12-03).
// The horizons asked for (`horizon_frames` h, predictor.h; docs/MODELS.md §15): when the caller says
// how far ahead it will ask, and hold_blend_frames is not given, H = clamp(ceil(h), 2, 8). Weights
// learnt on one and two frames do not tell whether a five-frame extrapolation beats hold (a tremor
// or a burst has turned by then; measured: docs/PERFORMANCE.md "The horizons asked for"). At h <= 2
// nothing changes.
// The weight's own uncertainty (`hold_blend_sigmas` n, opt-in: default kDefaultHoldBlendSigmas = 0,
// off): each of the H regressions' weights is multiplied by the significance of its least-squares
// value w_ls = S_dy / S_dd, w <- clamp(w_ls, 0, 1) w_ls^2 / (w_ls^2 + n^2 var(w_ls)), with
// var(w_ls) = (S_yy - S_dy^2 / S_dd) / ((S_n - 1) S_dd), S_yy and S_n the forgetting sums of y^2
// and of 1 (the residual variance over the count less one, over S_dd: the usual approximation for
// a forgetting regression), once S_n > 2. Why: about tau * rate noisy samples make the weight, and
// where the model's step is no better than hold's the clamp at 0 keeps the positive half of their
// scatter, so the weight handed out sits above the best one on such tracks (the second generator's
// minimum-jerk dashes at 10-15 Hz, where the filters lost to hold by a few per cent). A weight
// within about n standard errors of 0 goes towards hold, a well determined one is kept (an exact
// ramp leaves no residual once the start's misfits are forgotten: w -> 1). The price: the first
// seconds of a track, whose residuals the filter's convergence from rest makes, hold back part of
// the model's step (a ramp from rest, tests/predictors/hold_blend_test.cpp). n = 0, the default, is
// the least-squares weight. Only the forecast changes (imm's mode probabilities score the blended
// forecasts, so imm's filter moves too); the fit keeps n (it is not a forecast variant).
// Two weights, one for the smoothing and one for the step (`hold_blend_split`, default 1; 0 = the
// one weight above): the model's forecast step from hold is two steps, the filter's correction of
// the last measurement, d_s = p0 - z_hold (p0 = x(k|k)(0), the forecast's start position), and the
// extrapolation from there, d_x = x_m(0) - p0. A target at rest under noise wants all of the first
// (the filtered position is closer to the truth than the last measurement) and none of the second
// (its velocity is noise); a target in short dashes wants the second only where it pays. One weight
// on d = d_s + d_x has to trade the two. With the split, each regression is
//   y ~ w_s d_s + w_x d_x,   (w_s, w_x) = the least squares of the forgetting sums (S_ss, S_sx,
// S_xx, S_sy, S_xy, with l as above) when both lie in [0, 1]; else the one outside is clamped and
// the other is its least squares given that, clamped (one step towards the box's optimum: grid
// figures within 0.04 % of the exact search of the box's edges, for a third of its added run time).
// Steps in one direction only (det ~ 0: the first sample, or a converged filter on an exact ramp,
// whose d_s is 0) keep w for both. A forecast made on a measured frame is
//   z_hold + w_s (p0 - z_hold) + w_x (x_m(0) - p0),
// its velocity (and acceleration) scaled by w_x; over H horizons each weight is the smallest of its
// H. A forecast made in a gap keeps the one weight w (both are learnt): there p0 has coasted away
// from the last measurement, so d_s would hold coasted extrapolation, which the smoothing weight
// never saw (measured both ways: the split in gaps too, 18 -> 34 losses to hold on the 5 %-drop
// grid; on measured frames only, 18 -> 15).
// hold_blend_sigmas applies to w only. Figures: docs/PERFORMANCE.md "Two blend weights".
// The start of a track (`hold_blend_prior` p, samples, default kDefaultHoldBlendPrior = 4; 0 = off):
// a regression that has learnt from c samples hands out its weights (w, w_s, w_x) multiplied by
//   1 - exp(-(c / p)^2),
// so a horizon with no sample yet forecasts hold, p samples give 0.63 of the least-squares weight,
// 2p samples 0.98, and from c = 6.3 p on (25 samples for p = 4) the factor is 1 to the last bit: the
// weights are the regression's own. c counts every sample of the track (no forgetting; gaps do not
// reset it). A factor c^2 / (c^2 + p^2), of the same cost in losses and means for p = 3, was not
// kept: its tail 1 - p^2 / c^2 leaves the forecast of an exact line 1 % short after 30 samples.
// Why: without it the first forecasts of a track extrapolated the velocity of two or three
// measurements at full weight, and where the motion does not last that long (a track that begins
// inside a short dash at 10 Hz, a hand's tremor at 50 Hz) those few forecasts cost more than the
// rest of the track gained. The price is caution at the start of a track whose first steps are
// steady, most at low frame rates and low noise. imm starts its regressions (per mode and of the
// combination) the same way. Figures: docs/PERFORMANCE.md "The blend's start".
// A query at the last update's time (a zero horizon: a servo loop without vision delay asks its
// rates there) gets the posterior, its velocity and acceleration times the same factor of the
// one-frame regression's c: the velocity of two or three measurements at 10 Hz under 5 px of noise
// is +-100 px/s, and e8-vtc's law turned it into a first command that lost the target on 4 of 330
// runs (none with the factor, the means within 2 %; docs/PERFORMANCE.md "Innovations made white").
// The position stays the posterior's. (imm's zero-horizon query is its combined posterior, as before.)
// Extrapolations the track has not shown (`extrapolation_cap` rho, default kDefaultExtrapolationCap;
// 0 = off; with the split, on forecasts made on a measured frame): each channel keeps the forgetting
// mean square of the rates of its one-frame extrapolations, r = d_x / dt on the frames the blend
// learns from, time-weighted as the coast's RMS velocity (r_rms^2 = sum l r^2 dt / sum l dt, the
// same l); once that memory spans kCoastFastMinMemoryS of measured time, a forecast over h seconds
// whose extrapolation d_x = x_m(0) - p0 exceeds rho r_rms h is scaled down to that size, its velocity
// and acceleration by the same factor, before the blend (the first second of a track is the start's
// business, "The start of a track" above). Why: a one-frame step of the image (a camera bumped, a frame
// the recording skipped, mire-2's five dots at frames 200 and 332) reads as a velocity and an
// acceleration tens of times those the track has shown, and the filters with an acceleration state
// extrapolated it over the whole horizon; at 10-20 Hz that one forecast cost more than the rest of
// the track gained (mire-2 stamped at 10 Hz). The blend's weights
// cannot catch it: they are least squares over seconds, and the step is one frame. The cap sees
// only the track's own rates (px/s), so it holds at any rate and noise. The price: the first frame
// or two of a real manoeuvre that starts from a slow, steady drift are held back too (a noise-free
// drift then a dash). Figures: docs/PERFORMANCE.md "A recorded track at other frame rates".
// The feed-forward's velocity (Predictor::feedforwardVelocity(), with the blend only; docs/MODELS.md
// §15): the servo loop's `feedforward` mode acts on the last measurement and feeds the target's
// velocity forward, and the law integrates it over its own time constant. The blend's weight is the
// wrong judge of that velocity: one or two frames ahead a slow target's step is smaller than the
// noise (15 px/s at 25 Hz is 0.6 px a frame under 1 px of noise), so the weight falls to 0 and the
// feed-forward with it, though its noise would have been averaged out by the law. The velocity is
// judged instead on what the law sees: the one-frame extrapolated steps d_x and the measured steps
// y, each low-passed with the time constant kFeedforwardTauS (1 s), are regressed like the blend's
// one-frame samples (the same pairs, forgetting and start-up prior):
//   D <- a D + (1 - a) d_x,  Y <- a Y + (1 - a) y,  a = exp(-dt / kFeedforwardTauS),
//   w_ff = clamp(S_DY / S_DD, 0, 1),  feed-forward velocity = w_ff (F x_ff)(1),
// x_ff the feed-forward's start (below).
// The low-pass also removes the regression's bias of the one-frame samples: the noise of the
// measurement a step starts from raises the filter's velocity and lowers the measured step; summed
// over the filter's response, the two cancel. The velocity is not weighted by its significance
// (shrink_v_sigmas; the acceleration keeps its weight w_a): that weight shrinks towards hold a
// velocity that is small against its own standard deviation, right for a forecast one or two frames
// ahead, where it trades a bias for less noise, but a slow target's velocity is always small against
// it (5 px/s under 1 px of noise at 25 Hz), and the law averages the noise out while the bias
// stays: kf-ca fed 1.8 px/s of e5-line's 5 forward. d_x is then the unweighted start's step, and
// w_ff judges that velocity. At a zero horizon (a query at the last update's time: a loop without
// vision delay, e8) the feed-forward's velocity is predictVelocity()'s, the filter's own with the
// start-up factor (below, "The start of a track"): there w_ff times it fed e8-vtc and e8-ibvs 11 %
// less well (10 seeds, every predictor at its defaults, geometric mean), while over a horizon w_ff is
// what lets e5's slow leaders be followed. The servo loop feeds this velocity forward in both its
// modes that feed one (`feedforward`, `both`): in `both` the blended forecast's own velocity, scaled
// towards hold on e5's slow leaders as its position is, had left every predictor behind hold there
// (4.6 px against 4.0 on e5-line), now 0.7-1.0. Figures: docs/PERFORMANCE.md "The feed-forward's
// velocity" and "Innovations made white".
// Units: px, s; the weight is dimensionless, so the rule holds at any frame rate and noise level.
// tau = 0 switches the blend off; its default is kDefaultHoldBlendTauS whatever the other keys say
// (`shrink_sigmas: 0` turns the weighting off, not the blend: the papers' plain filters give both,
// `shrink_sigmas: 0, hold_blend_tau_s: 0`, as their scenarios and data/params do).
#pragma once

#include "predvs/predictors/kalman_math.h"
#include "predvs/predictors/noise_estimate.h"
#include "predvs/predictors/predictor.h"
#include "predvs/predictors/process_noise_adapt.h"
#include "predvs/predictors/recent_values.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
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
/// coast_tau_s in a closed loop (`closed_loop: 1`; coastTauParam).
inline constexpr double kDefaultClosedLoopCoastTauS = 0.5;

/// Default forgetting time constant (s) of the forecast's blend with hold (`hold_blend_tau_s`, file
/// comment). About tau * rate one-frame forecasts make the weight: 60 at 10 Hz, so its standard error
/// under pure noise is about 1/sqrt(60) = 0.13. Measured with `predvs track-study` (docs/PERFORMANCE.md
/// "Defaults that hold", wide grids): tau = 1.5 / 3 / 6 / 20 s leaves 11 / 3 / 0 / 1 losses to hold on
/// the 2160 tracks of seeds 401-430 (all predictors but imm together), and 0 on the repo's three grids.
inline constexpr double kDefaultHoldBlendTauS = 6.0;
/// Default `hold_blend_frames` H (file comment): the blend's weight is the smallest of those learnt
/// on the forecasts of 1..H frames. Measured with `predvs track-study` and scripts/foreign-tracks.py
/// (docs/PERFORMANCE.md "The blend on two horizons"): losses to hold of the nine per-channel filters
/// on make-track's wide grids (seeds 401-430 and the three drop grids) and on the second generator's
/// 576 tracks, H = 1 / 2 / 3: see there.
inline constexpr int kDefaultHoldBlendFrames = 2;
inline constexpr int kMaxBlendFrames = 8;
/// Time constant (s) of the low-pass under the feed-forward's weight (file comment, "The
/// feed-forward's velocity"): about a control law's own (lambda 1 /s). Measured with `predvs servo`
/// on the closed-loop scenarios (docs/PERFORMANCE.md "The feed-forward's velocity").
inline constexpr double kFeedforwardTauS = 1.0;
/// Default `hold_blend_split` (file comment, "Two weights"): 1, on. Measured with `predvs track-study`
/// and scripts/foreign-tracks.py (docs/PERFORMANCE.md "Two blend weights").
inline constexpr double kDefaultHoldBlendSplit = 1.0;

/// Default `hold_blend_sigmas` n (file comment, "The weight's own uncertainty"): 0, off. Measured with
/// `predvs track-study` and scripts/foreign-tracks.py (docs/PERFORMANCE.md "The blend weight's own
/// uncertainty", n = 0.5 to 2): a larger n leaves fewer losses to hold on the second generator's
/// tracks and costs more on every grid's mean ratio; n = 0.5 and 1 each tip one track of the tuning
/// grid over the `--fit` criterion's 10 %, so it is not on by default.
inline constexpr double kDefaultHoldBlendSigmas = 0.0;
/// Default `hold_blend_prior` p (samples >= 0, file comment "The start of a track"; 0 = off): each
/// blend weight learnt from c samples is handed out times 1 - exp(-(c / p)^2). Measured with `predvs
/// track-study` and scripts/foreign-tracks.py (docs/PERFORMANCE.md "The blend's start").
inline constexpr double kDefaultHoldBlendPrior = 4.0;
/// Default `extrapolation_cap` rho (dimensionless >= 0, file comment "Extrapolations the track has
/// not shown"; 0 = off): a forecast extrapolates at most rho times the RMS rate of the channel's
/// one-frame extrapolations. Measured with scripts/recorded-track.py, `predvs track-study` and
/// scripts/foreign-tracks.py (docs/PERFORMANCE.md "A recorded track at other frame rates").
inline constexpr double kDefaultExtrapolationCap = 4.0;
/// (c / p)^2 from which 1 - exp(-(c / p)^2) is 1 in double precision (exp(-40) < 2^-54): the factor
/// is not computed beyond it.
inline constexpr double kBlendPriorExponentEnd = 40.0;
/// The start-up prior's factor after c samples, prior p > 0 (file comment, "The start of a track"):
/// 1 - exp(-(c / p)^2), exactly 1 from kBlendPriorExponentEnd on (not computed there).
inline double blendPriorFactor(double count, double prior) {
  const double u = count / prior;
  return u * u < kBlendPriorExponentEnd ? 1.0 - std::exp(-u * u) : 1.0;
}

/// Default `coast_stop_fraction` c (dimensionless, file comment): a gap that begins while the target
/// decelerates coasts with min(coast_tau_s, c t_stop). Measured with `predvs track-study` on the wide
/// grids (docs/PERFORMANCE.md "A stop before the gap"): 0.35 / 0.5 leave 34 / 39 losses to hold of the
/// 46 on seeds 501-530 (5 % drops) and 8 / 9 of 29 on seeds 601-630 (8 %); 0.35 costs up to +0.007
/// on a grid's mean ratio, 0.5 at most +0.004.
inline constexpr double kDefaultCoastStopFraction = 0.5;
/// The filter velocity's fall is measured from the oldest remembered frame of the last 0.2 s (the
/// coasting time) to the last: 0.2 s back at 10-30 Hz, 7 frames (0.12 s) at 60 Hz, where the ring of
/// CoastStop::kFrames ends first.
inline constexpr double kCoastStopWindowS = 0.2;
/// ... and counts when larger than 1 standard deviation of the velocity (sqrt P_vv).
inline constexpr double kCoastStopVelocitySigmas = 1.0;
/// The quadratic fit: the last 6 measured frames (the fewest that give its deceleration three
/// degrees of freedom), counted when larger than 2 standard errors (sqrt(R (A'A)^-1_aa)).
inline constexpr int kCoastStopFitFrames = 6;
inline constexpr double kCoastStopFitSigmas = 2.0;

/// Default `coast_fast_ratio` rho_0 (dimensionless, file comment; 0 = off): a gap that begins at a
/// channel speed above rho_0 times the channel's recent RMS velocity coasts shorter. Measured with
/// `predvs track-study` (docs/PERFORMANCE.md "Unusual speeds and the shape of the coast"), with
/// kCoastFastPower 1.5 and kDefaultCoastShape 1.5: losses to hold of the ten predictors on the three
/// drop grids (seeds 501/601/701) 39 / 9 / 3 -> 21 / 5 / 2, every grid's mean ratios within +0.0044;
/// 1.4 with coast_shape 1.6: 21 / 1 / 2 but +0.0085 on seeds 701-730; alone (exponential coast, p 2)
/// 1.5: 18 / 1 / 2 at +0.009..+0.023, 2: 26 / 8 / 2 at up to +0.0095.
inline constexpr double kDefaultCoastFastRatio = 1.5;
/// The exponent p of tau (rho_0 / rho)^p (file comment): 1.5 (p = 2 with the same shape: 20 / 1 / 2
/// losses, but +0.010 on the mean ratio of seeds 701-730).
inline constexpr double kCoastFastPower = 1.5;
/// The RMS velocity is used once its forgetting sum spans this much measured time (s).
inline constexpr double kCoastFastMinMemoryS = 1.0;
/// Default `coast_shape` k (dimensionless >= 1, file comment; 1 = the exponential decay). 1.5 pays
/// for the shorter coasts of kDefaultCoastFastRatio on the grids' mean ratios (k = 2 alone lowers
/// them by 0.015-0.03 but doubles the losses on the drop grids, 39 -> 75 on seeds 501-530: it coasts
/// further through occlusions of 0.1-0.2 s; with the speed rule (p 2) 27 / 3 / 4).
inline constexpr double kDefaultCoastShape = 1.5;
/// Default `coast_lag_sigmas` n_l (dimensionless >= 0, file comment "Measurements falling behind
/// before the gap"; 0 = off): a gap that begins while the last kCoastLagFrames measurements fell
/// behind the filter's motion by more than n_l standard deviations coasts shorter. Measured with
/// `predvs track-study` (docs/PERFORMANCE.md "Measurements falling behind before a gap").
inline constexpr double kDefaultCoastLagSigmas = 2.0;
/// The measured frames whose normalised innovations are summed (file comment).
inline constexpr int kCoastLagFrames = 5;
/// The exponent of tau (n_l / |z_l|)^p (file comment).
inline constexpr double kCoastLagPower = 2.0;
/// Default `coast_lag_share` (0 | 1; file comment "Measurements falling behind before a gap"): the
/// lag rule's cut is at most down to the share of its one-frame step the filter's last measurements
/// still made. Measured with `predvs track-study` (docs/PERFORMANCE.md "The lag rule cuts no more
/// than the lag shows").
inline constexpr double kDefaultCoastLagShare = 1.0;
/// Default `coast_crossing` (0 | 1; file comment "A turn or a stop through zero"). Measured with
/// `predvs track-study --draws 5` (docs/PERFORMANCE.md "Losses are draws, not motions").
inline constexpr double kDefaultCoastCrossing = 1.0;

/// The last measured frames of one channel (time s, measurement px, the filter's velocity px/s after
/// the update) and the stop time they give when a gap begins (file comment, "A stop before the gap").
struct CoastStop {
  static constexpr int kFrames = 8;
  std::array<double, kFrames> t{}, z{}, v{};
  /// Each frame's innovation eps and its variance S (S = 0: none; normalised only when a gap asks).
  std::array<double, kFrames> eps{}, S{};
  int n = 0, head = 0;
  double v_sq_time = 0.0;  ///< forgetting sum of v^2 dt over the measured frames, px^2/s
  double time_s = 0.0;     ///< forgetting sum of dt, s
  /// One measured frame; keep = exp(-dt / hold_blend_tau_s) for dt = t_s - the previous measured
  /// frame's time (the forgetting of the RMS velocity; unused on the first frame); in = the
  /// update's innovation (none: not valid).
  void remember(double t_s, double z_px, double v_px_s, double keep, const Innovation& in) {
    sign_changed = n > 0 && v[static_cast<size_t>(head)] * v_px_s < 0.0;
    if (n > 0) {
      const double dt = t_s - t[static_cast<size_t>(head)];
      v_sq_time = keep * v_sq_time + v_px_s * v_px_s * dt;
      time_s = keep * time_s + dt;
    }
    head = (head + 1) % kFrames;
    t[static_cast<size_t>(head)] = t_s;
    z[static_cast<size_t>(head)] = z_px;
    v[static_cast<size_t>(head)] = v_px_s;
    eps[static_cast<size_t>(head)] = in.valid ? in.eps : 0.0;
    S[static_cast<size_t>(head)] = in.valid ? in.S : 0.0;
    n = std::min(n + 1, kFrames);
  }
  /// z_l: the normalised innovations eps / sqrt(S) of the last kCoastLagFrames frames summed, over
  /// sqrt(kCoastLagFrames) (a standard normal when the filter fits; fewer frames, or frames without
  /// an innovation, count as 0).
  double lagScore() const {
    double sum = 0.0;
    for (int i = 0; i < kCoastLagFrames && i < n; ++i) {
      const auto j = static_cast<size_t>((head - i + kFrames) % kFrames);
      sum += S[j] > 0.0 ? eps[j] / std::sqrt(S[j]) : 0.0;
    }
    return sum / std::sqrt(static_cast<double>(kCoastLagFrames));
  }
  /// The share of the filter's one-frame step that its last measurements still made: 1 + mean(eps) /
  /// (v dt) over the newest j frames, the smallest of j = 1 .. kCoastLagFrames, clamped to [0, 1];
  /// v the last velocity, dt the mean interval of those frames, eps their innovations (a frame without
  /// one counts as 0, as in lagScore()). 1 for a target that went on as the filter forecast, 0 for one
  /// that stopped dead (a measurement a whole step short); 1 before two frames or at v = 0 (file
  /// comment, "Measurements falling behind before a gap").
  double lagVelocityShare() const {
    const int k = std::min(kCoastLagFrames, n), intervals = std::min(k, n - 1);
    if (intervals < 1) return 1.0;
    const double span = t[static_cast<size_t>(head)] - t[static_cast<size_t>((head - intervals + kFrames) % kFrames)];
    const double step = v[static_cast<size_t>(head)] * span / intervals;  // the filter's step over a mean frame
    if (!(std::abs(step) > 0.0)) return 1.0;
    double sum = 0.0, share = 1.0;
    for (int j = 1; j <= k; ++j) {
      sum += eps[static_cast<size_t>((head - j + 1 + kFrames) % kFrames)];
      share = std::min(share, 1.0 + sum / j / step);
    }
    return std::max(share, 0.0);
  }
  /// The filter's velocity after the last measured frame (px/s; 0 before any).
  double lastVelocity() const { return n > 0 ? v[static_cast<size_t>(head)] : 0.0; }
  /// The time (s) the target takes to come to rest at its current deceleration, +inf when it is not
  /// significantly decelerating; var_v = P_vv of the last velocity (px^2/s^2), r = R (px^2).
  double stopTime(double var_v, double r) const {
    double t_stop = std::numeric_limits<double>::infinity();
    if (n < 2) return t_stop;
    const double t_last = t[static_cast<size_t>(head)], v_last = v[static_cast<size_t>(head)];
    // The filter's velocity fall over the last kCoastStopWindowS.
    const int oldest = windowStart();
    if (oldest >= 0) {
      const double dv = v_last - v[static_cast<size_t>(oldest)];
      if (dv * v_last < 0.0 && dv * dv >= kCoastStopVelocitySigmas * kCoastStopVelocitySigmas * var_v)
        t_stop = std::abs(v_last) * (t_last - t[static_cast<size_t>(oldest)]) / std::abs(dv);
    }
    // The quadratic p + v u + a u^2 / 2 (u = t - t_last) through the last kCoastStopFitFrames.
    if (n >= kCoastStopFitFrames && r > 0.0) {
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
      Eigen::Vector3d b = Eigen::Vector3d::Zero();
      for (int i = 0; i < kCoastStopFitFrames; ++i) {
        const auto j = static_cast<size_t>((head - i + kFrames) % kFrames);
        const double u = t[j] - t_last;
        const Eigen::Vector3d phi(1.0, u, 0.5 * u * u);
        A.noalias() += phi * phi.transpose();
        b += phi * z[j];
      }
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(A);
      const Eigen::Vector3d c = ldlt.solve(b);
      const double var_a = r * ldlt.solve(Eigen::Vector3d::UnitZ())(2);
      if (c(1) * c(2) < 0.0 && c(2) * c(2) >= kCoastStopFitSigmas * kCoastStopFitSigmas * var_a)
        t_stop = std::min(t_stop, std::abs(c(1) / c(2)));
    }
    return t_stop;
  }
  /// The time of the last measured frame (s).
  double lastTime() const { return t[static_cast<size_t>(head)]; }
  /// The oldest remembered frame within kCoastStopWindowS before the last one (-1: none).
  int windowStart() const {
    int oldest = -1;
    const double t_last = t[static_cast<size_t>(head)];
    for (int i = 1; i < n; ++i) {
      const int j = (head - i + kFrames) % kFrames;
      if (t[static_cast<size_t>(j)] < t_last - kCoastStopWindowS - 1e-9) break;
      oldest = j;
    }
    return oldest;
  }
  /// True when the filter's velocity fell through zero within kCoastStopWindowS before the last
  /// measured frame, by more than kCoastStopVelocitySigmas sqrt(var_v); *v0 = the velocity at the
  /// window's start (file comment, "A turn or a stop through zero").
  bool crossedZero(double var_v, double* v0 = nullptr) const {
    const int oldest = n >= 2 ? windowStart() : -1;
    if (oldest < 0) return false;
    const double v_first = v[static_cast<size_t>(oldest)], v_last = v[static_cast<size_t>(head)];
    const double dv = v_last - v_first;
    if (v0) *v0 = v_first;
    return v_first * v_last < 0.0 && dv * dv >= kCoastStopVelocitySigmas * kCoastStopVelocitySigmas * var_v;
  }
  /// True when watchCrossing() has something to do on this frame: a crossing's outcome is pending,
  /// or the velocity changed sign (most frames: neither).
  bool watching() const { return cross_due_t >= 0.0 || sign_changed; }
  /// After remember(), when watching(): scores a crossing whose outcome is due, and notes a new one
  /// (file comment); var_v = P_vv of the last velocity, tau_s = hold_blend_tau_s (the forgetting of
  /// the outcomes).
  void watchCrossing(double var_v, double tau_s) {
    const double t_last = t[static_cast<size_t>(head)];
    if (cross_due_t >= 0.0 && t_last >= cross_due_t) {
      const double keep = std::exp(-(t_last - cross_scored_t) / tau_s);
      turn_sum = keep * turn_sum + std::clamp(-v[static_cast<size_t>(head)] / cross_v0, 0.0, 1.0);
      turn_n = keep * turn_n + 1.0;
      cross_scored_t = t_last;
      cross_due_t = -1.0;
    }
    double v0 = 0.0;
    if (cross_due_t < 0.0 && sign_changed && crossedZero(var_v, &v0)) {
      cross_due_t = t_last + kCoastStopWindowS;
      cross_v0 = v0;
    }
  }
  /// The forgetting mean of the crossings' outcomes: the share of them that turned (file comment).
  double turnShare() const { return turn_sum / turn_n; }
  /// At the start of a gap: the factor on the acceleration, the turn share when the velocity fell
  /// through zero just before, else 1 (file comment, "A turn or a stop through zero").
  double gapAccelerationFactor(double var_v) const { return crossedZero(var_v) ? turnShare() : 1.0; }
  double cross_due_t = -1.0;  ///< when the outcome of the last crossing is scored (s; < 0: none pending)
  double cross_v0 = 0.0;      ///< the velocity before that crossing (px/s)
  double turn_sum = 1.0, turn_n = 1.0;  ///< forgetting sums of the outcomes and their count (one turn as the prior)
  double cross_scored_t = 0.0;  ///< time of the last scored outcome (s)
  bool sign_changed = false;    ///< the last remember()'s velocity has the other sign than the one before
  /// |v| / v_rms of the last measured frame (file comment), 0 before kCoastFastMinMemoryS of memory.
  double speedRatio() const {
    if (n == 0 || time_s < kCoastFastMinMemoryS || !(v_sq_time > 0.0)) return 0.0;
    return std::abs(v[static_cast<size_t>(head)]) / std::sqrt(v_sq_time / time_s);
  }
};

/// The `hold_blend_tau_s` parameter (s, >= 0, default kDefaultHoldBlendTauS; 0 = off; file
/// comment). Read by every per-channel filter (readShrinkParams) and by imm.
inline double holdBlendTauParam(const Params& params) {
  return params.get("hold_blend_tau_s", kDefaultHoldBlendTauS, 0.0, 1e6);
}

/// The `hold_blend_sigmas` parameter n (dimensionless >= 0, default kDefaultHoldBlendSigmas; 0 = off;
/// file comment, "The weight's own uncertainty"). Read by every per-channel filter and by imm.
inline double holdBlendSigmasParam(const Params& params) {
  return params.get("hold_blend_sigmas", kDefaultHoldBlendSigmas, 0.0, 1e3);
}

/// The `hold_blend_prior` parameter p (samples >= 0, default kDefaultHoldBlendPrior; 0 = off; file
/// comment, "The start of a track").
inline double holdBlendPriorParam(const Params& params) { return params.get("hold_blend_prior", kDefaultHoldBlendPrior, 0.0, 1e6); }

/// The `extrapolation_cap` parameter rho (>= 0, default kDefaultExtrapolationCap; 0 = off; file
/// comment, "Extrapolations the track has not shown").
inline double extrapolationCapParam(const Params& params) {
  return params.get("extrapolation_cap", kDefaultExtrapolationCap, 0.0, 1e6);
}

/// The cap's state (file comment, "Extrapolations the track has not shown"): forgetting sums of the
/// one-frame extrapolation rates squared times dt (px^2/s) and of dt (s), r_rms^2 = ss / t.
struct ExtrapolationRates {
  double ss = 0.0, t = 0.0;
  /// One one-frame extrapolation d_x (px) over dt (s), lambda the blend's forgetting.
  void learn(double d_x, double dt, double lambda) {
    ss = lambda * ss + d_x * d_x / dt;  // (d_x / dt)^2 dt
    t = lambda * t + dt;
  }
  /// The factor (in [0, 1]) on an extrapolated step e (px) over h seconds: 1, or rho r_rms h / |e|
  /// when |e| is larger, once the memory spans kCoastFastMinMemoryS (rho = cap; 0 = off). Compared
  /// in squares, |e|^2 t > rho^2 ss h^2: no root on the forecasts it lets through.
  double factor(double cap, double e, double h) const;
  /// The forecast position f, extrapolated from p0 over h seconds, with its step p0 -> f capped.
  double capped(double cap, double p0, double f, double h) const {
    const double k = factor(cap, f - p0, h);
    return k < 1.0 ? p0 + k * (f - p0) : f;
  }
  /// A forecast state [p, v(, a)] extrapolated from the position p0 over h seconds, capped: the
  /// position's step and the derivatives scaled by the same factor.
  template <int N>
  void capState(double cap, double p0, Vec<N>& x, double h) const {
    const double k = factor(cap, x(0) - p0, h);
    if (!(k < 1.0)) return;
    x(0) = p0 + k * (x(0) - p0);
    for (int i = 1; i < N; ++i) x(i) *= k;
  }
};

/// The `hold_blend_split` parameter (0 | 1, default kDefaultHoldBlendSplit; file comment, "Two weights").
inline bool holdBlendSplitParam(const Params& params) {
  return params.get("hold_blend_split", kDefaultHoldBlendSplit, 0.0, 1.0) != 0.0;
}

/// The `hold_blend_frames` parameter H (whole frames 1..kMaxBlendFrames; file comment). Its default
/// is kDefaultHoldBlendFrames, or the horizons asked for, clamp(ceil(horizon_frames), default,
/// kMaxBlendFrames) when the caller gives `horizon_frames` (file comment, "The horizons asked
/// for"). Read by every per-channel filter and by imm.
inline int holdBlendFramesParam(const Params& params) {
  // ceil with a tolerance: a horizon of --horizon-s over the median frame period is 5 frames when it
  // comes out a rounding above 5
  const double asked = std::ceil(horizonFramesParam(params) - 1e-6);
  const double fallback = std::clamp(asked, static_cast<double>(kDefaultHoldBlendFrames), static_cast<double>(kMaxBlendFrames));
  const double h = params.get("hold_blend_frames", fallback, 1, kMaxBlendFrames);
  if (h != std::floor(h))
    throw std::invalid_argument("hold_blend_frames: expected a whole number of frames from 1 to " + std::to_string(kMaxBlendFrames));
  return static_cast<int>(h);
}

/// The forecast variants (Predictor::forecastVariants()) of a blend with hold on H > 1 horizons:
/// the blend on the one-frame horizon alone, {hold_blend_frames: 1}, which a fit under the
/// prediction objective compares with H on the fit rows (docs/MODELS.md §15, "The blend on more
/// than one horizon"). None when the blend is off or H is 1 already. (`hold_blend_sigmas` is not
/// offered: a fit keeps its default, so that the fixed KFs it is compared with and imm, whose
/// filter it changes, use the same.)
inline std::vector<Params> blendHorizonVariants(double blend_tau_s, int blend_frames) {
  if (!(blend_tau_s > 0.0) || blend_frames == 1) return {};
  Params one;
  one.set("hold_blend_frames", 1.0);
  return {one};
}

/// The regression of the blend with hold (file comment): the forgetting sums of a model's
/// one-frame steps against the measured ones, and the weight in [0, 1] they give. imm keeps one
/// per mode besides its channel's HoldBlend (imm.h, "Each moving mode blended with hold").
struct BlendWeight {
  double s_dd = 0.0;  ///< forgetting sums of the regression, px^2
  double s_dy = 0.0;
  double s_yy = 0.0;  ///< forgetting sum of y^2, px^2 (kept with hold_blend_sigmas > 0 only)
  double s_n = 0.0;   ///< forgetting count of the samples (likewise)
  double w = 1.0;     ///< weight of the model forecast against hold, [0, 1]
  /// The split regression y ~ w_s d_s + w_x d_x (file comment, "Two weights"; kept with the split only).
  double s_ss = 0.0, s_sx = 0.0, s_xx = 0.0, s_sy = 0.0, s_xy = 0.0;
  double w_s = 1.0;  ///< weight of the smoothing step d_s, [0, 1]
  double w_x = 1.0;  ///< weight of the extrapolated step d_x, [0, 1]
  double count = 0.0;  ///< samples learnt so far (no forgetting; with hold_blend_prior > 0 only)
  /// The weights before the first sample: hold's (0) with a start-up prior p > 0 (file comment, "The
  /// start of a track"), else the model's (1).
  void start(double prior) { w = w_s = w_x = prior > 0.0 ? 0.0 : 1.0; }
  /// One sample: the model's forecast step d = f - z_hold against the measured step y = z - z_hold
  /// (both from the hold of the frame the forecast was made at), lambda = exp(-dt / tau);
  /// n_sigmas = hold_blend_sigmas (file comment, "The weight's own uncertainty"; 0 = the
  /// least-squares weight as it is). With split, d_s = p0 - z_hold (the forecast's start position
  /// p0) also feeds the two-weight regression, d_x = d - d_s. prior = hold_blend_prior p (file
  /// comment, "The start of a track"; 0 = off): the weights times 1 - exp(-(c / p)^2) after c samples.
  void learn(double d, double d_s, double y, double lambda, double n_sigmas, bool split, double prior) {
    s_dd = lambda * s_dd + d * d;
    s_dy = lambda * s_dy + d * y;
    w = s_dd > 0.0 ? std::clamp(s_dy / s_dd, 0.0, 1.0) : 1.0;
    if (split) learnSplit(d_s, d - d_s, y, lambda);
    if (n_sigmas > 0.0) {
      s_yy = lambda * s_yy + y * y;
      s_n = lambda * s_n + 1.0;
      if (s_dd > 0.0 && s_n > 2.0) w *= significanceWeight(s_dy / s_dd, weightVariance(), n_sigmas);
    }
    if (prior > 0.0) {
      count += 1.0;
      const double k = blendPriorFactor(count, prior);
      if (k != 1.0) {  // 1 from kBlendPriorExponentEnd on: nothing to do
        w *= k;
        if (split) {  // w_s, w_x: learnt (each sample anew) and read with the split only
          w_s *= k;
          w_x *= k;
        }
      }
    }
  }
  /// The variance of the least-squares weight: the residual variance of the regression over its
  /// forgetting count less one, over S_dd (the usual approximation for a forgetting regression).
  double weightVariance() const {
    const double rss = std::max(0.0, s_yy - s_dy * s_dy / s_dd);
    return rss / (s_n - 1.0) / s_dd;
  }
  /// The forecast f blended with hold's z_hold: z_hold + w (f - z_hold).
  double blend(double z_hold, double f) const { return z_hold + w * (f - z_hold); }
  /// The forecast f from the start position p0 blended with the two weights:
  /// z_hold + w_s (p0 - z_hold) + w_x (f - p0).
  double blendSplit(double z_hold, double p0, double f) const { return z_hold + w_s * (p0 - z_hold) + w_x * (f - p0); }
  /// A forecast state [p, v(, a)] from the start position p0 blended with the two weights: the
  /// position by blendSplit(), the derivatives scaled by w_x.
  template <int N>
  void blendStateSplit(double z_hold, double p0, Vec<N>& x) const {
    x(0) = blendSplit(z_hold, p0, x(0));
    for (int i = 1; i < N; ++i) x(i) *= w_x;
  }
  /// A forecast state [p, v(, a)] blended likewise: the position by blend(), the derivatives (those
  /// of the blended position) scaled by w.
  template <int N>
  void blendState(double z_hold, Vec<N>& x) const {
    x(0) = blend(z_hold, x(0));
    for (int i = 1; i < N; ++i) x(i) *= w;
  }

 private:
  /// The split regression's sample and its weights (file comment, "Two weights"): the free least
  /// squares when it lies in [0, 1]^2, else the weight outside clamped and the other one's least
  /// squares given it, clamped; w for both when the two steps are (nearly) collinear.
  void learnSplit(double d_s, double d_x, double y, double lambda) {
    s_ss = lambda * s_ss + d_s * d_s;
    s_sx = lambda * s_sx + d_s * d_x;
    s_xx = lambda * s_xx + d_x * d_x;
    s_sy = lambda * s_sy + d_s * y;
    s_xy = lambda * s_xy + d_x * y;
    const double det = s_ss * s_xx - s_sx * s_sx;
    if (!(det > 1e-12 * s_ss * s_xx)) {  // one direction only (or none): the one weight for both
      w_s = w_x = w;
      return;
    }
    const double a = (s_xx * s_sy - s_sx * s_xy) / det, b = (s_ss * s_xy - s_sx * s_sy) / det;
    const bool a_in = a >= 0.0 && a <= 1.0, b_in = b >= 0.0 && b <= 1.0;
    if (a_in && b_in) {
      w_s = a;
      w_x = b;
    } else if (!a_in) {  // a clamped, b its least squares given a
      w_s = std::clamp(a, 0.0, 1.0);
      w_x = std::clamp((s_xy - w_s * s_sx) / s_xx, 0.0, 1.0);
    } else {
      w_x = std::clamp(b, 0.0, 1.0);
      w_s = std::clamp((s_sy - w_x * s_sx) / s_ss, 0.0, 1.0);
    }
  }
};

/// The regressions of a blend on the forecasts of 2..kMaxBlendFrames frames (longer[h - 2], file
/// comment "The same regression is also kept on the forecasts of 2, ..., H frames").
using LongerBlendWeights = std::array<BlendWeight, kMaxBlendFrames - 1>;
/// The weights handed out on H = frames horizons: w.w (w.w_s, w.w_x) lowered to the smallest of
/// longer[0 .. H - 2]'s.
inline void minOverHorizons(BlendWeight& w, const LongerBlendWeights& longer, int frames) {
  for (int h = 2; h <= frames; ++h) {
    const BlendWeight& l = longer[static_cast<size_t>(h - 2)];
    w.w = std::min(w.w, l.w);
    w.w_s = std::min(w.w_s, l.w_s);
    w.w_x = std::min(w.w_x, l.w_x);
  }
}
/// The slot `back` places behind `head` in a ring of kMaxBlendFrames forecast starts (0 <= back < size).
inline size_t blendRingSlot(int head, int back) {
  const int i = head - back;
  return static_cast<size_t>(i < 0 ? i + kMaxBlendFrames : i);
}

/// The feed-forward's weight on one channel (file comment, "The feed-forward's velocity"): the
/// low-passed one-frame steps and the forgetting sums of their regression. The weight is worked out
/// when asked (weight()), not on every frame.
struct FeedforwardWeight {
  double d = 0.0, y = 0.0;        ///< the low-passed extrapolated and measured steps, px
  double s_dd = 0.0, s_dy = 0.0;  ///< forgetting sums of the regression, px^2
  double count = 0.0;             ///< samples learnt so far (the start-up prior)
  /// One pair: extrapolated step d_x, measured step y_step; a = exp(-dt / kFeedforwardTauS), lambda
  /// the blend's forgetting.
  void learn(double d_x, double y_step, double a, double lambda) {
    d = a * d + (1.0 - a) * d_x;
    y = a * y + (1.0 - a) * y_step;
    s_dd = lambda * s_dd + d * d;
    s_dy = lambda * s_dy + d * y;
    count += 1.0;
  }
  /// w_ff in [0, 1], times 1 - exp(-(c / prior)^2) after c samples when prior > 0 (BlendWeight's
  /// start-up prior, hold_blend_prior): 0 before the first sample then, else 1.
  double weight(double prior) const {
    const double w = s_dd > 0.0 ? std::clamp(s_dy / s_dd, 0.0, 1.0) : 1.0;
    return prior > 0.0 ? w * blendPriorFactor(count, prior) : w;
  }
};

/// The blend with hold on one channel (file comment): hold's forecast, the regression's weight
/// (BlendWeight) and the coasting of a gap.
struct HoldBlend : BlendWeight {
  double z_hold = 0.0;  ///< last measurement (hold's forecast), px
  CoastStop recent;     ///< the last measured frames, for the coasting time of a gap
  double gap_tau_s = 0.0;  ///< coasting time of the current gap (s; file comment)
  /// Chooses gap_tau_s on a gap's first frame: min(tau_s, fraction t_stop, tau_s (rho_0 / rho)^p,
  /// tau_s max((n_l / |z_l|)^2, share) when |z_l| > n_l opposes the velocity) (file comment;
  /// fast_ratio = rho_0, lag_sigmas = n_l, 0 = off; share = CoastStop::lagVelocityShare() when
  /// lag_share, else 0).
  void startGap(double tau_s, double fraction, double fast_ratio, double lag_sigmas, bool lag_share, double var_v, double r) {
    gap_tau_s = fraction > 0.0 ? std::min(tau_s, fraction * recent.stopTime(var_v, r)) : tau_s;
    const double rho = fast_ratio > 0.0 ? recent.speedRatio() : 0.0;
    if (rho > fast_ratio) gap_tau_s = std::min(gap_tau_s, tau_s * std::pow(fast_ratio / rho, kCoastFastPower));
    if (lag_sigmas > 0.0) {
      const double z_l = recent.lagScore();
      if (z_l * recent.lastVelocity() < 0.0 && std::abs(z_l) > lag_sigmas) {
        double k = std::pow(lag_sigmas / std::abs(z_l), kCoastLagPower);
        if (lag_share) k = std::max(k, recent.lagVelocityShare());
        gap_tau_s = std::min(gap_tau_s, tau_s * k);
      }
    }
    gap_tau_s = std::max(gap_tau_s, 1e-6);  // coast() divides by it
  }
  /// The factor on the velocity of the gap frame that ends at t_s (dt after the previous frame),
  /// tau_s = coast_tau_s, shape = coast_shape (file comment): exp(-dt / gap_tau_s) when the gap was
  /// shortened or shape = 1, else S(u) / S(u - dt), u = t_s - the last measured frame's time.
  double gapDecay(double t_s, double dt, double tau_s, double shape) const {
    if (gap_tau_s < tau_s || shape == 1.0) return std::exp(-dt / gap_tau_s);
    const double u = t_s - recent.lastTime(), u0 = std::max(u - dt, 0.0);
    return std::exp(-(std::pow(u / tau_s, shape) - std::pow(u0 / tau_s, shape)));
  }
  /// The blended position hold + w (f - hold).
  double position(double f) const { return blend(z_hold, f); }
};

/// The `coast_tau_s` parameter (s, >= 0; 0 = no coasting). Default kDefaultCoastTauS, and
/// kDefaultClosedLoopCoastTauS when the caller says `closed_loop: 1` (predictor.h): in a servo loop
/// the velocity drives the camera through a gap, and a velocity that decays within 0.2 s stops the
/// camera while the target goes on; the loop's own rule for a lost feature (lost.timeout_s, 1 s by
/// default, and lost.action, servo/lost_feature_policy.h) takes over later. Not 0: a loop told to
/// extrapolate through a long occlusion (e8-vtc-occlusion's 3 s) then has no brake, and the CA
/// filters ran off (kf-ca 2.1, stkf 31 times the error with 0.2 s). Measured: docs/PERFORMANCE.md
/// "Coasting in a closed loop".
inline double coastTauParam(const Params& params) {
  return params.get("coast_tau_s", closedLoopParam(params) ? kDefaultClosedLoopCoastTauS : kDefaultCoastTauS, 0.0,
                    1e6);
}
/// The `coast_stop_fraction` parameter (>= 0, default kDefaultCoastStopFraction; 0 = off; file comment).
inline double coastStopFractionParam(const Params& params) {
  return params.get("coast_stop_fraction", kDefaultCoastStopFraction, 0.0, 1e3);
}
/// The `coast_fast_ratio` parameter (>= 0, default kDefaultCoastFastRatio; 0 = off; file comment).
inline double coastFastRatioParam(const Params& params) {
  return params.get("coast_fast_ratio", kDefaultCoastFastRatio, 0.0, 1e3);
}
/// The `coast_lag_sigmas` parameter (>= 0, default kDefaultCoastLagSigmas; 0 = off; file comment).
inline double coastLagSigmasParam(const Params& params) {
  return params.get("coast_lag_sigmas", kDefaultCoastLagSigmas, 0.0, 1e3);
}
/// The `coast_lag_share` parameter (0 | 1, default kDefaultCoastLagShare; file comment).
inline bool coastLagShareParam(const Params& params) {
  return params.get("coast_lag_share", kDefaultCoastLagShare, 0.0, 1.0) != 0.0;
}
/// The `coast_shape` parameter (1..10, default kDefaultCoastShape; 1 = exponential; file comment).
inline double coastShapeParam(const Params& params) { return params.get("coast_shape", kDefaultCoastShape, 1.0, 10.0); }
/// The `coast_crossing` parameter (0 | 1, default kDefaultCoastCrossing; file comment, "A turn or a
/// stop through zero").
inline bool coastCrossingParam(const Params& params) {
  return params.get("coast_crossing", kDefaultCoastCrossing, 0.0, 1.0) != 0.0;
}

inline double ExtrapolationRates::factor(double cap, double e, double h) const {
  if (!(cap > 0.0) || !(t >= kCoastFastMinMemoryS)) return 1.0;
  const double limit_sq_t = cap * cap * ss * h * h;  // (rho r_rms h)^2 t
  if (!(e * e * t > limit_sq_t)) return 1.0;
  return std::sqrt(limit_sq_t / t) / std::abs(e);
}

/// v <- v e, a <- a e^2 on a state [p, v(, a)] for a given factor e (the gap's coasting,
/// HoldBlend::gapDecay, or coast() below).
template <int N>
inline void coastBy(Vec<N>& x, double e) {
  x(1) *= e;
  if constexpr (N == 3) x(2) *= e * e;
}
/// The coasting decay of an unmeasured frame (above): coastBy(x, exp(-dt / tau_s)); tau_s > 0.
template <int N>
inline void coast(Vec<N>& x, double dt, double tau_s) {
  coastBy(x, std::exp(-dt / tau_s));
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
    const double dt = advanceClock(t_s, z);
    // kept per frame period: the blend's forgetting and the feed-forward's low-pass
    const std::array<double, 2> keep = blend_tau_s_ > 0.0 ? blendKeeps(dt) : std::array<double, 2>{0.0, 0.0};
    const double blend_keep = keep[0], feedforward_keep = keep[1];
    for (int c = 0; c < channels(); ++c) {
      ChannelState& s = state_[c];
      s.innovation = Innovation{};
      s.start_now = false;
      if (!r_est_.empty()) r_est_[static_cast<size_t>(c)].push(t_s, z(c));
      if (!s.initialized) {
        if (isMeasured(z(c))) {
          initialize(c, z(c));
          s.initialized = true;
          s.blend.z_hold = z(c);
          s.blend.start(blend_prior_);
          for (BlendWeight& l : s.longer) l.start(blend_prior_);
          s.feedforward = FeedforwardWeight{};
          s.blend.recent.remember(t_s, z(c), s.g.x(1), 0.0, Innovation{});
          if (blend_tau_s_ > 0.0) rememberForecastStart(c, t_s);
        }
        continue;
      }
      if (coast_tau_s_ > 0.0 && !isMeasured(z(c))) {
        if (blend_tau_s_ > 0.0) {  // the blend's coasting: a gap after a stop coasts shorter (file comment)
          if (s.run > 0) {
            s.blend.startGap(coast_tau_s_, coast_stop_fraction_, coast_fast_ratio_, coast_lag_sigmas_, coast_lag_share_, s.g.P(1, 1),
                             measurementNoise(c));
            if constexpr (N == 3) {
              if (coast_crossing_) s.g.x(2) *= s.blend.recent.gapAccelerationFactor(s.g.P(1, 1));
            }
          }
          coastBy(s.g.x, s.blend.gapDecay(t_s, dt, coast_tau_s_, coast_shape_));
        } else {
          coast(s.g.x, dt, coast_tau_s_);
        }
      }
      step(c, dt, z(c));
      s.unmeasured_last = !isMeasured(z(c));
      if (blend_tau_s_ > 0.0) learnBlend(c, t_s, z(c), blend_keep, feedforward_keep);
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
    if (!(dt > 0.0)) {  // the posterior, its derivatives times the start-up factor (file comment)
      ChannelEstimate e = toEstimate(s.g);
      const double k = startFactor(s);
      for (int i = 1; i < N; ++i) e.x(i) *= k;
      return e;
    }
    Gaussian<N> g = forecastWeightingOn() ? weightedForecastStart(channel) : s.g;
    timeUpdate(g, transition(channel, dt), processNoise(channel, dt));
    blendForecast(s, dt, g.x);
    return toEstimate(g);
  }

  /// predict(channel, t_s).velocity() without the covariance: x(1) of the same F x, capped and
  /// blended the same way; at a zero horizon the posterior's times startFactor().
  double predictVelocity(int channel, double t_s) const override {
    const ChannelState& s = state_.at(channel);
    if (!s.initialized) return std::numeric_limits<double>::quiet_NaN();
    const double dt = t_s - time();
    if (!(dt > 0.0)) return s.g.x(1) * startFactor(s);
    Vec<N> x;
    if (forecastWeightingOn()) weightedForecastMean(channel, x);
    else x = s.g.x;
    x = predictedMean(x, transition(channel, dt));
    blendForecast(s, dt, x);
    return x(1);
  }

  /// x(1) of F x from the feed-forward's start (feedforwardStartMean(): the velocity not weighted by
  /// its significance), neither capped nor blended with hold but times the feed-forward's weight
  /// w_ff when the blend is on (Predictor::feedforwardVelocity(), file comment "The feed-forward's
  /// velocity"); at a zero horizon, and without the blend and the weighting, predictVelocity()'s
  /// number.
  double feedforwardVelocity(int channel, double t_s) const override {
    const ChannelState& s = state_.at(channel);
    if (!s.initialized) return std::numeric_limits<double>::quiet_NaN();
    const double dt = t_s - time();
    if (!(dt > 0.0)) return predictVelocity(channel, t_s);  // a zero horizon: the filter's own (file comment)
    const double w = blend_tau_s_ > 0.0 ? s.feedforward.weight(blend_prior_) : 1.0;
    Vec<N> x;
    if (forecastWeightingOn()) feedforwardStartMean(channel, x);
    else x = s.g.x;
    return w * predictedMean(x, transition(channel, dt))(1);
  }

  /// predict(channel, t_s).position() without the covariance: x(0) of the same F x product.
  double predictPosition(int channel, double t_s) const override {
    const ChannelState& s = state_.at(channel);
    if (!s.initialized) return std::numeric_limits<double>::quiet_NaN();
    const double dt = t_s - time();
    if (!(dt > 0.0)) return s.g.x(0);
    double f;
    if (s.start_now) {  // the forecast start this update kept for the blend: the same x, the same bits
      f = predictedPosition(s.x_start[static_cast<size_t>(s.head)], transition(channel, dt));
    } else {
      f = forecastWeightingOn() ? predictedPosition(weightedForecastStart(channel), transition(channel, dt))
                                : predictedPosition(s.g, transition(channel, dt));
    }
    if (!(blend_tau_s_ > 0.0)) return f;
    if (!splitsBlend(s)) return s.blend.position(f);
    const double p0 = s.x_start[static_cast<size_t>(s.head)](0);
    return s.blend.blendSplit(s.blend.z_hold, p0, s.rates.capped(extrapolation_cap_, p0, f, dt));
  }

  Innovation innovation(int channel) const override { return state_.at(channel).innovation; }
  std::vector<Params> forecastVariants() const override { return blendHorizonVariants(blend_tau_s_, blend_frames_); }

  /// The filtered Gaussian of a channel at the last update time (tests, monitors).
  const Gaussian<N>& gaussian(int channel) const { return state_.at(channel).g; }
  bool initialized(int channel) const { return state_.at(channel).initialized; }

 protected:
  struct ChannelState {
    Gaussian<N> g;
    bool initialized = false;
    Innovation innovation;
    HoldBlend blend;  ///< its BlendWeight learns on one-frame forecasts; its w is the handed-out weight
    /// The regressions on forecasts of 2..hold_blend_frames frames (longer[h - 2]).
    LongerBlendWeights longer{};
    FeedforwardWeight feedforward;  ///< the feed-forward's weight (file comment)
    /// The feed-forward's start (feedforwardStartMean()) of the last measured update, with the
    /// weighting on: its one-frame step is what w_ff learns from.
    Vec<N> x_ff_start = Vec<N>::Zero();
    int run = 0;           ///< consecutive measured frames up to the last update
    /// The forecast starts of the last kMaxBlendFrames measured updates (ring, newest at head).
    std::array<Vec<N>, kMaxBlendFrames> x_start{};
    std::array<double, kMaxBlendFrames> t_start{};
    std::array<double, kMaxBlendFrames> z_start{};
    int head = 0;
    /// x_start[head] is the forecast start of g as it is now: kept by the last update (cleared at
    /// the start of every update, set by rememberForecastStart), so predictPosition reuses it.
    bool start_now = false;
    /// The last update after initialisation had no measurement (inside step(): the one before
    /// this update; set after it).
    bool unmeasured_last = false;
    ExtrapolationRates rates;  ///< the cap's (file comment, "Extrapolations the track has not shown")
  };

  /// The blend with hold (and the cap) of a forecast mean x over dt of channel state s, when the
  /// blend is on: what predict() and predictVelocity() hand out.
  void blendForecast(const ChannelState& s, double dt, Vec<N>& x) const {
    if (!(blend_tau_s_ > 0.0)) return;
    if (splitsBlend(s)) {
      const double p0 = s.x_start[static_cast<size_t>(s.head)](0);
      s.rates.capState(extrapolation_cap_, p0, x, dt);
      s.blend.blendStateSplit(s.blend.z_hold, p0, x);
    } else {
      s.blend.blendState(s.blend.z_hold, x);
    }
  }
  /// The start-up prior's factor 1 - exp(-(c / p)^2) of the blend's c samples on channel s, with the
  /// blend and hold_blend_prior p on; else 1. A zero-horizon query's velocity (and acceleration) is
  /// the posterior's times it (file comment, "The start of a track").
  double startFactor(const ChannelState& s) const {
    return blend_tau_s_ > 0.0 && blend_prior_ > 0.0 ? blendPriorFactor(s.blend.count, blend_prior_) : 1.0;
  }
  /// True when a forecast of channel s now is blended with the two weights (file comment, "Two
  /// weights"): the split is on and the last update was measured, so x_start[head] is its start.
  bool splitsBlend(const ChannelState& s) const { return blend_split_ && !s.unmeasured_last; }
  /// Keeps the forecast start (x(k|k), significance-weighted) of channel c at t_s for the blend.
  void rememberForecastStart(int c, double t_s) {
    ChannelState& s = state_[static_cast<size_t>(c)];
    s.head = (s.head + 1) % kMaxBlendFrames;
    Vec<N>& start = s.x_start[static_cast<size_t>(s.head)];
    if (forecastWeightingOn()) {  // the feed-forward's start, and the forecast's: it weighted by w_v
      feedforwardStartMean(c, s.x_ff_start);
      start = s.x_ff_start;
      weighVelocity(c, start);
    } else {
      start = s.g.x;
    }
    s.t_start[static_cast<size_t>(s.head)] = t_s;
    s.z_start[static_cast<size_t>(s.head)] = s.blend.z_hold;
    s.run = std::min(s.run + 1, kMaxBlendFrames + 1);
    s.start_now = true;
  }
  /// exp(-dt / hold_blend_tau_s), kept for the last few distinct dt (recent_values.h): the same bits
  /// as std::exp.
  double blendForgetting(double dt) { return blendKeeps(dt)[0]; }
  /// {blendForgetting(dt), exp(-dt / kFeedforwardTauS)}, kept together.
  const std::array<double, 2>& blendKeeps(double dt) {
    return blend_keep_.get({dt}, [&] { return std::array<double, 2>{std::exp(-dt / blend_tau_s_), std::exp(-dt / kFeedforwardTauS)}; });
  }
  /// One regression sample of the blend (file comment) on channel c after the update at t_s;
  /// lambda = blendForgetting(dt) of the update's dt, feedforward_keep = exp(-dt / kFeedforwardTauS)
  /// (the feed-forward's low-pass, which learns from the same one-frame pair).
  void learnBlend(int c, double t_s, double z, double lambda, double feedforward_keep) {
    ChannelState& s = state_[static_cast<size_t>(c)];
    if (!isMeasured(z)) {
      s.run = 0;
      return;
    }
    if (s.run >= 1) {  // frame k - 1 measured: the one-frame forecast made there
      const auto j = static_cast<size_t>(s.head);
      const Mat<N> F = transition(c, t_s - s.t_start[j]);
      const double f = predictedPosition(s.x_start[j], F);
      s.blend.learn(f - s.z_start[j], s.x_start[j](0) - s.z_start[j], z - s.z_start[j], lambda, blend_sigmas_, blend_split_,
                    blend_prior_);
      if (extrapolation_cap_ > 0.0 && blend_split_) s.rates.learn(f - s.x_start[j](0), t_s - s.t_start[j], lambda);
      // the feed-forward's own one-frame step (its start's velocity not weighted; file comment)
      const double d_ff = forecastWeightingOn() ? predictedPosition(s.x_ff_start, F) - s.x_ff_start(0) : f - s.x_start[j](0);
      s.feedforward.learn(d_ff, z - s.z_start[j], feedforward_keep, lambda);
      // The forecasts of h = 2..H frames made at k - h, when frames k - h .. k - 1 were measured;
      // the handed-out weight is the smallest over the horizons (file comment).
      for (int h = 2; h <= blend_frames_ && h <= s.run; ++h) {
        const size_t jh = blendRingSlot(s.head, h - 1);
        // (F x)(0) as Eigen's dot sums it (x0 F00 + (x1 F01 + x2 F02) for 3 states, not the product's
        // left-to-right order of predictedPosition): kept so, as its bits are the regression's history.
        const double fh = transition(c, t_s - s.t_start[jh]).row(0).dot(s.x_start[jh]);
        s.longer[static_cast<size_t>(h - 2)].learn(fh - s.z_start[jh], s.x_start[jh](0) - s.z_start[jh], z - s.z_start[jh], lambda,
                                                   blend_sigmas_, blend_split_, blend_prior_);
      }
      minOverHorizons(s.blend, s.longer, blend_frames_);
    }
    s.blend.z_hold = z;
    s.blend.recent.remember(t_s, z, s.g.x(1), blendForgetting(t_s - s.blend.recent.lastTime()), s.innovation);
    if (N == 3 && coast_crossing_ && s.blend.recent.watching()) s.blend.recent.watchCrossing(s.g.P(1, 1), blend_tau_s_);
    rememberForecastStart(c, t_s);
  }

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
  /// Reads `coast_tau_s` (s, >= 0, default kDefaultCoastTauS), and `coast_stop_fraction` (>= 0,
  /// default kDefaultCoastStopFraction), `coast_fast_ratio` (>= 0, default kDefaultCoastFastRatio),
  /// `coast_lag_sigmas` (>= 0, default kDefaultCoastLagSigmas), `coast_shape` (1..10, default
  /// kDefaultCoastShape) and `coast_crossing` (0 | 1, default kDefaultCoastCrossing), used with the
  /// blend only; called by every
  /// derived constructor whose state has a velocity.
  void readCoastParam(const Params& params) {
    coast_tau_s_ = coastTauParam(params);
    coast_stop_fraction_ = coastStopFractionParam(params);
    coast_fast_ratio_ = coastFastRatioParam(params);
    coast_lag_sigmas_ = coastLagSigmasParam(params);
    coast_lag_share_ = coastLagShareParam(params);
    coast_shape_ = coastShapeParam(params);
    coast_crossing_ = coastCrossingParam(params);
  }
  double coastTauS() const { return coast_tau_s_; }
  /// Reads `adapt_after_gap` (0 | 1, default 0; file comment, "The first measurement after a
  /// gap"); called by the derived constructors whose adaptation learns from the innovations.
  void readAdaptAfterGapParam(const Params& params) {
    adapt_after_gap_ = params.get("adapt_after_gap", 0.0, 0.0, 1.0) >= 0.5;
  }
  /// True, inside step() on a measured frame, when channel c's adaptation skips it: the update before
  /// had no measurement (so this is the first measured one after a gap), the filter coasts, and
  /// `adapt_after_gap` is 0 (file comment).
  bool adaptationPausedAfterGap(int c) const {
    return !adapt_after_gap_ && coast_tau_s_ > 0.0 && state_[static_cast<size_t>(c)].unmeasured_last;
  }
  /// Reads `shrink_sigmas` (n of the acceleration weight w_a, dimensionless >= 0, default
  /// default_sigmas; with N = 2 there is no acceleration and it only sets the default of the next
  /// key) and `shrink_v_sigmas` (n of the velocity weight w_v, default: shrink_sigmas when
  /// weigh_velocity, else 0); see the file comment. Called by the derived constructors whose
  /// forecast is weighted; without the call the forecast is unweighted. Also reads `hold_blend_tau_s`
  /// (s, >= 0, default kDefaultHoldBlendTauS, 0 = off; file comment).
  void readShrinkParams(const Params& params, double default_sigmas, bool weigh_velocity) {
    shrink_a_sigmas_ = params.get("shrink_sigmas", default_sigmas, 0.0, 1e3);
    shrink_v_sigmas_ = params.get("shrink_v_sigmas", weigh_velocity ? shrink_a_sigmas_ : 0.0, 0.0, 1e3);
    if constexpr (N == 2) shrink_a_sigmas_ = 0.0;
    blend_tau_s_ = holdBlendTauParam(params);
    blend_frames_ = holdBlendFramesParam(params);
    blend_sigmas_ = holdBlendSigmasParam(params);
    blend_prior_ = holdBlendPriorParam(params);
    blend_split_ = holdBlendSplitParam(params);
    extrapolation_cap_ = extrapolationCapParam(params);
  }
  /// True when the forecast is weighted (a shrink key > 0).
  bool forecastWeightingOn() const { return shrink_a_sigmas_ > 0.0 || shrink_v_sigmas_ > 0.0; }
  /// The Gaussian the forecast of channel c extrapolates: x(k|k) with a weighted by w_a w_v and v by
  /// w_v (file comment), P(k|k) unchanged.
  Gaussian<N> weightedForecastStart(int c) const {
    Gaussian<N> g = state_[static_cast<size_t>(c)].g;
    weightedForecastMean(c, g.x);
    return g;
  }
  /// The start of the feed-forward's velocity (feedforwardVelocity()): x(k|k) with a weighted by w_a
  /// alone and v not weighted (file comment, "The feed-forward's velocity").
  void feedforwardStartMean(int c, Vec<N>& x) const {
    const Gaussian<N>& g = state_[static_cast<size_t>(c)].g;
    x(0) = g.x(0);
    x(1) = g.x(1);
    if constexpr (N == 3) x(2) = g.x(2) * significanceWeight(g.x(2), g.P(2, 2), shrink_a_sigmas_);
  }
  /// Its mean alone, written into x entry by entry (no Gaussian copied): the feed-forward's start
  /// with its derivatives weighted by w_v (the same products in the same order).
  void weightedForecastMean(int c, Vec<N>& x) const {
    feedforwardStartMean(c, x);
    weighVelocity(c, x);
  }
  /// x(1) (and x(2)) of a start of channel c times w_v = w(v, P_vv; shrink_v_sigmas) (file comment).
  void weighVelocity(int c, Vec<N>& x) const {
    const Gaussian<N>& g = state_[static_cast<size_t>(c)].g;
    const double w_v = significanceWeight(g.x(1), g.P(1, 1), shrink_v_sigmas_);
    x(1) *= w_v;
    if constexpr (N == 3) x(2) *= w_v;
  }
  /// The adaptation of a density set by the key `q` (process_noise_adapt.h): `q: auto`, covariance
  /// matching; `q` absent, the raise (readProcessNoiseRaise: the whitening in a closed loop);
  /// a number, none (q fixed). Called by the derived constructors whose `q` takes `auto` (kf-cv,
  /// kf-ca, st-akf, fakf-classic); `white_rho`, the default of the whitening's target (q_white_rho,
  /// process_noise_adapt.h).
  void readProcessNoiseAdaptation(const Params& params, double white_rho = kDefaultQWhiteRho) {
    if (isAutoProcessNoise(params, "q")) {
      processNoiseRaiseRatio(params);  // known keys there too, unused
      processNoiseWhiteRho(params, white_rho);
      q_auto_.assign(state_.size(), ProcessNoiseMatcher());
    } else {
      readProcessNoiseRaise(params, {"q"}, InnovationStatistic::Whiteness, white_rho);
    }
  }
  /// The raise above the default density while the innovations exceed q_raise_ratio times their
  /// predicted variance, when none of `fixing_keys` (the keys that set the density: `q`, stkf's
  /// q_pos / q_vel, the CS variance bounds) is given and the blend with hold is on
  /// (readShrinkParams() first); in a closed loop (`closed_loop: 1`) the adaptation `in_closed_loop`
  /// instead (the whitening unless said): processNoiseRaise(). Called by the derived constructors
  /// whose processNoise() scales its density by processNoiseScale().
  void readProcessNoiseRaise(const Params& params, std::initializer_list<const char*> fixing_keys,
                             InnovationStatistic in_closed_loop = InnovationStatistic::Whiteness,
                             double white_rho = kDefaultQWhiteRho) {
    if (const auto raise = processNoiseRaise(params, fixing_keys, blend_tau_s_ > 0.0, in_closed_loop, white_rho))
      q_auto_.assign(state_.size(), *raise);
  }
  /// q / q0 of channel c: 1 unless q is adapted (readProcessNoiseAdaptation, readProcessNoiseRaise).
  /// A derived processNoise() multiplies its nominal density by it.
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
  std::vector<ProcessNoiseMatcher> q_auto_;   ///< empty unless q is adapted
  double r0_;
  double p0_vel_;
  double p0_acc_;
  double coast_tau_s_ = 0.0;  ///< 0 until readCoastParam(): hold never coasts
  double coast_stop_fraction_ = 0.0;  ///< coast_stop_fraction (with the blend only)
  double coast_fast_ratio_ = 0.0;     ///< coast_fast_ratio (with the blend only)
  double coast_lag_sigmas_ = 0.0;     ///< coast_lag_sigmas (with the blend only)
  bool coast_lag_share_ = false;      ///< coast_lag_share (with the blend only)
  double coast_shape_ = 1.0;          ///< coast_shape (with the blend only)
  bool coast_crossing_ = false;       ///< coast_crossing (with the blend only, on a state with an acceleration)
  bool adapt_after_gap_ = true;       ///< adapt_after_gap; true until readAdaptAfterGapParam()
  double shrink_a_sigmas_ = 0.0;  ///< 0 until readShrinkParams(): unweighted forecast
  double shrink_v_sigmas_ = 0.0;
  double blend_tau_s_ = 0.0;
  RecentValues<std::array<double, 2>> blend_keep_;  ///< blendKeeps(dt) of the last few dt
  int blend_frames_ = kDefaultHoldBlendFrames;
  double blend_sigmas_ = kDefaultHoldBlendSigmas;  ///< hold_blend_sigmas
  double blend_prior_ = kDefaultHoldBlendPrior;    ///< hold_blend_prior
  bool blend_split_ = kDefaultHoldBlendSplit != 0.0;  ///< hold_blend_split
  double extrapolation_cap_ = 0.0;  ///< extrapolation_cap; 0 until readShrinkParams()
};

}  // namespace predvs
