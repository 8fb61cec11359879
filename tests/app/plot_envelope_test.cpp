// plotEnvelope() (app/plots.h), the thinning of predictions.png's data beyond kMaxPlotRows rows:
// every time slice keeps each value column's min and max (in the order the data reached them) and
// its first and last time, and a table with at most 2 rows per slice comes back unchanged.
#include "plots.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <vector>

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool sameBits(double a, double b) { return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0; }

/// The slice of x by the documented rule.
size_t sliceOf(double x, double x0, double x1, size_t slices) {
  if (x1 == x0) return 0;
  const double b = std::floor((x - x0) * (static_cast<double>(slices) / (x1 - x0)));
  return b >= static_cast<double>(slices - 1) ? slices - 1 : static_cast<size_t>(std::max(0.0, b));
}

TEST(PlotEnvelope, EverySliceKeepsEachColumnsMinAndMaxInTheOrderReached) {
  // GIVEN 30,000 rows at jittered times with a gap, repeated times, a time column, a noisy series
  // with NaN cells and one spike per 1,000 rows, and a series that is NaN over a whole stretch
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const size_t rows = 30000, slices = 300;
  std::vector<double> x, shifted, noisy, partly;
  double t = 10.0;
  for (size_t i = 0; i < rows; ++i) {
    if (i == 12000) t += 500.0;  // a gap: several empty slices
    if (uni(rng) > 0.05) t += 0.02 + 0.04 * uni(rng);  // else the same time again
    x.push_back(t);
    shifted.push_back(t + 0.1);
    double v = 100.0 * std::sin(t / 7.0) + 3.0 * (uni(rng) - 0.5);
    if (i % 1000 == 417) v += 500.0 * (uni(rng) - 0.5);
    noisy.push_back(uni(rng) < 0.03 ? kNaN : v);
    partly.push_back(i >= 20000 && i < 24000 ? kNaN : -v);
  }
  const std::vector<predvs::EnvelopeColumn> columns{
      {x.data(), true}, {noisy.data(), false}, {shifted.data(), true}, {partly.data(), false}};
  // WHEN it is thinned to 300 slices
  const std::vector<double> out = predvs::plotEnvelope(x, columns, slices);
  // THEN each slice of the input has, in the output, its first and last time, then each value
  // column's extremes, the one reached first in the first row (two rows: n > 2; else the rows)
  ASSERT_EQ(out.size() % columns.size(), 0u);
  const size_t out_rows = out.size() / columns.size();
  EXPECT_LE(out_rows, 2 * slices);
  std::map<size_t, std::vector<size_t>> in_slice, out_slice;  // slice -> rows
  for (size_t i = 0; i < rows; ++i) in_slice[sliceOf(x[i], x.front(), x.back(), slices)].push_back(i);
  for (size_t r = 0; r < out_rows; ++r)
    out_slice[sliceOf(out[r * columns.size()], x.front(), x.back(), slices)].push_back(r);
  EXPECT_LT(in_slice.size(), slices);  // the gap left slices empty
  ASSERT_EQ(in_slice.size(), out_slice.size());
  size_t spikes_kept = 0, nan_slices = 0;
  for (const auto& [b, in_rows] : in_slice) {
    const std::vector<size_t>& o = out_slice[b];
    ASSERT_EQ(o.size(), std::min<size_t>(2, in_rows.size())) << "slice " << b;
    auto at = [&](size_t r, size_t c) { return out[o[r] * columns.size() + c]; };
    EXPECT_EQ(at(0, 0), x[in_rows.front()]) << "slice " << b;
    EXPECT_EQ(at(o.size() - 1, 0), x[in_rows.back()]) << "slice " << b;
    EXPECT_EQ(at(0, 2), shifted[in_rows.front()]) << "slice " << b;
    EXPECT_EQ(at(o.size() - 1, 2), shifted[in_rows.back()]) << "slice " << b;
    for (size_t c : {1u, 3u}) {
      const double* v = columns[c].values;
      double lo = kNaN, hi = kNaN;
      size_t lo_at = 0, hi_at = 0;
      for (size_t i : in_rows) {
        if (std::isnan(v[i])) continue;
        if (std::isnan(lo) || v[i] < lo) lo = v[i], lo_at = i;
        if (std::isnan(hi) || v[i] > hi) hi = v[i], hi_at = i;
      }
      if (in_rows.size() <= 2) {
        for (size_t r = 0; r < o.size(); ++r) EXPECT_TRUE(sameBits(at(r, c), v[in_rows[r]])) << "slice " << b;
        continue;
      }
      if (std::isnan(lo)) ++nan_slices;
      const double first = lo_at <= hi_at ? lo : hi, last = lo_at <= hi_at ? hi : lo;
      EXPECT_TRUE(sameBits(at(0, c), first)) << "slice " << b << " column " << c;
      EXPECT_TRUE(sameBits(at(1, c), last)) << "slice " << b << " column " << c;
      for (size_t i : in_rows)
        if (c == 1 && i % 1000 == 417 && !std::isnan(v[i]) && (v[i] == lo || v[i] == hi)) ++spikes_kept;
    }
  }
  EXPECT_GT(nan_slices, 10u);     // the NaN stretch gives NaN extremes, not a number
  EXPECT_GE(spikes_kept, 25u);    // the spikes (one row in 1,000) stay in the plot
}

TEST(PlotEnvelope, AtMostTwoRowsPerSliceComeBackUnchanged) {
  // GIVEN tables with one or two rows per slice (and a lone row, and no row)
  for (const size_t rows : {0u, 1u, 2u, 7u, 600u, 1200u, 2400u}) {
    std::vector<double> x, v;
    for (size_t i = 0; i < rows; ++i) {
      x.push_back(3.0 + 0.5 * static_cast<double>(i));
      v.push_back(i % 3 == 1 ? kNaN : std::cos(static_cast<double>(i)));
    }
    // WHEN thinned to 1200 slices
    const std::vector<double> out = predvs::plotEnvelope(x, {{x.data(), true}, {v.data(), false}}, 1200);
    // THEN the rows are the input's, bit for bit
    ASSERT_EQ(out.size(), 2 * rows) << rows;
    for (size_t i = 0; i < rows; ++i) {
      EXPECT_TRUE(sameBits(out[2 * i], x[i])) << rows << " row " << i;
      EXPECT_TRUE(sameBits(out[2 * i + 1], v[i])) << rows << " row " << i;
    }
  }
}

TEST(PlotEnvelope, FedInBlocksOfAnySizeTheBuilderGivesTheWholeTablesEnvelope) {
  // GIVEN 20,000 rows at jittered (sometimes repeated) times: a time column, a shifted time column,
  // a noisy series with NaN cells, a column with no values (NaN in every row)
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const size_t rows = 20000, slices = 700;
  std::vector<double> x, noisy;
  double t = 0.0;
  for (size_t i = 0; i < rows; ++i) {
    if (uni(rng) > 0.1) t += 0.01 + 0.02 * uni(rng);
    x.push_back(t);
    noisy.push_back(uni(rng) < 0.05 ? kNaN : std::sin(t) + 0.1 * uni(rng));
  }
  std::vector<predvs::EnvelopeColumn> columns(4);
  columns[0] = {x.data(), true};
  columns[1] = {noisy.data(), false};
  columns[2] = {x.data(), true, true, 0.25};
  columns[3] = {nullptr, false};
  const std::vector<double> whole = predvs::plotEnvelope(x, columns, slices);
  ASSERT_FALSE(whole.empty());
  // WHEN a builder is fed the same rows in blocks of 1 row, 2 rows, a slice's size, and random sizes
  for (const size_t fixed : {1u, 2u, 29u, 0u}) {
    predvs::EnvelopeBuilder builder({true, false, true, false}, x.front(), x.back(), slices);
    std::uniform_int_distribution<size_t> size_of(1, 500);
    for (size_t i0 = 0; i0 < rows;) {
      const size_t n = std::min(rows - i0, fixed > 0 ? fixed : size_of(rng));
      std::vector<predvs::EnvelopeColumn> block = columns;
      for (auto& c : block)
        if (c.values) c.values += i0;
      builder.addBlock(x.data() + i0, n, block.data());
      i0 += n;
    }
    // THEN its table is the whole table's envelope, bit for bit
    const std::vector<double>& fed = builder.table();
    ASSERT_EQ(fed.size(), whole.size()) << fixed;
    for (size_t i = 0; i < whole.size(); ++i) ASSERT_TRUE(sameBits(fed[i], whole[i])) << fixed << " cell " << i;
  }
  // AND the shifted column is the time plus its shift, the empty one NaN
  EXPECT_EQ(whole[2], x.front() + 0.25);
  EXPECT_TRUE(std::isnan(whole[3]));
}

}  // namespace
