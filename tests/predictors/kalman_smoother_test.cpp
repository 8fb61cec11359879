#include "predvs/predictors/kalman_smoother.h"
#include "predictors/eigen_test_utils.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace predvs {
namespace {

// The smoother and the batch solution are two exact solutions of the same normal equations, each
// with a few Cholesky / LDLT solves of well-conditioned matrices.
constexpr double kSolutionTol = 1e-9;
// Covariance identities on O(1) matrices: round-off only.
constexpr double kCovTol = 1e-12;

Eigen::MatrixXd randomSpd(Eigen::Index n, std::mt19937& rng, double floor) {
  const Eigen::MatrixXd G = randomMatrix(n, n, rng);
  return G * G.transpose() + floor * Eigen::MatrixXd::Identity(n, n);
}

/// A linear Gaussian problem: x0 ~ N(m0, P0), x(k+1) = F x(k) + w, w ~ N(0, Q), z(k) = H x(k) + v
/// for k = 0..K.
struct Problem {
  Eigen::VectorXd m0;
  Eigen::MatrixXd P0, F, Q, H, R;
  std::vector<Eigen::VectorXd> z;
};

Problem makeProblem(std::mt19937& rng, int K) {
  const int n = 3, p = 2;
  Problem pr;
  pr.m0 = randomMatrix(n, 1, rng);
  pr.P0 = randomSpd(n, rng, 0.5);
  pr.F = Eigen::MatrixXd::Identity(n, n) + randomMatrix(n, n, rng, 0.1);
  pr.Q = 0.1 * randomSpd(n, rng, 0.2);
  pr.H = randomMatrix(p, n, rng);
  pr.R = 0.2 * randomSpd(p, rng, 0.5);
  for (int k = 0; k <= K; ++k) pr.z.push_back(randomMatrix(p, 1, rng));
  return pr;
}

/// The smoothed means are the minimiser over (x0..xK) of
///   |x0 - m0|^2_{P0^-1} + sum |x(k+1) - F x(k)|^2_{Q^-1} + sum |z(k) - H x(k)|^2_{R^-1},
/// solved here as one dense linear least-squares problem (normal equations).
std::vector<Eigen::VectorXd> batchLeastSquares(const Problem& pr) {
  const Eigen::Index n = pr.m0.size(), K = static_cast<Eigen::Index>(pr.z.size()) - 1, N = n * (K + 1);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(N, N);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(N);
  const Eigen::MatrixXd P0i = pr.P0.inverse(), Qi = pr.Q.inverse(), Ri = pr.R.inverse();
  A.block(0, 0, n, n) += P0i;
  b.segment(0, n) += P0i * pr.m0;
  for (Eigen::Index k = 0; k < K; ++k) {
    // r = x(k+1) - F x(k): d r / d x(k) = -F, d r / d x(k+1) = I
    A.block(k * n, k * n, n, n) += pr.F.transpose() * Qi * pr.F;
    A.block(k * n, (k + 1) * n, n, n) -= pr.F.transpose() * Qi;
    A.block((k + 1) * n, k * n, n, n) -= Qi * pr.F;
    A.block((k + 1) * n, (k + 1) * n, n, n) += Qi;
  }
  for (Eigen::Index k = 0; k <= K; ++k) {
    A.block(k * n, k * n, n, n) += pr.H.transpose() * Ri * pr.H;
    b.segment(k * n, n) += pr.H.transpose() * Ri * pr.z[static_cast<size_t>(k)];
  }
  const Eigen::VectorXd x = A.ldlt().solve(b);
  std::vector<Eigen::VectorXd> out;
  for (Eigen::Index k = 0; k <= K; ++k) out.push_back(x.segment(k * n, n));
  return out;
}

TEST(KalmanSmoother, RtsPassEqualsBatchLeastSquares) {
  // GIVEN a random linear Gaussian problem of 3 states, 2 measurements per step, 12 steps
  std::mt19937 rng(11);
  const int K = 12;
  const Problem pr = makeProblem(rng, K);
  // WHEN the filter runs forward (update at k = 0, then predict + update) and smooths back
  KalmanSmoother<> ks(3);
  ks.reset(pr.m0, pr.P0);
  ks.update<Eigen::Dynamic>(pr.z[0], pr.H, pr.R);
  for (int k = 1; k <= K; ++k) {
    ks.predict(pr.F, pr.Q);
    ks.update<Eigen::Dynamic>(pr.z[static_cast<size_t>(k)], pr.H, pr.R);
  }
  ks.smooth();
  // THEN every smoothed mean is the batch least-squares solution, and the last one is the filter's
  const std::vector<Eigen::VectorXd> batch = batchLeastSquares(pr);
  ASSERT_EQ(ks.steps(), K);
  for (int k = 0; k <= K; ++k) EXPECT_TRUE(matricesNear(ks.smoothed(k), batch[static_cast<size_t>(k)], kSolutionTol)) << k;
  EXPECT_TRUE(matricesNear(ks.smoothed(K), ks.state(), 0.0));
}

TEST(KalmanSmoother, JosephUpdateEqualsTheStandardFormAndStaysSymmetricPsd) {
  // GIVEN a prior and one measurement of the whole state
  std::mt19937 rng(3);
  const Eigen::MatrixXd P = randomSpd(4, rng, 0.1), R = randomSpd(4, rng, 0.1);
  const Eigen::VectorXd x0 = randomMatrix(4, 1, rng), z = randomMatrix(4, 1, rng);
  KalmanSmoother<4> ks;
  ks.reset(x0, Eigen::Matrix4d::Zero());
  // WHEN predicted (F = I, Q = P) and updated with H = I
  ks.predict(Eigen::Matrix4d(P));
  ks.update(Eigen::Vector4d(z), Eigen::Matrix4d(R));
  // THEN x and P are the textbook values: K = P (P + R)^-1, P+ = P - K (P + R) K'
  const Eigen::MatrixXd S = P + R, Kg = P * S.inverse();
  EXPECT_TRUE(matricesNear(ks.state(), x0 + Kg * (z - x0), kCovTol));
  EXPECT_TRUE(matricesNear(ks.covariance(), P - Kg * S * Kg.transpose(), kCovTol));
  EXPECT_TRUE(isSymmetricPsd(ks.covariance(), kCovTol));
}

TEST(KalmanSmoother, RandomWalkWithRankDeficientNoiseMatchesConstrainedLeastSquares) {
  // GIVEN a random walk from a known start (P0 = 0) whose noise Q = G G' has rank 2 in 4 states
  // (the reference filter's J Qc J'), observed fully with R at every step: P(k+1|k) is singular
  std::mt19937 rng(5);
  const int n = 4, r = 2, K = 6;
  const Eigen::MatrixXd G = randomMatrix(n, r, rng), Q = G * G.transpose(), R = randomSpd(n, rng, 0.5);
  const Eigen::VectorXd x0 = randomMatrix(n, 1, rng);
  std::vector<Eigen::VectorXd> z;
  for (int k = 1; k <= K; ++k) z.push_back(randomMatrix(n, 1, rng));
  KalmanSmoother<> ks(n);
  ks.reset(x0, Eigen::MatrixXd::Zero(n, n));
  for (int k = 1; k <= K; ++k) {
    ks.predict(Q);
    ks.update(z[static_cast<size_t>(k) - 1], R);
  }
  // WHEN smoothed (the gain through a generalised inverse)
  ks.smooth();
  // THEN the means equal the least-squares solution over the noise coefficients eta_j (w_j =
  // G eta_j, eta_j ~ N(0, I)): x(k) = x0 + G sum_{j<=k} eta_j minimising
  // sum |eta_j|^2 + sum |z(k) - x(k)|^2_{R^-1}
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(r * K, r * K);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(r * K);
  const Eigen::MatrixXd Ri = R.inverse();
  for (int k = 1; k <= K; ++k) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, r * K);  // x(k) - x0 = M eta
    for (int j = 1; j <= k; ++j) M.middleCols((j - 1) * r, r) = G;
    A += M.transpose() * Ri * M;
    b += M.transpose() * Ri * (z[static_cast<size_t>(k) - 1] - x0);
  }
  const Eigen::VectorXd eta = A.ldlt().solve(b);
  for (int k = 1; k <= K; ++k) {
    Eigen::VectorXd x = x0;
    for (int j = 1; j <= k; ++j) x += G * eta.segment((j - 1) * r, r);
    EXPECT_TRUE(matricesNear(ks.smoothed(k), x, kSolutionTol)) << k;
  }
  EXPECT_TRUE(matricesNear(ks.smoothed(0), x0, kSolutionTol));
}

TEST(KalmanSmoother, SolvePsdIgnoresNullDirections) {
  // GIVEN a rank-2 PSD matrix A = G G' of size 4 (its null pivots are round-off, not zeros) and a
  // right-hand side in its range plus 1e-9 off it
  std::mt19937 rng(9);
  const Eigen::MatrixXd G = randomMatrix(4, 2, rng);
  const Eigen::Matrix4d A = G * G.transpose();
  const Eigen::LDLT<Eigen::Matrix4d> ldlt(A);
  const Eigen::Vector4d b = A * Eigen::Vector4d(randomMatrix(4, 1, rng));
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(G.transpose());
  const Eigen::Vector4d off = lu.kernel().col(0).normalized();  // orthogonal to range(A)
  // WHEN solved through the generalised inverse
  const Eigen::Vector4d x = solvePsd(ldlt, b), y = solvePsd(ldlt, Eigen::Vector4d(b + 1e-9 * off));
  // THEN A x = b, and the off-range component is not amplified by the inverse of a round-off pivot
  EXPECT_TRUE(matricesNear(A * x, b, kSolutionTol));
  EXPECT_LT((y - x).norm(), 1e-3 * x.norm());
}

TEST(KalmanSmoother, RejectsSmoothedBeforeSmoothAndAWrongSizedStart) {
  KalmanSmoother<2> ks;
  ks.reset(Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity());
  ks.predict(Eigen::Matrix2d::Identity());
  EXPECT_THROW(ks.smoothed(0), std::logic_error);
  KalmanSmoother<> dyn(3);
  EXPECT_THROW(dyn.reset(Eigen::VectorXd::Zero(2), Eigen::MatrixXd::Identity(2, 2)), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
