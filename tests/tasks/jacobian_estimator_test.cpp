// Tests of the online Jacobian estimators (docs/MODELS.md §7): recovery of a known linear map, tracking
// of a changing map with forgetting, the target-motion term, the excitation threshold, the
// covariance cap, lost rows and configuration errors.
#include "predvs/tasks/jacobian_estimator.h"

#include "predictors/eigen_test_utils.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

constexpr int kFeatures = 8;
constexpr int kInputs = 6;
constexpr double kDt = 0.1;

Eigen::MatrixXd randomMatrix(int rows, int cols, std::mt19937& rng, double scale) {
  std::normal_distribution<double> g(0.0, scale);
  Eigen::MatrixXd M(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) M(i, j) = g(rng);
  return M;
}

double relativeError(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth) {
  return (estimate - truth).norm() / truth.norm();
}

/// Feeds `steps` random increments dp ~ N(0, dp_scale^2 I) of df = J dp + ft dt (+ noise) to `est`.
void feed(JacobianEstimator& est, const Eigen::MatrixXd& J, int steps, std::mt19937& rng, double dp_scale,
          const Eigen::VectorXd& ft_true = Eigen::VectorXd(), const Eigen::VectorXd& ft_given = Eigen::VectorXd(),
          double noise = 0.0) {
  std::normal_distribution<double> g(0.0, 1.0);
  for (int k = 0; k < steps; ++k) {
    Eigen::VectorXd dp(J.cols());
    for (Eigen::Index i = 0; i < dp.size(); ++i) dp(i) = dp_scale * g(rng);
    Eigen::VectorXd df = J * dp;
    if (ft_true.size()) df += ft_true * kDt;
    for (Eigen::Index i = 0; i < df.size(); ++i) df(i) += noise * g(rng);
    est.update(df, dp, ft_given, kDt);
  }
}

class EstimatorMethods : public ::testing::TestWithParam<JacobianMethod> {};

TEST_P(EstimatorMethods, RecoversKnownLinearMapFromExcitingIncrements) {
  // GIVEN a known 8 x 6 linear map (pixel-like scale) and an estimator started at J = 0
  std::mt19937 rng(7);
  const Eigen::MatrixXd J = randomMatrix(kFeatures, kInputs, rng, 500.0);
  JacobianEstimator est(kFeatures, kInputs, {GetParam(), 1.0, 1e-9});
  est.reset(Eigen::MatrixXd::Zero(kFeatures, kInputs), 1e6);
  // WHEN it is fed 300 noise-free random increments
  feed(est, J, 300, rng, 0.01);
  // THEN it recovers J. Tolerance: RLS solves the least-squares problem exactly up to the bias of
  // the prior J0 = 0, weight 1/p0 = 1e-6 against sum |dp_i|^2 ~ 300 * 1e-4 = 0.03 per direction,
  // i.e. ~3e-5 relative; Broyden contracts the error by ~(1 - 1/m) per random direction,
  // (5/6)^300 ~ 1e-24.
  constexpr double kRecoveryTol = 1e-4;
  EXPECT_LT(relativeError(est.jacobian(), J), kRecoveryTol);
  EXPECT_EQ(est.updates(), 300);
}

TEST_P(EstimatorMethods, TargetTermRemovesTheBiasOfAKnownDrift) {
  // GIVEN a static map and a target drifting in the image at a constant 20 px/s on every feature
  std::mt19937 rng(11);
  const Eigen::MatrixXd J = randomMatrix(kFeatures, kInputs, rng, 500.0);
  const Eigen::VectorXd ft = Eigen::VectorXd::Constant(kFeatures, 20.0);
  JacobianEstimatorConfig config{GetParam(), 1.0, 1e-9};
  JacobianEstimator with(kFeatures, kInputs, config), without(kFeatures, kInputs, config);
  with.reset(Eigen::MatrixXd::Zero(kFeatures, kInputs), 1e6);
  without.reset(Eigen::MatrixXd::Zero(kFeatures, kInputs), 1e6);
  // WHEN both see the same increments (0.3 px noise), one told ft, the other not
  std::mt19937 rng_a(3), rng_b(3);
  feed(with, J, 400, rng_a, 0.01, ft, ft, 0.3);
  feed(without, J, 400, rng_b, 0.01, ft, Eigen::VectorXd(), 0.3);
  // THEN the one given ft is unbiased and the other is not. The drift adds 2 px per step against
  // ~5 px of J dp per entry, so ignoring it errs by tens of percent (Broyden) or, for the RLS
  // average, by the projection of a constant on zero-mean dp (smaller but far above the noise
  // floor); with ft only the 0.3 px noise remains (a few percent at most for Broyden, which
  // keeps no memory, under 1 % for RLS).
  const double tol_with = GetParam() == JacobianMethod::Rls ? 0.01 : 0.1;
  EXPECT_LT(relativeError(with.jacobian(), J), tol_with);
  EXPECT_GT(relativeError(without.jacobian(), J), 2.0 * relativeError(with.jacobian(), J));
}

INSTANTIATE_TEST_SUITE_P(JacobianEstimator, EstimatorMethods,
                         ::testing::Values(JacobianMethod::Broyden, JacobianMethod::Rls),
                         [](const auto& info) { return jacobianMethodName(info.param); });

TEST(JacobianEstimator, RlsWithForgettingTracksAChangingJacobian) {
  // GIVEN a map that jumps from J_a to J_b, and RLS with and without forgetting
  std::mt19937 rng(5);
  const Eigen::MatrixXd J_a = randomMatrix(kFeatures, kInputs, rng, 500.0);
  const Eigen::MatrixXd J_b = J_a + randomMatrix(kFeatures, kInputs, rng, 100.0);
  JacobianEstimator forgetting(kFeatures, kInputs, {JacobianMethod::Rls, 0.8, 1e-9});
  JacobianEstimator remembering(kFeatures, kInputs, {JacobianMethod::Rls, 1.0, 1e-9});
  forgetting.reset(Eigen::MatrixXd::Zero(kFeatures, kInputs), 1e6);
  remembering.reset(Eigen::MatrixXd::Zero(kFeatures, kInputs), 1e6);
  std::mt19937 r1(9), r2(9);
  feed(forgetting, J_a, 200, r1, 0.01, {}, {}, 0.1);
  feed(remembering, J_a, 200, r2, 0.01, {}, {}, 0.1);
  // WHEN 60 increments of J_b follow
  feed(forgetting, J_b, 60, r1, 0.01, {}, {}, 0.1);
  feed(remembering, J_b, 60, r2, 0.01, {}, {}, 0.1);
  // THEN forgetting (memory 1 / (1 - 0.8) = 5 steps) has converged to J_b, to the noise floor
  // (0.1 px against ~5 px per entry: well under 5 %), while plain RLS still averages in J_a
  constexpr double kTrackingTol = 0.05;
  EXPECT_LT(relativeError(forgetting.jacobian(), J_b), kTrackingTol);
  EXPECT_GT(relativeError(remembering.jacobian(), J_b), 3.0 * relativeError(forgetting.jacobian(), J_b));
}

TEST(JacobianEstimator, SkipsIncrementsBelowTheExcitationThreshold) {
  // GIVEN an estimator with min_dp = 1e-3
  for (const JacobianMethod method : {JacobianMethod::Broyden, JacobianMethod::Rls}) {
    JacobianEstimator est(2, 2, {method, 0.9, 1e-3});
    const Eigen::MatrixXd J0 = Eigen::MatrixXd::Identity(2, 2);
    est.reset(J0, 10.0);
    const Eigen::VectorXd df = Eigen::Vector2d(5.0, -3.0);
    // WHEN the increment is just below the threshold
    const bool below = est.update(df, Eigen::Vector2d(0.9e-3, 0.0), {}, kDt);
    // THEN nothing changes (not even P, which forgetting would otherwise inflate)
    EXPECT_FALSE(below);
    EXPECT_EQ(est.jacobian(), J0);
    EXPECT_EQ(est.covariance(), Eigen::MatrixXd(10.0 * Eigen::MatrixXd::Identity(2, 2)));
    EXPECT_EQ(est.updates(), 0);
    // AND just above it, J moves
    EXPECT_TRUE(est.update(df, Eigen::Vector2d(1.1e-3, 0.0), {}, kDt));
    EXPECT_NE(est.jacobian(), J0);
    EXPECT_EQ(est.updates(), 1);
  }
}

TEST(JacobianEstimator, CovarianceStaysSymmetricAndBoundedUnderPoorExcitation) {
  // GIVEN RLS with strong forgetting, excited along one input direction only for 2000 steps
  JacobianEstimator est(4, 3, {JacobianMethod::Rls, 0.7, 1e-9});
  // (p0 |dp|^2 = 100: the prior is weak against one increment, as in the task's default)
  constexpr double kP0 = 1e6;
  est.reset(Eigen::MatrixXd::Zero(4, 3), kP0);
  const Eigen::Vector4d df(1.0, 2.0, 3.0, 4.0);
  for (int k = 0; k < 2000; ++k) est.update((k % 2 ? 1.0 : -1.0) * df, Eigen::Vector3d((k % 2 ? 1.0 : -1.0) * 0.01, 0.0, 0.0), {}, kDt);
  // THEN P (unexcited directions would grow as 0.7^-2000 without the cap) stays symmetric PSD and
  // no eigenvalue exceeds p0 (tolerance: round-off of a 3 x 3 eigen-decomposition)
  constexpr double kRoundOff = 1e-9;
  EXPECT_TRUE(isSymmetricPsd(est.covariance(), kRoundOff));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(est.covariance());
  EXPECT_LE(es.eigenvalues().maxCoeff(), kP0 * (1.0 + kRoundOff));
  EXPECT_GT(est.covarianceCaps(), 0);
  EXPECT_TRUE(est.jacobian().allFinite());
  // AND the excited column is still learnt (df = J e_0 * 0.01 => J column 0 = 100 df; consistent
  // data, so only round-off remains: its P settles at (1 - lambda) / |dp|^2 = 3000, below the cap),
  // while the unexcited columns stay at J0 = 0
  constexpr double kLearntTol = 1e-9;
  EXPECT_TRUE(matricesNear(est.jacobian().col(0), Eigen::VectorXd(100.0 * df), kLearntTol));
  EXPECT_TRUE(matricesNear(est.jacobian().rightCols(2), Eigen::MatrixXd::Zero(4, 2), kLearntTol));
}

TEST(JacobianEstimator, LostRowsAreLeftUntouched) {
  // GIVEN an estimator at J0 and an increment whose feature 1 is lost (NaN)
  JacobianEstimator est(3, 2, {JacobianMethod::Rls, 1.0, 1e-9});
  const Eigen::MatrixXd J0 = Eigen::MatrixXd::Constant(3, 2, 1.0);
  est.reset(J0, 100.0);
  const Eigen::Vector3d df(0.5, std::numeric_limits<double>::quiet_NaN(), 0.7);
  // WHEN it updates
  EXPECT_TRUE(est.update(df, Eigen::Vector2d(0.1, 0.2), {}, kDt));
  // THEN row 1 is unchanged and finite, the others moved
  EXPECT_EQ(est.jacobian().row(1), J0.row(1));
  EXPECT_NE(est.jacobian().row(0), J0.row(0));
  EXPECT_TRUE(est.jacobian().allFinite());
  // AND an increment with nothing finite is skipped
  EXPECT_FALSE(est.update(Eigen::Vector3d::Constant(std::nan("")), Eigen::Vector2d(0.1, 0.2), {}, kDt));
}

TEST(JacobianEstimator, RejectsBadConfigurationNamingTheKey) {
  // GIVEN forgetting factors outside (0, 1] and a negative threshold, THEN construction throws
  // naming the parameter
  for (const double lambda : {0.0, -0.5, 1.5}) {
    try {
      JacobianEstimator est(2, 2, {JacobianMethod::Rls, lambda, 0.0});
      ADD_FAILURE() << "lambda " << lambda << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("lambda"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(JacobianEstimator(2, 2, {JacobianMethod::Rls, 0.9, -1.0}), std::invalid_argument);
  EXPECT_THROW(parseJacobianMethod("newton", "task.method"), std::invalid_argument);
  EXPECT_EQ(parseJacobianMethod("broyden"), JacobianMethod::Broyden);
  JacobianEstimator est(2, 3);
  EXPECT_THROW(est.reset(Eigen::MatrixXd::Zero(3, 2), 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
