// predvs — the baselines every adaptive predictor is compared with (docs/MODELS.md §1).
#pragma once

#include "predvs/predictors/channel_predictor.h"

namespace predvs {

/// Default white-acceleration density of kf-cv (px^2/s^3) and white-jerk density of kf-ca
/// (px^2/s^5); see the class comments.
/// Chosen on the generated maneuvering tracks (servo/maneuver_tracks.h: 6 kinds x 10..60 Hz x
/// 0.5..3 px, `predvs track-study`, docs/PERFORMANCE.md): q = 1e4 px^2/s^3 is an acceleration
/// change of ~100 px/s^2 per sqrt(s), the turns and sways of a hand-moved or robot-carried target
/// at image speeds of 50..400 px/s. Before issue 11 the defaults were 100 and 1000, tuned on the
/// slow E1-E4 scenarios (10 px/s), and lost to `hold` on faster targets.
inline constexpr double kDefaultQCv = 1e4;
inline constexpr double kDefaultQCa = 3e5;
/// Default `shrink_sigmas` of kf-cv and kf-ca, and whether kf-ca's shrink_v_sigmas defaults to it
/// (channel_predictor.h, significance-weighted forecast; docs/MODELS.md §15). kf-ca: 2, the
/// smallest n (0.5 steps) that beats hold on the 216 tracks of `predvs track-study` and both
/// held-out grids (1.5 loses bursts 10 Hz 3 px #101 by x1.03); mean ratio 0.560 -> 0.531. kf-cv:
/// 0 (0.25 would win its one held-out loss, x1.003, but kf-cv is the servo tests' and goldens'
/// reference; docs/MODELS.md §15).
inline constexpr double kDefaultShrinkSigmasKfCv = 0.0;
inline constexpr double kDefaultShrinkSigmasKfCa = 2.0;
inline constexpr bool kDefaultShrinkVelocityKfCa = true;

/// `hold`: the no-prediction baseline. The estimate at any time is the last measurement
/// (zero velocity), which is what a servo loop without a predictor acts on.
class HoldPredictor : public ChannelPredictor<2> {
 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<HoldPredictor>(*this); }
  HoldPredictor(int channels, const Params& params);
  std::string name() const override { return "hold"; }
  bool extrapolates() const override { return false; }

 protected:
  Mat<2> transition(int, double) const override { return Mat<2>::Identity(); }
  Mat<2> processNoise(int, double) const override { return Mat<2>::Zero(); }
  void step(int c, double dt, double z) override;
};

/// `kf-cv`: constant-velocity Kalman filter per channel, x = [p, v],
/// F = [[1, T], [0, 1]], Q = q [[T^3/3, T^2/2], [T^2/2, T]] (white acceleration, q in px^2/s^3).
/// Parameters: q (px^2/s^3, default kDefaultQCv = 1e4, raised above it while the innovations are
/// more than q_raise_ratio (default 2) times their predicted variance when q is not given and the
/// blend with hold is on; `auto`: adapted both ways from that value by covariance matching, opt-in;
/// in a closed loop, `closed_loop: 1`, whitened instead, towards the lag-one correlation
/// q_white_rho, default kDefaultQWhiteRho = 0; predictors/process_noise_adapt.h, docs/MODELS.md
/// §15), r (measurement variance px^2;
/// default `auto`: estimated from the first frames of each channel, predictors/noise_estimate.h; a
/// number fixes it), p0_vel ((px/s)^2, default 1e4), coast_tau_s (s, default 0.2: the velocity
/// decays with this time constant on frames without a measurement, channel_predictor.h),
/// shrink_sigmas (default 0 = off) / shrink_v_sigmas (default shrink_sigmas): significance weight
/// of the forecast velocity (channel_predictor.h).
class KfCvPredictor : public ChannelPredictor<2> {
 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<KfCvPredictor>(*this); }
  KfCvPredictor(int channels, const Params& params);
  std::string name() const override { return "kf-cv"; }
  std::vector<NoiseParameter> noiseParameters() const override {
    return {accelerationDensityParameter("q", q_), measurementNoiseParameter()};
  }

 protected:
  Mat<2> transition(int, double dt) const override { return cvTransition(dt); }
  Mat<2> processNoise(int c, double dt) const override { return cvProcessNoise(q_ * processNoiseScale(c), dt); }

 private:
  double q_;
};

/// `kf-ca`: constant-acceleration Kalman filter per channel, x = [p, v, a],
/// F = [[1, T, T^2/2], [0, 1, T], [0, 0, 1]], white-jerk Q of density q (px^2/s^5).
/// Parameters: q (px^2/s^5, default kDefaultQCa = 3e5, raised as kf-cv's; or `auto` as kf-cv;
/// q_raise_ratio as kf-cv; in a closed loop whitened towards q_white_rho, default
/// kDefaultQWhiteRhoAcceleration = 0.2: process_noise_adapt.h, "The whitening's target"), r (px^2, default
/// `auto` as kf-cv), p0_vel ((px/s)^2, 1e4), p0_acc ((px/s^2)^2, 1e4), coast_tau_s (s, 0.2, as
/// kf-cv; the acceleration decays twice as fast), shrink_sigmas (n of the acceleration weight of
/// the forecast, default kDefaultShrinkSigmasKfCa = 2; 0 = the unweighted filter),
/// shrink_v_sigmas (n of the velocity weight, default shrink_sigmas; channel_predictor.h).
class KfCaPredictor : public ChannelPredictor<3> {
 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<KfCaPredictor>(*this); }
  KfCaPredictor(int channels, const Params& params);
  std::string name() const override { return "kf-ca"; }
  std::vector<NoiseParameter> noiseParameters() const override {
    return {jerkDensityParameter("q", q_), measurementNoiseParameter()};
  }

 protected:
  Mat<3> transition(int, double dt) const override { return caTransition(dt); }
  Mat<3> processNoise(int c, double dt) const override { return caProcessNoise(q_ * processNoiseScale(c), dt); }

 private:
  double q_;
};

}  // namespace predvs
