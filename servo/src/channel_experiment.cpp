#include "predvs/servo/channel_experiment.h"

#include <cmath>
#include <deque>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct PendingFrame {
  double t_acq_s;
  long release_tick;
  bool lost;
  Eigen::VectorXd z;
};

bool occluded(const std::vector<OcclusionInterval>& occ, double t) {
  for (const auto& o : occ)
    if (t >= o.start_s && t < o.end_s) return true;
  return false;
}

}  // namespace

ChannelExperimentResult runChannelExperiment(const PredictionExperimentConfig& config,
                                             const ChannelTrajectory& trajectory, Predictor& predictor) {
  if (!(config.duration_s > 0.0) || !std::isfinite(config.duration_s)) {
    std::ostringstream msg;
    msg << "duration_s must be > 0, got " << config.duration_s;
    throw std::invalid_argument(msg.str());
  }
  for (size_t i = 0; i < config.occlusions.size(); ++i) {
    const OcclusionInterval& o = config.occlusions[i];
    if (!(o.start_s < o.end_s)) {
      std::ostringstream msg;
      msg << "occlusions[" << i << "]: start_s (" << o.start_s << ") must be < end_s (" << o.end_s << ")";
      throw std::invalid_argument(msg.str());
    }
  }
  const int n = trajectory.channels();
  if (predictor.channels() != n)
    throw std::invalid_argument("prediction experiment: predictor '" + predictor.name() + "' has " +
                                std::to_string(predictor.channels()) + " channels, trajectory '" + trajectory.name() +
                                "' has " + std::to_string(n));
  if (config.lost.action == LostAction::Drop)
    throw std::invalid_argument("lost.action: 'drop' needs a closed loop (a task that runs without the feature); "
                                "the open-loop experiment takes 'hold' or 'extrapolate'");
  LostFeatureTracker lost(config.lost, n);
  const TimingModel timing(config.timing);
  NoiseModel noise(config.noise, config.seed);
  predictor.reset();

  ChannelExperimentResult result;
  result.predictor = predictor.name();
  result.trajectory = trajectory.name();
  result.channel_names = trajectory.channelNames();
  const long last_tick = timing.tickAtOrAfter(config.duration_s);
  result.trace.reserve(static_cast<size_t>(last_tick + 1));

  std::deque<PendingFrame> pending;
  bool delivered_any = false, latest_valid = false;
  double t_acq_latest = kNaN;
  Eigen::VectorXd z_latest = Eigen::VectorXd::Constant(n, kNaN);
  int alarms = 0;

  for (long k = 0; k <= last_tick; ++k) {
    const double t = timing.tickTime(k);
    if (timing.isAcquisitionTick(k)) {
      PendingFrame f{t, timing.releaseTick(t), occluded(config.occlusions, t), Eigen::VectorXd::Constant(n, kNaN)};
      if (!f.lost) {
        f.z = trajectory.position(t);
        for (int c = 0; c < n; ++c) f.z(c) = noise.apply(f.z(c));
      }
      pending.push_back(std::move(f));
    }
    while (!pending.empty() && pending.front().release_tick <= k) {
      const PendingFrame& f = pending.front();
      // The whole target lost past lost.timeout_s and back: restart the predictor from this frame.
      if (lost.observe(f.t_acq_s, f.z)) predictor.reset();
      if (f.lost)
        predictor.update(f.t_acq_s);
      else
        predictor.update(f.t_acq_s, f.z);
      for (const int now = predictor.monitorAlarms(); alarms < now; ++alarms) result.alarm_t_acq_s.push_back(f.t_acq_s);
      delivered_any = true;
      t_acq_latest = f.t_acq_s;
      latest_valid = !f.lost;
      z_latest = f.z;
      pending.pop_front();
    }
    if (!delivered_any) continue;

    ChannelSample s;
    s.t_s = t;
    s.t_acq_s = t_acq_latest;
    s.t_pred_s = timing.effectTime(t);
    s.measured_valid = latest_valid;
    s.measured = z_latest;
    s.predicted.resize(n);
    s.predicted_velocity.resize(n);
    s.lost_expired = lost.anyExpired();
    const NamedValues diag = predictor.diagnostics();
    if (result.diagnostic_names.empty())
      for (const auto& kv : diag) result.diagnostic_names.push_back(kv.first);
    s.diagnostics.resize(static_cast<Eigen::Index>(diag.size()));
    for (size_t k = 0; k < diag.size(); ++k) s.diagnostics(static_cast<Eigen::Index>(k)) = diag[k].second;
    for (int c = 0; c < n; ++c) {
      if (lost.expired(c)) {  // held: the last measured value, standing still
        s.predicted(c) = lost.lastValue(c);
        s.predicted_velocity(c) = 0.0;
        continue;
      }
      const ChannelEstimate e = predictor.predict(c, s.t_pred_s);
      s.predicted(c) = e.position();
      s.predicted_velocity(c) = e.velocity();
    }
    s.truth = trajectory.position(s.t_pred_s);
    s.true_velocity = trajectory.velocity(s.t_pred_s);
    s.error = (s.predicted - s.truth).norm();  // NaN while the filter is uninitialised
    result.trace.push_back(std::move(s));
  }

  std::vector<double> ts, es;
  ts.reserve(result.trace.size());
  es.reserve(result.trace.size());
  Eigen::VectorXd pos_sum = Eigen::VectorXd::Zero(n), vel_sum = Eigen::VectorXd::Zero(n);
  Eigen::VectorXi count = Eigen::VectorXi::Zero(n);
  for (const auto& s : result.trace) {
    ts.push_back(s.t_s);
    es.push_back(s.error);
    for (int c = 0; c < n; ++c) {
      if (!std::isfinite(s.predicted(c))) continue;
      pos_sum(c) += (s.predicted(c) - s.truth(c)) * (s.predicted(c) - s.truth(c));
      vel_sum(c) += (s.predicted_velocity(c) - s.true_velocity(c)) * (s.predicted_velocity(c) - s.true_velocity(c));
      ++count(c);
    }
  }
  result.position_mse.resize(n);
  result.velocity_mse.resize(n);
  for (int c = 0; c < n; ++c) {
    result.position_mse(c) = count(c) > 0 ? pos_sum(c) / count(c) : kNaN;
    result.velocity_mse(c) = count(c) > 0 ? vel_sum(c) / count(c) : kNaN;
  }
  result.metrics = computeMetrics(ts, es, config.metrics);
  return result;
}

}  // namespace predvs
