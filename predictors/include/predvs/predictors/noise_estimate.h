// predvs — measurement-noise variance estimated from a channel's first frames (the default R of
// the predictors whose `r` is not given; issue 11 "defaults that hold").
//
// No motion model is needed: the third difference of four consecutive, equally spaced
// measurements,
//   d3(k) = z(k) - 3 z(k-1) + 3 z(k-2) - z(k-3),
// removes any constant-acceleration motion exactly, and for white noise of variance sigma^2 it has
// variance (1 + 9 + 9 + 1) sigma^2 = 20 sigma^2. Manoeuvres (a jerk spike at a hard stop, a turn)
// leave a few large d3. A robust scale s = 1.4826 median|d3| (the std of a Gaussian) first sets
// them apart, then the mean square of the d3 with |d3| <= 3 s, corrected for that truncation
// (/ 0.97334), gives var(d3), and sigma^2 = var(d3) / 20. (The median alone is too inefficient
// here: consecutive d3 share three samples, corr -0.75, and 20 of them spread the median estimate
// by a factor 0.8..2.4.) The differences used: the first `count`, default 50, i.e. 53 frames
// (0.9 s at 60 Hz, 5.3 s at 10 Hz): with 20 the estimate spread by x0.4..2 over seeds (23
// frames of noise hold little information, and consecutive d3 overlap), with 50 by about +-30 %. A gap (no measurement) or a change of frame period (> 10 %) restarts the run of
// consecutive samples, never the collected differences. Until `min_count` (5) differences exist
// the prior (the predictor's nominal 1 px^2) is used; between min_count and count the running
// estimate is used; after count the estimate is frozen (the filter's R is then constant). The
// estimate is floored at floor_px2 (0.01 px^2: no feature tracker resolves better than 0.1 px, and
// a noise-free simulation must not give R = 0).
#pragma once

#include "predvs/predictors/params.h"

#include <vector>

namespace predvs {

/// True when a predictor's measurement variance `r` is to be estimated by StartupNoiseEstimator:
/// the key is absent or holds the word `auto`. False when it holds a number (read it with get()).
bool isAutoMeasurementNoise(const Params& params);
/// The number given for `r` (checked against [lo, hi], naming the key), or `prior` when `r` is
/// absent or `auto` (the estimator's prior).
double measurementNoiseParam(const Params& params, double prior, double lo = 1e-12, double hi = 1e12);

class StartupNoiseEstimator {
 public:
  explicit StartupNoiseEstimator(double prior_px2 = 1.0, int count = 50, int min_count = 5, double floor_px2 = 0.01);
  void reset();
  /// Feeds one measurement at t_s (NaN: not measured, ends the run of consecutive samples).
  void push(double t_s, double z);
  /// The variance to use now (px^2).
  double variance() const { return variance_; }
  /// True once `count` differences have been collected (the estimate is frozen).
  bool done() const { return static_cast<int>(d3_.size()) >= count_; }

 private:
  double prior_, floor_;
  int count_, min_count_;
  double t_[4] = {0, 0, 0, 0};
  double z_[4] = {0, 0, 0, 0};
  int run_ = 0;  ///< consecutive equally spaced samples in t_/z_ (at most 4)
  std::vector<double> d3_;
  double variance_;
};

}  // namespace predvs
