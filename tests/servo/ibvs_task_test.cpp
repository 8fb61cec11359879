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

struct Square {
  Eigen::VectorXd sd = (Eigen::VectorXd(8) << -0.1, -0.1, 0.1, -0.1, 0.1, 0.1, -0.1, 0.1).finished();
  Eigen::VectorXd Zd = Eigen::VectorXd::Constant(4, 0.5);
  Eigen::VectorXd s = (Eigen::VectorXd(8) << -0.08, -0.12, 0.12, -0.09, 0.11, 0.1, -0.09, 0.12).finished();
  Eigen::VectorXd Z = Eigen::VectorXd::Constant(4, 0.55);
};

TEST(IbvsTask, ClassicLawWithCurrentMatrix) {
  // GIVEN a square slightly off its goal
  const Square q;
  IbvsTask task({0.8, InteractionMatrixType::Current}, q.sd, q.Zd);
  // WHEN computing the command
  const CameraTwist v = task.computeVelocity(q.s, q.Z);
  // THEN v = -lambda L(s, Z)^+ (s - s*)
  Eigen::MatrixXd L(8, 6);
  for (int i = 0; i < 4; ++i) L.middleRows<2>(2 * i) = IbvsTask::pointInteraction(q.s(2 * i), q.s(2 * i + 1), q.Z(i));
  const Eigen::VectorXd expected = -0.8 * pinv(L) * (q.s - q.sd);
  EXPECT_NEAR((v - expected).norm(), 0.0, kTol);
  EXPECT_NEAR((task.error() - (q.s - q.sd)).norm(), 0.0, kTol);
  EXPECT_NEAR((task.interactionMatrix() - L).norm(), 0.0, kTol);
}

TEST(IbvsTask, FeedForwardSubtractsPseudoInverseOfTargetRate) {
  const Square q;
  IbvsTask plain({1.0, InteractionMatrixType::Desired}, q.sd, q.Zd);
  IbvsTask ff({1.0, InteractionMatrixType::Desired}, q.sd, q.Zd);
  const Eigen::VectorXd rate = (Eigen::VectorXd(8) << 0.01, 0.02, 0.01, 0.02, 0.01, 0.02, 0.01, 0.02).finished();
  const CameraTwist d = ff.computeVelocity(q.s, q.Z, rate) - plain.computeVelocity(q.s, q.Z);
  Eigen::MatrixXd Ld(8, 6);
  for (int i = 0; i < 4; ++i) Ld.middleRows<2>(2 * i) = IbvsTask::pointInteraction(q.sd(2 * i), q.sd(2 * i + 1), 0.5);
  EXPECT_NEAR((d + pinv(Ld) * rate).norm(), 0.0, 1e-8);
}

TEST(IbvsTask, Validation) {
  const Square q;
  EXPECT_THROW(IbvsTask({0.0, InteractionMatrixType::Current}, q.sd, q.Zd), std::invalid_argument);
  EXPECT_THROW(IbvsTask({1.0, InteractionMatrixType::Current}, q.sd, Eigen::VectorXd::Constant(3, 0.5)), std::invalid_argument);
  IbvsTask t({1.0, InteractionMatrixType::Mean}, q.sd, q.Zd);
  EXPECT_THROW(t.computeVelocity(q.s, q.Z, Eigen::VectorXd::Zero(3)), std::invalid_argument);
  EXPECT_EQ(parseInteractionMatrixType("mean"), InteractionMatrixType::Mean);
  EXPECT_THROW(parseInteractionMatrixType("average"), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
