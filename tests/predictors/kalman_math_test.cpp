// The 2-state specialisations of timeUpdate / measurementUpdate (kalman_math.h) against the
// textbook matrix expressions, on random symmetric PSD covariances, transitions and noises; and
// predictedPosition against the first row of the product it stands for.
#include "predvs/predictors/kalman_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace predvs {
namespace {

// Relative agreement of two evaluations of the same expression in double precision.
constexpr double kRelTol = 1e-12;

void expectNear(const Mat<2>& a, const Mat<2>& b) {
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(), kRelTol * scale) << "\n" << a << "\nvs\n" << b;
}

TEST(KalmanMath, TwoStateSpecialisationsEqualTheMatrixExpressions) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 1000; ++trial) {
    // GIVEN a random state, a random PSD P = L L', a random F, a random PSD Q and R > 0
    Mat<2> L, M;
    L << u(rng), 0.0, u(rng), u(rng);
    M << u(rng), 0.0, u(rng), u(rng);
    Gaussian<2> g;
    g.x << u(rng), u(rng);
    g.P = L * L.transpose();
    Mat<2> F;
    F << u(rng), u(rng), u(rng), u(rng);
    const Mat<2> Q = M * M.transpose();
    const double R = 0.1 + std::abs(u(rng));
    const double z = u(rng);

    // WHEN the specialised time update runs
    Gaussian<2> s = g;
    timeUpdate(s, F, Q);
    // THEN it equals x = F x, P = F P F' + Q
    const Vec<2> x1 = F * g.x;
    const Mat<2> P1 = F * g.P * F.transpose() + Q;
    EXPECT_NEAR((s.x - x1).cwiseAbs().maxCoeff(), 0.0, kRelTol * std::max(1.0, x1.cwiseAbs().maxCoeff()));
    expectNear(s.P, P1);

    // WHEN the specialised measurement update runs on that prediction
    const Innovation in = measurementUpdate(s, z, R);
    // THEN it equals the Joseph form with K = P H' / S
    const double S = P1(0, 0) + R;
    const Vec<2> K = P1.col(0) / S;
    Mat<2> A = Mat<2>::Identity();
    A.col(0) -= K;
    const Mat<2> P2 = A * P1 * A.transpose() + R * K * K.transpose();
    const Vec<2> x2 = x1 + K * (z - x1(0));
    EXPECT_NEAR(in.S, S, kRelTol * S);
    EXPECT_NEAR(in.eps, z - x1(0), kRelTol * std::max(1.0, std::abs(z - x1(0))));
    EXPECT_NEAR((s.x - x2).cwiseAbs().maxCoeff(), 0.0, kRelTol * std::max(1.0, x2.cwiseAbs().maxCoeff()));
    expectNear(s.P, P2);
    // AND P is exactly symmetric
    EXPECT_EQ(s.P(0, 1), s.P(1, 0));
  }
}

template <int N>
void expectPositionIsTheProductsBits(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-3.0, 3.0);
  auto value = [&] { return u(rng) * std::pow(10.0, std::round(e(rng))); };
  for (int trial = 0; trial < 20000; ++trial) {
    Mat<N> F;
    Vec<N> x;
    for (int i = 0; i < N * N; ++i) F.data()[i] = value();
    for (int i = 0; i < N; ++i) x(i) = value();
    const Vec<N> Fx = (F * x).eval();
    const double p = predictedPosition(x, F);
    ASSERT_EQ(std::memcmp(&p, &Fx(0), sizeof p), 0) << "N = " << N << ", trial " << trial << ": " << p << " vs " << Fx(0);
  }
}

TEST(KalmanMath, PredictedPositionHasTheBitsOfTheProductsFirstRow) {
  // GIVEN random transitions and states over six decades (sums that round differently in another
  // order: Eigen's row(0).dot(x) sums x0 F00 + (x1 F01 + x2 F02) and differs on about a fifth)
  std::mt19937 rng(23);
  // THEN predictedPosition(x, F) is (F x)(0) as timeUpdate's product computes it, bit for bit
  expectPositionIsTheProductsBits<2>(rng);
  expectPositionIsTheProductsBits<3>(rng);
}

}  // namespace
}  // namespace predvs
