// Helpers shared by the servo tests that compare against ViSP types.
#pragma once

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace predvs {

inline vpColVector toVisp(const Eigen::VectorXd& v) {
  vpColVector out(static_cast<unsigned>(v.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i) out[static_cast<unsigned>(i)] = v(i);
  return out;
}

/// Largest entry-wise difference of two homogeneous matrices.
inline double maxAbsDiff(const vpHomogeneousMatrix& a, const vpHomogeneousMatrix& b) {
  double d = 0.0;
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c) d = std::max(d, std::abs(a[r][c] - b[r][c]));
  return d;
}

}  // namespace predvs
