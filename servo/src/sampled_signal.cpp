#include "predvs/servo/sampled_signal.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace predvs {

double interpolateAt(const std::vector<double>& t_s, const std::vector<double>& y, double t) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  // Last finite sample at or before t, first finite sample at or after t.
  const auto it = std::lower_bound(t_s.begin(), t_s.end(), t);
  long hi = static_cast<long>(it - t_s.begin());
  const long n = static_cast<long>(t_s.size());
  while (hi < n && !std::isfinite(y[static_cast<size_t>(hi)])) ++hi;
  if (hi >= n) return kNaN;
  if (t_s[static_cast<size_t>(hi)] == t) return y[static_cast<size_t>(hi)];
  long lo = static_cast<long>(it - t_s.begin()) - 1;
  while (lo >= 0 && !std::isfinite(y[static_cast<size_t>(lo)])) --lo;
  if (lo < 0) return kNaN;
  const double t0 = t_s[static_cast<size_t>(lo)], t1 = t_s[static_cast<size_t>(hi)];
  const double w = (t - t0) / (t1 - t0);
  return (1.0 - w) * y[static_cast<size_t>(lo)] + w * y[static_cast<size_t>(hi)];
}

std::vector<double> interpolateShifted(const std::vector<double>& t_s, const std::vector<double>& y, double shift_s) {
  std::vector<double> r(t_s.size());
  interpolateShifted(t_s, y, shift_s, 0, t_s.size(), r.data());
  return r;
}

void interpolateShifted(const std::vector<double>& t_s, const std::vector<double>& y, double shift_s, size_t i0,
                        size_t i1, double* out) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const size_t n = t_s.size();
  if (i0 >= i1) return;
  // first row with t_s >= t (std::lower_bound), kept as a cursor from row to row
  size_t bound = static_cast<size_t>(std::lower_bound(t_s.begin(), t_s.end(), t_s[i0] + shift_s) - t_s.begin());
  for (size_t i = i0; i < i1; ++i) {
    double& r = out[i - i0];
    const double t = t_s[i] + shift_s;
    while (bound < n && t_s[bound] < t) ++bound;
    size_t hi = bound;
    while (hi < n && !std::isfinite(y[hi])) ++hi;
    if (hi >= n) {
      r = kNaN;
      continue;
    }
    if (t_s[hi] == t) {
      r = y[hi];
      continue;
    }
    size_t lo = bound;  // one past the candidate
    while (lo > 0 && !std::isfinite(y[lo - 1])) --lo;
    if (lo == 0) {
      r = kNaN;
      continue;
    }
    const double t0 = t_s[lo - 1], t1 = t_s[hi];
    const double w = (t - t0) / (t1 - t0);
    r = (1.0 - w) * y[lo - 1] + w * y[hi];
  }
}

}  // namespace predvs
