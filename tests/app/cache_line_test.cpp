// Memory of its own cache lines (app/cache_line.h), and the plot's per-row state on it
// (docs/PERFORMANCE.md, "Thirteenth pass").
#include "cache_line.h"
#include "plots.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace predvs {
namespace {

bool onALine(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % kCacheLineBytes == 0; }

TEST(CacheLine, EveryAllocationStartsOnALine) {
  // GIVEN vectors of 1 to 40 doubles and of 1 to 40 bytes, each allocated beside the one before
  std::vector<CacheLineVector<double>> doubles;
  std::vector<CacheLineVector<char>> bytes;
  for (size_t n = 1; n <= 40; ++n) {
    doubles.emplace_back(n, 1.0);
    bytes.emplace_back(n, 'x');
  }
  // THEN each starts on a cache line, so no two of them (nor anything else) share one
  for (size_t k = 0; k < doubles.size(); ++k) {
    EXPECT_TRUE(onALine(doubles[k].data())) << k + 1 << " doubles";
    EXPECT_TRUE(onALine(bytes[k].data())) << k + 1 << " bytes";
  }
  // AND growing a vector keeps it so
  CacheLineVector<double> grown;
  for (int i = 0; i < 1000; ++i) {
    grown.push_back(i);
    ASSERT_TRUE(onALine(grown.data())) << grown.size();
  }
}

TEST(CacheLine, TheEnvelopeBuilderTakesLinesOfItsOwn) {
  static_assert(alignof(EnvelopeBuilder) == kCacheLineBytes, "EnvelopeBuilder is aligned to a line");
  static_assert(sizeof(EnvelopeBuilder) % kCacheLineBytes == 0, "and takes whole lines");
  auto a = std::make_unique<EnvelopeBuilder>(std::vector<bool>{true, false}, 0.0, 1.0, 4);
  auto b = std::make_unique<EnvelopeBuilder>(std::vector<bool>{true, false}, 0.0, 1.0, 4);
  EXPECT_TRUE(onALine(a.get()));
  EXPECT_TRUE(onALine(b.get()));
}

}  // namespace
}  // namespace predvs
