#include "predvs/tasks/reference_filtering_task.h"

#include "predvs/predictors/dual_rate_kf.h"
#include "predvs/predictors/ekf_smoother.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// Two times closer than this fraction of a base period are the same tick (rounding of k delta).
constexpr double kTickFraction = 1e-6;
// Prior on a feature's velocity before the second frame: what the acceleration noise reaches in 1 s.
constexpr double kInitialVelocityHorizon_s = 1.0;

/// x = A^+ b through the SVD, singular values below kPinvRelTolerance sigma_max dropped.
Eigen::VectorXd pinvSolve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.cols());
  if (sigma.size() == 0 || !(sigma(0) > 0.0)) return x;
  const Eigen::VectorXd Utb = svd.matrixU().transpose() * b;
  for (Eigen::Index i = 0; i < sigma.size(); ++i)
    if (sigma(i) > kPinvRelTolerance * sigma(0)) x += svd.matrixV().col(i) * (Utb(i) / sigma(i));
  return x;
}

/// The reference smoother at a size fixed at compile time where it is known (4 points: 12).
class SmootherRunner {
 public:
  virtual ~SmootherRunner() = default;
  virtual void runSingle(const Eigen::VectorXd& s, const Eigen::VectorXd& sd, const Eigen::MatrixXd& JQcJt,
                         const Eigen::VectorXd& rc, double dt, int steps) = 0;
  virtual void runDual(const Eigen::VectorXd& s, const Eigen::VectorXd& sd, const Eigen::MatrixXd& JQcJt,
                       const Eigen::VectorXd& rc, double delta, int N, int h) = 0;
  virtual Eigen::VectorXd reference(int k) const = 0;
};

template <int Dim>
class SmootherRunnerOf final : public SmootherRunner {
 public:
  explicit SmootherRunnerOf(Eigen::Index dim) : smoother_(dim) {}
  void runSingle(const Eigen::VectorXd& s, const Eigen::VectorXd& sd, const Eigen::MatrixXd& JQcJt,
                 const Eigen::VectorXd& rc, double dt, int steps) override {
    smoother_.runSingleRate(s, sd, JQcJt, rc, dt, steps);
  }
  void runDual(const Eigen::VectorXd& s, const Eigen::VectorXd& sd, const Eigen::MatrixXd& JQcJt,
               const Eigen::VectorXd& rc, double delta, int N, int h) override {
    smoother_.runDualRate(s, sd, JQcJt, rc, delta, N, h);
  }
  Eigen::VectorXd reference(int k) const override { return smoother_.reference(k); }

 private:
  ReferenceSmoother<Dim> smoother_;
};

std::unique_ptr<SmootherRunner> makeRunner(Eigen::Index dim) {
  if (dim == 12) return std::make_unique<SmootherRunnerOf<12>>(dim);
  return std::make_unique<SmootherRunnerOf<Eigen::Dynamic>>(dim);
}

bool usesSmoother(ReferenceFilteringLaw law) {
  return law == ReferenceFilteringLaw::SrLfEkfsIbvs || law == ReferenceFilteringLaw::SrHfEkfsIbvs ||
         law == ReferenceFilteringLaw::DrEkfsIbvs;
}
bool oncePerFrame(ReferenceFilteringLaw law) {
  return law == ReferenceFilteringLaw::SrLfIbvs || law == ReferenceFilteringLaw::SrLfEkfsIbvs;
}

}  // namespace

std::string referenceFilteringLawName(ReferenceFilteringLaw law) {
  switch (law) {
    case ReferenceFilteringLaw::SrLfIbvs: return "sr-lf-ibvs";
    case ReferenceFilteringLaw::SrHfIbvs: return "sr-hf-ibvs";
    case ReferenceFilteringLaw::SrLfEkfsIbvs: return "sr-lf-ekfs-ibvs";
    case ReferenceFilteringLaw::SrHfEkfsIbvs: return "sr-hf-ekfs-ibvs";
    case ReferenceFilteringLaw::DrEkfsIbvs: return "dr-ekfs-ibvs";
  }
  return "?";
}

struct ReferenceFilteringTask::Impl {
  std::unique_ptr<SmootherRunner> smoother;
  std::unique_ptr<DualRateKf> kf;
  bool have_frame = false;
  double last_t_acq_s = kNaN;
  double t_kf_s = kNaN;  // time of the DR-KF's estimate (acquisition of its last frame)
  // The current plan: once-per-frame laws hold commands[0]; the dual-rate law applies commands[i]
  // at the i-th base period after plan_t_s.
  double plan_t_s = kNaN;
  std::vector<Eigen::VectorXd> commands;
  std::vector<double> feature_errors, reference_errors;
};

ReferenceFilteringTask::ReferenceFilteringTask(ReferenceFilteringLaw law, const Params& params,
                                               const TaskContext& context)
    : PointTask(context),
      law_(law),
      lambda_(params.get("lambda", 1.0)),
      interaction_(parseInteractionMatrixType(params.text("interaction", "current"))),
      depth_m_(params.get("depth", 0.0, 0.0, kInf)),
      depth_rows_(params.get("depth_rows", 0.0, 0.0, 1.0) != 0.0),
      delta_s_(context.base_period_s),
      impl_(std::make_unique<Impl>()) {
  const std::string what = "task '" + name() + "'";
  if (!(lambda_ > 0.0) || !std::isfinite(lambda_))
    throw std::invalid_argument("task.lambda must be > 0, got " + std::to_string(lambda_));
  if (!(delta_s_ > 0.0) || !std::isfinite(delta_s_) || !(context.frame_period_s >= delta_s_))
    throw std::invalid_argument(what + ": needs base_period_s > 0 and frame_period_s >= base_period_s");
  N_ = static_cast<int>(std::lround(context.frame_period_s / delta_s_));
  if (std::abs(N_ * delta_s_ - context.frame_period_s) > kTickFraction * delta_s_)
    throw std::invalid_argument(what + ": the frame period is not a whole number of base periods");
  const int n = context.desired_points.points();
  if (context.command_space.size() < 1) throw std::invalid_argument(what + ": the robot has no command");
  for (int i = 0; i < n; ++i)
    if (!(context.desired_points.Z_m(i) > 0.0) && !(depth_m_ > 0.0))
      throw std::invalid_argument(what + ": desired depth of point " + std::to_string(i) + " must be > 0");

  if (usesSmoother(law_)) {
    horizon_frames_ = static_cast<int>(params.get("horizon", 8.0, 1.0, 10000.0));
    if (params.get("horizon", 8.0) != horizon_frames_)
      throw std::invalid_argument("task.horizon must be a whole number of frames");
    qc_ = params.get("qc", 1.0, 1e-300, kInf);
    const double rc = params.get("rc", 1.0, 1e-300, kInf);
    const double rc_z = params.get("rc_z", rc, 1e-300, kInf);
    rc_diag_.resize(3 * n);
    for (int i = 0; i < n; ++i) rc_diag_.segment<3>(3 * i) << rc, rc, rc_z;
    impl_->smoother = makeRunner(3 * n);
  }
  if (law_ == ReferenceFilteringLaw::DrEkfsIbvs) {
    const CameraIntrinsics& cam = context.camera;
    const double accel_px = params.get("kf_accel", 2000.0, 0.0, kInf);
    const double sigma_px = params.get("kf_sigma", 0.5, 1e-300, kInf);
    const double accel_z = params.get("kf_accel_z", 2.0, 0.0, kInf);
    const double sigma_z = params.get("kf_sigma_z", 0.001, 1e-300, kInf);
    DualRateKfConfig kc;
    kc.base_period_s = delta_s_;
    kc.frame_ticks = N_;
    kc.accel_std.resize(3 * n);
    kc.measurement_std.resize(3 * n);
    for (int i = 0; i < n; ++i) {
      kc.accel_std.segment<3>(3 * i) << accel_px / cam.px, accel_px / cam.py, accel_z;
      kc.measurement_std.segment<3>(3 * i) << sigma_px / cam.px, sigma_px / cam.py, sigma_z;
    }
    kc.initial_velocity_std = (kInitialVelocityHorizon_s * kc.accel_std).cwiseMax(kc.measurement_std);
    impl_->kf = std::make_unique<DualRateKf>(kc);
  }
  params.requireAllUsed(what);

  desired_xyz_ = toXyz(context.desired_points.uv_px, context.desired_points.Z_m);
  H_diag_.resize(3 * n);
  for (int i = 0; i < n; ++i) H_diag_.segment<3>(3 * i) << 1.0, 1.0, 0.0;
  J_px_ = Eigen::MatrixXd::Zero(2 * n, context.command_space.size());
  reference_ = desired_xyz_;
}

ReferenceFilteringTask::~ReferenceFilteringTask() = default;

Eigen::VectorXd ReferenceFilteringTask::toXyz(const Eigen::VectorXd& s_px, const Eigen::VectorXd& Z_m) const {
  const CameraIntrinsics& cam = context().camera;
  const PointFeatures& desired = context().desired_points;
  const Eigen::Index n = s_px.size() / 2;
  Eigen::VectorXd xyz(3 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    double Z = depth_m_;
    if (!(Z > 0.0)) {
      Z = i < Z_m.size() ? Z_m(i) : kNaN;
      if (!(Z > 0.0) || !std::isfinite(Z)) Z = desired.Z_m(i);
    }
    xyz.segment<3>(3 * i) << (s_px(2 * i) - cam.u0) / cam.px, (s_px(2 * i + 1) - cam.v0) / cam.py, Z;
  }
  return xyz;
}

Eigen::Matrix<double, 3, 6> ReferenceFilteringTask::pointInteraction(double x, double y, double Z) {
  Eigen::Matrix<double, 3, 6> L;
  L << -1.0 / Z, 0.0, x / Z, x * y, -(1.0 + x * x), y,  //
      0.0, -1.0 / Z, y / Z, 1.0 + y * y, -x * y, -x,     //
      0.0, 0.0, -1.0, -y * Z, x * Z, 0.0;
  return L;
}

Eigen::MatrixXd ReferenceFilteringTask::interactionMatrix(const Eigen::VectorXd& xyz) {
  const Eigen::Index n = xyz.size() / 3;
  Eigen::MatrixXd L(3 * n, 6);
  for (Eigen::Index i = 0; i < n; ++i) L.middleRows<3>(3 * i) = pointInteraction(xyz(3 * i), xyz(3 * i + 1), xyz(3 * i + 2));
  return L;
}

Eigen::MatrixXd ReferenceFilteringTask::chosenInteraction(const Eigen::VectorXd& s) const {
  switch (interaction_) {
    case InteractionMatrixType::Current: return interactionMatrix(s);
    case InteractionMatrixType::Desired: return interactionMatrix(desired_xyz_);
    case InteractionMatrixType::Mean: return 0.5 * (interactionMatrix(s) + interactionMatrix(desired_xyz_));
  }
  return interactionMatrix(s);
}

Eigen::VectorXd ReferenceFilteringTask::law(const Eigen::VectorXd& s, const Eigen::VectorXd& s_ref,
                                            const Eigen::MatrixXd& robot_jacobian) const {
  return -lambda_ * pinvSolve(lawJacobian(s, robot_jacobian), H_diag_.cwiseProduct(s - s_ref));
}

Eigen::MatrixXd ReferenceFilteringTask::lawJacobian(const Eigen::VectorXd& s, const Eigen::MatrixXd& robot_jacobian) const {
  Eigen::MatrixXd J = chosenInteraction(s) * robot_jacobian;
  if (!depth_rows_) J = H_diag_.asDiagonal() * J;
  return J;
}

Eigen::VectorXd ReferenceFilteringTask::singleRateReference(const Eigen::VectorXd& s,
                                                            const Eigen::MatrixXd& robot_jacobian, double dt,
                                                            int steps) {
  const Eigen::MatrixXd J = chosenInteraction(s) * robot_jacobian;
  impl_->smoother->runSingle(s, desired_xyz_, qc_ * J * J.transpose(), rc_diag_, dt, steps);
  return impl_->smoother->reference(1);
}

void ReferenceFilteringTask::setPixelJacobian(const Eigen::VectorXd& xyz, const Eigen::MatrixXd& robot_jacobian) {
  // The x, y rows of the interaction matrix the law used, in pixels: diag(px, py) L_xy J_c.
  const CameraIntrinsics& cam = context().camera;
  const Eigen::MatrixXd LJ = chosenInteraction(xyz) * robot_jacobian;
  const Eigen::Index n = xyz.size() / 3;
  for (Eigen::Index i = 0; i < n; ++i) {
    J_px_.row(2 * i) = cam.px * LJ.row(3 * i);
    J_px_.row(2 * i + 1) = cam.py * LJ.row(3 * i + 1);
  }
}

void ReferenceFilteringTask::planFrame(const TaskInput& in, bool new_frame) {
  Impl& m = *impl_;
  const int N = N_;
  const Eigen::Index n_cmd = in.robot_jacobian.cols();
  m.plan_t_s = in.t_s;
  m.commands.assign(static_cast<size_t>(N), Eigen::VectorXd::Zero(n_cmd));
  m.feature_errors.assign(static_cast<size_t>(N), kNaN);
  m.reference_errors.assign(static_cast<size_t>(N), kNaN);

  if (law_ != ReferenceFilteringLaw::DrEkfsIbvs) {
    // Once per frame on the features the loop gives, the command held for the frame.
    const Eigen::VectorXd s = toXyz(in.used, in.depths_m);
    if (!s.allFinite()) return;
    reference_ = law_ == ReferenceFilteringLaw::SrLfEkfsIbvs
                     ? singleRateReference(s, in.robot_jacobian, N * delta_s_, horizon_frames_)
                     : desired_xyz_;
    m.commands.assign(static_cast<size_t>(N), law(s, reference_, in.robot_jacobian));
    m.feature_errors.assign(static_cast<size_t>(N), H_diag_.cwiseProduct(s - desired_xyz_).norm());
    m.reference_errors.assign(static_cast<size_t>(N), H_diag_.cwiseProduct(reference_ - desired_xyz_).norm());
    setPixelJacobian(s, in.robot_jacobian);
    return;
  }

  // Algorithm 1 with the latency of the timing model. DR-KF (Algorithm 2): predict over the frames
  // since its last estimate (more than one when frames were missed), then fuse this frame.
  DualRateKf& kf = *m.kf;
  if (new_frame) {
    const Eigen::VectorXd z = toXyz(in.measured, in.depths_m);
    const double T = N * delta_s_;
    if (std::isfinite(m.t_kf_s)) {
      const long frames = std::max(1L, std::lround((in.t_acq_s - m.t_kf_s) / T));
      for (long f = 0; f < frames; ++f) kf.predict();
    }
    kf.update(z);
    m.t_kf_s = in.t_acq_s;
  }
  // Predictions s(t+i|t_acq), i = 0..N, at the base periods from this tick on.
  const double offset = (in.t_s - m.t_kf_s) / delta_s_;
  std::vector<Eigen::VectorXd> p(static_cast<size_t>(N) + 1);
  for (int i = 0; i <= N; ++i) {
    p[static_cast<size_t>(i)] = kf.predictTicks(offset + i);
    if (!p[static_cast<size_t>(i)].allFinite()) return;  // a channel never measured: wait
  }
  // DR-EKFS (Algorithm 3) from the prediction at this tick.
  const Eigen::MatrixXd J0 = chosenInteraction(p[0]) * in.robot_jacobian;
  m.smoother->runDual(p[0], desired_xyz_, qc_ * J0 * J0.transpose(), rc_diag_, delta_s_, N, horizon_frames_);
  // DR-IBVS (Algorithm 5): one command per base period of the frame.
  for (int i = 0; i < N; ++i) {
    const Eigen::VectorXd r = m.smoother->reference(i + 1);
    const Eigen::VectorXd& s_i = p[static_cast<size_t>(i)];
    const Eigen::VectorXd& s_next = p[static_cast<size_t>(i) + 1];
    m.commands[static_cast<size_t>(i)] =
        -lambda_ * pinvSolve(lawJacobian(s_i, in.robot_jacobian), H_diag_.cwiseProduct(s_next - r));
    m.feature_errors[static_cast<size_t>(i)] = H_diag_.cwiseProduct(s_next - desired_xyz_).norm();
    m.reference_errors[static_cast<size_t>(i)] = H_diag_.cwiseProduct(r - desired_xyz_).norm();
  }
  reference_ = m.smoother->reference(1);
  setPixelJacobian(p[0], in.robot_jacobian);
}

Eigen::VectorXd ReferenceFilteringTask::computeCommand(const TaskInput& in) {
  Impl& m = *impl_;
  const Eigen::Index n = featureSize() / 2, n_cmd = context().command_space.size();
  if (in.used.size() != 2 * n || in.measured.size() != 2 * n || in.depths_m.size() != n ||
      in.robot_jacobian.rows() != 6 || in.robot_jacobian.cols() != n_cmd) {
    std::ostringstream msg;
    msg << "task '" << name() << "': got " << in.used.size() << " features, " << in.depths_m.size() << " depths and a "
        << in.robot_jacobian.rows() << "x" << in.robot_jacobian.cols() << " robot Jacobian for " << n << " points and "
        << n_cmd << " commands";
    throw std::invalid_argument(msg.str());
  }
  const bool new_frame = !m.have_frame || in.t_acq_s != m.last_t_acq_s;
  m.have_frame = true;
  m.last_t_acq_s = in.t_acq_s;

  Eigen::VectorXd u = Eigen::VectorXd::Zero(n_cmd);
  if (law_ == ReferenceFilteringLaw::SrHfIbvs || law_ == ReferenceFilteringLaw::SrHfEkfsIbvs) {
    // Every base period, on the latest features the loop gives.
    const Eigen::VectorXd s = toXyz(in.used, in.depths_m);
    if (s.allFinite()) {
      reference_ = law_ == ReferenceFilteringLaw::SrHfEkfsIbvs
                       ? singleRateReference(s, in.robot_jacobian, delta_s_, horizon_frames_ * N_)
                       : desired_xyz_;
      u = law(s, reference_, in.robot_jacobian);
      feature_error_norm_ = H_diag_.cwiseProduct(s - desired_xyz_).norm();
      reference_error_norm_ = H_diag_.cwiseProduct(reference_ - desired_xyz_).norm();
      setPixelJacobian(s, in.robot_jacobian);
    }
  } else {
    const double ticks = std::isfinite(m.plan_t_s) ? (in.t_s - m.plan_t_s) / delta_s_ : kInf;
    const bool replan = new_frame || (!oncePerFrame(law_) && ticks > N_ - 1 + kTickFraction);
    if (replan) planFrame(in, new_frame);
    const long i = replan ? 0 : std::lround((in.t_s - m.plan_t_s) / delta_s_);
    // A once-per-frame law holds its command until the next frame.
    const size_t k = static_cast<size_t>(std::clamp<long>(i, 0, N_ - 1));
    u = m.commands[k];
    feature_error_norm_ = m.feature_errors[k];
    reference_error_norm_ = m.reference_errors[k];
  }
  peak_command_ = std::max(peak_command_, u.norm());
  return u;
}

NamedValues ReferenceFilteringTask::diagnostics() const {
  if (usesSmoother(law_))
    return {{"feature_error_norm", feature_error_norm_}, {"reference_error_norm", reference_error_norm_}};
  return {{"feature_error_norm", feature_error_norm_}};
}

NamedValues ReferenceFilteringTask::runSummary() const { return {{"peak_command", peak_command_}}; }

}  // namespace predvs
