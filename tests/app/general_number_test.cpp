// writeGeneral (app/general_number.h) writes the characters of std::to_chars general format
// ("%.{P}g") for every double: its fast path on the usual values, to_chars itself elsewhere. The
// outputs of `predvs predict` stay byte for byte what they were (issue 11 item 8).
#include "general_number.h"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

std::string viaToChars(double x, int precision) {
  char buf[64];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, precision).ptr);
}

std::string viaWriteGeneral(double x, int precision) {
  char buf[64];
  return std::string(buf, predvs::writeGeneral(buf, x, precision));
}

/// Values of every kind the fast path must get right or hand over: log-uniform magnitudes of both
/// signs from 1e-7 to 1e12, arbitrary bit patterns (subnormals, inf, NaN), neighbours of powers of
/// ten and of values that round up to them (carries), exact binary fractions (halfway cases) and
/// integers beyond 10 digits, pixel-like values and 30 Hz times.
std::vector<double> testValues() {
  std::vector<double> v;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> log_mag(-7.0, 12.0);
  for (int i = 0; i < 300000; ++i) v.push_back((rng() & 1 ? -1.0 : 1.0) * std::pow(10.0, log_mag(rng)));
  for (int i = 0; i < 100000; ++i) {
    const uint64_t bits = rng();
    double x;
    std::memcpy(&x, &bits, sizeof x);
    v.push_back(x);
  }
  for (int k = -8; k <= 12; ++k) {
    const double p = std::pow(10.0, k);
    for (double f : {1.0, 9.9999999995, 9.999999995, 9.99999995, 9.9999995, 1.00000000005, 5.0, 2.5, 1.25}) {
      double lo = f * p, hi = f * p;
      for (int j = 0; j < 60; ++j) {
        v.push_back(lo);
        v.push_back(-hi);
        lo = std::nextafter(lo, 0.0);
        hi = std::nextafter(hi, 1e300);
      }
    }
  }
  for (int j = 1; j < 60; ++j)
    for (int n = 1; n < 400; ++n) {
      v.push_back(std::ldexp(static_cast<double>(2 * n + 1), -j));
      v.push_back(std::ldexp(static_cast<double>(2 * n + 1), -j) * 1e-3);
    }
  std::normal_distribution<double> px(320.0, 150.0);
  for (int n = 0; n < 100000; ++n) {
    v.push_back(n / 30.0);
    v.push_back(px(rng));
    v.push_back(12345678905.0 + n);
  }
  for (double x : {0.0, -0.0, 1.0, -1.0, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308, 1e-4, 1e-5,
                   9.99999999995e-5, 0.05, 0.1, 0.3, 66666.66667})
    v.push_back(x);
  v.push_back(std::numeric_limits<double>::infinity());
  v.push_back(-std::numeric_limits<double>::infinity());
  v.push_back(std::numeric_limits<double>::quiet_NaN());
  return v;
}

TEST(GeneralNumber, WritesTheCharactersOfToChars) {
  const std::vector<double> values = testValues();
  for (int precision : {10, 8, 6, 1, 12, 17}) {
    int mismatches = 0;
    for (double x : values) {
      const std::string expected = viaToChars(x, precision), got = viaWriteGeneral(x, precision);
      if (got != expected && ++mismatches <= 5)
        ADD_FAILURE() << "precision " << precision << ", x = " << viaToChars(x, 17) << ": to_chars '" << expected
                      << "', writeGeneral '" << got << "'";
    }
    EXPECT_EQ(mismatches, 0) << "precision " << precision << " over " << values.size() << " values";
  }
}

TEST(GeneralNumber, KnownTexts) {
  EXPECT_EQ(viaWriteGeneral(318.5719833, 10), "318.5719833");
  EXPECT_EQ(viaWriteGeneral(0.03333333333333333, 10), "0.03333333333");
  EXPECT_EQ(viaWriteGeneral(-0.05, 10), "-0.05");
  EXPECT_EQ(viaWriteGeneral(9999999999.7, 10), "1e+10");
  EXPECT_EQ(viaWriteGeneral(99.999999999, 10), "100");
  EXPECT_EQ(viaWriteGeneral(1.5e-5, 10), "1.5e-05");
  EXPECT_EQ(viaWriteGeneral(-0.0, 10), "-0");
  EXPECT_EQ(viaWriteGeneral(240.0, 8), "240");
}

}  // namespace
