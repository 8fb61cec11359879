// IBVS task: interaction matrix against ViSP's and the control law against its formula.
#include "predvs/tasks/ibvs_task.h"

#include <visp3/visual_features/vpFeaturePoint.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <limits>
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
  // GIVEN the papers' law: no damping in the feed-forward
  const Square q;
  Params params = ibvsParams(1.0, "desired");
  params.set("feedforward_damping", 0.0);
  IbvsTask plain(params, q.context());
  IbvsTask ff(params, q.context());
  const Eigen::VectorXd rate = (Eigen::VectorXd(8) << 0.01, 0.02, 0.01, 0.02, 0.01, 0.02, 0.01, 0.02).finished();
  const Eigen::VectorXd d = q.command(ff, rate) - q.command(plain);
  Eigen::MatrixXd Ld(8, 6);
  for (int i = 0; i < 4; ++i) Ld.middleRows<2>(2 * i) = IbvsTask::pointInteraction(q.sd(2 * i), q.sd(2 * i + 1), 0.5);
  EXPECT_NEAR((d + pinv(Ld) * rate).norm(), 0.0, 1e-8);
}

/// (J' J + mu^2 I)^-1 J' rate: the damped least-squares solution, by the normal equations.
Eigen::VectorXd dampedSolve(const Eigen::MatrixXd& J, double kappa, const Eigen::VectorXd& rate) {
  const double mu = kappa * Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues()(0);
  const Eigen::MatrixXd A = J.transpose() * J + mu * mu * Eigen::MatrixXd::Identity(J.cols(), J.cols());
  return A.ldlt().solve(J.transpose() * rate);
}

TEST(IbvsTask, TheFeedForwardGoesThroughADampedInverseByDefault) {
  // GIVEN the default task on the square (4 points 0.2 apart at 0.55 m: an ill-conditioned L)
  const Square q;
  IbvsTask plain(ibvsParams(1.0, "current"), q.context());
  IbvsTask ff(ibvsParams(1.0, "current"), q.context());
  EXPECT_EQ(ff.feedforwardDamping(), kDefaultFeedforwardDamping);
  EXPECT_GT(kDefaultFeedforwardDamping, 0.0);
  Eigen::MatrixXd L(8, 6);
  for (int i = 0; i < 4; ++i) L.middleRows<2>(2 * i) = IbvsTask::pointInteraction(q.s(2 * i), q.s(2 * i + 1), q.Z(i));
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(L, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  ASSERT_GT(sv(0) / sv(5), 100.0);  // the translation-rotation ambiguity
  // WHEN the target rate is any rate, the largest singular direction, or the smallest
  const Eigen::VectorXd rate = (Eigen::VectorXd(8) << 0.01, -0.02, 0.03, 0.02, -0.01, 0.02, 0.01, 0.04).finished();
  const Eigen::VectorXd big = svd.matrixU().col(0), small = svd.matrixU().col(5);
  auto feedForward = [&](const Eigen::VectorXd& r) { return Eigen::VectorXd(q.command(ff, r) - q.command(plain)); };
  // THEN the feed-forward is the damped least-squares solution, mu = kappa s_0
  EXPECT_NEAR((feedForward(rate) + dampedSolve(L, kDefaultFeedforwardDamping, rate)).norm(), 0.0, 1e-8);
  EXPECT_NEAR((IbvsTask::dampedPseudoInverse(L, 0.0) - pinv(L)).norm(), 0.0, 1e-8);
  // AND a rate on the largest direction passes within 0.1 %, one on the smallest is cut over 10x
  const double big_plain = (pinv(L) * big).norm(), small_plain = (pinv(L) * small).norm();
  EXPECT_NEAR(feedForward(big).norm() / big_plain, 1.0, 1e-3);
  EXPECT_LT(feedForward(small).norm() / small_plain, 0.1);
}

TEST(IbvsTask, WithAPointDroppedTheFeedForwardIsDampedOnTheOthers) {
  // GIVEN the default task and a rate, with point 2 dropped (NaN)
  const Square q;
  IbvsTask plain(ibvsParams(1.0, "current"), q.context());
  IbvsTask ff(ibvsParams(1.0, "current"), q.context());
  Eigen::VectorXd s = q.s;
  s.segment<2>(4).setConstant(std::numeric_limits<double>::quiet_NaN());
  const Eigen::VectorXd rate = (Eigen::VectorXd(8) << 0.01, -0.02, 0.03, 0.02, -0.01, 0.02, 0.01, 0.04).finished();
  const TaskInput with{0.0, 0.0, s, s, rate, q.Z, q.Jc, q.q, q.none}, without{0.0, 0.0, s, s, Eigen::VectorXd(), q.Z, q.Jc, q.q, q.none};
  const Eigen::VectorXd d = ff.computeCommand(with) - plain.computeCommand(without);
  // THEN the feed-forward is the damped solution on the three points left
  Eigen::MatrixXd L(6, 6);
  Eigen::VectorXd r(6);
  int k = 0;
  for (int i : {0, 1, 3}) {
    L.middleRows<2>(2 * k) = IbvsTask::pointInteraction(q.s(2 * i), q.s(2 * i + 1), q.Z(i));
    r.segment<2>(2 * k) = rate.segment<2>(2 * i);
    ++k;
  }
  EXPECT_NEAR((d + dampedSolve(L, kDefaultFeedforwardDamping, r)).norm(), 0.0, 1e-8);
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
  for (double bad : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    Params p = ibvsParams(1.0, "current");
    p.set("feedforward_damping", bad);
    EXPECT_THROW(IbvsTask(p, q.context()), std::invalid_argument) << bad;
  }
  EXPECT_EQ(parseInteractionMatrixType("mean"), InteractionMatrixType::Mean);
  EXPECT_THROW(parseInteractionMatrixType("average"), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
