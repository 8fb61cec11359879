// fakf-classic on either motion model (`model: cv | ca`, issue 11 item 3; docs/MODELS.md §3):
// the default (cv) gives the numbers of before, with its fuzzy R adaptation held still each model
// is the plain Kalman filter of that model, the structural variants build and run, and a bad
// word is a one-line error naming `model`.
#include "predvs/predictors/fakf.h"
#include "predvs/predictors/kalman_baselines.h"
#include "predvs/predictors/predictor.h"

#include "predictors/model_switch_scenario.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

namespace predvs {
namespace {

using namespace model_switch;

TEST(FakfClassicModel, DefaultModelGivesTheNumbersOfBeforeTheModelKey) {
  // GIVEN fakf-classic with its defaults, with and without `model: cv` spelt out (reference: the
  // same scenario through main at b41f742, before `model` existed, printed with %.17g; without the
  // significance-weighted forecast, the blend with hold and the pause of the adaptation after a
  // gap, which came later: shrink_sigmas 0, hold_blend_tau_s 0, adapt_after_gap 1, channel_predictor.h)
  const Pinned expected[2] = {{275.65671514078326, 19.259969196438178, 5.3110343284514707},
                              {3221.7393093856708, 546.09810957252671, 5.8619042444128189}};
  for (bool spelt : {false, true}) {
    SCOPED_TRACE(spelt ? "model: cv" : "default");
    Params params{{"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}, {"adapt_after_gap", 1.0}};
    if (spelt) params.setText("model", "cv");
    auto f = makePredictor("fakf-classic", 2, params);
    // WHEN it filters the scenario THEN the 2-frame predictions are the pinned ones
    expectPinned(*f, expected, 2);
  }
}

TEST(FakfClassicModel, WithRHeldEachModelIsThePlainKalmanFilterOfThatModel) {
  // GIVEN fakf-classic with r_min = r = r_max (the fuzzy adaptation runs but R cannot move) on each
  // model, and kf-cv / kf-ca with the same q, r, P_0 and forecast weighting (shrink_sigmas 1)
  for (const char* model : {"cv", "ca"}) {
    SCOPED_TRACE(model);
    const bool cv = std::string(model) == "cv";
    const double q = cv ? 2e3 : 5e4;
    Params params{{"q", q}, {"r", 1.5}, {"r_min", 1.5}, {"r_max", 1.5}, {"p0_vel", 300.0}, {"p0_acc", 700.0}, {"shrink_sigmas", 1.0}};
    params.setText("model", model);
    auto fakf = makePredictor("fakf-classic", 2, params);
    Params kf_params{{"q", q}, {"r", 1.5}, {"p0_vel", 300.0}, {"shrink_sigmas", 1.0}};
    if (!cv) kf_params.set("p0_acc", 700.0);
    auto kf = makePredictor(cv ? "kf-cv" : "kf-ca", 2, kf_params);
    // WHEN both filter the same scenario THEN they agree: the model is wired right
    expectSameFilter(*fakf, *kf);
  }
}

TEST(FakfClassicModel, OnCaTheFuzzyAdaptationStillRaisesR) {
  // GIVEN fakf-classic on the CA model assuming R = 1 px^2 on a ramp with 3 px noise (9 px^2)
  FakfClassicPredictor<3> f(1, {{"r", 1.0}});
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 3.0);
  Eigen::VectorXd z(1);
  for (int k = 0; k <= 300; ++k) {
    z(0) = 0.5 * k + noise(rng);
    f.update(0.1 * k, z);
  }
  // THEN R has grown well above its initial value (as on CV, FakfClassic.RaisesRWhen...)
  EXPECT_GT(f.adaptedR(0), 3.0);
}

TEST(FakfClassicModel, StructuralVariantsAreCvAndCaAndEachBuildsAndRuns) {
  // GIVEN the variants of the default predictor WHEN a predictor is built from each alone (plus r)
  // and runs THEN it has that model's state and noise keys, its default q, and a finite forecast
  expectModelVariantsBuildAndRun("fakf-classic", kDefaultQCv, kDefaultQFakfClassicCa);
}

TEST(FakfClassicModel, ABadModelIsAOneLineErrorNamingTheKey) { expectBadModelRejected("fakf-classic"); }

}  // namespace
}  // namespace predvs
