// Predictor::noiseParameters() for every registered predictor: what a noise fit
// (calibration/noise_fit.h) asks a predictor for instead of a table of names.
#include "predvs/predictors/predictor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

namespace predvs {
namespace {

TEST(NoiseParameters, KeysBoundsAndValuesOfEveryPredictor) {
  for (const PredictorInfo& info : predictorRegistry()) {
    SCOPED_TRACE(info.name);
    const auto params = makePredictor(info.name, 2)->noiseParameters();
    std::set<std::string> keys;
    for (const NoiseParameter& p : params) {
      SCOPED_TRACE(p.key);
      EXPECT_TRUE(keys.insert(p.key).second) << "duplicate key";
      EXPECT_GT(p.lo, 0.0);
      EXPECT_LT(p.lo, p.hi);
      EXPECT_TRUE(std::isfinite(p.hi));
      // The default lies inside the bounds, except a term switched off by default (stkf's q_pos = 0),
      // which a log-scale fit starts at its lower bound.
      if (p.value != 0.0) {
        EXPECT_GE(p.value, p.lo);
      }
      EXPECT_GE(p.value, 0.0);
      EXPECT_LE(p.value, p.hi);

      // The key is a parameter of the predictor, and `value` is the value the instance runs with.
      Params given;
      given.set(p.key, p.value);
      EXPECT_NO_THROW(makePredictor(info.name, 2, given));
      const double other = std::sqrt(p.lo * p.hi);
      Params changed;
      changed.set(p.key, other);
      bool read_back = false;
      for (const NoiseParameter& q : makePredictor(info.name, 2, changed)->noiseParameters())
        if (q.key == p.key) {
          read_back = true;
          EXPECT_DOUBLE_EQ(q.value, other);
        }
      EXPECT_TRUE(read_back);
    }
  }
}

TEST(NoiseParameters, HoldHasNoneAndEveryExtrapolatingPredictorHasSome) {
  EXPECT_TRUE(makePredictor("hold", 1)->noiseParameters().empty());
  for (const PredictorInfo& info : predictorRegistry()) {
    const auto p = makePredictor(info.name, 1);
    if (p->extrapolates()) {
      EXPECT_FALSE(p->noiseParameters().empty()) << info.name;
    }
  }
}

TEST(NoiseParameters, AutoRReportsThePriorAndAGivenRItself) {
  // `r` absent means `auto` for kf-cv: the reported value is the estimator's prior, 1 px^2.
  for (const NoiseParameter& p : makePredictor("kf-cv", 1)->noiseParameters())
    if (p.key == "r") {
      EXPECT_EQ(p.value, 1.0);
    }
  Params given;
  given.set("r", 4.0);
  for (const NoiseParameter& p : makePredictor("imm", 1, given)->noiseParameters())
    if (p.key == "r") {
      EXPECT_EQ(p.value, 4.0);
    }
}

}  // namespace
}  // namespace predvs
