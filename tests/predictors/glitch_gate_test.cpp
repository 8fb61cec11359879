// The glitch gate (predictors/include/predvs/predictors/glitch_gate.h,
// docs/MODELS.md §16).
#include "predvs/predictors/glitch_gate.h"
#include "predvs/predictors/predictor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRateHz = 30.0;

/// A smooth two-channel motion (px) with Gaussian noise, 30 Hz, 400 frames.
struct Track {
  std::vector<double> t, u, v, u_true, v_true;
};

Track makeTrack(double noise_px, unsigned seed) {
  Track tr;
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise_px);
  for (int k = 0; k < 400; ++k) {
    const double t = k / kRateHz;
    const double u = 300.0 + 60.0 * t + 40.0 * std::sin(0.8 * t),
                 v = 200.0 + 50.0 * std::sin(0.6 * t + 0.4);
    tr.t.push_back(t);
    tr.u_true.push_back(u);
    tr.v_true.push_back(v);
    tr.u.push_back(u + n(rng));
    tr.v.push_back(v + n(rng));
  }
  return tr;
}

/// The forecasts 2 frames ahead (u channel) after each frame.
std::vector<double> forecasts(Predictor& p, const Track& tr) {
  std::vector<double> f;
  Eigen::Vector2d z;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    z << tr.u[k], tr.v[k];
    p.update(tr.t[k], z);
    f.push_back(p.predictPosition(0, tr.t[k] + 2.0 / kRateHz));
  }
  return f;
}

bool same(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

std::vector<std::string> extrapolatingPredictors() {
  std::vector<std::string> names;
  for (const auto& info : predictorRegistry())
    if (makePredictor(info.name, 2)->extrapolates()) names.push_back(info.name);
  return names;
}

/// The predictor `name` behind the gate at the tracker's g.
std::unique_ptr<Predictor> gatedPredictor(const std::string& name) {
  return makePredictor(name, 2, {{"glitch_sigmas", kTrackerGlitchSigmas}});
}

TEST(GlitchGate, IsOnWithGlitchSigmasForEveryPredictorThatExtrapolates) {
  for (const auto& name : extrapolatingPredictors()) {
    auto p = gatedPredictor(name);
    EXPECT_NE(dynamic_cast<GlitchGate*>(p.get()), nullptr) << name;
    EXPECT_EQ(p->name(), name);
    EXPECT_EQ(dynamic_cast<GlitchGate*>(makePredictor(name, 2).get()), nullptr)
        << name << ": off by default";
  }
  EXPECT_EQ(dynamic_cast<GlitchGate*>(makePredictor("hold", 2, {{"glitch_sigmas", 8.0}}).get()),
            nullptr);
  EXPECT_THROW(makePredictor("kf-cv", 2, {{"glitch_sigmas", -1.0}}), std::invalid_argument);
}

TEST(GlitchGate, ACleanTrackNeverRaisesADoubtAndGivesTheSameBits) {
  const Track tr = makeTrack(1.0, 3);
  for (const auto& name : extrapolatingPredictors()) {
    auto gated = gatedPredictor(name), plain = makePredictor(name, 2);
    const auto fg = forecasts(*gated, tr), fp = forecasts(*plain, tr);
    const auto* gate = dynamic_cast<GlitchGate*>(gated.get());
    ASSERT_NE(gate, nullptr);
    EXPECT_EQ(gate->glitches() + gate->steps(), 0) << name;
    for (size_t k = 0; k < fg.size(); ++k) ASSERT_TRUE(same(fg[k], fp[k])) << name << " frame " << k;
  }
}

TEST(GlitchGate, AGlitchNeverEntersThePredictor) {
  // GIVEN a track whose frame 200 is 40 px off on u and v (a tracker glitch),
  // and the same track with frame 200 not measured
  const Track clean = makeTrack(0.5, 5);
  Track glitched = clean, without = clean;
  glitched.u[200] += 40.0;
  glitched.v[200] -= 30.0;
  without.u[200] = without.v[200] = kNaN;
  for (const auto& name : extrapolatingPredictors()) {
    auto gated = gatedPredictor(name), fed = makePredictor(name, 2), skipping = makePredictor(name, 2);
    const auto fg = forecasts(*gated, glitched), ff = forecasts(*fed, glitched),
               fs = forecasts(*skipping, without);
    // THEN the gate settles it as a glitch, and from the next frame on its
    // forecasts are, bit for bit, those of the predictor that never saw frame
    // 200
    EXPECT_EQ(dynamic_cast<GlitchGate*>(gated.get())->glitches(), 1) << name;
    const NamedValues tallies = gated->tallies();  // what a report sums (Predictor::tallies())
    ASSERT_GE(tallies.size(), 2u) << name;
    EXPECT_EQ(tallies[tallies.size() - 2], (std::pair<std::string, double>{"glitches", 1.0})) << name;
    EXPECT_EQ(tallies.back().first, "steps") << name;
    EXPECT_TRUE(fed->tallies().empty()) << name;
    for (size_t k = 201; k < fg.size(); ++k) ASSERT_TRUE(same(fg[k], fs[k])) << name << " frame " << k;
    // AND the forecasts made on frames 200-203 are nearer the truth than the
    // ungated predictor's
    double eg = 0.0, ef = 0.0;
    for (size_t k = 200; k <= 203; ++k) {
      eg += std::pow(fg[k] - clean.u_true[k + 2], 2);
      ef += std::pow(ff[k] - clean.u_true[k + 2], 2);
    }
    EXPECT_LT(eg, 0.5 * ef) << name;
  }
}

TEST(GlitchGate, AStepIsSettledAsAStepAndLeavesThePredictorAsWithoutTheGate) {
  // GIVEN a track that jumps 40 px at frame 200 and stays there (a tracker
  // re-acquiring elsewhere)
  Track stepped = makeTrack(0.5, 7);
  for (size_t k = 200; k < stepped.t.size(); ++k) stepped.u[k] += 40.0;
  for (const auto& name : extrapolatingPredictors()) {
    auto gated = gatedPredictor(name), plain = makePredictor(name, 2);
    const auto fg = forecasts(*gated, stepped), fp = forecasts(*plain, stepped);
    const auto* gate = dynamic_cast<GlitchGate*>(gated.get());
    // THEN the doubt of frame 200 is settled as a step on frame 201, and every
    // forecast but the one made on frame 200 is the ungated predictor's
    EXPECT_EQ(gate->glitches(), 0) << name;
    EXPECT_GE(gate->steps(), 1) << name;
    for (size_t k = 0; k < 200; ++k) ASSERT_TRUE(same(fg[k], fp[k])) << name << " frame " << k;
    for (size_t k = 201; k < fg.size(); ++k) ASSERT_TRUE(same(fg[k], fp[k])) << name << " frame " << k;
    // AND the forecast made on frame 200 lies between the two hypotheses' (p =
    // 1/2 before any is settled)
    EXPECT_FALSE(same(fg[200], fp[200])) << name;
  }
}

TEST(GlitchGate, InDoubtTheCovarianceFreeFormsArePredictsBitForBit) {
  // GIVEN the track that jumps 40 px at frame 200, fed up to that frame: the gate is in doubt, its
  // forecast a mixture of the two hypotheses
  Track stepped = makeTrack(0.5, 7);
  for (size_t k = 200; k < stepped.t.size(); ++k) stepped.u[k] += 40.0;
  for (const auto& name : extrapolatingPredictors()) {
    auto gated = gatedPredictor(name), plain = makePredictor(name, 2);
    Eigen::Vector2d z;
    for (size_t k = 0; k <= 200; ++k) {
      z << stepped.u[k], stepped.v[k];
      gated->update(stepped.t[k], z);
      plain->update(stepped.t[k], z);
    }
    const double t = stepped.t[200] + 2.0 / kRateHz;
    ASSERT_FALSE(same(gated->predictPosition(0, t), plain->predictPosition(0, t))) << name << ": not in doubt";
    // THEN predictPosition and predictVelocity give predict()'s position and velocity
    for (int c = 0; c < 2; ++c) {
      const ChannelEstimate e = gated->predict(c, t);
      EXPECT_TRUE(same(gated->predictPosition(c, t), e.position())) << name << " channel " << c;
      EXPECT_TRUE(same(gated->predictVelocity(c, t), e.velocity())) << name << " channel " << c;
    }
  }
}

TEST(GlitchGate, APointReacquiredAfterAGapIsNotDoubted) {
  // GIVEN a track with frames 190-199 not measured, after which the tracker
  // finds the point 40 px further on u than the motion explains (re-acquired
  // elsewhere, or moved faster while unseen)
  Track gapped = makeTrack(0.5, 11);
  for (size_t k = 190; k < 200; ++k) gapped.u[k] = gapped.v[k] = kNaN;
  for (size_t k = 200; k < gapped.t.size(); ++k) gapped.u[k] += 40.0;
  for (const auto& name : extrapolatingPredictors()) {
    auto gated = gatedPredictor(name), plain = makePredictor(name, 2);
    const auto fg = forecasts(*gated, gapped), fp = forecasts(*plain, gapped);
    const auto* gate = dynamic_cast<GlitchGate*>(gated.get());
    // THEN no frame is doubted (the test needs the two frames before it
    // measured: the first frames after a gap are taken as they are, the file
    // comment of glitch_gate.h), and every forecast is the ungated predictor's
    EXPECT_EQ(gate->glitches() + gate->steps(), 0) << name;
    for (size_t k = 0; k < fg.size(); ++k) ASSERT_TRUE(same(fg[k], fp[k])) << name << " frame " << k;
  }
}

}  // namespace
}  // namespace predvs
