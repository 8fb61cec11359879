// Test helper: how far a predictor's forecasts run through a gap on a noise-free 1-channel track
// (tests/predictors/coast_stop_test.cpp, coast_fast_test.cpp).
#pragma once

#include "predvs/predictors/registry.h"

#include <Eigen/Dense>

#include <cmath>
#include <string>

namespace predvs {

/// Sum of squared forecast errors (px^2) of `name` (its defaults overridden by `params`), 2 frames
/// ahead, over a gap of `gap_s` seconds on the noise-free 1-channel track `truth(t)` [px] sampled at
/// `rate_hz`: measured up to and including the frame nearest `last_measured_s`, then missing; the
/// forecasts made on the missing frames are scored against the truth 2 frames later.
template <class Truth>
double gapSquaredError(const std::string& name, const Params& params, const Truth& truth, double rate_hz,
                       double last_measured_s, double gap_s) {
  auto p = makePredictor(name, 1, params);
  const double dt = 1.0 / rate_hz;
  const int gap_begin = static_cast<int>(std::lround(last_measured_s * rate_hz)) + 1;
  const int gap_end = gap_begin + static_cast<int>(std::lround(gap_s * rate_hz));
  double sse = 0.0;
  Eigen::VectorXd z(1);
  for (int k = 0; k < gap_end; ++k) {
    const double t = k * dt;
    z(0) = k < gap_begin ? truth(t) : std::nan("");
    p->update(t, z);
    if (k >= gap_begin) sse += std::pow(p->predictPosition(0, t + 2 * dt) - truth(t + 2 * dt), 2);
  }
  return sse;
}

}  // namespace predvs
