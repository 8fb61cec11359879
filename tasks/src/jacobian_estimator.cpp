#include "predvs/tasks/jacobian_estimator.h"

#include "predvs/predictors/named_enum.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace predvs {

namespace {
/// A value as the scenario file would spell it (0.5, not 0.500000).
std::string spelled(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

constexpr EnumName<JacobianMethod> kMethods[] = {{JacobianMethod::Broyden, "broyden"}, {JacobianMethod::Rls, "rls"}};
}  // namespace

JacobianMethod parseJacobianMethod(const std::string& name, const std::string& key) {
  return enumFromName(kMethods, key, name);
}
std::string jacobianMethodName(JacobianMethod method) { return enumToName(kMethods, method); }

JacobianEstimator::JacobianEstimator(int features, int inputs, const JacobianEstimatorConfig& config)
    : config_(config) {
  if (features < 1 || inputs < 1)
    throw std::invalid_argument("Jacobian estimator: needs >= 1 feature and >= 1 input, got " +
                                std::to_string(features) + " x " + std::to_string(inputs));
  if (!(config.lambda > 0.0 && config.lambda <= 1.0))
    throw std::invalid_argument("parameter 'lambda' (forgetting factor) must be in (0, 1], got " +
                                spelled(config.lambda));
  if (!(config.min_dp >= 0.0) || !std::isfinite(config.min_dp))
    throw std::invalid_argument("parameter 'min_dp' must be finite and >= 0, got " + spelled(config.min_dp));
  reset(Eigen::MatrixXd::Zero(features, inputs), 1.0);
}

void JacobianEstimator::reset(const Eigen::MatrixXd& J0, const Eigen::MatrixXd& P0) {
  const Eigen::Index n = J_.size() ? J_.rows() : J0.rows(), m = J_.size() ? J_.cols() : J0.cols();
  if (J0.rows() != n || J0.cols() != m || P0.rows() != m || P0.cols() != m)
    throw std::invalid_argument("Jacobian estimator reset: J0 must be " + std::to_string(n) + " x " +
                                std::to_string(m) + " and P0 " + std::to_string(m) + " x " + std::to_string(m));
  if (!J0.allFinite() || !P0.allFinite())
    throw std::invalid_argument("Jacobian estimator reset: J0 and P0 must be finite");
  if (!(P0.diagonal().minCoeff() > 0.0) ||
      !(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (P0 + P0.transpose()), Eigen::EigenvaluesOnly)
            .eigenvalues()
            .minCoeff() > 0.0))
    throw std::invalid_argument("Jacobian estimator reset: P0 must be positive definite");
  J_ = J0;
  P0_ = 0.5 * (P0 + P0.transpose());
  P_ = P0_;
  eigen_cap_ = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P0_, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  updates_ = 0;
  caps_ = 0;
}

void JacobianEstimator::reset(const Eigen::MatrixXd& J0, double p0) {
  if (!(p0 > 0.0) || !std::isfinite(p0))
    throw std::invalid_argument("Jacobian estimator reset: p0 must be finite and > 0, got " + std::to_string(p0));
  reset(J0, Eigen::MatrixXd(p0 * Eigen::MatrixXd::Identity(J0.cols(), J0.cols())));
}

bool JacobianEstimator::update(const Eigen::VectorXd& df, const Eigen::VectorXd& dp, const Eigen::VectorXd& ft,
                               double dt_s) {
  const Eigen::Index n = J_.rows(), m = J_.cols();
  if (df.size() != n || dp.size() != m || (ft.size() != 0 && ft.size() != n))
    throw std::invalid_argument("Jacobian estimator update: df must have " + std::to_string(n) + " entries, dp " +
                                std::to_string(m) + ", ft 0 or " + std::to_string(n));
  if (!dp.allFinite() || !std::isfinite(dt_s)) return false;
  const double dp_norm = dp.norm();
  if (dp_norm < config_.min_dp || dp_norm == 0.0) return false;

  // Rows usable for this increment (finite feature and target-rate entries).
  std::vector<Eigen::Index> rows;
  rows.reserve(static_cast<size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    if (std::isfinite(df(i)) && (ft.size() == 0 || std::isfinite(ft(i)))) rows.push_back(i);
  if (rows.empty()) return false;

  // Gain row vector g' such that J <- J + r g'.
  Eigen::RowVectorXd gain;
  if (config_.method == JacobianMethod::Broyden) {
    gain = dp.transpose() / (dp_norm * dp_norm);
  } else {
    const Eigen::VectorXd Pdp = P_ * dp;
    const double denom = config_.lambda + dp.dot(Pdp);
    gain = Pdp.transpose() / denom;
    P_ = (P_ - Pdp * Pdp.transpose() / denom) / config_.lambda;
    P_ = 0.5 * (P_ + P_.transpose());
    if (!P_.allFinite()) {
      P_ = P0_;
      ++caps_;
    } else {
      // Clip the eigenvalues to [kFloor * cap, cap]: only the unexcited directions are bounded.
      constexpr double kFloor = 1e-12;
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(P_);
      const Eigen::VectorXd& ev = es.eigenvalues();  // ascending
      if (ev(ev.size() - 1) > eigen_cap_ || ev(0) < kFloor * eigen_cap_) {
        const Eigen::VectorXd clipped = ev.cwiseMax(kFloor * eigen_cap_).cwiseMin(eigen_cap_);
        P_ = es.eigenvectors() * clipped.asDiagonal() * es.eigenvectors().transpose();
        P_ = 0.5 * (P_ + P_.transpose());
        ++caps_;
      }
    }
  }
  for (const Eigen::Index i : rows) {
    const double r = df(i) - J_.row(i).dot(dp) - (ft.size() ? ft(i) * dt_s : 0.0);
    J_.row(i) += r * gain;
  }
  ++updates_;
  return true;
}

}  // namespace predvs
