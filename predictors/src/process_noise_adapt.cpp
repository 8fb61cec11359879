#include "predvs/predictors/process_noise_adapt.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace predvs {

bool isAutoProcessNoise(const Params& params, const std::string& key) {
  if (!params.texts().count(key)) return false;
  const std::string word = params.text(key, "auto");
  if (word != "auto")
    throw std::invalid_argument("parameter '" + key + "' expects a number or 'auto', got '" + word + "'");
  return true;
}

double processNoiseParam(const Params& params, const std::string& key, double fallback, double lo, double hi) {
  if (isAutoProcessNoise(params, key)) return fallback;
  return params.get(key, fallback, lo, hi);
}

ProcessNoiseMatcher::ProcessNoiseMatcher(double tau_s, double scale_min, double scale_max)
    : tau_s_(tau_s), log_min_(std::log(scale_min)), log_max_(std::log(scale_max)) {
  if (!(tau_s_ > 0.0) || !(scale_min > 0.0) || !(scale_min <= 1.0 && 1.0 <= scale_max))
    throw std::invalid_argument("process-noise adaptation: need tau_s > 0 and scale_min <= 1 <= scale_max");
}

void ProcessNoiseMatcher::observe(double eps, double S, double dt_s) {
  if (!(S > 0.0) || !(dt_s > 0.0) || !std::isfinite(eps)) return;
  const double ratio = std::min(eps * eps / S, kQAutoRatioMax);
  log_scale_ = std::clamp(log_scale_ + dt_s / tau_s_ * (ratio - 1.0), log_min_, log_max_);
}

double ProcessNoiseMatcher::scale() const { return std::exp(log_scale_); }

}  // namespace predvs
