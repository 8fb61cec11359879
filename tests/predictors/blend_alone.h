// Test helper: the parameters of a filter with the blend with hold alone (hold_blend_test.cpp,
// period_cache_test.cpp).
#pragma once

#include "predvs/predictors/predictor.h"

#include <initializer_list>

namespace predvs {

/// The blend with hold with forgetting time tau_s, and `extra`: the coasting rules that come with
/// the blend (the shorter coast of a gap after a stop, coast_stop_test.cpp; the speed rule and the
/// shape of the coast, coast_fast_test.cpp; measurements falling behind, coast_lag_test.cpp; the turn
/// share at a zero crossing, coast_crossing_test.cpp) and the
/// raise of q are off, as they change the filter, not only the forecast, so its filter stays a
/// twin's without the blend; and the start-up prior (hold_blend_prior, blend_start_test.cpp) is
/// off, so the weights are the regressions' own.
inline Params blendAlone(double tau_s, const Params& extra) {
  Params p{{"hold_blend_tau_s", tau_s}, {"coast_stop_fraction", 0.0}, {"coast_fast_ratio", 0.0},
           {"coast_lag_sigmas", 0.0},   {"coast_shape", 1.0},          {"q_raise_ratio", 0.0},
           {"hold_blend_prior", 0.0},   {"coast_crossing", 0.0}};
  p.setAll(extra);
  return p;
}

/// Frame k of the blend tests' noise-free ramp, 5 px + 80 px/s sampled at rate_hz, fed to each of
/// `predictors` (one channel); returns the measurement.
inline double feedRamp(int k, double rate_hz, std::initializer_list<Predictor*> predictors) {
  const double t = k / rate_hz;
  Eigen::VectorXd z(1);
  z(0) = 5.0 + 80.0 * t;
  for (Predictor* p : predictors) p->update(t, z);
  return z(0);
}

}  // namespace predvs
