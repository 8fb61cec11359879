#include "predvs/tasks/ibvs_task.h"

#include "predvs/predictors/named_enum.h"

#include <visp3/core/vpVelocityTwistMatrix.h>
#include <visp3/visual_features/vpFeaturePoint.h>
#include <visp3/vs/vpServo.h>

#include <Eigen/SVD>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace predvs {

namespace {
constexpr EnumName<InteractionMatrixType> kInteractionTypes[] = {{InteractionMatrixType::Current, "current"},
                                                                 {InteractionMatrixType::Desired, "desired"},
                                                                 {InteractionMatrixType::Mean, "mean"}};

/// V diag(s_i / (s_i^2 + mu^2)) U' of the thin SVD U diag(s_i) V', mu = damping s_0; 1 / s_i when
/// damping = 0 (the Moore-Penrose inverse); singular values below 1e-6 s_0 are dropped, as
/// vpMatrix::pseudoInverse() does (IbvsTask::dampedPseudoInverse()).
Eigen::MatrixXd inverseFromSvd(const Eigen::JacobiSVD<Eigen::MatrixXd>& svd, double damping) {
  const Eigen::VectorXd& sv = svd.singularValues();
  const double mu = damping * (sv.size() > 0 ? sv(0) : 0.0);
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(sv.size());
  for (Eigen::Index i = 0; i < sv.size(); ++i)
    if (sv(i) > 1e-6 * sv(0)) inv(i) = damping > 0.0 ? sv(i) / (sv(i) * sv(i) + mu * mu) : 1.0 / sv(i);
  return svd.matrixV() * inv.asDiagonal() * svd.matrixU().transpose();
}

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
  vpMatrix eJe;
  // Form of the task Jacobian: L alone while the robot's camera Jacobian is the identity (the
  // free-flying camera: vpServo's EYEINHAND_CAMERA, which skips two 6x6 products per step), else
  // L cVe eJe (EYEINHAND_L_cVe_eJe). Both give the same command for J_c = I.
  bool camera_frame = false;
  bool form_chosen = false;
};

IbvsTask::IbvsTask(const Params& params, const TaskContext& context)
    : PointTask(context),
      lambda_(params.get("lambda", 1.0)),
      interaction_(parseInteractionMatrixType(params.text("interaction", "current"))),
      feedforward_damping_(params.get("feedforward_damping", kDefaultFeedforwardDamping)),
      impl_(std::make_unique<Impl>()) {
  if (!(lambda_ > 0.0) || !std::isfinite(lambda_))
    throw std::invalid_argument("task.lambda must be > 0, got " + std::to_string(lambda_));
  if (!(feedforward_damping_ >= 0.0) || !(feedforward_damping_ <= 1.0))
    throw std::invalid_argument("task.feedforward_damping must be in [0, 1], got " +
                                std::to_string(feedforward_damping_));
  params.requireAllUsed("task 'ibvs'");
  const int m = context.command_space.size();
  if (m < 1) throw std::invalid_argument("task 'ibvs': the robot has no command");
  const PointFeatures& desired = context.desired_points;
  const int n = desired.points();
  const Eigen::VectorXd xy = context.camera.toNormalized(desired.uv_px);
  for (int i = 0; i < n; ++i)
    if (!(desired.Z_m(i) > 0.0))
      throw std::invalid_argument("task 'ibvs': desired depth of point " + std::to_string(i) + " must be > 0");

  impl_->s.resize(static_cast<size_t>(n));
  impl_->sd.resize(static_cast<size_t>(n));
  impl_->eJe.resize(6, static_cast<unsigned>(m));
  vpServo& task = impl_->servo;
  task.setServo(vpServo::EYEINHAND_L_cVe_eJe);
  task.set_cVe(vpVelocityTwistMatrix());  // identity: the command acts through the robot's camera Jacobian
  vpServo::vpServoIteractionMatrixType type = vpServo::CURRENT;
  if (interaction_ == InteractionMatrixType::Desired) type = vpServo::DESIRED;
  if (interaction_ == InteractionMatrixType::Mean) type = vpServo::MEAN;
  task.setInteractionMatrixType(type, vpServo::PSEUDO_INVERSE);
  task.setLambda(lambda_);
  for (int i = 0; i < n; ++i) {
    impl_->sd[i].buildFrom(xy(2 * i), xy(2 * i + 1), desired.Z_m(i));
    // Until the first measurement the current feature is the desired one (zero error).
    impl_->s[i].buildFrom(xy(2 * i), xy(2 * i + 1), desired.Z_m(i));
    task.addFeature(impl_->s[i], impl_->sd[i]);
  }
  error_ = Eigen::VectorXd::Zero(2 * n);
  L_ = Eigen::MatrixXd::Zero(2 * n, 6);
  J_px_ = Eigen::MatrixXd::Zero(2 * n, m);
}

IbvsTask::~IbvsTask() = default;

Eigen::VectorXd IbvsTask::computeCommand(const TaskInput& in) {
  const Eigen::Index n = static_cast<Eigen::Index>(impl_->s.size());
  const CameraIntrinsics& cam = context().camera;
  const Eigen::Index m = in.robot_jacobian.cols();
  if (in.used.size() != 2 * n || in.depths_m.size() != n || in.robot_jacobian.rows() != 6 ||
      m != static_cast<Eigen::Index>(impl_->eJe.getCols()))
    throw std::invalid_argument("task 'ibvs': got " + std::to_string(in.used.size()) + " features, " +
                                std::to_string(in.depths_m.size()) + " depths and a " +
                                std::to_string(in.robot_jacobian.rows()) + "x" + std::to_string(m) +
                                " robot Jacobian for " + std::to_string(n) + " points");
  if (in.target_rate.size() != 0 && in.target_rate.size() != 2 * n)
    throw std::invalid_argument("task 'ibvs': feed-forward has " + std::to_string(in.target_rate.size()) +
                                " entries, expected " + std::to_string(2 * n));
  std::vector<Eigen::Index> active;
  for (Eigen::Index i = 0; i < n; ++i)
    if (in.used.segment<2>(2 * i).allFinite()) active.push_back(i);
  if (static_cast<Eigen::Index>(active.size()) < n) return commandOnPoints(in, active);
  for (Eigen::Index i = 0; i < n; ++i)
    impl_->s[i].buildFrom((in.used(2 * i) - cam.u0) / cam.px, (in.used(2 * i + 1) - cam.v0) / cam.py, in.depths_m(i));

  vpServo& task = impl_->servo;
  const bool identity = m == 6 && in.robot_jacobian.isIdentity(0.0);
  if (!impl_->form_chosen || identity != impl_->camera_frame) {
    task.setServo(identity ? vpServo::EYEINHAND_CAMERA : vpServo::EYEINHAND_L_cVe_eJe);
    impl_->camera_frame = identity;
    impl_->form_chosen = true;
  }
  if (!identity) {
    for (unsigned r = 0; r < 6; ++r)
      for (unsigned c = 0; c < static_cast<unsigned>(m); ++c) impl_->eJe[r][c] = in.robot_jacobian(r, c);
    task.set_eJe(impl_->eJe);
  }
  const vpColVector u = task.computeControlLaw();
  const vpColVector e = task.getError();
  const vpMatrix L = task.getInteractionMatrix();
  error_.resize(e.size());
  for (unsigned i = 0; i < e.size(); ++i) error_(i) = e[i];
  for (unsigned r = 0; r < L.getRows(); ++r)
    for (unsigned c = 0; c < L.getCols(); ++c) L_(r, c) = L[r][c];
  const Eigen::MatrixXd J = L_ * in.robot_jacobian;
  J_px_ = J;
  for (Eigen::Index r = 0; r < 2 * n; ++r) J_px_.row(r) *= r % 2 ? cam.py : cam.px;

  Eigen::VectorXd out(m);
  for (Eigen::Index i = 0; i < m; ++i) out(i) = u[static_cast<unsigned>(i)];
  if (in.target_rate.size() != 0) {
    if (feedforward_damping_ > 0.0) {
      // The damped inverse of L J_c (header), applied to the target rate in normalised units.
      Eigen::VectorXd rate(2 * n);
      for (Eigen::Index c = 0; c < 2 * n; ++c) rate(c) = in.target_rate(c) / (c % 2 ? cam.py : cam.px);
      out -= dampedPseudoInverse(J, feedforward_damping_) * rate;
      return out;
    }
    // (L J_c)^+ as vpServo computed it, applied to the target rate in normalised units.
    const vpMatrix Jp = task.getTaskJacobianPseudoInverse();
    for (Eigen::Index r = 0; r < m; ++r) {
      double acc = 0.0;
      for (Eigen::Index c = 0; c < 2 * n; ++c)
        acc += Jp[static_cast<unsigned>(r)][static_cast<unsigned>(c)] * in.target_rate(c) / (c % 2 ? cam.py : cam.px);
      out(r) -= acc;
    }
  }
  return out;
}

Eigen::VectorXd IbvsTask::commandOnPoints(const TaskInput& in, const std::vector<Eigen::Index>& active) {
  const CameraIntrinsics& cam = context().camera;
  const Eigen::Index m = in.robot_jacobian.cols();
  const Eigen::Index rows = 2 * static_cast<Eigen::Index>(active.size());
  if (rows == 0) return Eigen::VectorXd::Zero(m);
  const PointFeatures& desired = context().desired_points;
  const Eigen::VectorXd xy_d = cam.toNormalized(desired.uv_px);
  Eigen::MatrixXd L(rows, 6);
  Eigen::VectorXd e(rows), ff = Eigen::VectorXd::Zero(rows);
  for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(active.size()); ++k) {
    const Eigen::Index i = active[static_cast<size_t>(k)];
    const double x = (in.used(2 * i) - cam.u0) / cam.px, y = (in.used(2 * i + 1) - cam.v0) / cam.py;
    const double xd = xy_d(2 * i), yd = xy_d(2 * i + 1);
    const Eigen::Matrix<double, 2, 6> Lc = pointInteraction(x, y, in.depths_m(i));
    const Eigen::Matrix<double, 2, 6> Ld = pointInteraction(xd, yd, desired.Z_m(i));
    L.middleRows<2>(2 * k) = interaction_ == InteractionMatrixType::Current   ? Lc
                             : interaction_ == InteractionMatrixType::Desired ? Ld
                                                                              : Eigen::Matrix<double, 2, 6>(0.5 * (Lc + Ld));
    e.segment<2>(2 * k) << x - xd, y - yd;
    if (in.target_rate.size() != 0)
      ff.segment<2>(2 * k) << in.target_rate(2 * i) / cam.px, in.target_rate(2 * i + 1) / cam.py;
    L_.middleRows<2>(2 * i) = L.middleRows<2>(2 * k);
    error_.segment<2>(2 * i) = e.segment<2>(2 * k);
  }
  // (L J_c)^+ as vpMatrix::pseudoInverse() forms it, and the feed-forward's damped inverse, from one SVD.
  const Eigen::MatrixXd J = L * in.robot_jacobian;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::MatrixXd Jp = inverseFromSvd(svd, 0.0);
  for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(active.size()); ++k) {
    const Eigen::Index i = active[static_cast<size_t>(k)];
    J_px_.row(2 * i) = cam.px * J.row(2 * k);
    J_px_.row(2 * i + 1) = cam.py * J.row(2 * k + 1);
  }
  if (feedforward_damping_ > 0.0) return -lambda_ * (Jp * e) - inverseFromSvd(svd, feedforward_damping_) * ff;
  return -lambda_ * (Jp * e) - Jp * ff;
}

Eigen::MatrixXd IbvsTask::dampedPseudoInverse(const Eigen::MatrixXd& J, double damping) {
  return inverseFromSvd(Eigen::JacobiSVD<Eigen::MatrixXd>(J, Eigen::ComputeThinU | Eigen::ComputeThinV), damping);
}

Eigen::Matrix<double, 2, 6> IbvsTask::pointInteraction(double x, double y, double Z) {
  Eigen::Matrix<double, 2, 6> L;
  L << -1.0 / Z, 0.0, x / Z, x * y, -(1.0 + x * x), y,  //
      0.0, -1.0 / Z, y / Z, 1.0 + y * y, -x * y, -x;
  return L;
}

}  // namespace predvs
