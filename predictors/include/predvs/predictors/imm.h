// predvs — interacting multiple model (IMM) predictor: constant velocity + Singer (correlated)
// acceleration.
//
// docs/MODELS.md §14. Not in any of the five papers: the standard estimator for manoeuvring targets in the tracking
// literature (Blom & Bar-Shalom 1988; Bar-Shalom, Li, Kirubarajan, "Estimation with Applications
// to Tracking and Navigation", 2001, §11.6). Each channel runs two Kalman filters on a common
// state x = [p, v, a] (px, px/s, px/s^2) and H = [1, 0, 0]:
//   mode 0, CV:  F0 = [[1, T, 0], [0, 1, 0], [0, 0, 0]],  Q0 = q_cv [[T^3/3, T^2/2, 0], [T^2/2, T, 0], [0, 0, 0]]
//                (the acceleration entry is forced to 0: the CV model written in the CA state)
//   mode 1, CS:  F1 = singerTransition(alpha, T),  Q1 = singerProcessNoise(alpha, q_ca / (2 alpha), T)
//                (cs_akf.h: acceleration a first-order Markov process of rate alpha driven by white
//                noise of density q_ca; alpha -> 0 is the white-jerk CA model of density q_ca)
// Choice: CV + Singer rather than CV + CA. With a pure CA mode a dropped frame right after a hard
// stop extrapolates the stop's -3000 px/s^2 quadratically (measured: 3x the error of kf-cv on a
// "stops" track at 30 Hz); alpha = 5 /s lets an acceleration fade over ~0.2 s.
// with a Markov chain between the modes whose rates are stated in seconds, so they hold at any
// frame period T: p_jj(T) = exp(-T / tau_j) (mean sojourn time tau_j), p_ij = 1 - p_ii for i != j.
//
// One cycle over a step T, per channel (mu_i: mode probabilities after the last update):
//   mixing        c_j = sum_i p_ij mu_i,   mu_i|j = p_ij mu_i / c_j,
//                 x0_j = sum_i mu_i|j x_i,  P0_j = sum_i mu_i|j (P_i + (x_i - x0_j)(x_i - x0_j)')
//   mode-matched  x_j- = F_j x0_j,  P_j- = F_j P0_j F_j' + Q_j;  if z is measured:
//                 eps_j = z - x_j-(0),  S_j = P_j-(0,0) + R,  Joseph update of (x_j, P_j)
//   probabilities mu_j = c_j L_j / sum_i c_i L_i,  L_j = N(eps_j; 0, S_j)  (computed in logs);
//                 without a measurement mu_j = c_j
//   combination   x = sum_j mu_j x_j,  P = sum_j mu_j (P_j + (x_j - x)(x_j - x)')
// The innovation reported by innovation(c) is the moment-matched one of the mixture prior:
//   xbar = sum_j c_j x_j-(0),  eps = z - xbar,  S = sum_j c_j (S_j + (x_j-(0) - xbar)^2),
// so a Gaussian likelihood from (eps, S) approximates the IMM's mixture likelihood.
// Prediction query (const) to t = t_last + h: each mode's posterior is propagated over h with its
// own model, the mode probabilities by the chain over h (c_j(h) = sum_i p_ij(h) mu_i), and the
// result is combined as above.
//
// Parameters (defaults in px and s, chosen on the generated tracks of servo/maneuver_tracks.h,
// docs/PERFORMANCE.md "IMM"): q_cv (px^2/s^3, default 100: the CV mode is the quiet one; 3000
// gave the same figures on the generated tracks and 1.2-1.6x the error on the slow E1-E7), q_ca
// (px^2/s^5, default 1e6),
// alpha (1/s, default 5),
// r (px^2; default: estimated from the first frames, predictors/noise_estimate.h; a number fixes it),
// tau_cv_s (s, default 10: the stationary probability of the noisy mode is then ~5 %; 2 gave
// 1.2-1.6x the error on the slow E1-E4), tau_ca_s (s, default 0.5), mu0_ca (initial CA probability, 0.5),
// p0_vel ((px/s)^2, 1e4), p0_acc ((px/s^2)^2, 1e4).
// Mode probabilities: modeProbability(c, j) (accessor), and diagnostics() (per channel "mu_ca_<c>").
#pragma once

#include "predvs/predictors/kalman_math.h"
#include "predvs/predictors/noise_estimate.h"
#include "predvs/predictors/predictor.h"

#include <array>
#include <vector>

namespace predvs {

class ImmPredictor : public Predictor {
 public:
  ImmPredictor(int channels, const Params& params);
  std::string name() const override { return "imm"; }
  void reset() override;
  void update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) override;
  using Predictor::update;
  ChannelEstimate predict(int channel, double t_s) const override;
  Innovation innovation(int channel) const override { return chan_.at(static_cast<size_t>(channel)).innovation; }
  NamedValues diagnostics() const override;
  /// q_cv, q_ca and r: the number given, or, when `r` is `auto`, the estimator's prior (1 px^2).
  std::vector<NoiseParameter> noiseParameters() const override {
    return {accelerationDensityParameter("q_cv", q_cv_), jerkDensityParameter("q_ca", q_ca_),
            measurementVarianceParameter(r_)};
  }

  /// Probability of mode j (0 = CV, 1 = CA) of channel c after the last update.
  double modeProbability(int c, int j) const { return chan_.at(static_cast<size_t>(c)).mu[static_cast<size_t>(j)]; }
  /// R used by channel c now (px^2).
  double measurementNoise(int c) const;

 private:
  struct Channel {
    std::array<Gaussian<3>, 2> g;
    std::array<double, 2> mu{{0.5, 0.5}};
    bool initialized = false;
    Innovation innovation;
    StartupNoiseEstimator r_est;
  };
  Mat<3> transition(int mode, double dt) const;
  Mat<3> processNoise(int mode, double dt) const;
  /// Transition probabilities p_ij over dt.
  Mat<2> chain(double dt) const;

  double q_cv_, q_ca_, alpha_, r_, tau_cv_s_, tau_ca_s_, mu0_ca_, p0_vel_, p0_acc_;
  bool r_auto_;
  std::vector<Channel> chan_;
};

}  // namespace predvs
