// predvs — self-tuning Kalman filter (STKF, docs/MODELS.md §4, paper 001 §4), on a
// constant-velocity (the paper's) or a constant-acceleration motion model.
#pragma once

#include "predvs/predictors/channel_predictor.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace predvs {

/// `stkf`: Kalman filter whose measurement noise is re-estimated every frame from the scatter of
/// the recent measurements about a fitted polynomial (paper 001 §4.2: a straight line).
///
/// The key `model` (a word) chooses the motion model: `cv` (the paper's) or `ca` (the registry's
/// default since issue 11: with its weighted forecast, shrink_sigmas 3, it beats hold on all 216
/// generated tracks and both held-out grids, where the paper's cv filter loses on 3, 5 and 2
/// tracks whatever its weighting; docs/PERFORMANCE.md "Defaults that hold"). The paper-001
/// scenarios pin `model: cv`. The registry builds StkfFilter<2> (StkfPredictor) for cv and
/// StkfFilter<3> (StkfCaPredictor) for ca (makeStkfPredictor()); a class built directly is its
/// own model; any other word is an error naming `model`.
///
/// Model, per channel (the paper's A, B, H, Q_0, R_0 are block-diagonal over x_i, y_i, d_x, so
/// running one filter per channel is exact):
///   cv: x = [p, v],     x(n) = [[1, T], [0, 1]] x(n-1) + [T; 0] u(n-1),
///   ca: x = [p, v, a],  x(n) = [[1, T, T^2/2], [0, 1, T], [0, 0, 1]] x(n-1) + [T; 0; 0] u(n-1),
///   z = p + noise,
/// where u is a known image velocity caused by the robot's own motion (B_i times the previous
/// command in the paper; see setKnownImageVelocity()). In both models u moves the position only.
///
/// Self-tuning R: the last k measurements Y = [y_1..y_k]' of a channel are fitted by a polynomial
/// in the sample index n of degree 1 (cv: y = a n + b, A_st = [[1,1],[2,1],..,[k,1]], the paper)
/// or 2 (ca: y = a n^2 + b n + c, A_st = [n^2, n, 1]: a window that follows a constant
/// acceleration is not scatter for a CA model, just as a ramp is not for a CV model). The
/// residuals are T_st Y, T_st = I_k - A_st (A_st' A_st)^-1 A_st' (fixed, computed once by a
/// solve). The residual variance sigma^2 = var(T_st Y) (sample variance, divisor k-1, as MATLAB's
/// var the paper used; kept for ca too) sets R_n = R_0 + (sigma^2)^2 (paper eq. 41, `squared` =
/// 1) or R_n = R_0 + sigma^2 (`squared` = 0). While fewer than k consecutive measurements are
/// stored, R_n = R_0. The window assumes equally spaced samples, so a missed measurement or a
/// re-initialisation empties it. A fit needs residual degrees of freedom: k >= 3 (cv), k >= 4 (ca).
///
/// Process noise, cv: the paper's Q_0 = diag(q_pos, q_vel) is a per-step covariance at its frame
/// period T_0 = 0.1 s. For another step dt it is scaled linearly, Q(dt) = (dt / T_0) Q_0: the
/// variance of independent increments grows with elapsed time, and dt = T_0 gives the paper's
/// filter exactly. (Choice documented here; the paper only runs at T_0.)
/// Process noise, cv with `process_noise: white-acceleration` (the default is `diagonal`, the
/// above): kf-cv's white acceleration of density q (px^2/s^3, default kDefaultQCv = 1e4),
/// Q(dt) = q [[dt^3/3, dt^2/2], [dt^2/2, dt]], and kf-cv's other defaults with it: P_0 = diag(R,
/// 1e4) (p0_pos, if given, replaces R), shrink_sigmas kf-cv's (0), and no re-initialisation
/// (reinit_threshold and reinit_threshold_vel default to +inf; given, each compares its own
/// diagonal, as on ca). So with the self-tuning off (window 0) this structure IS kf-cv's filter
/// (tests/predictors/stkf_white_acceleration_test.cpp: equal to rounding), and with a window it is
/// kf-cv with the paper's self-tuned R. Why: the paper's diagonal Q per T_0 has no position-velocity
/// correlation and a different shape over dt, and on the generated tracks the best fixed KF is
/// often kf-cv (docs/PERFORMANCE.md "Warm start"); the noise fit tries this structure too
/// (structuralVariants()). The key is checked and unused on ca (already a white jerk).
/// Process noise, ca: a white jerk of density q (px^2/s^5), Q(dt) = q [[dt^5/20, dt^4/8, dt^3/6],
/// [dt^4/8, dt^3/3, dt^2/2], [dt^3/6, dt^2/2, dt]] (kalman_math.h caProcessNoise, as kf-ca). Chosen
/// over a diag(q_pos, q_vel, q_acc) per T_0: one key for a noise fit instead of three, exact over
/// any dt, and with the self-tuning off (window = 0) the filter is kf-ca with the same q, r, P_0.
///
/// Occlusion: a frame without measurement is predict-only. When a diagonal of P exceeds its
/// threshold the channel is marked for re-initialisation: predictions continue from the
/// extrapolated state, and the next measurement restarts the channel at x = [z, 0(, 0)], P = P_0.
/// cv: P(0,0) or P(1,1) above `reinit_threshold` (paper: 4800; measured 37 frames = 3.7 s without
/// measurement at the paper's values, the position crossing first).
/// ca: one threshold per diagonal, P(0,0) > `reinit_threshold` (px^2, 4800 as the paper),
/// P(1,1) > `reinit_threshold_vel` ((px/s)^2), P(2,2) > `reinit_threshold_acc` ((px/s^2)^2); the
/// last two default to +inf (not compared), so by default the CA filter restarts when its
/// position is uncertain by more than ~69 px, the paper's criterion. Why not 4800 on every
/// diagonal: under the default q the acceleration variance after a measured frame is already
/// 2.7e4..6.1e4 (px/s^2)^2 at 60..10 Hz and 0.5..3 px noise (steady state of the Riccati
/// recursion), so that threshold restarts the filter on every frame (measured: 180/216 tracks
/// beat hold instead of 212); and the velocity variance (10 Hz, 3 px: 2.9e3 (px/s)^2 after one
/// missed frame) crosses 4800 in the second missed frame at 10 Hz, so each short occlusion
/// restarted the filter at v = a = 0 (210/216, mean ratio 0.606 instead of 0.564).
///
/// Parameters, both models: model (cv | ca), process_noise (cv: diagonal | white-acceleration,
/// above), r (R_0, px^2; default `auto`,
/// predictors/noise_estimate.h), p0_pos (px^2, default 1), p0_vel ((px/s)^2; cv default 1, P_0 =
/// I as the paper; ca default 1e4 as kf-ca), window (k; 0 disables the self-tuning, giving the
/// plain KF of the model; cv: default 15, k = 1..2 rejected; ca: default 4, k = 1..3 rejected),
/// squared (default 0), reinit_threshold (px^2, 4800), coast_tau_s (s, default 0.2: velocity (and
/// acceleration) decay on unmeasured frames, channel_predictor.h; the occlusion scenarios of
/// paper 001 pin 0).
/// cv only: q_pos (px^2 per q_period_s, default 0), q_vel ((px/s)^2 per q_period_s, default 3000,
/// i.e. a white acceleration of 3e4 px^2/s^3), q_period_s (T_0 = 0.1 s).
/// ca only: q (px^2/s^5, default kDefaultQStkfCa = 3e5, kf-ca's), p0_acc ((px/s^2)^2, default 1e4),
/// reinit_threshold_vel ((px/s)^2, +inf), reinit_threshold_acc ((px/s^2)^2, +inf).
/// Both models: shrink_sigmas (significance weight of the forecast acceleration, default 0 on cv,
/// 3 on ca; 0 = the unweighted filter), shrink_v_sigmas (velocity, default shrink_sigmas):
/// channel_predictor.h. The paper-001 scenarios pin shrink_sigmas 0 (and hold_blend_tau_s 0).
/// q_raise_ratio (default 2; 0 = off): when none of q, q_pos, q_vel is given and the blend with hold
/// is on, the process noise (either model) is multiplied by a factor >= 1 that rises while the
/// innovations are more than this many times their predicted variance (process_noise_adapt.h).
/// The ca defaults were chosen with `predvs track-study --predictors hold,stkf --param
/// stkf.model=ca` (docs/PERFORMANCE.md "stkf on either motion model"): on the 216 generated
/// tracks the self-tuned R costs at every window (k = 0, i.e. kf-ca: 214 beat hold, mean ratio
/// 0.560; k = 4: 212, 0.564; k = 5: 202, 0.568; k = 15: 184, 0.611): a manoeuvre that a quadratic
/// does not follow (a burst's start, a zigzag's reversal) is read as noise and slows the filter
/// when it should be fastest. k = 4, the shortest window with a residual, keeps the self-tuning
/// (R then grows with the squared third difference of the last four samples) at the least cost.
/// P_0 = I cost too (0.596 against 0.564 with kf-ca's 1e4), q = 1e5 / 1e6 were worse than 3e5.
/// The paper's values (r 5, q_pos 5, q_vel 20, squared 1) were the cv defaults before issue 11;
/// they lost to hold on 128 of 144 generated maneuvering tracks (the squared variance of a line
/// fit through a manoeuvre makes R huge, and q_vel = 20 cannot follow a turn), so they are now
/// given explicitly by the paper-001 scenarios (data/scenarios/e6-*, e7-*, e8-*).
/// Default `shrink_sigmas` of stkf (cv, ca), and whether shrink_v_sigmas defaults to it
/// (channel_predictor.h, significance-weighted forecast; docs/MODELS.md §15). ca: 3, the smallest
/// n that beats hold on the 216 tracks of `predvs track-study` and both held-out grids (2: 215 /
/// 214 / 108; mean ratio 0.564 -> 0.552). cv: 0, since no n does (0.5..3: 213-214 / 211-214 /
/// 104-106, the mean ratio growing from 0.616 to 0.62-0.77): cv's losses are lag, not an
/// insignificant velocity.
inline constexpr double kDefaultShrinkSigmasStkf = 0.0;
inline constexpr double kDefaultShrinkSigmasStkfCa = 3.0;
inline constexpr bool kDefaultShrinkVelocityStkf = true;

template <int N>
class StkfFilter : public ChannelPredictor<N> {
  using Base = ChannelPredictor<N>;

 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<StkfFilter>(*this); }
  StkfFilter(int channels, const Params& params);
  std::string name() const override { return "stkf"; }
  /// cv: r (R_0), q_pos, q_vel (white-acceleration: r, q). q_pos defaults to 0, below its bound:
  /// a fit starts it at the bound. ca: r, q (white-jerk density).
  std::vector<NoiseParameter> noiseParameters() const override;
  /// {model: cv}, {model: cv, window: 3}, {model: ca}, each model with window 0 (no
  /// self-tuning), and {model: cv, process_noise: white-acceleration} with window 3 and with
  /// window 0 (the latter is kf-cv's filter).
  std::vector<Params> structuralVariants() const override;
  /// ca and white-acceleration cv: q from kf-ca's / kf-cv's fitted q. Diagonal cv: q_pos =
  /// q T_0^3 / 3 and q_vel = q T_0 from kf-cv's q (the diagonal of its Q over T_0 = q_period_s).
  std::vector<FitSeed> fitSeeds() const override;

  void update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) override;
  using Predictor::update;
  /// Includes the known image velocity set for the next update, if any.
  ChannelEstimate predict(int channel, double t_s) const override;
  double predictPosition(int channel, double t_s) const override;

  /// Known image velocity (px/s per channel) induced by the robot's own motion, B_i u in paper
  /// 001 eq. 30: the next time update adds dt * v to each position. Applies to the next update()
  /// only and is then cleared.
  void setKnownImageVelocity(const Eigen::VectorXd& v_px_s);

  /// R currently used by channel c (R_0 plus the self-tuned term).
  double currentR(int c) const { return r_.at(static_cast<size_t>(c)); }
  /// Number of re-initialisations (P diagonal above the threshold) over all channels.
  int reinitialisations() const { return reinits_; }
  /// True while channel c waits for a measurement to re-initialise.
  bool reinitPending(int c) const { return pending_.at(static_cast<size_t>(c)) != 0; }
  /// The fixed k x k residual maker T_st (empty when window = 0).
  const Eigen::MatrixXd& residualMaker() const { return T_st_; }

  /// T_st = I_k - A (A'A)^-1 A' for the polynomial of degree N-1 in n = 1..k (N = 2:
  /// A = [[1,1],[2,1],..,[k,1]]; N = 3: A = [n^2, n, 1]), computed with an LDLT solve. For N = 3 the
  /// columns are formed on the centred, scaled index s = (2n - k - 1) / (k - 1) in [-1, 1]: the
  /// same column space, so the same projector, but A'A stays well conditioned for large k.
  static Eigen::MatrixXd makeResidualMaker(int k);

 protected:
  using typename Base::ChannelState;
  using Base::state_;
  using Base::r0_;
  using Base::p0_vel_;
  using Base::p0_acc_;

  Mat<N> transition(int, double dt) const override;
  Mat<N> processNoise(int c, double dt) const override;
  double measurementNoise(int c) const override { return r_[static_cast<size_t>(c)]; }
  void resetAdaptation() override;
  void initialize(int c, double z) override;
  void step(int c, double dt, double z) override;

 private:
  void pushSample(int c, double z);
  bool pastReinitThreshold(const Mat<N>& P) const;

  double q_pos_ = 0.0, q_vel_ = 0.0, q_period_s_ = 0.1;  // cv
  double q_ = 0.0;                                       // ca; cv with process_noise white-acceleration
  double p0_pos_;
  bool white_acceleration_;  // cv: process_noise white-acceleration
  bool p0_pos_is_r_;         // P_0(0,0) = R (kf-cv's), white-acceleration without p0_pos
  int window_;
  bool squared_;
  double reinit_threshold_;
  double reinit_threshold_vel_;  // ca (cv: reinit_threshold_)
  double reinit_threshold_acc_;  // ca
  Eigen::MatrixXd T_st_;
  Eigen::VectorXd eps_;  ///< the window's residuals T_st y (scratch of pushSample, sized window)
  Eigen::VectorXd known_v_px_s_;
  // Per channel: window of the last k measurements (oldest first), adapted R, pending flag.
  std::vector<Eigen::VectorXd> window_y_;
  std::vector<int> window_count_;
  std::vector<double> r_;
  std::vector<char> pending_;
  int reinits_ = 0;
};

/// The paper's filter: constant velocity.
using StkfPredictor = StkfFilter<2>;
/// `stkf` with `model: ca`.
using StkfCaPredictor = StkfFilter<3>;

extern template class StkfFilter<2>;
extern template class StkfFilter<3>;

/// Default white-jerk density of `stkf` with `model: ca` (px^2/s^5); see docs/PERFORMANCE.md
/// ("stkf on either motion model") for the track-study figure that chose it.
inline constexpr double kDefaultQStkfCa = 3e5;
/// Default `window` of `model: ca` (the shortest quadratic fit with a residual); see the class comment.
inline constexpr double kDefaultStkfCaWindow = 4.0;
/// Default `p0_vel` ((px/s)^2) and `p0_acc` ((px/s^2)^2) of `model: ca` (kf-ca's).
inline constexpr double kDefaultStkfCaP0 = 1e4;

/// The registry's factory: StkfPredictor for `model: cv`, StkfCaPredictor for `model: ca` (or no
/// model); any other word throws std::invalid_argument naming `model` and the words allowed.
std::unique_ptr<Predictor> makeStkfPredictor(int channels, const Params& params);

}  // namespace predvs
