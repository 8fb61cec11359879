#include "predvs/predictors/monitor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace predvs {

DiscontinuityMonitor::DiscontinuityMonitor(const MonitorConfig& config) : config_(config) {
  if (config_.window < 2) throw std::invalid_argument("discontinuity monitor: window must be >= 2");
  if (!(config_.band_factor > 0.0) || !(config_.chi2_threshold > 0.0) || !(config_.band_floor >= 0.0) ||
      !(config_.centre_gain > 0.0 && config_.centre_gain <= 1.0) || config_.warmup < 0)
    throw std::invalid_argument(
        "discontinuity monitor: need band_factor > 0, chi2_threshold > 0, band_floor >= 0, 0 < centre_gain <= 1, "
        "warmup >= 0");
  history_.assign(static_cast<size_t>(config_.window), 0.0);
  prefix_.assign(static_cast<size_t>(config_.window) + 1, 0.0);
}

void DiscontinuityMonitor::restart() {
  count_ = 0;
  head_ = 0;
  centre_ = 0.0;
  last_ratio_ = std::numeric_limits<double>::quiet_NaN();
}

void DiscontinuityMonitor::reset() {
  restart();
  alarms_ = 0;
  last_alarm_t_s_ = std::numeric_limits<double>::quiet_NaN();
}

bool DiscontinuityMonitor::observe(double t_s, double error, double variance) {
  if (!std::isfinite(error)) return false;
  bool alarm = false;
  if (config_.statistic == MonitorConfig::Statistic::kChiSquare) {
    if (count_ >= config_.warmup && variance > 0.0) {
      last_ratio_ = error * error / variance / config_.chi2_threshold;
      alarm = last_ratio_ >= 1.0;
    } else {
      last_ratio_ = std::numeric_limits<double>::quiet_NaN();
    }
    ++count_;
  } else {
    const int n = config_.window;
    if (count_ >= n) {
      // sigma_n^2 of the n previous errors (population variance about their mean, eq. 26). The sum
      // of the mean is prefix_[n]: history_[0] + ... + history_[n-1] added left to right from 0.0.
      const double mean = prefix_[static_cast<size_t>(n)] / n;
      double var = 0.0;
      for (double e : history_) var += (e - mean) * (e - mean);
      var /= n;
      const double delta = std::max(config_.band_factor * std::sqrt(var), config_.band_floor);
      last_ratio_ = std::abs(error - centre_) / delta;
      alarm = last_ratio_ >= 1.0;
    } else {
      last_ratio_ = std::numeric_limits<double>::quiet_NaN();
    }
    centre_ = count_ == 0 ? error : (1.0 - config_.centre_gain) * centre_ + config_.centre_gain * error;
    history_[static_cast<size_t>(head_)] = error;
    // The sums before head_ keep their value; those after it are added again from there, in the
    // same order (so prefix_[n] has the bits of the loop over history_, half of it on average).
    for (size_t k = static_cast<size_t>(head_); k < static_cast<size_t>(n); ++k) prefix_[k + 1] = prefix_[k] + history_[k];
    head_ = (head_ + 1) % n;
    ++count_;
  }
  if (alarm) {
    ++alarms_;
    last_alarm_t_s_ = t_s;
  }
  return alarm;
}

}  // namespace predvs
