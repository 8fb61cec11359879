#include "predvs/predictors/ekf_smoother.h"
#include "predictors/eigen_test_utils.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <gtest/gtest.h>

#include <random>

namespace predvs {
namespace {

// Two runs of the same arithmetic in the same order, or closed forms on O(1) matrices.
constexpr double kExactTol = 1e-12;
// A reference off s_t + range(J) by round-off only (a few hundred LDLT solves of 12x12 matrices).
constexpr double kRangeTol = 1e-9;
// The forward pass reaches its fixed point geometrically (rate ~0.5 per step here); 200 steps.
constexpr double kFixedPointTol = 1e-8;

constexpr int kDim = 12;  // (x, y, Z) of 4 points
constexpr int kCommands = 6;

using Smoother = ReferenceSmoother<kDim>;
using Vec = Smoother::Vector;
using Mat = Smoother::Matrix;

struct Case {
  Vec s_t, s_star, rc;
  Eigen::Matrix<double, kDim, kCommands> J;
  Mat JQcJt;
};

Case makeCase(unsigned seed, double qc = 1.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Case c;
  for (int i = 0; i < kDim; ++i) {
    c.s_t(i) = 0.3 * g(rng);
    c.s_star(i) = 0.3 * g(rng);
    c.rc(i) = 0.5 + 0.1 * i;
    for (int j = 0; j < kCommands; ++j) c.J(i, j) = g(rng);
  }
  c.JQcJt = qc * c.J * c.J.transpose();
  return c;
}

TEST(ReferenceSmoother, StepCovariancesFollowEquations18To21) {
  // GIVEN J Qc J', the diagonal of Rc and a step of dt
  const Case c = makeCase(1);
  const double dt = 0.08;
  Mat Q, R;
  // WHEN the step covariances are formed
  Smoother::stepCovariances(c.JQcJt, c.rc, dt, Q, R);
  // THEN Q = dt J Qc J' and R = dt^3 / 3 J Qc J' + dt Rc
  EXPECT_TRUE(matricesNear(Q, dt * c.JQcJt, kExactTol));
  Mat R_expected = dt * dt * dt / 3.0 * c.JQcJt;
  R_expected.diagonal() += dt * c.rc;
  EXPECT_TRUE(matricesNear(R, R_expected, kExactTol));
}

TEST(ReferenceSmoother, DualRateWithOneTickFramesIsTheSingleRateSmoother) {
  // GIVEN N = 1: the slow steps of Algorithm 3 are as long as its fast ones
  const Case c = makeCase(2);
  Smoother dr, sr;
  // WHEN Algorithm 3 runs with N = 1, h = 6 and Algorithm 4 with 6 steps of delta
  dr.runDualRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 1, 6);
  sr.runSingleRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 6);
  // THEN every smoothed reference is the same
  ASSERT_EQ(dr.steps(), 6);
  ASSERT_EQ(sr.steps(), 6);
  for (int k = 1; k <= 6; ++k) EXPECT_TRUE(matricesNear(dr.reference(k), sr.reference(k), kExactTol)) << k;
}

TEST(ReferenceSmoother, DualRateWithAOneFrameHorizonIsTheFastPassAlone) {
  // GIVEN h = 1: no slow step
  const Case c = makeCase(3);
  Smoother dr, sr;
  dr.runDualRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 8, 1);
  sr.runSingleRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 8);
  // THEN Algorithm 3 is Algorithm 4 over the N fast steps
  for (int k = 1; k <= 8; ++k) EXPECT_TRUE(matricesNear(dr.reference(k), sr.reference(k), kExactTol)) << k;
}

TEST(ReferenceSmoother, DualRateTakesNPlusHMinusOneStepsToTheSameHorizon) {
  // GIVEN delta = 10 ms, N = 8, h = 8
  const Case c = makeCase(4);
  Smoother dr, hf;
  // WHEN both algorithms run to T = t + h N delta
  dr.runDualRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 8, 8);
  hf.runSingleRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 64);
  // THEN the dual-rate pass has N + h - 1 = 15 steps against h N = 64, both ending at 0.64 s,
  // with the fast steps on the base periods of the first frame
  EXPECT_EQ(dr.steps(), 15);
  EXPECT_EQ(hf.steps(), 64);
  EXPECT_NEAR(dr.stepTime(15), 0.64, kExactTol);
  EXPECT_NEAR(hf.stepTime(64), 0.64, kExactTol);
  for (int i = 1; i <= 8; ++i) EXPECT_NEAR(dr.stepTime(i), 0.01 * i, kExactTol);
  EXPECT_NEAR(dr.stepTime(9), 0.16, kExactTol);
}

TEST(ReferenceSmoother, ReferencesStayWhereTheRobotCanMoveTheFeatures) {
  // GIVEN a 12 x 6 Jacobian: J Qc J' has rank 6, so P(k+1|k) is singular along the whole pass
  const Case c = makeCase(5);
  Smoother dr;
  // WHEN Algorithm 3 runs
  dr.runDualRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 8, 8);
  // THEN every reference (filtered and smoothed) lies in s_t + range(J): the kinematic constraint
  const Eigen::HouseholderQR<Eigen::Matrix<double, kDim, kCommands>> qr(c.J);
  const Eigen::Matrix<double, kDim, kCommands> U = qr.householderQ() * Eigen::Matrix<double, kDim, kCommands>::Identity();
  const Mat off_range = Mat::Identity() - U * U.transpose();
  for (int k = 1; k <= dr.steps(); ++k) {
    const Vec d = dr.reference(k) - c.s_t, f = dr.filtered(k) - c.s_t;
    ASSERT_TRUE(d.allFinite()) << k;
    EXPECT_LT((off_range * d).norm(), kRangeTol * std::max(1.0, d.norm())) << k;
    EXPECT_LT((off_range * f).norm(), kRangeTol * std::max(1.0, f.norm())) << k;
  }
  // AND the references move towards the goal
  EXPECT_LT((dr.reference(8) - c.s_star).norm(), (c.s_t - c.s_star).norm());
}

TEST(ReferenceSmoother, LongHorizonEndsOnTheWeightedProjectionOfTheGoal) {
  // GIVEN a long single-rate pass
  const Case c = makeCase(6);
  Smoother sr;
  sr.runSingleRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 200);
  // THEN its end point is the R-weighted least-squares projection of s* onto s_t + range(J):
  // x = s_t + J a, J' R^-1 (s* - x) = 0 (the fixed point of x <- x + K (s* - x), K = P (P + R)^-1
  // with P in range(J); R is the same at every step)
  Mat Q, R;
  Smoother::stepCovariances(c.JQcJt, c.rc, 0.01, Q, R);
  const Mat Ri = R.inverse();
  const Eigen::Matrix<double, kCommands, kCommands> M = c.J.transpose() * Ri * c.J;
  const Eigen::Matrix<double, kCommands, 1> a = M.ldlt().solve(c.J.transpose() * Ri * (c.s_star - c.s_t));
  EXPECT_TRUE(matricesNear(sr.filtered(200), Vec(c.s_t + c.J * a), kFixedPointTol));
  EXPECT_TRUE(matricesNear(sr.reference(200), sr.filtered(200), 0.0));
}

TEST(ReferenceSmoother, RejectsBadSizesAndHorizons) {
  const Case c = makeCase(7);
  Smoother s;
  EXPECT_THROW(s.runDualRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 8, 0), std::invalid_argument);
  EXPECT_THROW(s.runDualRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.01, 0, 8), std::invalid_argument);
  EXPECT_THROW(s.runSingleRate(c.s_t, c.s_star, c.JQcJt, c.rc, 0.0, 8), std::invalid_argument);
  ReferenceSmoother<> dyn(6);
  EXPECT_THROW(dyn.runSingleRate(Eigen::VectorXd(c.s_t), Eigen::VectorXd(c.s_star), Eigen::MatrixXd(c.JQcJt),
                                 Eigen::VectorXd(c.rc), 0.01, 8),
               std::invalid_argument);
}

}  // namespace
}  // namespace predvs
