// predvs — Eigen matrix comparison for GoogleTest (after manif's test/gtest_eigen_utils.h).
//
// matricesNear(a, b, tol) passes when every entry satisfies |a_ij - b_ij| <= tol * max(1, |b_ij|):
// an absolute tolerance for entries near zero (where a relative one would demand exact zeros) and a
// relative one for large entries. On failure the message prints both matrices and the worst entry.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

namespace predvs {

template <class A, class B>
::testing::AssertionResult matricesNear(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b, double tol) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    return ::testing::AssertionFailure() << "size mismatch: " << a.rows() << "x" << a.cols() << " vs " << b.rows()
                                         << "x" << b.cols();
  double worst = 0.0;
  Eigen::Index wi = 0, wj = 0;
  bool ok = true;
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      const double ai = static_cast<double>(a(i, j)), bi = static_cast<double>(b(i, j));
      const double excess = std::abs(ai - bi) / std::max(1.0, std::abs(bi));
      if (!(excess <= tol)) ok = false;  // NaN fails too
      if (!(excess <= worst)) {
        worst = excess;
        wi = i;
        wj = j;
      }
    }
  if (ok) return ::testing::AssertionSuccess();
  const Eigen::IOFormat fmt(Eigen::FullPrecision, 0, ", ", "\n", "  [", "]");
  std::ostringstream msg;
  msg << "matrices differ (tol " << tol << ", worst scaled error " << worst << " at (" << wi << ", " << wj
      << "))\nfirst:\n"
      << a.format(fmt) << "\nsecond:\n"
      << b.format(fmt);
  return ::testing::AssertionFailure() << msg.str();
}

/// P symmetric to tol (scaled as above) and positive semi-definite down to -tol * max(1, |P|).
template <class M>
::testing::AssertionResult isSymmetricPsd(const Eigen::MatrixBase<M>& P, double tol) {
  const auto sym = matricesNear(P, P.transpose(), tol);
  if (!sym) return ::testing::AssertionFailure() << "not symmetric: " << sym.message();
  using Plain = typename M::PlainObject;
  Eigen::SelfAdjointEigenSolver<Plain> es(Plain(0.5 * (P + P.transpose())));
  const double scale = std::max(1.0, P.cwiseAbs().maxCoeff());
  if (!(es.eigenvalues().minCoeff() >= -tol * scale)) {
    std::ostringstream msg;
    msg << "not PSD: smallest eigenvalue " << es.eigenvalues().minCoeff() << "\n" << P;
    return ::testing::AssertionFailure() << msg.str();
  }
  return ::testing::AssertionSuccess();
}

/// A matrix of independent N(0, scale^2) entries from `rng` (seeded by the test).
inline Eigen::MatrixXd randomMatrix(Eigen::Index r, Eigen::Index c, std::mt19937& rng, double scale = 1.0) {
  std::normal_distribution<double> g(0.0, scale);
  Eigen::MatrixXd M(r, c);
  for (Eigen::Index i = 0; i < r; ++i)
    for (Eigen::Index j = 0; j < c; ++j) M(i, j) = g(rng);
  return M;
}

}  // namespace predvs
