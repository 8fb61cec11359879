// CentroidTable: its fast paths (one set, two neighbouring sets of opposite monotonicity) against
// its general path (three or more sets on an interval), which share no code beyond the integral
// of a linear function.
#include "predvs/predictors/fuzzy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace predvs {
namespace fuzzy {
namespace {

/// Two exact centroids computed over different decompositions differ by rounding only.
constexpr double kExactTol = 1e-12;

/// Random partition of [0, 10]: n trapezoids in order, each overlapping only its neighbours
/// (set i falls on [e_i, s_i+1 ... ] while set i+1 rises there); shoulders at the bounds.
std::vector<MembershipFunction> randomPartition(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // 2n sorted cut points inside (0, 10): set i rises on [c_{2i-1}, c_{2i}] and falls on [c_{2i+1}, c_{2i+2}]
  std::vector<double> c;
  for (int k = 0; k < 2 * n; ++k) c.push_back(0.1 + 9.8 * u(rng));
  std::sort(c.begin(), c.end());
  std::vector<MembershipFunction> sets;
  for (int i = 0; i < n; ++i) {
    const double a = i == 0 ? 0.0 : c[static_cast<size_t>(2 * i - 2)];
    const double b = i == 0 ? 0.0 : c[static_cast<size_t>(2 * i - 1)];
    const double cc = i == n - 1 ? 10.0 : c[static_cast<size_t>(2 * i)];
    const double d = i == n - 1 ? 10.0 : c[static_cast<size_t>(2 * i + 1)];
    sets.push_back(MembershipFunction::trapezoid(a, b, std::max(b, cc), std::max(std::max(b, cc), d)));
  }
  return sets;
}

TEST(CentroidTable, PartitionFastPathsMatchTheGeneralPath) {
  std::mt19937 rng(20261122);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int opposite_intervals = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // GIVEN a random partition and random clip levels (some sets not firing, some at 1)
    const int n = 2 + trial % 5;
    std::vector<MembershipFunction> sets = randomPartition(rng, n);
    std::vector<double> w;
    for (int i = 0; i < n; ++i) {
      const double r = u(rng);
      w.push_back(r < 0.2 ? 0.0 : (r > 0.9 ? 1.0 : u(rng)));
    }
    if (*std::max_element(w.begin(), w.end()) == 0.0) w[0] = 0.5;
    const CentroidTable fast(sets.data(), n, 0.0, 10.0);
    for (const auto& iv : fast.intervals()) opposite_intervals += iv.opposite ? 1 : 0;
    // WHEN two sets that cover everything are added with clip level 0 (the aggregated set is
    // unchanged, but every interval now holds three or more sets: the general path)
    std::vector<MembershipFunction> with_blankets = sets;
    with_blankets.push_back(MembershipFunction::triangle(0.0, 5.0, 10.0));
    with_blankets.push_back(MembershipFunction::trapezoid(0.0, 0.0, 10.0, 10.0));
    std::vector<double> w_blankets = w;
    w_blankets.push_back(0.0);
    w_blankets.push_back(0.0);
    const CentroidTable general(with_blankets.data(), n + 2, 0.0, 10.0);
    for (const auto& iv : general.intervals()) ASSERT_GE(iv.count, 3);
    // THEN both give the same centroid
    EXPECT_NEAR(fast.centroid(w.data()), general.centroid(w_blankets.data()), kExactTol) << "trial " << trial;
  }
  // and the fast two-set path was actually exercised
  EXPECT_GT(opposite_intervals, 100);
}

TEST(CentroidTable, SameDirectionPairMatchesTheGeneralPath) {
  // GIVEN two rising edges overlapping (not a partition: both increase on (2, 6))
  const MembershipFunction sets[2] = {MembershipFunction::trapezoid(0.0, 6.0, 10.0, 10.0),
                                      MembershipFunction::trapezoid(2.0, 4.0, 10.0, 10.0)};
  const CentroidTable pair(sets, 2, 0.0, 10.0);
  const MembershipFunction sets3[3] = {sets[0], sets[1], MembershipFunction::trapezoid(0.0, 0.0, 10.0, 10.0)};
  const CentroidTable general(sets3, 3, 0.0, 10.0);
  for (double wa : {0.2, 0.5, 0.9, 1.0})
    for (double wb : {0.0, 0.3, 0.7, 1.0}) {
      // WHEN evaluated with the two-set path and with the general path
      const double w2[2] = {wa, wb}, w3[3] = {wa, wb, 0.0};
      // THEN they agree
      EXPECT_NEAR(pair.centroid(w2), general.centroid(w3), kExactTol) << wa << " " << wb;
    }
}

TEST(CentroidTable, EmptyAggregateIsNaN) {
  // GIVEN a set outside the universe, or no set firing THEN the centroid is NaN
  const MembershipFunction outside = MembershipFunction::triangle(20.0, 21.0, 22.0);
  const double w1 = 1.0, w0 = 0.0;
  EXPECT_TRUE(std::isnan(CentroidTable(&outside, 1, 0.0, 10.0).centroid(&w1)));
  const MembershipFunction inside = MembershipFunction::triangle(2.0, 3.0, 4.0);
  EXPECT_TRUE(std::isnan(CentroidTable(&inside, 1, 0.0, 10.0).centroid(&w0)));
  EXPECT_NEAR(CentroidTable(&inside, 1, 0.0, 10.0).centroid(&w1), 3.0, kExactTol);
}

}  // namespace
}  // namespace fuzzy
}  // namespace predvs
