#include "predvs/servo/run_metrics.h"

#include "predvs/servo/metrics.h"
#include "predvs/servo/timing_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Slack when comparing an acquisition time with a multiple of the frame period (s): the times are
/// sums of periods, exact to well below this.
constexpr double kTimeSlackS = 1e-9;


/// ResponseMetrics of the run to the trajectory's manoeuvre, on the effect-time axis (the
/// prediction for t_pred is scored against the truth at t_pred, so the change is at t_pred =
/// manoeuvre time).
ResponseMetrics responseOf(const ChannelExperimentResult& r, const Manoeuvre& man, const MetricsOptions& opt) {
  std::vector<double> t, e, s;
  for (const auto& row : r.trace) {
    t.push_back(row.t_pred_s);
    e.push_back(row.error);
    s.push_back((row.predicted - row.truth).dot(man.direction));
  }
  return computeResponse(t, e, s, man.t_s, opt);
}

}  // namespace

NamedValues openLoopRunValues(const ChannelExperimentResult& r, const PredictionExperimentConfig& config,
                              const ChannelTrajectory& trajectory) {
  NamedValues v;
  for (const auto& kv : metricValues(r.metrics))
    if (kv.first != "effort") v.push_back(kv);
  const auto& channels = trajectory.channelNames();
  for (size_t c = 0; c < channels.size(); ++c)
    v.emplace_back("pos_mse_" + channels[c], r.position_mse(static_cast<Eigen::Index>(c)));
  for (size_t c = 0; c < channels.size(); ++c)
    v.emplace_back("vel_mse_" + channels[c], r.velocity_mse(static_cast<Eigen::Index>(c)));
  if (!config.occlusions.empty())
  {
    std::vector<double> t, e;
    std::vector<bool> lost;
    for (const auto& row : r.trace) t.push_back(row.t_s), e.push_back(row.error), lost.push_back(!row.measured_valid);
    for (const auto& kv : occlusionValues(t, e, lost)) v.push_back(kv);
    std::vector<bool> expired;
    for (const auto& row : r.trace) expired.push_back(row.lost_expired);
    v.push_back(lostPolicyValue(expired, TimingModel(config.timing).basePeriod()));
  }

  // Monitor alarms; an onset at or before the first frame cannot be seen, so it has no detection.
  const double onset = trajectory.onsetTime();
  const double frame_s = TimingModel(config.timing).framePeriod();
  double delay_frames = kNaN;
  if (onset > 0.0) {
    const double first_frame = std::ceil(onset / frame_s - kTimeSlackS) * frame_s;
    for (double t : r.alarm_t_acq_s)
      if (t >= first_frame - kTimeSlackS && t < onset + kDetectWindowS) {
        delay_frames = std::round((t - first_frame) / frame_s);
        break;
      }
  }
  const bool detected = std::isfinite(delay_frames);
  const double alarms = static_cast<double>(r.alarm_t_acq_s.size());
  v.emplace_back("alarms", alarms);
  v.emplace_back("false_alarms_per_min", (alarms - (detected ? 1.0 : 0.0)) / (config.duration_s / 60.0));
  if (onset > 0.0) {
    v.emplace_back("detected", detected ? 1.0 : 0.0);
    v.emplace_back("detect_delay_frames", delay_frames);
  }

  const Manoeuvre man = trajectory.manoeuvre();
  if (man.exists()) {
    const ResponseMetrics resp = responseOf(r, man, config.metrics);
    v.insert(v.end(), {{"resp_max_lag", resp.max_lag},
                       {"resp_overshoot", resp.overshoot},
                       {"resp_mean_3s", resp.mean_after},
                       {"resp_time_s", resp.response_s}});
  }
  return v;
}

std::string runMetricDefinition(const std::string& name) {
  struct Definition {
    const char* name;
    const char* text;
  };
  static const Definition kExact[] = {
      {"rmse", "sqrt(mean e^2) over the steady window (from metrics.steady_start_fraction of the run on)"},
      {"final", "mean e over the last metrics.final_fraction of the run"},
      {"max", "max e over the steady window"},
      {"peak", "max e over the whole run"},
      {"iae", "integral of e dt over the whole run (error units x s)"},
      {"settling_s", "first time after which the trailing mean of e stays within final + max(settling_band (peak - "
                     "final), 3 sd of the final window) (s; null if never)"},
      {"effort", "sum of ||u||^2 dt of the applied command over the run (closed loop)"},
      {"converged", "1 if the run did not fail and e stayed at or below metrics.converge_px from some time to the end, "
                    "for at least metrics.converge_hold_s, else 0 (metrics.outcome)"},
      {"convergence_time_s", "start of the final stretch of e at or below metrics.converge_px (s; null if not "
                             "converged)"},
      {"failed", "1 if the run stopped at a failing true state: a point behind the camera, a point outside the image "
                 "(metrics.fail_outside_image), the robot at a hard limit (metrics.fail_robot_limit), else 0"},
      {"failure_time_s", "time of the failing state (s; null if the run did not fail)"},
      {"fail_behind", "1 if the run failed with a point at depth <= 0 (behind the camera), else 0"},
      {"fail_image", "1 if the run failed with a point outside the camera.width x camera.height image, else 0"},
      {"fail_robot", "1 if the run failed with the robot at a hard limit (an arm joint at its stop), else 0"},
      {"occl_rmse", "RMS of e over the ticks whose latest delivered frame was lost (occlusion)"},
      {"occl_max", "max e over the ticks whose latest delivered frame was lost"},
      {"occl_end_error", "e at the last tick before a frame is delivered again, mean over the occlusions"},
      {"reacq_error", "e at the first tick after a frame is delivered again, mean over the occlusions"},
      {"reacq_1s_rmse", "RMS of e over the 1 s from re-acquisition, mean over the occlusions"},
      {"lost_policy_s", "time during which the lost-feature policy held or dropped at least one channel "
                        "(lost.timeout_s, lost.action; s)"},
      {"alarms", "discontinuity-monitor alarms in the run (st-akf family; 0 for the others)"},
      {"false_alarms_per_min", "alarms that are not the detection of the onset, per minute of run"},
      {"detected", "1 if an alarm came from a frame acquired within 0.5 s after the onset, else 0"},
      {"detect_delay_frames", "frames from the first frame at or after the onset to the detecting one (null if none)"},
      {"resp_max_lag", "largest lag behind the manoeuvre within metrics.response_window_s (3 s) after it: -(error along its direction), 0.5 s trailing mean"},
      {"resp_overshoot", "largest overshoot past the manoeuvre within metrics.response_window_s (3 s) after it: +(error along its direction), 0.5 s trailing mean"},
      {"resp_mean_3s", "mean e over the 3 s after the manoeuvre"},
      {"resp_time_s", "time from the manoeuvre until e settles (s)"},
  };
  for (const auto& d : kExact)
    if (name == d.name) return d.text;
  auto channelOf = [&](const std::string& prefix) {
    return name.rfind(prefix, 0) == 0 ? name.substr(prefix.size()) : std::string();
  };
  if (const std::string c = channelOf("pos_mse_"); !c.empty())
    return "mean over the run of (predicted - true)^2 of channel " + c + " at the effect time (units^2)";
  if (const std::string c = channelOf("vel_mse_"); !c.empty())
    return "mean over the run of (predicted - true velocity)^2 of channel " + c + " at the effect time ((units/s)^2)";
  return "";
}

}  // namespace predvs
