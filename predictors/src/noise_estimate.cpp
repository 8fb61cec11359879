#include "predvs/predictors/noise_estimate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace predvs {

bool isAutoMeasurementNoise(const Params& params) {
  if (params.values().count("r")) return false;
  if (!params.texts().count("r")) return true;
  const std::string word = params.text("r", "auto");
  if (word != "auto") throw std::invalid_argument("parameter 'r' expects a number (px^2) or 'auto', got '" + word + "'");
  return true;
}

double measurementNoiseParam(const Params& params, double prior, double lo, double hi) {
  return isAutoMeasurementNoise(params) ? prior : params.get("r", prior, lo, hi);
}

StartupNoiseEstimator::StartupNoiseEstimator(double prior_px2, int count, int min_count, double floor_px2)
    : prior_(prior_px2), floor_(floor_px2), count_(count), min_count_(min_count), variance_(prior_px2) {
  if (!(prior_px2 > 0.0) || count < 1 || min_count < 1 || min_count > count || !(floor_px2 > 0.0))
    throw std::invalid_argument("noise estimator: need prior > 0, 1 <= min_count <= count, floor > 0");
  d3_.reserve(static_cast<size_t>(count));
}

void StartupNoiseEstimator::reset() {
  run_ = 0;
  d3_.clear();
  variance_ = prior_;
}

void StartupNoiseEstimator::push(double t_s, double z) {
  if (done()) return;
  if (!std::isfinite(z)) {
    run_ = 0;
    return;
  }
  if (run_ >= 2) {
    const double dt_prev = t_[run_ - 1] - t_[run_ - 2];
    const double dt = t_s - t_[run_ - 1];
    if (!(std::abs(dt - dt_prev) <= 0.1 * dt_prev)) {  // irregular period: start a new run
      t_[0] = t_[run_ - 1];
      z_[0] = z_[run_ - 1];
      run_ = 1;
    }
  }
  if (run_ == 4) {
    for (int i = 0; i < 3; ++i) {
      t_[i] = t_[i + 1];
      z_[i] = z_[i + 1];
    }
    run_ = 3;
  }
  t_[run_] = t_s;
  z_[run_] = z;
  ++run_;
  if (run_ < 4) return;
  d3_.push_back(z_[3] - 3.0 * z_[2] + 3.0 * z_[1] - z_[0]);
  if (static_cast<int>(d3_.size()) < min_count_) return;
  std::vector<double> a(d3_.size());
  for (size_t i = 0; i < d3_.size(); ++i) a[i] = std::abs(d3_[i]);
  const size_t mid = a.size() / 2;
  std::nth_element(a.begin(), a.begin() + static_cast<long>(mid), a.end());
  double med = a[mid];
  if (a.size() % 2 == 0) med = 0.5 * (med + *std::max_element(a.begin(), a.begin() + static_cast<long>(mid)));
  // Robust scale of d3 from the median, then the mean square of the d3 within 3 of those scales
  // (a manoeuvre's few large d3 are left out), corrected for the truncation: for a Gaussian,
  // E[X^2 | |X| < 3 s] = 0.97334 s^2.
  const double s = 1.4826 * med;
  double sum = 0.0;
  int n = 0;
  for (double d : d3_)
    if (std::abs(d) <= 3.0 * s) {
      sum += d * d;
      ++n;
    }
  const double var_d3 = n > 0 && s > 0.0 ? sum / n / 0.97334 : s * s;
  variance_ = std::max(floor_, var_d3 / 20.0);
}

}  // namespace predvs
