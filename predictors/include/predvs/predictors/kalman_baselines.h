// predvs — the baselines every adaptive predictor is compared with (METHODS §1).
#pragma once

#include "predvs/predictors/channel_predictor.h"

namespace predvs {

/// `hold`: the no-prediction baseline. The estimate at any time is the last measurement
/// (zero velocity), which is what a servo loop without a predictor acts on.
class HoldPredictor : public ChannelPredictor<2> {
 public:
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
/// Parameters: q (default 100), r (measurement variance px^2, default 1), p0_vel (default 1e4).
class KfCvPredictor : public ChannelPredictor<2> {
 public:
  KfCvPredictor(int channels, const Params& params);
  std::string name() const override { return "kf-cv"; }

 protected:
  Mat<2> transition(int, double dt) const override { return cvTransition(dt); }
  Mat<2> processNoise(int, double dt) const override { return cvProcessNoise(q_, dt); }

 private:
  double q_;
};

/// `kf-ca`: constant-acceleration Kalman filter per channel, x = [p, v, a],
/// F = [[1, T, T^2/2], [0, 1, T], [0, 0, 1]], white-jerk Q of density q (px^2/s^5).
/// Parameters: q (default 1000), r (default 1), p0_vel (1e4), p0_acc (1e4).
class KfCaPredictor : public ChannelPredictor<3> {
 public:
  KfCaPredictor(int channels, const Params& params);
  std::string name() const override { return "kf-ca"; }

 protected:
  Mat<3> transition(int, double dt) const override { return caTransition(dt); }
  Mat<3> processNoise(int, double dt) const override { return caProcessNoise(q_, dt); }

 private:
  double q_;
};

}  // namespace predvs
