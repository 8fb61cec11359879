// The per-frame-period caches of the predictors (imm's chain, F, Q and forgetting factors per dt,
// imm.h; the blend's forgetting exp(-dt / hold_blend_tau_s) per dt, channel_predictor.h; the
// Singer matrices per thread, cs_akf.h): a recorded track's frame period varies in its last bits,
// so these keep several dt and replace them in turn. Whatever a cache holds, a prediction must be
// what a fresh instance gives, bit for bit.
#include "predvs/predictors/predictor.h"
#include "predictors/blend_alone.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace predvs {
namespace {

/// A two-channel track whose frame period takes `periods` distinct values, each used several
/// times in a shuffled order (more than any cache holds), with a dropped frame now and then.
struct Track {
  std::vector<double> t;
  std::vector<Eigen::Vector2d> z;
};
Track jitteredTrack(int periods, double base_s, double spread_s, unsigned seed) {
  std::vector<double> dts;
  for (int round = 0; round < 12; ++round)
    for (int k = 0; k < periods; ++k) dts.push_back(base_s + spread_s * k / periods);
  std::mt19937_64 rng(seed);
  std::shuffle(dts.begin(), dts.end(), rng);
  std::normal_distribution<double> noise(0.0, 1.0);
  Track tr;
  double t = 0.0;
  for (size_t i = 0; i < dts.size(); ++i) {
    t += dts[i];
    tr.t.push_back(t);
    const bool dropped = i % 13 == 5;
    const double nan = std::nan("");
    tr.z.emplace_back(dropped ? nan : 300.0 + 80.0 * std::sin(0.7 * t) + noise(rng),
                      dropped ? nan : 200.0 + 40.0 * t + 5.0 * t * t * (t < 3.0) + noise(rng));
  }
  return tr;
}

/// The predicted positions (both channels, 2 frames of the base period ahead) after every update.
std::vector<double> run(Predictor& p, const Track& tr, double horizon_s) {
  std::vector<double> out;
  Eigen::VectorXd x(2);
  for (size_t i = 0; i < tr.t.size(); ++i) {
    p.update(tr.t[i], tr.z[i]);
    p.predictPositions(tr.t[i] + horizon_s, x);
    out.push_back(x(0));
    out.push_back(x(1));
  }
  return out;
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(PeriodCache, EveryPredictorGivesAFreshInstancesBitsWhateverItsCachesHold) {
  // GIVEN every registered predictor (and imm without its CP mode, and in Singer mode), a track
  // whose frame period takes 20 values around 1/30 s and another one with 20 other values around
  // 1/60 s;
  std::vector<std::pair<std::string, Params>> specs;
  for (const auto& info : predictorRegistry()) specs.emplace_back(info.name, Params{});
  specs.emplace_back("imm", Params{{"cp", 0.0}});
  specs.emplace_back("imm", Params{{"alpha", 0.5}});
  const Track track = jitteredTrack(20, 1.0 / 30.0, 2e-3, 11);
  const Track other = jitteredTrack(20, 1.0 / 60.0, 1e-3, 12);
  const double horizon_s = 2.0 / 30.0;
  for (const auto& [name, params] : specs) {
    // WHEN one instance runs the other track, is reset and runs the track, and a fresh one runs it
    auto used = makePredictor(name, 2, params);
    run(*used, other, horizon_s);
    used->reset();
    const std::vector<double> got = run(*used, track, horizon_s);
    auto fresh = makePredictor(name, 2, params);
    const std::vector<double> want = run(*fresh, track, horizon_s);
    // THEN every prediction is the same bits (a cache entry given for the wrong dt would differ:
    // the periods differ by up to 6 %)
    ASSERT_EQ(got.size(), want.size());
    int finite = 0;
    for (size_t i = 0; i < got.size(); ++i) {
      ASSERT_TRUE(sameBits(got[i], want[i])) << name << " row " << i / 2 << ": " << got[i] << " vs " << want[i];
      finite += std::isfinite(got[i]) ? 1 : 0;
    }
    EXPECT_GT(finite, static_cast<int>(got.size()) * 9 / 10) << name;
  }
}

TEST(PeriodCache, BlendForgettingIsExpOfTheFramePeriodOnAJitteredTrack) {
  // GIVEN kf-cv with the blend (tau 1 s) and a twin without it, on a track whose period takes 20
  // values from 0.05 to 0.15 s, shuffled (the blend's forgetting is kept per dt); the blend alone
  // (blend_alone.h: the coasting rules that come with it off, as they change the filter in a gap,
  // not only the forecast), the one-frame regression and one weight;
  const double tau_s = 1.0;
  auto on = makePredictor("kf-cv", 1, blendAlone(tau_s, {{"hold_blend_frames", 1.0}, {"hold_blend_split", 0.0}}));
  auto off = makePredictor("kf-cv", 1, {{"hold_blend_tau_s", 0.0}});
  const Track tr = jitteredTrack(20, 0.05, 0.1, 3);
  double s_dd = 0.0, s_dy = 0.0, w = 1.0, z_hold = 0.0, t_prev = 0.0;
  bool last_measured = false;
  Eigen::VectorXd z(1);
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    z(0) = tr.z[k](0);
    const bool measured = std::isfinite(z(0));
    const double f = k > 0 ? off->predictPosition(0, t) : 0.0;
    if (measured && last_measured) {  // the regression with exp(-dt / tau) of this frame's dt
      const double lambda = std::exp(-(t - t_prev) / tau_s), d = f - z_hold, y = z(0) - z_hold;
      s_dd = lambda * s_dd + d * d;
      s_dy = lambda * s_dy + d * y;
      w = s_dd > 0.0 ? std::clamp(s_dy / s_dd, 0.0, 1.0) : 1.0;
    }
    if (measured) z_hold = z(0);
    last_measured = measured;
    t_prev = t;
    on->update(t, z);
    off->update(t, z);
    // THEN the forecast is hold + w (model forecast - hold) with that weight
    const double t_f = t + 0.2;
    ASSERT_NEAR(on->predictPosition(0, t_f), z_hold + w * (off->predictPosition(0, t_f) - z_hold), 1e-9) << k;
  }
  EXPECT_LT(w, 0.999);  // the weight moved
}

}  // namespace
}  // namespace predvs
