#include "predvs/servo/lost_feature_policy.h"

#include "predvs/predictors/named_enum.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Slack on the timeout comparison (s): acquisition times are sums of frame periods, so 10 frames
/// of 0.1 s may differ from 1.0 by a few ulps; the policy must engage at exactly timeout_s.
constexpr double kTimeSlackS = 1e-9;

constexpr EnumName<LostAction> kLostActions[] = {
    {LostAction::Hold, "hold"}, {LostAction::Drop, "drop"}, {LostAction::Extrapolate, "extrapolate"}};

}  // namespace

LostAction parseLostAction(const std::string& name) { return enumFromName(kLostActions, "lost.action", name); }
std::string lostActionName(LostAction action) { return enumToName(kLostActions, action); }

void validateLostFeatureConfig(const LostFeatureConfig& config) {
  if (!(config.timeout_s > 0.0) || !std::isfinite(config.timeout_s)) {
    std::ostringstream msg;
    msg << "lost.timeout_s must be > 0, got " << config.timeout_s;
    throw std::invalid_argument(msg.str());
  }
}

LostFeatureTracker::LostFeatureTracker(const LostFeatureConfig& config, int channels)
    : config_(config),
      last_value_(Eigen::VectorXd::Constant(channels, kNaN)),
      last_seen_s_(Eigen::VectorXd::Constant(channels, kNaN)),
      expired_(static_cast<size_t>(channels), false) {
  validateLostFeatureConfig(config);
}

bool LostFeatureTracker::observe(double t_acq_s, const Eigen::VectorXd& fed) {
  const int n = channels();
  bool all_expired = n > 0, any_measured = false;
  for (int c = 0; c < n; ++c) {
    all_expired = all_expired && expired_[static_cast<size_t>(c)];
    any_measured = any_measured || std::isfinite(fed(c));
  }
  const bool reset = config_.active() && all_expired && any_measured;
  for (int c = 0; c < n; ++c) {
    if (std::isfinite(fed(c))) {
      last_value_(c) = fed(c);
      last_seen_s_(c) = t_acq_s;
      expired_[static_cast<size_t>(c)] = false;
    } else {
      // NaN last_seen (never measured) compares false: not expired.
      expired_[static_cast<size_t>(c)] =
          config_.active() && t_acq_s - last_seen_s_(c) >= config_.timeout_s - kTimeSlackS;
    }
  }
  return reset;
}

bool LostFeatureTracker::anyExpired() const {
  for (bool e : expired_)
    if (e) return true;
  return false;
}

}  // namespace predvs
