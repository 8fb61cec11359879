#include "predvs/tasks/ibvs_task.h"

#include "predvs/predictors/named_enum.h"

#include <visp3/visual_features/vpFeaturePoint.h>
#include <visp3/vs/vpServo.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace predvs {

namespace {
constexpr EnumName<InteractionMatrixType> kInteractionTypes[] = {{InteractionMatrixType::Current, "current"},
                                                                 {InteractionMatrixType::Desired, "desired"},
                                                                 {InteractionMatrixType::Mean, "mean"}};
}  // namespace

InteractionMatrixType parseInteractionMatrixType(const std::string& name) {
  return enumFromName(kInteractionTypes, "task.interaction", name);
}
std::string interactionMatrixTypeName(InteractionMatrixType type) { return enumToName(kInteractionTypes, type); }

struct IbvsTask::Impl {
  // vpServo keeps pointers to the features: they live here, sized once, never reallocated.
  std::vector<vpFeaturePoint> s;
  std::vector<vpFeaturePoint> sd;
  vpServo servo;
};

IbvsTask::IbvsTask(const IbvsTaskConfig& config, const Eigen::VectorXd& desired_xy, const Eigen::VectorXd& desired_Z)
    : config_(config), impl_(std::make_unique<Impl>()) {
  if (!(config.lambda > 0.0) || !std::isfinite(config.lambda)) {
    std::ostringstream msg;
    msg << "task.lambda must be > 0, got " << config.lambda;
    throw std::invalid_argument(msg.str());
  }
  const Eigen::Index n = desired_Z.size();
  if (n < 1 || desired_xy.size() != 2 * n)
    throw std::invalid_argument("IBVS task: desired features have " + std::to_string(desired_xy.size()) +
                                " entries for " + std::to_string(n) + " depths (expected 2 per point, >= 1 point)");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(desired_Z(i) > 0.0)) throw std::invalid_argument("IBVS task: desired depth of point " + std::to_string(i) + " must be > 0");

  impl_->s.resize(static_cast<size_t>(n));
  impl_->sd.resize(static_cast<size_t>(n));
  vpServo& task = impl_->servo;
  task.setServo(vpServo::EYEINHAND_CAMERA);
  vpServo::vpServoIteractionMatrixType type = vpServo::CURRENT;
  if (config.interaction == InteractionMatrixType::Desired) type = vpServo::DESIRED;
  if (config.interaction == InteractionMatrixType::Mean) type = vpServo::MEAN;
  task.setInteractionMatrixType(type, vpServo::PSEUDO_INVERSE);
  task.setLambda(config.lambda);
  for (Eigen::Index i = 0; i < n; ++i) {
    impl_->sd[i].buildFrom(desired_xy(2 * i), desired_xy(2 * i + 1), desired_Z(i));
    // Until the first measurement the current feature is the desired one (zero error).
    impl_->s[i].buildFrom(desired_xy(2 * i), desired_xy(2 * i + 1), desired_Z(i));
    task.addFeature(impl_->s[i], impl_->sd[i]);
  }
  error_ = Eigen::VectorXd::Zero(2 * n);
  L_ = Eigen::MatrixXd::Zero(2 * n, 6);
}

IbvsTask::~IbvsTask() = default;
IbvsTask::IbvsTask(IbvsTask&&) noexcept = default;
IbvsTask& IbvsTask::operator=(IbvsTask&&) noexcept = default;

int IbvsTask::points() const { return static_cast<int>(impl_->s.size()); }

CameraTwist IbvsTask::computeVelocity(const Eigen::VectorXd& current_xy, const Eigen::VectorXd& current_Z,
                                      const Eigen::VectorXd& target_feature_rate) {
  const Eigen::Index n = points();
  if (current_xy.size() != 2 * n || current_Z.size() != n)
    throw std::invalid_argument("IBVS task: got " + std::to_string(current_xy.size()) + " features and " +
                                std::to_string(current_Z.size()) + " depths for " + std::to_string(n) + " points");
  if (target_feature_rate.size() != 0 && target_feature_rate.size() != 2 * n)
    throw std::invalid_argument("IBVS task: feed-forward has " + std::to_string(target_feature_rate.size()) +
                                " entries, expected " + std::to_string(2 * n));
  for (Eigen::Index i = 0; i < n; ++i) impl_->s[i].buildFrom(current_xy(2 * i), current_xy(2 * i + 1), current_Z(i));

  vpServo& task = impl_->servo;
  const vpColVector v = task.computeControlLaw();
  const vpColVector e = task.getError();
  const vpMatrix L = task.getInteractionMatrix();
  error_.resize(e.size());
  for (unsigned i = 0; i < e.size(); ++i) error_(i) = e[i];
  L_.resize(L.getRows(), L.getCols());
  for (unsigned r = 0; r < L.getRows(); ++r)
    for (unsigned c = 0; c < L.getCols(); ++c) L_(r, c) = L[r][c];

  CameraTwist out;
  for (int i = 0; i < 6; ++i) out(i) = v[i];
  if (target_feature_rate.size() != 0) {
    // For EYEINHAND_CAMERA the task Jacobian is L, so this is L^+ as vpServo computed it.
    const vpMatrix Lp = task.getTaskJacobianPseudoInverse();
    for (int r = 0; r < 6; ++r) {
      double acc = 0.0;
      for (Eigen::Index c = 0; c < 2 * n; ++c) acc += Lp[r][static_cast<unsigned>(c)] * target_feature_rate(c);
      out(r) -= acc;
    }
  }
  return out;
}

Eigen::Matrix<double, 2, 6> IbvsTask::pointInteraction(double x, double y, double Z) {
  Eigen::Matrix<double, 2, 6> L;
  L << -1.0 / Z, 0.0, x / Z, x * y, -(1.0 + x * x), y,  //
      0.0, -1.0 / Z, y / Z, 1.0 + y * y, -x * y, -x;
  return L;
}

}  // namespace predvs
