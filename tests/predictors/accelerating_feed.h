// predvs tests — the accelerating-target feed on which the significance-weighted forecast is
// checked (tests/predictors/forecast_weighting_test.cpp, cs_akf_test.cpp): 1 s at 10 Hz (11 frames,
// t = 0, 0.1, ..., 1 s) of one channel z(t) = 20 t + 50 t^2 / 2 px (20 px/s, 50 px/s^2), plus
// Gaussian noise of noise_px standard deviation (std::mt19937 seeded with `seed`; none at 0). At
// 3 px the velocity and acceleration are not many standard deviations from zero after 1 s, the
// corner where the weights act.
#pragma once

#include <Eigen/Core>

#include <random>

namespace predvs {

/// Time step (s) of the feed: 10 Hz.
inline constexpr double kAcceleratingFeedStepS = 0.1;

/// Feeds the 11 frames above to `f` (any predictor with update(t_s, z)).
template <class F>
void feedAcceleratingTarget(F& f, unsigned seed, double noise_px = 3.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_px > 0.0 ? noise_px : 1.0);
  Eigen::VectorXd z(1);
  for (int k = 0; k <= 10; ++k) {
    const double t = kAcceleratingFeedStepS * k;
    z << 20.0 * t + 0.5 * 50.0 * t * t + (noise_px > 0.0 ? noise(rng) : 0.0);
    f.update(t, z);
  }
}

}  // namespace predvs
