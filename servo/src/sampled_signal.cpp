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

}  // namespace predvs
