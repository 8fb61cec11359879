// predvs — what the loop does with a feature that stays lost (scenario key `lost`, issue 9 item 2).
//
// A predictor fed no measurement runs predict-only: it extrapolates. Over a short gap that is what
// prediction is for; over a long one the extrapolation of a manoeuvring target drifts away (E7:
// kf-cv 32 px and st-akf 794 px after 3 s, against 9.7 px for holding the last position). The
// policy bounds the extrapolation, per channel, in the loop (not in each predictor):
//
//   lost_for(c) = t_acq(latest delivered frame) - t_acq(last frame that measured channel c)
//   expired(c)  = lost_for(c) >= timeout_s            (both acquisition times, seconds; a channel
//                                                       never measured is not expired: it has no
//                                                       last value)
//
// While a channel is expired the loop no longer uses the predictor's output for it; `action`
// (lost.action) says what it uses instead:
//   hold         the last value the predictor was fed for that channel, velocity 0: the target is
//                assumed to stand where it was last seen (in the closed loop with ego-motion
//                compensation the held value is the compensated one, so the camera's own motion
//                since is still accounted for; servo_loop.h);
//   drop         closed loop only: the task runs without that feature (NaN in TaskInput::used),
//                which needs a law that can (Task::canDropFeatures(); the loop refuses the
//                configuration otherwise, naming lost.action); the open-loop experiment has no
//                task to drop rows from and refuses it too;
//   extrapolate  the policy off: the predictor's extrapolation is used however long the gap (the
//                behaviour before this policy existed).
// Default: hold after 1 s (the "about 1 s": 10 frames at E7's 10 Hz, where E7's kf-cv has
// drifted about 3 px).
//
// Re-acquisition: a measured channel stops being expired at once and the predictor's output is
// used again. If *every* channel had expired (the whole target lost for longer than timeout_s),
// the predictor is reset() before that frame is fused, so it restarts from the new measurement as
// on the first frame: the stale velocity and the adaptive terms (fading factors, adapted
// variances) from before the gap are thrown away. When only some channels expired there is no
// reset (Predictor has no per-channel reset, and the other channels' estimates are good); their
// covariance has grown through the gap, so the first update pulls the position to the measurement.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace predvs {

/// lost.action: hold | drop | extrapolate.
enum class LostAction { Hold, Drop, Extrapolate };
LostAction parseLostAction(const std::string& name);  ///< throws naming lost.action
std::string lostActionName(LostAction action);

/// Scenario key `lost: {timeout_s: 1.0, action: hold}` (both kinds of scenario).
struct LostFeatureConfig {
  double timeout_s = 1.0;                ///< lost.timeout_s, > 0, compared with acquisition times
  LostAction action = LostAction::Hold;  ///< lost.action
  bool active() const { return action != LostAction::Extrapolate; }
};

/// Throws std::invalid_argument naming lost.timeout_s when it is not a finite value > 0.
void validateLostFeatureConfig(const LostFeatureConfig& config);

/// The per-channel bookkeeping of the policy (no predictor inside: the loop asks it).
class LostFeatureTracker {
 public:
  LostFeatureTracker(const LostFeatureConfig& config, int channels);

  /// Records a delivered frame acquired at t_acq_s with the values the predictor is fed (NaN = the
  /// channel was not measured). Returns true when the predictor must be reset() before fusing it:
  /// the policy is active, every channel had expired, and this frame measures at least one.
  bool observe(double t_acq_s, const Eigen::VectorXd& fed);
  /// Whether channel c is past the timeout at the latest observed frame (never with extrapolate).
  bool expired(int c) const { return expired_[static_cast<size_t>(c)]; }
  bool anyExpired() const;
  /// The last finite value fed for channel c (NaN if never measured).
  double lastValue(int c) const { return last_value_(c); }
  /// Acquisition time of the last frame that measured channel c (NaN if never).
  double lastSeen(int c) const { return last_seen_s_(c); }
  const LostFeatureConfig& config() const { return config_; }
  int channels() const { return static_cast<int>(expired_.size()); }

 private:
  LostFeatureConfig config_;
  Eigen::VectorXd last_value_;
  Eigen::VectorXd last_seen_s_;
  std::vector<bool> expired_;
};

}  // namespace predvs
