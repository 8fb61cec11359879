// IBVS task: interaction matrix against ViSP's and the control law against its formula.
#include "predvs/tasks/ibvs_task.h"

#include <visp3/visual_features/vpFeaturePoint.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <stdexcept>

namespace predvs {
namespace {

constexpr double kTol = 1e-9;  // the same closed forms, evaluated by two codes

Eigen::MatrixXd pinv(const Eigen::MatrixXd& L) {
  return L.completeOrthogonalDecomposition().pseudoInverse();
}

TEST(IbvsTask, PointInteractionMatchesViSP) {
  vpFeaturePoint p;
  p.buildFrom(0.13, -0.21, 0.7);
  const vpMatrix Lv = p.interaction();
  const Eigen::Matrix<double, 2, 6> L = IbvsTask::pointInteraction(0.13, -0.21, 0.7);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 6; ++c) EXPECT_NEAR(L(r, c), Lv[r][c], kTol);
}

// Square slightly off its goal, in normalised coordinates; the task sees pixels through a camera
// with px = py = 1, u0 = v0 = 0, so pixels and normalised coordinates coincide.
struct Square {
  Eigen::VectorXd sd = (Eigen::VectorXd(8) << -0.1, -0.1, 0.1, -0.1, 0.1, 0.1, -0.1, 0.1).finished();
  Eigen::VectorXd Zd = Eigen::VectorXd::Constant(4, 0.5);
  Eigen::VectorXd s = (Eigen::VectorXd(8) << -0.08, -0.12, 0.12, -0.09, 0.11, 0.1, -0.09, 0.12).finished();
  Eigen::VectorXd Z = Eigen::VectorXd::Constant(4, 0.55);
  Eigen::MatrixXd Jc = Eigen::MatrixXd::Identity(6, 6);  // free-flying camera
  Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  Eigen::MatrixXd none;

  TaskContext context(int m = 6) const {
    TaskContext c;
    c.camera = CameraIntrinsics{1.0, 1.0, 0.0, 0.0};
    c.desired_points.uv_px = sd;
    c.desired_points.Z_m = Zd;
    c.desired_points.seen.assign(4, true);
    c.command_space.kind = "camera-twist";
    c.command_space.names.assign(static_cast<size_t>(m), "u");
    return c;
  }
  Eigen::VectorXd command(Task& task, const Eigen::VectorXd& rate = Eigen::VectorXd(), const Eigen::MatrixXd* J = nullptr) const {
    const TaskInput in{0.0, 0.0, s, s, rate, Z, J ? *J : Jc, q, none};
    return task.computeCommand(in);
  }
};

Params ibvsParams(double lambda, const char* interaction) {
  Params p{{"lambda", lambda}};
  p.setText("interaction", interaction);
  return p;
}

TEST(IbvsTask, ClassicLawWithCurrentMatrix) {
  // GIVEN a square slightly off its goal
  const Square q;
  IbvsTask task(ibvsParams(0.8, "current"), q.context());
  // WHEN computing the command
  const Eigen::VectorXd v = q.command(task);
  // THEN v = -lambda L(s, Z)^+ (s - s*)
  Eigen::MatrixXd L(8, 6);
  for (int i = 0; i < 4; ++i) L.middleRows<2>(2 * i) = IbvsTask::pointInteraction(q.s(2 * i), q.s(2 * i + 1), q.Z(i));
  const Eigen::VectorXd expected = -0.8 * pinv(L) * (q.s - q.sd);
  EXPECT_NEAR((v - expected).norm(), 0.0, kTol);
  EXPECT_NEAR((task.error() - (q.s - q.sd)).norm(), 0.0, kTol);
  EXPECT_NEAR((task.interactionMatrix() - L).norm(), 0.0, kTol);
  // and the feature Jacobian it exposes is that L (pixels = normalised here)
  EXPECT_NEAR((task.featureJacobian() - L).norm(), 0.0, kTol);
}

TEST(IbvsTask, RobotJacobianEntersTheLaw) {
  // GIVEN a robot whose command reaches the camera through a 6 x 3 Jacobian (eJe form of vpServo)
  const Square q;
  Eigen::MatrixXd Jc = Eigen::MatrixXd::Zero(6, 3);
  Jc(0, 0) = 1.0, Jc(2, 1) = 0.5, Jc(5, 2) = 2.0;
  IbvsTask task(ibvsParams(1.0, "current"), q.context(3));
  const Eigen::VectorXd u = q.command(task, Eigen::VectorXd(), &Jc);
  // THEN u = -lambda (L Jc)^+ e and ds/du = L Jc
  Eigen::MatrixXd L(8, 6);
  for (int i = 0; i < 4; ++i) L.middleRows<2>(2 * i) = IbvsTask::pointInteraction(q.s(2 * i), q.s(2 * i + 1), q.Z(i));
  EXPECT_NEAR((u + pinv(L * Jc) * (q.s - q.sd)).norm(), 0.0, kTol);
  EXPECT_NEAR((task.featureJacobian() - L * Jc).norm(), 0.0, kTol);
}

TEST(IbvsTask, FeedForwardSubtractsPseudoInverseOfTargetRate) {
  const Square q;
  IbvsTask plain(ibvsParams(1.0, "desired"), q.context());
  IbvsTask ff(ibvsParams(1.0, "desired"), q.context());
  const Eigen::VectorXd rate = (Eigen::VectorXd(8) << 0.01, 0.02, 0.01, 0.02, 0.01, 0.02, 0.01, 0.02).finished();
  const Eigen::VectorXd d = q.command(ff, rate) - q.command(plain);
  Eigen::MatrixXd Ld(8, 6);
  for (int i = 0; i < 4; ++i) Ld.middleRows<2>(2 * i) = IbvsTask::pointInteraction(q.sd(2 * i), q.sd(2 * i + 1), 0.5);
  EXPECT_NEAR((d + pinv(Ld) * rate).norm(), 0.0, 1e-8);
}

TEST(IbvsTask, Validation) {
  const Square q;
  EXPECT_THROW(IbvsTask(ibvsParams(0.0, "current"), q.context()), std::invalid_argument);
  EXPECT_THROW(IbvsTask(ibvsParams(1.0, "average"), q.context()), std::invalid_argument);
  Params typo = ibvsParams(1.0, "current");
  typo.set("lamda", 2.0);
  EXPECT_THROW(makeTask("ibvs", typo, q.context()), std::invalid_argument);
  EXPECT_THROW(makeTask("ibvz", Params{}, q.context()), std::invalid_argument);
  IbvsTask t(ibvsParams(1.0, "mean"), q.context());
  EXPECT_THROW(q.command(t, Eigen::VectorXd::Zero(3)), std::invalid_argument);
  EXPECT_EQ(parseInteractionMatrixType("mean"), InteractionMatrixType::Mean);
  EXPECT_THROW(parseInteractionMatrixType("average"), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
