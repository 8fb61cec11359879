#include "predvs/tasks/vsc_task.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Damped pseudo-inverse solve x = A^+ b: exact inverse of the singular values >= rcond *
/// sigma_max, sigma / (rcond sigma_max)^2 below (continuous at the threshold, 0 at sigma = 0).
Eigen::VectorXd dampedSolve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double rcond) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.cols());
  if (sigma.size() == 0 || !(sigma(0) > 0.0)) return x;
  const double threshold = rcond * sigma(0);
  const Eigen::VectorXd Utb = svd.matrixU().transpose() * b;
  for (Eigen::Index i = 0; i < sigma.size(); ++i) {
    const double s = sigma(i);
    const double inv = s >= threshold ? 1.0 / s : s / (threshold * threshold);
    x += svd.matrixV().col(i) * (inv * Utb(i));
  }
  return x;
}
}  // namespace

VscTaskConfig VscTaskConfig::fromParams(const Params& params, double period_s) {
  VscTaskConfig c;
  c.q_near_per_s = params.get("q_near", c.q_near_per_s, 1e-9, kInf);
  // q_far defaults to min(1 /s, q_near), so that a q_near below the default q_far alone is a
  // constant gain rather than an error about a key the user never wrote; a given q_far must not
  // exceed q_near (the gain grows towards the goal).
  c.q_far_per_s = params.get("q_far", std::min(c.q_far_per_s, c.q_near_per_s), 1e-9, kInf);
  if (c.q_far_per_s > c.q_near_per_s) {
    std::ostringstream msg;
    msg << "task 'vsc': q_far = " << c.q_far_per_s << " must not exceed q_near = " << c.q_near_per_s
        << " (the scheduled gain grows from q_far far from the goal to q_near at it)";
    throw std::invalid_argument(msg.str());
  }
  c.s_half_px = params.get("s_half", c.s_half_px, 1e-9, kInf);
  c.eps_px_per_s = params.get("eps_s", c.eps_px_per_s, 0.0, kInf);
  c.phi_px = params.get("phi", c.phi_px, 1e-9, kInf);
  const double c_all = params.get("c", 1.0, 1e-9, kInf);
  c.c_u = params.get("c_u", c_all, 1e-9, kInf);
  c.c_v = params.get("c_v", c_all, 1e-9, kInf);
  c.rcond = params.get("rcond", c.rcond, 1e-12, 0.5);
  // Inside the boundary layer the step is S <- (1 - (q + eps_s / phi) T) S: keep the factor in
  // (0, 1) for every q the schedule can take (q_far <= q <= q_near).
  const double factor = (c.q_near_per_s + c.eps_px_per_s / c.phi_px) * period_s;
  if (!(factor < 1.0)) {
    std::ostringstream msg;
    msg << "task 'vsc': (q_near + eps_s / phi) * T = (" << c.q_near_per_s << " + " << c.eps_px_per_s << " / "
        << c.phi_px << ") * " << period_s << " = " << factor
        << " must be < 1 for a monotone discrete reaching law: lower q_near or eps_s, or widen phi";
    throw std::invalid_argument(msg.str());
  }
  return c;
}

double VscTaskConfig::gain(double sliding_norm_px) const {
  const double r = sliding_norm_px / s_half_px;
  return q_far_per_s + (q_near_per_s - q_far_per_s) / (1.0 + r * r);
}

VscTask::VscTask(const Params& params, const TaskContext& context)
    : PointTask(context), period_s_(context.base_period_s) {
  if (!(period_s_ > 0.0) || !std::isfinite(period_s_))
    throw std::invalid_argument("task 'vsc': the control period base_period_s must be > 0");
  config_ = VscTaskConfig::fromParams(params, period_s_);
  params.requireAllUsed("task 'vsc'");
  const int m = context.command_space.size();
  if (m < 1) throw std::invalid_argument("task 'vsc': the robot's command space is empty");
  J_ = Eigen::MatrixXd::Zero(featureSize(), m);
  S_ = Eigen::VectorXd::Zero(featureSize());
}

Eigen::VectorXd VscTask::computeCommand(const TaskInput& in) {
  const Eigen::Index n2 = featureSize(), n = n2 / 2;
  const Eigen::Index m = context().command_space.size();
  if (in.used.size() != n2 || in.robot_jacobian.rows() != 6 || in.robot_jacobian.cols() != m ||
      (in.target_rate.size() != 0 && in.target_rate.size() != n2))
    throw std::invalid_argument("task 'vsc': got " + std::to_string(in.used.size()) + " features (expected " +
                                std::to_string(n2) + "), a " + std::to_string(in.robot_jacobian.rows()) + " x " +
                                std::to_string(in.robot_jacobian.cols()) + " robot Jacobian (expected 6 x " +
                                std::to_string(m) + ") and " + std::to_string(in.target_rate.size()) +
                                " target rates (expected 0 or " + std::to_string(n2) + ")");
  const Eigen::VectorXd& sd = desiredFeatures();
  const PointFeatures& desired = context().desired_points;
  const double T = period_s_;

  // Model rows of the usable points; the others stay zero (left out of the step).
  J_.setZero();
  S_.setZero();
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n2), ft = Eigen::VectorXd::Zero(n2), Cdiag(n2);
  double sum_sq = 0.0;
  int used_points = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    Cdiag(2 * i) = config_.c_u;
    Cdiag(2 * i + 1) = config_.c_v;
    const Eigen::Vector2d s = in.used.segment<2>(2 * i);
    double Z = i < in.depths_m.size() ? in.depths_m(i) : std::numeric_limits<double>::quiet_NaN();
    if (!(Z > 0.0) || !std::isfinite(Z)) Z = i < desired.Z_m.size() ? desired.Z_m(i) : Z;
    if (!s.allFinite() || !(Z > 0.0) || !std::isfinite(Z)) continue;
    J_.middleRows<2>(2 * i) =
        pixelInteraction(s, Eigen::VectorXd::Constant(1, Z), context().camera) * in.robot_jacobian;
    e.segment<2>(2 * i) = s - sd.segment<2>(2 * i);
    if (in.target_rate.size() != 0 && in.target_rate.segment<2>(2 * i).allFinite())
      ft.segment<2>(2 * i) = in.target_rate.segment<2>(2 * i);
    S_.segment<2>(2 * i) = Cdiag.segment<2>(2 * i).cwiseProduct(e.segment<2>(2 * i));
    sum_sq += S_.segment<2>(2 * i).squaredNorm();
    ++used_points;
  }
  sliding_norm_px_ = used_points > 0 ? std::sqrt(sum_sq / used_points) : 0.0;
  gain_q_per_s_ = config_.gain(sliding_norm_px_);
  sliding_norm_history_.push_back(sliding_norm_px_);
  if (used_points == 0) return Eigen::VectorXd::Zero(m);

  // Reaching law target for S(k+1) and the command that meets it through the model.
  const Eigen::VectorXd sat = (S_ / config_.phi_px).cwiseMax(-1.0).cwiseMin(1.0);
  const Eigen::VectorXd S_next = (1.0 - gain_q_per_s_ * T) * S_ - config_.eps_px_per_s * T * sat;
  const Eigen::VectorXd rhs = S_next - Cdiag.cwiseProduct(e + T * ft);
  const Eigen::MatrixXd A = Cdiag.asDiagonal() * (T * J_);
  return dampedSolve(A, rhs, config_.rcond);
}

NamedValues VscTask::diagnostics() const {
  return {{"sliding_norm", sliding_norm_px_}, {"s_u", S_(0)}, {"s_v", S_(1)}, {"gain_q", gain_q_per_s_}};
}

NamedValues VscTask::runSummary() const {
  const size_t n = sliding_norm_history_.size();
  if (n == 0) return {{"sliding_rms_final", std::numeric_limits<double>::quiet_NaN()}};
  const size_t last = std::max<size_t>(1, (n + 9) / 10);
  double sum_sq = 0.0;
  for (size_t k = n - last; k < n; ++k) sum_sq += sliding_norm_history_[k] * sliding_norm_history_[k];
  return {{"sliding_rms_final", std::sqrt(sum_sq / static_cast<double>(last))}};
}

}  // namespace predvs
