#include "predvs/predictors/process_noise_adapt.h"

#include "predvs/predictors/predictor.h"

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

double processNoiseRaiseRatio(const Params& params) {
  const double c = params.get("q_raise_ratio", kDefaultQRaiseRatio, 0.0, kQAutoRatioMax);
  if (c > 0.0 && c < 1.0)
    throw std::invalid_argument("parameter 'q_raise_ratio' expects 0 (no raise) or a ratio from 1 to " +
                                std::to_string(static_cast<int>(kQAutoRatioMax)));
  return c;
}

double processNoiseWhiteRho(const Params& params, double fallback) {
  return params.get("q_white_rho", fallback, -kQWhiteRhoMax, kQWhiteRhoMax);
}

std::optional<ProcessNoiseMatcher> processNoiseRaise(const Params& params, std::initializer_list<const char*> fixing_keys,
                                                     bool blend_on, InnovationStatistic in_closed_loop, double white_rho) {
  const double ratio = processNoiseRaiseRatio(params);
  const double rho = processNoiseWhiteRho(params, white_rho);
  const bool closed_loop = closedLoopParam(params);
  for (const char* key : fixing_keys)
    if (params.has(key)) return std::nullopt;
  if (closed_loop)
    return in_closed_loop == InnovationStatistic::Whiteness ? ProcessNoiseMatcher::whitening(rho) : ProcessNoiseMatcher();
  if (!blend_on || !(ratio > 0.0)) return std::nullopt;
  return ProcessNoiseMatcher::raise(ratio);
}

ProcessNoiseMatcher::ProcessNoiseMatcher(double tau_s, double scale_min, double scale_max, double target)
    : tau_s_(tau_s), log_min_(std::log(scale_min)), log_max_(std::log(scale_max)), target_(target) {
  if (!(tau_s_ > 0.0) || !(scale_min > 0.0) || !(scale_min <= 1.0 && 1.0 <= scale_max) || !(target > 0.0))
    throw std::invalid_argument("process-noise adaptation: need tau_s > 0, scale_min <= 1 <= scale_max and target > 0");
}

ProcessNoiseMatcher ProcessNoiseMatcher::whitening(double rho) {
  ProcessNoiseMatcher m(kDefaultQWhitenTauS);
  m.statistic_ = InnovationStatistic::Whiteness;
  m.target_ = rho;
  return m;
}

void ProcessNoiseMatcher::observe(double eps, double S, double dt_s) {
  if (!(S > 0.0) || !(dt_s > 0.0) || !std::isfinite(eps)) return;
  double step;
  if (statistic_ == InnovationStatistic::Whiteness) {
    const double e = eps / std::sqrt(S);
    const bool first = !have_last_e_;
    step = std::clamp(last_e_ * e, -kQWhitenStepMax, kQWhitenStepMax) - target_;
    last_e_ = e;
    have_last_e_ = true;
    if (first) return;
  } else {
    step = std::min(eps * eps / S, kQAutoRatioMax) - target_;
  }
  const double l = std::clamp(log_scale_ + dt_s / tau_s_ * step, log_min_, log_max_);
  if (l != log_scale_) {
    log_scale_ = l;
    scale_ = std::exp(l);
  }
}

}  // namespace predvs
