// predvs — predictive monitor: detects discontinuities of the target motion (docs/MODELS.md §6,
// paper 004 §4).
//
// A filter tuned for smooth motion reacts slowly to a sudden start, stop or reversal. The monitor
// watches a prediction error of the filter and raises an alarm when that error leaves a band that
// adapts to the noise and to the slowly varying model error; the filter then re-initialises.
//
// Two statistics are offered:
//  * band (paper 004 eqs. 23-27): e(k) is the two-step prediction error dxp(k) = y(k) - C x(k|k-2).
//    The band half-width is delta(k) = lambda_b * sigma_n(k), sigma_n^2 the variance of the n
//    previous errors e(k-n..k-1); the band centre mu is a first-order low-pass of e,
//    mu(k) = (1-g) mu(k-1) + g e(k) with g = 0.5. Alarm when |e(k) - mu(k-1)| >= max(delta(k), floor).
//    Both the width and the centre are taken from past samples only, so a single large error
//    cannot widen its own band (the paper's sum in eq. 26 also stops at k-1).
//  * chi-square (paper 004 eq. 25): e(k) is an innovation with predicted variance S(k); alarm when
//    e^2 / S >= threshold (1 degree of freedom per channel). The caller must pass the variance the
//    filter predicted before any adaptation driven by this same innovation (an adaptive filter
//    that inflates S to fit the innovation would otherwise hide every step).
//
// The monitor needs `window` past samples (band) before it may raise an alarm; after restart()
// (the filter was re-initialised) it waits again. Counters survive restart() and are cleared by
// reset().
#pragma once

#include <limits>
#include <vector>

namespace predvs {

struct MonitorConfig {
  enum class Statistic { kBand = 0, kChiSquare = 1 };
  Statistic statistic = Statistic::kBand;
  // Defaults n = 20, lambda_b = 6: on st-akf (CA, fading) tracking a smooth noisy sinusoid at
  // 25 Hz, n = 10 / lambda_b = 4 gave 11.6 false alarms per minute, n = 20 / lambda_b = 6 gave 0.1
  // (the faded gain makes the two-step errors heavy-tailed, and sigma_n is estimated from few samples).
  int window = 20;                ///< n, number of past errors in sigma_n (band)
  double band_factor = 6.0;       ///< lambda_b (band)
  double centre_gain = 0.5;       ///< g of the centre low-pass (band; 0.5 as docs/MODELS.md §6)
  double band_floor = 1e-6;       ///< smallest band half-width, in the signal's units (band):
                                  ///< keeps a noise-free signal from alarming on round-off
  double chi2_threshold = 15.13;  ///< chi-square(1) quantile, 15.13 = false-alarm prob. 1e-4
  int warmup = 3;                 ///< chi-square: samples ignored after (re)start (filter transient)
};

class DiscontinuityMonitor {
 public:
  explicit DiscontinuityMonitor(const MonitorConfig& config = MonitorConfig{});

  /// Feeds one error sample taken at t_s. `variance` is used by the chi-square statistic only.
  /// Returns true if this sample is a discontinuity (alarm); the alarm is counted.
  bool observe(double t_s, double error, double variance = std::numeric_limits<double>::quiet_NaN());
  /// Forget the error history (after the filter was re-initialised); counters are kept.
  void restart();
  /// Forget history and counters.
  void reset();

  int alarms() const { return alarms_; }
  /// Acquisition time of the last alarm (NaN if none).
  double lastAlarmTime() const { return last_alarm_t_s_; }
  /// Value of the last statistic: |e - mu| / delta (band) or e^2/S / threshold (chi-square);
  /// an alarm is raised when it reaches 1. NaN while warming up.
  double lastRatio() const { return last_ratio_; }
  const MonitorConfig& config() const { return config_; }

 private:
  MonitorConfig config_;
  std::vector<double> history_;  // ring buffer of the last `window` errors
  std::vector<double> prefix_;   // prefix_[k] = history_[0] + ... + history_[k-1], left to right from 0.0
  int count_ = 0;                // samples since (re)start
  int head_ = 0;
  double centre_ = 0.0;
  int alarms_ = 0;
  double last_alarm_t_s_ = std::numeric_limits<double>::quiet_NaN();
  double last_ratio_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace predvs
