#include "predvs/servo/prediction_experiment.h"

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
  Eigen::Vector2d z;
};

void validate(const PredictionExperimentConfig& c) {
  if (!(c.duration_s > 0.0) || !std::isfinite(c.duration_s)) {
    std::ostringstream msg;
    msg << "duration_s must be > 0, got " << c.duration_s;
    throw std::invalid_argument(msg.str());
  }
  for (size_t i = 0; i < c.occlusions.size(); ++i) {
    const auto& o = c.occlusions[i];
    if (!(o.start_s < o.end_s)) {
      std::ostringstream msg;
      msg << "occlusions[" << i << "]: start_s (" << o.start_s << ") must be < end_s (" << o.end_s << ")";
      throw std::invalid_argument(msg.str());
    }
  }
}

bool occluded(const std::vector<OcclusionInterval>& occ, double t) {
  for (const auto& o : occ)
    if (t >= o.start_s && t < o.end_s) return true;
  return false;
}

}  // namespace

PredictionResult runPredictionExperiment(const PredictionExperimentConfig& config, const Trajectory& trajectory,
                                         Predictor& predictor) {
  validate(config);
  if (predictor.channels() != 2)
    throw std::invalid_argument("prediction experiment: predictor '" + predictor.name() + "' has " +
                                std::to_string(predictor.channels()) + " channels, expected 2 (x, y)");
  const TimingModel timing(config.timing);
  NoiseModel noise(config.noise, config.seed);
  predictor.reset();

  PredictionResult result;
  result.predictor = predictor.name();
  result.trajectory = trajectory.name();
  const long last_tick = timing.tickAtOrAfter(config.duration_s);
  result.trace.reserve(static_cast<size_t>(last_tick + 1));

  std::deque<PendingFrame> pending;
  bool delivered_any = false;
  double t_acq_latest = kNaN;
  bool latest_valid = false;
  Eigen::Vector2d z_latest = Eigen::Vector2d::Constant(kNaN);

  for (long k = 0; k <= last_tick; ++k) {
    const double t = timing.tickTime(k);
    if (timing.isAcquisitionTick(k)) {
      PendingFrame f{t, timing.releaseTick(t), occluded(config.occlusions, t), Eigen::Vector2d::Constant(kNaN)};
      if (!f.lost) {
        f.z = trajectory.position(t);
        f.z.x() = noise.apply(f.z.x());
        f.z.y() = noise.apply(f.z.y());
      }
      pending.push_back(f);
    }
    while (!pending.empty() && pending.front().release_tick <= k) {
      const PendingFrame& f = pending.front();
      if (f.lost)
        predictor.update(f.t_acq_s);
      else
        predictor.update(f.t_acq_s, f.z);
      delivered_any = true;
      t_acq_latest = f.t_acq_s;
      latest_valid = !f.lost;
      z_latest = f.z;
      pending.pop_front();
    }
    if (!delivered_any) continue;

    PredictionSample s;
    s.t_s = t;
    s.t_acq_s = t_acq_latest;
    s.t_pred_s = timing.effectTime(t);
    s.horizon_s = timing.horizon(t, t_acq_latest);
    s.measured_valid = latest_valid;
    s.measured = z_latest;
    s.predicted = Eigen::Vector2d(predictor.predict(0, s.t_pred_s).position(), predictor.predict(1, s.t_pred_s).position());
    s.truth = trajectory.position(s.t_pred_s);
    s.error = (s.predicted - s.truth).norm();  // NaN while the filter is uninitialised
    result.trace.push_back(s);
  }

  std::vector<double> ts, es;
  ts.reserve(result.trace.size());
  es.reserve(result.trace.size());
  for (const auto& s : result.trace) {
    ts.push_back(s.t_s);
    es.push_back(s.error);
  }
  result.metrics = computeMetrics(ts, es, config.metrics);
  return result;
}

const std::vector<std::string>& predictionTraceColumns() {
  static const std::vector<std::string> cols = {"t_s",    "t_acq_s", "t_pred_s", "horizon_s", "meas_x", "meas_y",
                                                "pred_x", "pred_y",  "true_x",   "true_y",    "error"};
  return cols;
}

std::vector<double> predictionTraceRow(const PredictionSample& s) {
  return {s.t_s,           s.t_acq_s,       s.t_pred_s,   s.horizon_s,  s.measured.x(), s.measured.y(),
          s.predicted.x(), s.predicted.y(), s.truth.x(), s.truth.y(), s.error};
}

}  // namespace predvs
