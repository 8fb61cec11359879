// predvs tests — the scenario on which the `model: cv | ca` switch of st-akf, st-akf-pm and
// fakf-classic is checked (tests/predictors/st_akf_test.cpp, fakf_classic_model_test.cpp):
// pinned numbers of the default model, "adaptation off = the plain KF of that model", and the
// structures a noise fit tries build and run.
#pragma once

#include "predvs/predictors/kalman_math.h"
#include "predvs/predictors/predictor.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace predvs {
namespace model_switch {

/// Pinned against the code before `model` existed: the default model must give the same numbers.
/// Bit-identical in practice; 1e-12 relative leaves room for a compiler's reassociation only.
constexpr double kPinnedRelTol = 1e-12;
/// Two implementations of the same Kalman recursion (an adaptive filter with its adaptation off vs
/// kf-cv / kf-ca) differ in the order of their floating-point operations only: 1e-9 relative
/// over 600 frames.
constexpr double kSameFilterRelTol = 1e-9;

inline void expectRelNear(double actual, double expected, double rel_tol) {
  EXPECT_NEAR(actual, expected, rel_tol * std::max(1.0, std::abs(expected)));
}

/// 600 frames at 30 Hz of two channels: a 100 px circle with uniform noise in [-2, 2) px from the
/// raw std::mt19937 output (fully specified by the standard, unlike the distributions); at
/// t = 10 s channel 0 jumps by 40 px and channel 1 starts accelerating at 60 px/s^2; channel 1 is
/// not measured on every 37th frame. Returns the last frame time.
inline double runScenario(Predictor& f) {
  std::mt19937 rng(42);
  auto noise = [&rng] { return 2.0 * (static_cast<double>(rng()) / 4294967296.0 - 0.5); };
  Eigen::VectorXd z(2);
  double t = 0.0;
  for (int k = 0; k <= 600; ++k) {
    t = k / 30.0;
    const double n0 = noise(), n1 = noise();
    z(0) = 320.0 + 100.0 * std::cos(0.5 * t) + 2.0 * n0 + (t > 10.0 ? 40.0 : 0.0);
    z(1) = 240.0 + 100.0 * std::sin(0.5 * t) + 2.0 * n1 + (t > 10.0 ? 30.0 * (t - 10.0) * (t - 10.0) : 0.0);
    if (k % 37 == 0) z(1) = std::nan("");
    f.update(t, z);
  }
  return t;
}

/// The 2-frame-ahead estimate of one channel after runScenario(), as pinned.
struct Pinned {
  double p, v, pp;  ///< position (px), velocity (px/s), position variance (px^2)
};

/// Runs `f` on the scenario and expects the pinned 2-frame predictions of both channels.
inline void expectPinned(Predictor& f, const Pinned (&expected)[2], int states) {
  const double t = runScenario(f);
  for (int c = 0; c < 2; ++c) {
    SCOPED_TRACE("channel " + std::to_string(c));
    const ChannelEstimate e = f.predict(c, t + 2.0 / 30.0);
    ASSERT_EQ(e.x.size(), states);
    expectRelNear(e.position(), expected[c].p, kPinnedRelTol);
    expectRelNear(e.velocity(), expected[c].v, kPinnedRelTol);
    expectRelNear(e.positionVariance(), expected[c].pp, kPinnedRelTol);
  }
}

/// Runs `a` and `b` on the scenario and expects the same states, covariances and innovation
/// variances.
inline void expectSameFilter(Predictor& a, Predictor& b) {
  const double t = runScenario(a);
  runScenario(b);
  for (int c = 0; c < 2; ++c) {
    SCOPED_TRACE("channel " + std::to_string(c));
    const ChannelEstimate ea = a.predict(c, t + 0.05), eb = b.predict(c, t + 0.05);
    ASSERT_EQ(ea.x.size(), eb.x.size());
    for (int i = 0; i < ea.x.size(); ++i) expectRelNear(ea.x(i), eb.x(i), kSameFilterRelTol);
    for (int i = 0; i < ea.P.size(); ++i) expectRelNear(ea.P(i), eb.P(i), kSameFilterRelTol);
    EXPECT_EQ(a.innovation(c).valid, b.innovation(c).valid);
    expectRelNear(a.innovation(c).S, b.innovation(c).S, kSameFilterRelTol);
  }
}

/// makePredictor(name, 1, {model: word}) throws a one-line std::invalid_argument naming `model`
/// and the words allowed; a number for `model` throws too.
inline void expectBadModelRejected(const std::string& name) {
  Params bad;
  bad.setText("model", "singer");
  try {
    makePredictor(name, 1, bad);
    ADD_FAILURE() << name << ": no error";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'model'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("cv or ca"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  EXPECT_THROW(makePredictor(name, 1, {{"model", 2.0}}), std::invalid_argument) << name;
}

/// The structures of `name` with its defaults (structuralVariants()): cv, ca, then each with
/// `adaptation: off` (adaptation_off_test.cpp). A predictor built from each alone (plus r = 2 px^2)
/// runs the scenario with that model's state ([p, v] or [p, v, a]), a finite forecast, its own four
/// structures, and the noise keys q (its default: q_cv px^2/s^3 on cv, q_ca px^2/s^5 on ca, within
/// that model's density bounds, kalman_math.h) and r.
inline void expectModelVariantsBuildAndRun(const std::string& name, double q_cv, double q_ca) {
  const auto variants = makePredictor(name, 1, {})->structuralVariants();
  ASSERT_EQ(variants.size(), 4u);
  EXPECT_EQ(variants[0].text("model", ""), "cv");
  EXPECT_EQ(variants[1].text("model", ""), "ca");
  for (const Params& v : variants) {
    const bool cv = v.text("model", "") == "cv";
    SCOPED_TRACE(cv ? "cv" : "ca");
    Params p = v;
    p.set("r", 2.0);
    auto f = makePredictor(name, 2, p);
    const double t = runScenario(*f);
    EXPECT_EQ(f->predict(0, t + 0.1).x.size(), cv ? 2 : 3);
    EXPECT_TRUE(std::isfinite(f->predictPosition(1, t + 0.1)));
    const auto noise = f->noiseParameters();
    ASSERT_EQ(noise.size(), 2u);
    EXPECT_EQ(noise[0].key, "q");
    EXPECT_EQ(noise[0].value, cv ? q_cv : q_ca);
    EXPECT_EQ(noise[0].hi, cv ? accelerationDensityParameter("q", 1.0).hi : jerkDensityParameter("q", 1.0).hi);
    EXPECT_EQ(noise[1].key, "r");
    EXPECT_EQ(f->structuralVariants().size(), 4u);
  }
}

}  // namespace model_switch
}  // namespace predvs
