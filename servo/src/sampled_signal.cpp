#include "predvs/servo/sampled_signal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <utility>

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

namespace {

/// The median of the differences t_s[i] - t_s[i - 1] when they take few distinct values (a steady
/// clock written with a fixed number of digits: 54 values over the 2 million rows of the throughput
/// track), without a copy of the differences: each distinct value is counted in a small
/// open-addressing table (keyed by its bits), then the values of rank mid and, for an even count,
/// mid - 1 are read off the sorted distinct values. These are the values nth_element finds below, so
/// the result is the same bits. false (nothing decided) beyond kMaxDistinct values, or on a
/// difference that is not > 0 (NaN, a zero, a time going back): the caller sorts a copy then.
bool medianOfFewDifferences(const std::vector<double>& t_s, double& median) {
  constexpr size_t kMaxDistinct = 256, kSlots = 1024;  // a load factor of 1/4 at most
  struct Slot {
    uint64_t bits = 0;
    size_t count = 0;  // 0: empty
  };
  std::array<Slot, kSlots> table{};
  size_t distinct = 0;
  for (size_t i = 1; i < t_s.size(); ++i) {
    const double d = t_s[i] - t_s[i - 1];
    if (!(d > 0.0)) return false;
    uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    size_t k = static_cast<size_t>((bits * 0x9E3779B97F4A7C15ull) >> 54);  // 10 bits: kSlots
    while (table[k].count != 0 && table[k].bits != bits) k = (k + 1) % kSlots;
    if (table[k].count == 0) {
      if (++distinct > kMaxDistinct) return false;
      table[k].bits = bits;
    }
    ++table[k].count;
  }
  std::vector<std::pair<double, size_t>> values;
  values.reserve(distinct);
  for (const Slot& slot : table) {
    if (slot.count == 0) continue;
    double v;
    std::memcpy(&v, &slot.bits, sizeof v);
    values.emplace_back(v, slot.count);
  }
  std::sort(values.begin(), values.end());
  const size_t n = t_s.size() - 1, mid = n / 2;
  auto valueOfRank = [&](size_t rank) {  // the value at position rank of the sorted differences
    size_t below = 0;
    for (const auto& [v, count] : values) {
      below += count;
      if (rank < below) return v;
    }
    return values.back().first;  // not reached: rank < n
  };
  const double upper = valueOfRank(mid);
  median = n % 2 == 1 ? upper : 0.5 * (valueOfRank(mid - 1) + upper);
  return true;
}

}  // namespace

double medianPeriod(const std::vector<double>& t_s) {
  if (t_s.size() < 2) throw std::invalid_argument("at least two rows are needed to measure the frame period");
  double few = 0.0;
  if (medianOfFewDifferences(t_s, few)) return few;
  std::vector<double> dt;
  dt.reserve(t_s.size() - 1);
  for (size_t i = 1; i < t_s.size(); ++i) dt.push_back(t_s[i] - t_s[i - 1]);
  const size_t mid = dt.size() / 2;
  std::nth_element(dt.begin(), dt.begin() + static_cast<long>(mid), dt.end());
  if (dt.size() % 2 == 1) return dt[mid];
  const double upper = dt[mid];
  const double lower = *std::max_element(dt.begin(), dt.begin() + static_cast<long>(mid));
  return 0.5 * (lower + upper);
}

}  // namespace predvs
