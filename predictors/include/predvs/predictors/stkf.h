// predvs — self-tuning Kalman filter (STKF, docs/MODELS.md §4, paper 001 §4).
#pragma once

#include "predvs/predictors/channel_predictor.h"

#include <Eigen/Core>

#include <vector>

namespace predvs {

/// `stkf`: constant-velocity Kalman filter whose measurement noise is re-estimated every frame
/// from the scatter of the recent measurements about a straight line (paper 001 §4.2).
///
/// Model, per channel (the paper's A, B, H, Q_0, R_0 are block-diagonal over x_i, y_i, d_x, so
/// running one [p, v] filter per channel is exact):
///   x = [p, v],  x(n) = [[1, T], [0, 1]] x(n-1) + [T; 0] u(n-1),  z = p + noise,
/// where u is a known image velocity caused by the robot's own motion (B_i times the previous
/// command in the paper; see setKnownImageVelocity()).
///
/// Self-tuning R: the last k measurements Y = [y_1..y_k]' of a channel are fitted by a line
/// y = a n + b. With A_st = [[1,1],[2,1],..,[k,1]] the residuals are T_st Y, where
/// T_st = I_k - A_st (A_st' A_st)^-1 A_st' is fixed (computed once, by a solve). The residual
/// variance sigma^2 = var(T_st Y) (sample variance, divisor k-1, as MATLAB's var the paper used)
/// sets R_n = R_0 + (sigma^2)^2 (paper eq. 41, `squared` = 1) or R_n = R_0 + sigma^2
/// (`squared` = 0). While fewer than k consecutive measurements are stored, R_n = R_0. The window
/// assumes equally spaced samples, so a missed measurement or a re-initialisation empties it.
///
/// Process noise: the paper's Q_0 = diag(q_pos, q_vel) is a per-step covariance at its frame
/// period T_0 = 0.1 s. For another step dt it is scaled linearly, Q(dt) = (dt / T_0) Q_0: the
/// variance of independent increments grows with elapsed time, and dt = T_0 gives the paper's
/// filter exactly. (Choice documented here; the paper only runs at T_0.)
///
/// Occlusion: a frame without measurement is predict-only. When any diagonal of P exceeds
/// `reinit_threshold` (paper: 4800; measured 37 frames = 3.7 s without measurement at the paper's
/// values) the channel is marked for re-initialisation: predictions continue from the
/// extrapolated state, and the next measurement restarts the channel at x = [z, 0], P = P_0.
///
/// Parameters: r (R_0, px^2; default `auto`, predictors/noise_estimate.h), q_pos (px^2 per
/// q_period_s, default 0), q_vel ((px/s)^2 per q_period_s, default 3000, i.e. a white acceleration
/// of 3e4 px^2/s^3), q_period_s (T_0 = 0.1 s), p0_pos (1), p0_vel (1) (P_0 = I as the paper),
/// window (k, default 15; 0 disables the self-tuning, giving the paper's plain KF; k = 1..2 is
/// rejected because a line fit needs k >= 3), squared (default 0), reinit_threshold (4800),
/// coast_tau_s (s, default 0.2: velocity decay on unmeasured frames, channel_predictor.h; the
/// occlusion scenarios of paper 001 pin 0).
/// The paper's values (r 5, q_pos 5, q_vel 20, squared 1) were the defaults before issue 11; they
/// lost to hold on 128 of 144 generated maneuvering tracks (the squared variance of a line fit
/// through a manoeuvre makes R huge, and q_vel = 20 cannot follow a turn), so they are now given
/// explicitly by the paper-001 scenarios (data/scenarios/e6-*, e7-*, e8-*).
class StkfPredictor : public ChannelPredictor<2> {
 public:
  StkfPredictor(int channels, const Params& params);
  std::string name() const override { return "stkf"; }
  /// r (R_0), q_pos, q_vel. q_pos defaults to 0, below its bound: a fit starts it at the bound.
  std::vector<NoiseParameter> noiseParameters() const override {
    return {measurementNoiseParameter(), {"q_pos", 1e-6, 1e4, q_pos_}, {"q_vel", 1e-4, 1e7, q_vel_}};
  }

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

  /// T_st = I_k - A (A'A)^-1 A' for A = [[1,1],[2,1],..,[k,1]], computed with an LDLT solve.
  static Eigen::MatrixXd makeResidualMaker(int k);

 protected:
  Mat<2> transition(int, double dt) const override { return cvTransition(dt); }
  Mat<2> processNoise(int, double dt) const override;
  double measurementNoise(int c) const override { return r_[static_cast<size_t>(c)]; }
  void resetAdaptation() override;
  void initialize(int c, double z) override;
  void step(int c, double dt, double z) override;

 private:
  void pushSample(int c, double z);

  double q_pos_, q_vel_, q_period_s_, p0_pos_;
  int window_;
  bool squared_;
  double reinit_threshold_;
  Eigen::MatrixXd T_st_;
  Eigen::VectorXd known_v_px_s_;
  // Per channel: window of the last k measurements (oldest first), adapted R, pending flag.
  std::vector<Eigen::VectorXd> window_y_;
  std::vector<int> window_count_;
  std::vector<double> r_;
  std::vector<char> pending_;
  int reinits_ = 0;
};

}  // namespace predvs
