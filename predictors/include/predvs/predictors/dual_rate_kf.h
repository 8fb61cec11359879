// predvs — the dual-rate Kalman filter of paper 003 (§3.1, Algorithm 2; docs/MODELS.md §9): features
// measured once per frame T = N delta, estimated and predicted at the base period delta.
//
// Model per base period delta (paper eqs. 4-5), per feature channel (x, y or Z of a point):
//     [s; s_dot](t+1) = [[1, delta], [0, 1]] [s; s_dot](t) + [delta^2 / 2; delta] w(t),
//     w ~ N(0, sigma_a^2) a piecewise-constant acceleration, and a measurement s(t) + v,
//     v ~ N(0, sigma_m^2), taken only at the first tick of each frame.
// Lifted over the frame (lifting.h with the noise input sampled every tick and the measurement at
// phase 0; paper eq. 12, Algorithm 2 lines 1-3):
//     A_bar = [[1, N delta], [0, 1]],
//     B_bar = [[(2N-1) delta^2 / 2, (2N-3) delta^2 / 2, ..., delta^2 / 2], [delta, ..., delta]],
//     Q_bar = B_bar (sigma_a^2 I_N) B_bar',      C_bar = [1, 0].
// C_bar reads the position at the frame instant (lifting.h: eq. 24 as written); the paper's
// eq. 13, C_bar = [1, delta], comes from its output convention (a read one tick later).
// One frame: predict() (lines 4-5), update(s) (lines 6-8, Joseph form), and the predictions of
// line 10, s(t+i|t) = s(t|t) + i delta s_dot(t|t), answered by predictTicks(i) without changing
// the filter, for any (fractional) i, e.g. beyond the frame when frames arrive late.
//
// With diagonal Q_tilde and R_tilde (per-channel sigmas) the 6n-state filter of Algorithm 2 is
// block diagonal: it is exactly 3n independent 2-state filters, run here on fixed-size 2x2
// matrices. Initialisation (Algorithm 1 lines 1-4): the first measurement of a channel sets
// s = z, s_dot = 0, P = diag(sigma_m^2, sigma_v0^2).
#pragma once

#include "predvs/predictors/kalman_math.h"
#include "predvs/predictors/lifting.h"

#include <Eigen/Core>

#include <vector>

namespace predvs {

struct DualRateKfConfig {
  double base_period_s = 0.01;    ///< delta (> 0)
  int frame_ticks = 8;            ///< N (>= 1)
  Eigen::VectorXd accel_std;      ///< sigma_a per channel (units/s^2, >= 0)
  Eigen::VectorXd measurement_std;  ///< sigma_m per channel (units, > 0)
  Eigen::VectorXd initial_velocity_std;  ///< sigma_v0 per channel (units/s, > 0)
};

class DualRateKf {
 public:
  /// Throws std::invalid_argument for a non-positive delta, N < 1, or per-channel vectors of
  /// different sizes or out of range.
  explicit DualRateKf(const DualRateKfConfig& config);

  int channels() const { return static_cast<int>(channels_.size()); }
  const DualRateKfConfig& config() const { return config_; }
  /// Every channel uninitialised.
  void reset();
  /// True once every channel has had a measurement.
  bool initialised() const;

  /// Lifted time update over one frame (Algorithm 2 lines 4-5); a no-op on an uninitialised
  /// channel. A frame without a measurement is predict() alone.
  void predict();
  /// Measurement update at the frame instant (lines 6-8, Joseph form); a NaN entry leaves its
  /// channel unmeasured; an uninitialised channel is initialised at its measurement.
  void update(const Eigen::VectorXd& s);

  /// s(t+i|t) = s(t|t) + i delta s_dot(t|t) for every channel (Algorithm 2 line 10), const; NaN on
  /// an uninitialised channel.
  Eigen::VectorXd predictTicks(double i) const;
  Eigen::VectorXd positions() const { return predictTicks(0.0); }
  Eigen::VectorXd velocities() const;
  /// State [s, s_dot] and covariance of one channel.
  const Gaussian<2>& channel(int c) const { return channels_.at(static_cast<size_t>(c)); }

  /// The lifted model (Algorithm 2 lines 1-3) of the scalar channel: A_bar, B_bar, C_bar.
  const LiftedSystem& lifted() const { return lifted_; }
  /// The lifted process noise B_bar Q_bar B_bar' of channel c.
  const Mat<2>& liftedProcessNoise(int c) const { return Q_bar_.at(static_cast<size_t>(c)); }

 private:
  DualRateKfConfig config_;
  LiftedSystem lifted_;
  Mat<2> A_bar_;
  std::vector<Mat<2>> Q_bar_;
  std::vector<Gaussian<2>> channels_;
  std::vector<bool> initialised_;
};

}  // namespace predvs
