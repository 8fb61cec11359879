#include "predvs/servo/metrics.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

// Noise floor of the settling band, in standard deviations of e over the final window: a noisy
// error whose excursion is small would otherwise "leave" a narrow band at its last sample.
constexpr double kSettlingNoiseSigmas = 3.0;

void requireFraction(const char* key, double v) {
  if (!(v > 0.0 && v < 1.0)) {
    std::ostringstream msg;
    msg << "metrics." << key << " must be in (0, 1), got " << v;
    throw std::invalid_argument(msg.str());
  }
}

/// Trailing mean of x over `window_s` (0: x itself); NaN where x is NaN.
std::vector<double> trailingMean(const std::vector<double>& t_s, const std::vector<double>& x, double window_s) {
  const size_t n = t_s.size();
  std::vector<double> smooth(n, std::nan(""));
  double sum = 0.0;
  int count = 0;
  size_t first = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!std::isnan(x[i])) {
      sum += x[i];
      ++count;
    }
    while (first < i && t_s[first] <= t_s[i] - window_s) {
      if (!std::isnan(x[first])) {
        sum -= x[first];
        --count;
      }
      ++first;
    }
    if (count > 0 && !std::isnan(x[i])) smooth[i] = sum / count;
  }
  return smooth;
}

}  // namespace

Metrics computeMetrics(const std::vector<double>& t_s, const std::vector<double>& error,
                       const MetricsOptions& options, const std::vector<Eigen::VectorXd>* velocity) {
  requireFraction("steady_start_fraction", options.steady_start_fraction);
  requireFraction("final_fraction", options.final_fraction);
  requireFraction("settling_band", options.settling_band);
  if (!(options.settling_smoothing_s >= 0.0)) {
    std::ostringstream msg;
    msg << "metrics.settling_smoothing_s must be >= 0, got " << options.settling_smoothing_s;
    throw std::invalid_argument(msg.str());
  }
  if (!(options.response_window_s > 0.0) || !std::isfinite(options.response_window_s)) {
    std::ostringstream msg;
    msg << "metrics.response_window_s must be > 0 (s), got " << options.response_window_s;
    throw std::invalid_argument(msg.str());
  }
  if (t_s.size() != error.size())
    throw std::invalid_argument("metrics: " + std::to_string(t_s.size()) + " times but " +
                                std::to_string(error.size()) + " errors");
  if (velocity && velocity->size() != t_s.size())
    throw std::invalid_argument("metrics: " + std::to_string(velocity->size()) + " velocities for " +
                                std::to_string(t_s.size()) + " samples");
  Metrics m;
  const size_t n = t_s.size();
  if (n == 0) return m;
  const double t0 = t_s.front();
  const double t1 = t_s.back();
  const double span = t1 - t0;
  const double t_steady = t0 + options.steady_start_fraction * span;
  const double t_final = t0 + (1.0 - options.final_fraction) * span;
  // Step of sample i: to the next sample; the last one reuses the previous step.
  auto step = [&](size_t i) {
    if (n < 2) return 0.0;
    return i + 1 < n ? t_s[i + 1] - t_s[i] : t_s[i] - t_s[i - 1];
  };

  double sum2 = 0.0, sum_final = 0.0, iae = 0.0, steady_max = 0.0, peak = 0.0;
  int n_steady = 0, n_final = 0;
  bool any = false;
  for (size_t i = 0; i < n; ++i) {
    const double e = error[i];
    if (std::isnan(e)) continue;
    any = true;
    iae += std::abs(e) * step(i);
    peak = std::max(peak, e);
    if (t_s[i] >= t_steady) {
      sum2 += e * e;
      steady_max = std::max(steady_max, e);
      ++n_steady;
    }
    if (t_s[i] >= t_final) {
      sum_final += e;
      ++n_final;
    }
  }
  if (!any) return m;
  m.iae = iae;
  m.peak_error = peak;
  m.steady_samples = n_steady;
  if (n_steady > 0) {
    m.rmse = std::sqrt(sum2 / n_steady);
    m.max_error = steady_max;
  }
  if (n_final > 0) m.final_error = sum_final / n_final;
  if (n_final > 0) {
    // Settling is judged on a trailing mean of e over settling_smoothing_s (0: raw e), so that
    // measurement noise does not decide it.
    const std::vector<double> smooth = trailingMean(t_s, error, options.settling_smoothing_s);
    double peak_s = 0.0, mean_final = 0.0, var_final = 0.0;
    int n_sf = 0;
    for (size_t i = 0; i < n; ++i) {
      if (std::isnan(smooth[i])) continue;
      peak_s = std::max(peak_s, smooth[i]);
      if (t_s[i] >= t_final) {
        mean_final += smooth[i];
        ++n_sf;
      }
    }
    mean_final /= std::max(n_sf, 1);
    for (size_t i = 0; i < n; ++i)
      if (!std::isnan(smooth[i]) && t_s[i] >= t_final) var_final += (smooth[i] - mean_final) * (smooth[i] - mean_final);
    const double sd_final = std::sqrt(var_final / std::max(n_sf, 1));
    const double band = mean_final + std::max(options.settling_band * (peak_s - mean_final), kSettlingNoiseSigmas * sd_final);
    // Walk back from the end: the settling time is the sample after the last one above the band.
    m.settling_time_s = 0.0;
    for (size_t i = n; i-- > 0;) {
      if (std::isnan(smooth[i])) continue;
      if (smooth[i] > band) {
        m.settling_time_s = i + 1 < n ? t_s[i + 1] - t0 : std::nan("");
        break;
      }
    }
  }

  if (velocity) {
    double effort = 0.0;
    for (size_t i = 0; i < n; ++i) effort += (*velocity)[i].squaredNorm() * step(i);
    m.control_effort = effort;
  }
  return m;
}

ResponseMetrics computeResponse(const std::vector<double>& t_s, const std::vector<double>& error,
                                const std::vector<double>& signed_error, double t_change_s,
                                const MetricsOptions& options, double window_s) {
  if (t_s.size() != error.size() || t_s.size() != signed_error.size())
    throw std::invalid_argument("response metrics: " + std::to_string(t_s.size()) + " times, " +
                                std::to_string(error.size()) + " errors, " + std::to_string(signed_error.size()) +
                                " signed errors");
  if (!(window_s > 0.0)) throw std::invalid_argument("response metrics: window must be > 0 s");
  ResponseMetrics r;
  // From the change on only: the samples before it belong to another regime.
  const auto begin = std::lower_bound(t_s.begin(), t_s.end(), t_change_s);
  const size_t i0 = static_cast<size_t>(begin - t_s.begin());
  const std::vector<double> t(t_s.begin() + i0, t_s.end());
  const std::vector<double> e(error.begin() + i0, error.end());
  const std::vector<double> s(signed_error.begin() + i0, signed_error.end());
  const std::vector<double> ms = trailingMean(t, s, options.settling_smoothing_s);
  if (!(options.response_window_s > 0.0)) throw std::invalid_argument("response metrics: metrics.response_window_s must be > 0 s");
  double lag = 0.0, over = 0.0, sum_after = 0.0;
  int n_after = 0;
  bool any = false;
  for (size_t i = 0; i < t.size(); ++i) {
    if (std::isnan(e[i]) || std::isnan(ms[i])) continue;
    any = true;
    if (t[i] <= t_change_s + options.response_window_s) {  // lag and overshoot: the window after the change
      lag = std::max(lag, -ms[i]);
      over = std::max(over, ms[i]);
    }
    if (t[i] <= t_change_s + window_s) {
      sum_after += e[i];
      ++n_after;
    }
  }
  if (!any) return r;
  r.max_lag = lag;
  r.overshoot = over;
  r.mean_after = n_after > 0 ? sum_after / n_after : std::nan("");
  // Settling of |e| on the part of the run after the change, measured from the change.
  const Metrics after = computeMetrics(t, e, options);
  r.response_s = after.settling_time_s + (t.front() - t_change_s);
  return r;
}

}  // namespace predvs

namespace predvs {

NamedValues featureErrorValues(const std::vector<double>& t_s, const std::vector<Eigen::VectorXd>& features,
                               const Eigen::VectorXd& desired, const std::vector<std::string>& names,
                               const MetricsOptions& options) {
  const size_t n = static_cast<size_t>(desired.size());
  if (features.size() != t_s.size() || names.size() != n)
    throw std::invalid_argument("metrics: per-feature errors need one feature vector per sample and one name per feature");
  std::vector<double> sum(n, 0.0), sum2(n, 0.0), mx(n, 0.0);
  std::vector<int> count(n, 0);
  if (!t_s.empty()) {
    const double t_steady = t_s.front() + options.steady_start_fraction * (t_s.back() - t_s.front());
    for (size_t i = 0; i < t_s.size(); ++i) {
      if (t_s[i] < t_steady) continue;
      for (size_t f = 0; f < n; ++f) {
        const double e = features[i](static_cast<Eigen::Index>(f)) - desired(static_cast<Eigen::Index>(f));
        if (!std::isfinite(e)) continue;
        sum[f] += e, sum2[f] += e * e, mx[f] = std::max(mx[f], std::fabs(e)), ++count[f];
      }
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  NamedValues out;
  for (size_t f = 0; f < n; ++f) out.emplace_back("mean_e_" + names[f], count[f] ? sum[f] / count[f] : nan);
  for (size_t f = 0; f < n; ++f) out.emplace_back("rms_e_" + names[f], count[f] ? std::sqrt(sum2[f] / count[f]) : nan);
  for (size_t f = 0; f < n; ++f) out.emplace_back("max_e_" + names[f], count[f] ? mx[f] : nan);
  return out;
}

NamedValues occlusionValues(const std::vector<double>& t_s, const std::vector<double>& e, const std::vector<bool>& lost) {
  if (t_s.size() != e.size() || lost.size() != e.size())
    throw std::invalid_argument("metrics: occlusion figures need one time, error and status per sample");
  constexpr double kReacquisitionWindowS = 1.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto finiteMean = [nan](const std::vector<double>& xs) {
    double sum = 0.0;
    int n = 0;
    for (double x : xs)
      if (std::isfinite(x)) sum += x, ++n;
    return n > 0 ? sum / n : nan;
  };
  double sq = 0.0, mx = nan;
  int n = 0;
  std::vector<double> end_errors, reacq_errors, reacq_rms;
  for (size_t k = 0; k < e.size(); ++k) {
    if (lost[k]) {
      if (std::isfinite(e[k])) {
        sq += e[k] * e[k];
        ++n;
        mx = std::isfinite(mx) ? std::max(mx, e[k]) : e[k];
      }
      continue;
    }
    if (k > 0 && lost[k - 1]) {  // first tick after a frame is delivered again
      end_errors.push_back(e[k - 1]);
      reacq_errors.push_back(e[k]);
      double s2 = 0.0;
      int m = 0;
      for (size_t j = k; j < e.size() && t_s[j] < t_s[k] + kReacquisitionWindowS; ++j)
        if (std::isfinite(e[j])) s2 += e[j] * e[j], ++m;
      reacq_rms.push_back(m > 0 ? std::sqrt(s2 / m) : nan);
    }
  }
  return {{"occl_rmse", n > 0 ? std::sqrt(sq / n) : nan},
          {"occl_max", mx},
          {"occl_end_error", finiteMean(end_errors)},
          {"reacq_error", finiteMean(reacq_errors)},
          {"reacq_1s_rmse", finiteMean(reacq_rms)}};
}

Outcome computeOutcome(const std::vector<double>& t_s, const std::vector<double>& error, FailureKind failure,
                       double failure_time_s, const MetricsOptions& options) {
  if (!(options.converge_px > 0.0) || !std::isfinite(options.converge_px)) {
    std::ostringstream msg;
    msg << "metrics.converge_px must be > 0, got " << options.converge_px;
    throw std::invalid_argument(msg.str());
  }
  if (!(options.converge_hold_s >= 0.0) || !std::isfinite(options.converge_hold_s)) {
    std::ostringstream msg;
    msg << "metrics.converge_hold_s must be >= 0, got " << options.converge_hold_s;
    throw std::invalid_argument(msg.str());
  }
  if (t_s.size() != error.size())
    throw std::invalid_argument("metrics: " + std::to_string(t_s.size()) + " times but " +
                                std::to_string(error.size()) + " errors");
  Outcome o;
  if (failure != FailureKind::None) {
    o.failure = failure;
    o.failure_time_s = failure_time_s;
    return o;
  }
  // The final stretch at or below the threshold: walk back from the last sample.
  size_t first_below = t_s.size();
  while (first_below > 0 && error[first_below - 1] <= options.converge_px) --first_below;  // NaN stops it
  if (first_below == t_s.size()) return o;  // ends above (or no samples)
  if (t_s.back() - t_s[first_below] < options.converge_hold_s) return o;
  o.converged = true;
  o.convergence_time_s = t_s[first_below] - t_s.front();
  return o;
}

NamedValues outcomeValues(const Outcome& o) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto is = [&](FailureKind k) { return o.failure == k ? 1.0 : 0.0; };
  return {{"converged", o.converged ? 1.0 : 0.0},
          {"convergence_time_s", o.converged ? o.convergence_time_s : nan},
          {"failed", o.failed() ? 1.0 : 0.0},
          {"failure_time_s", o.failed() ? o.failure_time_s : nan},
          {"fail_behind", is(FailureKind::Behind)},
          {"fail_image", is(FailureKind::OutsideImage)},
          {"fail_robot", is(FailureKind::RobotLimit)}};
}

Metrics withoutSteadyState(Metrics m) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.rmse = m.final_error = m.max_error = m.settling_time_s = nan;
  return m;
}

NamedValues metricValues(const Metrics& m) {
  return {{"rmse", m.rmse},       {"final", m.final_error},          {"max", m.max_error},     {"peak", m.peak_error},
          {"iae", m.iae},         {"settling_s", m.settling_time_s}, {"effort", m.control_effort}};
}

}  // namespace predvs

namespace predvs {

std::pair<std::string, double> lostPolicyValue(const std::vector<bool>& expired, double period_s) {
  double n = 0.0;
  for (bool e : expired) n += e ? 1.0 : 0.0;
  return {"lost_policy_s", n * period_s};
}

}  // namespace predvs
