// One property suite for every registered predictor: a predictor added to the registry is covered
// by these tests without editing this file (the suite is instantiated over predictorRegistry(),
// and again over each predictor's structural variants, e.g. st-akf on `model: cv`).
#include "predictors/eigen_test_utils.h"
#include "predvs/predictors/predictor.h"

#include <gtest/gtest.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kFramePeriod_s = 1.0 / 30.0;
// P is symmetrised after every update, so asymmetry is pure rounding; PSD to rounding of |P|.
constexpr double kSymPsdTol = 1e-9;

/// Seeded synthetic measurement stream: smooth bounded motion (two sinusoids per channel, px),
/// 1 px Gaussian noise, +-20 % jitter on the frame period, and 3 % of entries missing (NaN).
class Stream {
 public:
  Stream(int channels, unsigned seed, double dropout = 0.03) : channels_(channels), rng_(seed), dropout_(dropout) {}

  /// Advances to the next frame; returns its time and fills z.
  double next(Eigen::VectorXd& z) {
    t_ += kFramePeriod_s * (1.0 + 0.2 * (2.0 * uni_(rng_) - 1.0));
    z.resize(channels_);
    for (int c = 0; c < channels_; ++c) {
      const double truth = 200.0 + 100.0 * std::sin(0.5 * t_ + c) + 30.0 * std::sin(1.7 * t_ + 0.3 * c);
      const double n = noise_(rng_);
      z(c) = uni_(rng_) < dropout_ ? kNaN : truth + n;
    }
    return t_;
  }
  double time() const { return t_; }

 private:
  int channels_;
  std::mt19937 rng_;
  double dropout_;
  double t_ = 0.0;
  std::uniform_real_distribution<double> uni_{0.0, 1.0};
  std::normal_distribution<double> noise_{0.0, 1.0};
};

/// Next frame of `s` into `p` (z receives the measurement).
void feed(Predictor& p, Stream& s, Eigen::VectorXd& z) {
  const double t_s = s.next(z);
  p.update(t_s, z);
}

/// Everything the interface exposes about a predictor's state: time, and per channel the
/// estimate at the filter time and the last innovation.
struct Snapshot {
  double t = kNaN;
  std::vector<ChannelEstimate> est;
  std::vector<Innovation> inn;
};

Snapshot snapshot(const Predictor& p) {
  Snapshot s;
  s.t = p.time();
  for (int c = 0; c < p.channels(); ++c) {
    s.est.push_back(p.predict(c, p.time()));
    s.inn.push_back(p.innovation(c));
  }
  return s;
}

/// Bitwise equality (NaN equal to NaN): the same computation on the same data must give the same
/// doubles, so no tolerance is needed.
bool same(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

::testing::AssertionResult sameEstimate(const ChannelEstimate& a, const ChannelEstimate& b) {
  bool ok = a.x.size() == b.x.size() && a.P.rows() == b.P.rows();
  for (int i = 0; ok && i < a.x.size(); ++i) ok = same(a.x(i), b.x(i));
  for (int i = 0; ok && i < a.P.size(); ++i) ok = same(a.P.data()[i], b.P.data()[i]);
  if (ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "estimates differ:\nx1 = " << a.x.transpose() << "\nx2 = " << b.x.transpose()
                                       << "\nP1 =\n" << a.P << "\nP2 =\n" << b.P;
}

::testing::AssertionResult sameSnapshot(const Snapshot& a, const Snapshot& b) {
  if (!same(a.t, b.t)) return ::testing::AssertionFailure() << "times differ: " << a.t << " vs " << b.t;
  if (a.est.size() != b.est.size()) return ::testing::AssertionFailure() << "channel counts differ";
  for (size_t c = 0; c < a.est.size(); ++c) {
    const auto r = sameEstimate(a.est[c], b.est[c]);
    if (!r) return ::testing::AssertionFailure() << "channel " << c << ": " << r.message();
    if (!same(a.inn[c].eps, b.inn[c].eps) || !same(a.inn[c].S, b.inn[c].S) || a.inn[c].valid != b.inn[c].valid)
      return ::testing::AssertionFailure() << "channel " << c << ": innovations differ";
  }
  return ::testing::AssertionSuccess();
}

class PredictorProperty : public ::testing::TestWithParam<std::string> {
 protected:
  /// GetParam() is a registered name, optionally followed by the KEY=VALUE pairs of one of its
  /// structural variants ("st-akf model=cv", registeredNames()).
  /// `extra` overrides keys after those of the name (a forecast variant, say).
  std::unique_ptr<Predictor> make(int channels, const Params& extra = {}) const {
    std::istringstream words(GetParam());
    std::string name, kv;
    words >> name;
    Params params;
    while (words >> kv) {
      const auto eq = kv.find('=');
      const std::string key = kv.substr(0, eq), value = kv.substr(eq + 1);
      char* end = nullptr;
      const double x = std::strtod(value.c_str(), &end);
      if (end != value.c_str() && *end == '\0')
        params.set(key, x);
      else
        params.setText(key, value);
    }
    params.setAll(extra);
    return makePredictor(name, channels, params);
  }
};

TEST_P(PredictorProperty, CovarianceStaysSymmetricPsdAndFiniteOverAMillionSteps) {
  // GIVEN 10^6 noisy frames with jitter and dropouts on 2 channels
  constexpr long kSteps = 1000000;
  constexpr long kPsdEvery = 97;  // full eigen-decomposition every 97 steps (prime: no aliasing
                                  // with any periodic adaptation); finiteness and symmetry every step
  auto p = make(2);
  Stream stream(2, 1234);
  Eigen::VectorXd z;
  bool seen[2] = {false, false};  // a channel is uninitialised (NaN estimate) until measured
  const auto t0 = std::chrono::steady_clock::now();
  for (long k = 0; k < kSteps; ++k) {
    feed(*p, stream, z);
    for (int c = 0; c < 2; ++c) {
      seen[c] = seen[c] || std::isfinite(z(c));
      if (!seen[c]) continue;
      const ChannelEstimate e = p->predict(c, p->time());
      // THEN every state and covariance entry is finite, P symmetric, and PSD
      if (!e.x.allFinite() || !e.P.allFinite()) {
        FAIL() << "non-finite estimate at step " << k << " channel " << c << ":\n" << e.x.transpose() << "\n" << e.P;
      }
      if (const auto sym = matricesNear(e.P, e.P.transpose(), kSymPsdTol); !sym)
        FAIL() << "asymmetric P at step " << k << ": " << sym.message();
      if (k % kPsdEvery == 0 || k == kSteps - 1) {
        const auto psd = isSymmetricPsd(e.P, kSymPsdTol);
        if (!psd) FAIL() << "step " << k << " channel " << c << ": " << psd.message();
      }
      const Innovation in = p->innovation(c);
      if (in.valid && !(in.S > 0.0 && std::isfinite(in.eps)))
        FAIL() << "bad innovation at step " << k << ": eps " << in.eps << " S " << in.S;
    }
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("  %s: 1e6 steps x 2 channels with checks in %.2f s\n", GetParam().c_str(), secs);
}

TEST_P(PredictorProperty, PredictionQueryLeavesStateUnchanged) {
  // GIVEN two identical predictors on the same data
  auto a = make(2), b = make(2);
  Stream sa(2, 42), sb(2, 42);
  Eigen::VectorXd za, zb;
  for (int k = 0; k < 600; ++k) {
    feed(*a, sa, za);
    feed(*b, sb, zb);
    // WHEN only `a` is queried, at several horizons (including before its time: clamped)
    const Snapshot before = snapshot(*a);
    for (int c = 0; c < 2; ++c)
      for (double h : {-0.1, 0.0, 0.01, 0.1, 1.0, 3.0}) (void)a->predict(c, a->time() + h);
    (void)a->predictPositions(a->time() + 0.07);
    (void)a->predictVelocities(a->time() + 0.07);
    // THEN its full observable state is unchanged, and it stays identical to the unqueried one
    ASSERT_TRUE(sameSnapshot(before, snapshot(*a))) << "query changed the state at step " << k;
    ASSERT_TRUE(sameSnapshot(snapshot(*a), snapshot(*b))) << "queried and unqueried predictors diverged at step " << k;
  }
}

TEST_P(PredictorProperty, PredictOnlyThroughAThreeSecondGap) {
  // GIVEN a predictor that has tracked for 10 s
  auto p = make(2);
  Stream s(2, 7, 0.0);
  Eigen::VectorXd z;
  while (s.time() < 10.0) feed(*p, s, z);
  const Snapshot before = snapshot(*p);
  // WHEN 3 s pass with no measurement at all (predict-only frames)
  const double t_gap = p->time();
  int k = 1;
  for (; k * kFramePeriod_s <= 3.0; ++k) {
    p->update(t_gap + k * kFramePeriod_s);
    for (int c = 0; c < 2; ++c) {
      const ChannelEstimate e = p->predict(c, p->time());
      // THEN the estimate stays finite and the innovation is marked invalid
      ASSERT_TRUE(e.x.allFinite() && e.P.allFinite()) << "frame " << k << " of the gap";
      ASSERT_FALSE(p->innovation(c).valid);
    }
  }
  // and the position variance does not shrink without measurements (it grows for every model with
  // process noise; `hold` has none and keeps it constant)
  const Snapshot after = snapshot(*p);
  for (int c = 0; c < 2; ++c) {
    if (GetParam() == "hold")
      EXPECT_GE(after.est[c].positionVariance(), before.est[c].positionVariance());
    else
      EXPECT_GT(after.est[c].positionVariance(), before.est[c].positionVariance());
    EXPECT_TRUE(isSymmetricPsd(after.est[c].P, kSymPsdTol));
  }
  // and tracking resumes with finite estimates
  for (int i = 0; i < 30; ++i) {
    z = Eigen::VectorXd::Constant(2, 250.0);
    p->update(p->time() + kFramePeriod_s, z);
  }
  EXPECT_TRUE(p->predictPositions(p->time() + 0.1).allFinite());
}

TEST_P(PredictorProperty, ResetRestoresConstructedBehaviour) {
  // GIVEN a fresh predictor and one that has already processed another stream, then been reset
  auto fresh = make(2), used = make(2);
  Stream warm(2, 99);
  Eigen::VectorXd z;
  for (int k = 0; k < 500; ++k) feed(*used, warm, z);
  used->reset();
  EXPECT_TRUE(std::isnan(used->time()));
  EXPECT_TRUE(std::isnan(used->predict(0, 0.0).position()));
  // WHEN both process the same data (starting at an earlier time than the warm-up ended)
  Stream s1(2, 5), s2(2, 5);
  Eigen::VectorXd z1, z2;
  for (int k = 0; k < 500; ++k) {
    feed(*fresh, s1, z1);
    feed(*used, s2, z2);
    // THEN they produce identical outputs
    ASSERT_TRUE(sameSnapshot(snapshot(*fresh), snapshot(*used))) << "step " << k;
    ASSERT_TRUE(sameEstimate(fresh->predict(1, fresh->time() + 0.1), used->predict(1, used->time() + 0.1)));
  }
}

TEST_P(PredictorProperty, CloneGoesOnWithTheSameBits) {
  // (once as the predictor is, once behind the glitch gate of `predvs track`, glitch_gate.h)
  for (const double g : {0.0, 8.0}) {
    // GIVEN a predictor that has processed a stream whose last frame jumps 200 px on channel 0 (the
    // glitch gate is then in doubt), and its clone
    auto p = make(2, {{"glitch_sigmas", g}});
    Stream s(2, 17);
    Eigen::VectorXd z;
    for (int k = 0; k < 299; ++k) feed(*p, s, z);
    const double t_jump = s.next(z);
    z(0) = 200.0 + (std::isnan(z(0)) ? 200.0 : z(0));
    p->update(t_jump, z);
    auto q = p->clone();
    ASSERT_NE(q, nullptr);
    EXPECT_EQ(q->name(), p->name());
    ASSERT_TRUE(sameSnapshot(snapshot(*p), snapshot(*q)));
    // WHEN both go on with the same frames, THEN every output is the same double
    Stream s1 = s, s2 = s;
    Eigen::VectorXd z1, z2;
    for (int k = 0; k < 300; ++k) {
      feed(*p, s1, z1);
      feed(*q, s2, z2);
      ASSERT_TRUE(sameSnapshot(snapshot(*p), snapshot(*q))) << "g " << g << ", step " << k;
      for (int c = 0; c < 2; ++c)
        ASSERT_TRUE(same(p->predictPosition(c, p->time() + 0.07), q->predictPosition(c, q->time() + 0.07)))
            << "g " << g << ", step " << k;
    }
  }
}

TEST_P(PredictorProperty, NanChannelIsPredictOnlyForThatChannel) {
  // GIVEN three predictors on the same 2-channel data: X misses channel 1 on some frames,
  // W gets a predict-only update(t) on those frames, Z gets every measurement
  auto X = make(2), W = make(2), Z = make(2);
  Stream s(2, 11, 0.0);
  Eigen::VectorXd z;
  for (int k = 0; k < 400; ++k) {
    const double t = s.next(z);
    const bool drop = (k > 50 && k % 7 == 0) || (k > 200 && k < 260);
    Z->update(t, z);
    if (drop) {
      Eigen::VectorXd zx = z;
      zx(1) = kNaN;
      X->update(t, zx);
      W->update(t);
      // THEN the missed channel is not innovated
      ASSERT_FALSE(X->innovation(1).valid);
      ASSERT_TRUE(X->innovation(0).valid);
    } else {
      X->update(t, z);
      W->update(t, z);
    }
    // and channel 1 of X evolves exactly as under a predict-only update, channel 0 exactly as when
    // channel 1 is measured (channels are independent)
    ASSERT_TRUE(sameEstimate(X->predict(1, t), W->predict(1, t))) << "frame " << k;
    ASSERT_TRUE(sameEstimate(X->predict(0, t), Z->predict(0, t))) << "frame " << k;
  }
}

TEST_P(PredictorProperty, EachChannelIsThatOfAOneChannelPredictor) {
  // GIVEN a 3-channel predictor and three 1-channel ones, each fed one of its channels, on data
  // with single missing entries, whole frames missing, 0.4 s gaps (coasting) and a manoeuvre that
  // differs per channel (an acceleration jump on channel 1, a stop on channel 2), so that every
  // adaptive layer (q's raise, fading, the monitor, the blend with hold) acts differently per channel
  auto all = make(3);
  std::vector<std::unique_ptr<Predictor>> one;
  for (int c = 0; c < 3; ++c) one.push_back(make(1));
  Stream s(3, 23);
  Eigen::VectorXd z, zc(1);
  for (int k = 0; k < 900; ++k) {
    const double t = s.next(z);
    if (t > 8.0) z(1) += 400.0 * (t - 8.0) * (t - 8.0);
    if (t > 12.0) z(2) = 150.0 + 80.0 * std::min(t - 12.0, 0.5);
    const bool gap = (k % 150) >= 138 || k % 41 == 0;
    if (gap) z.setConstant(kNaN);
    all->update(t, z);
    for (int c = 0; c < 3; ++c) {
      zc(0) = z(c);
      one[static_cast<size_t>(c)]->update(t, zc);
    }
    // THEN every channel is, bit for bit, the 1-channel predictor's (what `predvs predict` relies
    // on to run a predictor's channels as separate work items)
    for (int c = 0; c < 3; ++c) {
      const Predictor& p1 = *one[static_cast<size_t>(c)];
      ASSERT_TRUE(sameEstimate(all->predict(c, t), p1.predict(0, t))) << "channel " << c << ", frame " << k;
      ASSERT_TRUE(same(all->predictPosition(c, t + 0.1), p1.predictPosition(0, t + 0.1)))
          << "channel " << c << ", frame " << k;
      const Innovation a = all->innovation(c), b = p1.innovation(0);
      ASSERT_TRUE(same(a.eps, b.eps) && same(a.S, b.S) && a.valid == b.valid) << "channel " << c << ", frame " << k;
    }
  }
}

TEST_P(PredictorProperty, ForecastVariantsChangeTheForecastOnly) {
  // GIVEN each forecast variant the predictor offers (Predictor::forecastVariants(), which a fit
  // compares without fitting the noise again: noise_fit.h), and the predictor without it, fed the
  // same data with gaps and an acceleration jump on channel 1
  for (const Params& variant : make(1)->forecastVariants()) {
    auto own = make(2), other = make(2, variant);
    Stream s(2, 31);
    Eigen::VectorXd z;
    int forecasts_differ = 0;
    for (int k = 0; k < 900; ++k) {
      const double t = s.next(z);
      if (t > 8.0) z(1) += 400.0 * (t - 8.0) * (t - 8.0);
      if ((k % 150) >= 138) z.setConstant(kNaN);
      own->update(t, z);
      other->update(t, z);
      // THEN the filters are the same bits (state at the update time, innovations, hence the
      // likelihood), and only the forecast ahead may differ
      const auto r = sameSnapshot(snapshot(*own), snapshot(*other));
      ASSERT_TRUE(r) << "frame " << k << ": " << r.message();
      for (int c = 0; c < 2; ++c) forecasts_differ += own->predictPosition(c, t + 0.1) != other->predictPosition(c, t + 0.1);
    }
    // and it does differ somewhere (a variant that changed nothing would be no choice)
    EXPECT_GT(forecasts_differ, 0);
  }
}

TEST_P(PredictorProperty, NonIncreasingTimeThrows) {
  auto p = make(2);
  Eigen::VectorXd z = Eigen::VectorXd::Constant(2, 1.0);
  p->update(1.0, z);
  EXPECT_THROW(p->update(1.0, z), std::invalid_argument);
  EXPECT_THROW(p->update(0.5, z), std::invalid_argument);
  EXPECT_THROW(p->update(1.0), std::invalid_argument);
  EXPECT_THROW(p->update(kNaN, z), std::invalid_argument);
  EXPECT_EQ(p->time(), 1.0);  // a rejected update leaves the clock where it was
  EXPECT_NO_THROW(p->update(1.1, z));
  EXPECT_THROW(p->update(1.2, Eigen::VectorXd::Constant(3, 1.0)), std::invalid_argument);
}

/// Every registered predictor with its defaults, then each of its structural variants
/// (Predictor::structuralVariants(), e.g. "st-akf model=cv"), so that a filter's other motion
/// model is held to the same properties.
std::vector<std::string> registeredNames() {
  std::vector<std::string> out;
  for (const auto& info : predictorRegistry()) out.push_back(info.name);
  for (const auto& info : predictorRegistry())
    for (const Params& variant : makePredictor(info.name, 1)->structuralVariants()) {
      std::ostringstream s;
      s << info.name;
      for (const auto& kv : variant.texts()) s << " " << kv.first << "=" << kv.second;
      for (const auto& kv : variant.values()) s << " " << kv.first << "=" << std::setprecision(17) << kv.second;
      out.push_back(s.str());
    }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Registry, PredictorProperty, ::testing::ValuesIn(registeredNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string n = info.param;
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

}  // namespace
}  // namespace predvs
