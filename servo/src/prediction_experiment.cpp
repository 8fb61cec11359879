#include "predvs/servo/prediction_experiment.h"

#include "predvs/servo/channel_experiment.h"
#include "predvs/servo/paper_trajectories.h"

#include <stdexcept>

namespace predvs {
namespace {

/// A planar Trajectory seen, without owning it, as the 2-channel (x, y) ChannelTrajectory that
/// runChannelExperiment() simulates. The planar experiment is that simulation on this view: one
/// implementation of the acquisition / delivery / prediction loop serves both headers.
class PlanarView : public ChannelTrajectory {
 public:
  explicit PlanarView(const Trajectory& t) : t_(t) {}
  std::string name() const override { return t_.name(); }
  const std::vector<std::string>& channelNames() const override {
    static const std::vector<std::string> xy = {"x", "y"};
    return xy;
  }
  Eigen::VectorXd position(double t_s) const override { return t_.position(t_s); }
  Eigen::VectorXd velocity(double t_s) const override { return t_.velocity(t_s); }

 private:
  const Trajectory& t_;
};

}  // namespace

PredictionResult runPredictionExperiment(const PredictionExperimentConfig& config, const Trajectory& trajectory,
                                         Predictor& predictor) {
  // Checked here, not left to runChannelExperiment(), to keep the planar message ("expected 2").
  if (predictor.channels() != 2)
    throw std::invalid_argument("prediction experiment: predictor '" + predictor.name() + "' has " +
                                std::to_string(predictor.channels()) + " channels, expected 2 (x, y)");
  ChannelExperimentResult run = runChannelExperiment(config, PlanarView(trajectory), predictor);

  PredictionResult result;
  result.predictor = std::move(run.predictor);
  result.trajectory = std::move(run.trajectory);
  result.metrics = run.metrics;
  result.trace.reserve(run.trace.size());
  for (const ChannelSample& c : run.trace) {
    PredictionSample s;
    s.t_s = c.t_s;
    s.t_acq_s = c.t_acq_s;
    s.t_pred_s = c.t_pred_s;
    s.horizon_s = c.t_pred_s - c.t_acq_s;  // TimingModel::horizon(t, t_acq), the same subtraction
    s.measured_valid = c.measured_valid;
    s.measured = c.measured;
    s.predicted = c.predicted;
    s.truth = c.truth;
    s.error = c.error;
    result.trace.push_back(s);
  }
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
