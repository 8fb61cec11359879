#include "predvs/tasks/ibvs_broyden_task.h"

#include "predvs/predictors/named_enum.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

namespace predvs {

namespace {

constexpr EnumName<IbvsBroydenTask::Init> kInits[] = {{IbvsBroydenTask::Init::Explore, "explore"},
                                                      {IbvsBroydenTask::Init::Model, "model"}};
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

int commandSize(const TaskContext& context) {
  if (context.command_space.size() < 1)
    throw std::invalid_argument("task 'ibvs-broyden': the robot's command space is empty");
  return context.command_space.size();
}

JacobianEstimatorConfig estimatorConfig(const Params& params) {
  JacobianEstimatorConfig c;
  c.method = parseJacobianMethod(params.text("method", "rls"), "parameter 'method'");
  c.lambda = params.get("lambda", 0.99, 0.0, 1.0);
  c.min_dp = params.get("min_dp", 1e-3, 0.0, kInf);
  return c;  // lambda = 0 is rejected by the estimator (naming 'lambda')
}

/// A value as the scenario file would spell it (0.5, not 0.500000).
std::string spelled(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double positive(const Params& params, const std::string& key, double fallback) {
  const double v = params.get(key, fallback, 0.0, kInf);
  if (!(v > 0.0)) throw std::invalid_argument("parameter '" + key + "' must be > 0, got " + spelled(v));
  return v;
}

}  // namespace

IbvsBroydenTask::IbvsBroydenTask(const Params& params, const TaskContext& context)
    : PointTask(context),
      gain_(positive(params, "gain", 1.0)),
      damping_(params.get("damping", 1e-2, 0.0, 1.0)),
      compensation_(params.get("delay_compensation", 1.0, 0.0, 1.0) != 0.0),
      init_(enumFromName(kInits, "parameter 'init'", params.text("init", "explore"))),
      probe_speed_(positive(params, "probe_speed", 0.05)),
      probe_frames_(static_cast<int>(params.get("probe_frames", 1.0, 1.0, 1000.0))),
      model_error_(params.get("model_error", 0.2, 0.0, 10.0)),
      p0_(positive(params, "p0", 1e6)),
      inputs_(commandSize(context)),
      estimator_(featureSize(), inputs_, estimatorConfig(params)) {
  const double flag = params.get("delay_compensation", 1.0);
  if (flag != 0.0 && flag != 1.0)
    throw std::invalid_argument("parameter 'delay_compensation' must be 0 or 1, got " + spelled(flag));
  if (params.get("probe_frames", 1.0) != static_cast<double>(probe_frames_))
    throw std::invalid_argument("parameter 'probe_frames' must be an integer >= 1, got " +
                                spelled(params.get("probe_frames", 1.0)));
  params.requireAllUsed("task 'ibvs-broyden'");
  estimator_.reset(Eigen::MatrixXd::Zero(featureSize(), inputs_), p0_);
}

Eigen::VectorXd IbvsBroydenTask::probeCommand(double t_s) const {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(inputs_);
  const double half_s = probe_frames_ * context().frame_period_s;
  // Small epsilon so that a tick exactly at a phase boundary starts the next phase.
  const long phase = static_cast<long>(std::floor((t_s - t0_s_) / half_s + 1e-9));
  if (phase >= 0 && phase < 2L * inputs_) u(phase / 2) = (phase % 2 == 0 ? 1.0 : -1.0) * probe_speed_;
  return u;
}

void IbvsBroydenTask::observe(const TaskMeasurement& m) {
  if (m.features.size() != featureSize() || m.command_integral.size() != inputs_) return;
  last_t_acq_s_ = m.t_acq_s;
  if (has_prev_ && learning_) {
    const Eigen::VectorXd df = m.features - prev_features_;
    const Eigen::VectorXd dp = m.command_integral - prev_p_;
    // The target's own feature motion over the increment: the mean of the predictor's rates at
    // its two ends. While probing it is left out (header: "Exploration and the target term").
    Eigen::VectorXd ft;
    if (compensation_ && !exploring_ && m.target_rate.size() == featureSize() && prev_rate_.size() == featureSize())
      ft = 0.5 * (m.target_rate + prev_rate_);
    if (estimator_.update(df, dp, ft, m.t_acq_s - prev_t_acq_s_)) updated_since_command_ = true;
  }
  prev_features_ = m.features;
  prev_p_ = m.command_integral;
  prev_rate_ = m.target_rate;
  prev_t_acq_s_ = m.t_acq_s;
  has_prev_ = true;
}

Eigen::VectorXd IbvsBroydenTask::computeCommand(const TaskInput& in) {
  const Eigen::Index n = featureSize();
  const bool truth = in.true_point_jacobian.rows() == n && in.true_point_jacobian.cols() == inputs_;
  if (!started_) {
    started_ = true;
    t0_s_ = in.t_s;
    if (init_ == Init::Model) {
      if (!truth)
        throw std::invalid_argument("task 'ibvs-broyden': init 'model' needs the true point Jacobian (" +
                                    std::to_string(n) + " x " + std::to_string(inputs_) + ") at the first tick");
      std::mt19937_64 rng(context().seed);
      std::uniform_real_distribution<double> unit(-1.0, 1.0);
      Eigen::MatrixXd J0 = in.true_point_jacobian;
      for (Eigen::Index i = 0; i < J0.rows(); ++i)
        for (Eigen::Index j = 0; j < J0.cols(); ++j) J0(i, j) *= 1.0 + model_error_ * unit(rng);
      estimator_.reset(J0, p0_);
    } else {
      exploring_ = true;
    }
    learning_ = true;
  }
  // Exploration ends once a measurement taken one frame after the last probe has been observed.
  if (exploring_ && last_t_acq_s_ >= t0_s_ + (2.0 * probe_frames_ * inputs_ + 1.0) * context().frame_period_s - 1e-9)
    exploring_ = false;

  Eigen::VectorXd u;
  if (exploring_) {
    u = probeCommand(in.t_s);
  } else {
    // Acts on the forecast when compensating (falling back to the measurement if the loop gave none).
    const Eigen::VectorXd& s = compensation_ && in.used.size() == n ? in.used : in.measured;
    const bool feed_forward = compensation_ && in.target_rate.size() == n;
    if (s.size() != n) {
      u = Eigen::VectorXd::Zero(inputs_);
    } else {
      Eigen::VectorXd r = -gain_ * (s - desiredFeatures());
      if (feed_forward) r -= in.target_rate;
      u = dampedSolve(estimator_.jacobian(), r, damping_);
    }
  }

  updated_ = updated_since_command_;
  updated_since_command_ = false;
  jacobian_error_ = kNaN;
  if (truth && in.true_point_jacobian.norm() > 0.0)
    jacobian_error_ = (estimator_.jacobian() - in.true_point_jacobian).norm() / in.true_point_jacobian.norm();
  jacobian_errors_.push_back(jacobian_error_);
  return u;
}

Eigen::VectorXd IbvsBroydenTask::dampedSolve(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, double damping) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(J.cols());
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < r.size(); ++i)
    if (std::isfinite(r(i)) && J.row(i).allFinite()) rows.push_back(i);
  if (rows.empty()) return u;
  Eigen::MatrixXd Jr(static_cast<Eigen::Index>(rows.size()), J.cols());
  Eigen::VectorXd rr(Jr.rows());
  for (Eigen::Index k = 0; k < Jr.rows(); ++k) {
    Jr.row(k) = J.row(rows[static_cast<size_t>(k)]);
    rr(k) = r(rows[static_cast<size_t>(k)]);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Jr, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  if (sigma.size() == 0 || !(sigma(0) > 0.0)) return u;
  const double mu2 = std::pow(damping * sigma(0), 2);
  const Eigen::VectorXd w = sigma.array() / (sigma.array().square() + mu2);
  u = svd.matrixV() * (w.asDiagonal() * (svd.matrixU().transpose() * rr));
  return u;
}

NamedValues IbvsBroydenTask::diagnostics() const {
  return {{"jacobian_error", jacobian_error_}, {"updated", updated_ ? 1.0 : 0.0}, {"exploring", exploring_ ? 1.0 : 0.0}};
}

NamedValues IbvsBroydenTask::runSummary() const {
  const size_t ticks = jacobian_errors_.size();
  const size_t tail = std::max<size_t>(1, ticks / 10);
  double sum = 0.0;
  int count = 0;
  for (size_t i = ticks - std::min(tail, ticks); i < ticks; ++i)
    if (std::isfinite(jacobian_errors_[i])) {
      sum += jacobian_errors_[i];
      ++count;
    }
  return {{"jacobian_error_final", count ? sum / count : kNaN},
          {"jacobian_updates", static_cast<double>(estimator_.updates())}};
}

}  // namespace predvs
