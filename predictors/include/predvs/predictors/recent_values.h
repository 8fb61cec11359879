// predvs — the values of a function for the last few distinct arguments asked.
//
// A recorded track's frame period takes a handful of values that differ in their last bits (times
// written with 10 significant digits: 54 distinct periods on the 2-million-row track of
// docs/PERFORMANCE.md, a new one on about 9 frames in 10, a few at a time), and a predictor asks
// the quantities of a period (exp(-dt / tau), a transition, a process noise) on every frame. A
// one-entry cache misses nearly every frame; RecentValues keeps the last N distinct keys (K doubles,
// compared exactly with ==) and replaces the oldest. A hit returns what the function returned for
// that key, so the results are the same bits as calling it. Used per predictor instance
// (channel_predictor.h, imm.h) and per thread (cs_akf.cpp); not synchronised.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <utility>

namespace predvs {

template <class T, int N = 8, int K = 1>
class RecentValues {
 public:
  using Key = std::array<double, K>;

  RecentValues() {
    for (Key& k : keys_) k.fill(std::numeric_limits<double>::quiet_NaN());  // NaN equals no key: empty
  }

  /// The value for key: the kept one, or compute() (a callable returning T) kept in place of the
  /// oldest entry.
  template <class Compute>
  const T& get(const Key& key, Compute&& compute) {
    for (int i = 0; i < N; ++i)
      if (keys_[static_cast<std::size_t>(i)] == key) return values_[static_cast<std::size_t>(i)];
    const auto slot = static_cast<std::size_t>(next_);
    next_ = (next_ + 1) % N;
    values_[slot] = std::forward<Compute>(compute)();
    keys_[slot] = key;
    return values_[slot];
  }

 private:
  std::array<Key, N> keys_;
  std::array<T, N> values_{};
  int next_ = 0;  ///< the entry replaced next
};

}  // namespace predvs
