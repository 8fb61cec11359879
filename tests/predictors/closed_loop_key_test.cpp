// The caller's key `closed_loop` (predictor.h closedLoopParam): every filter with the raise of q
// matches its density to its innovations instead when the keys that set the density are not given
// (those whose q takes `auto` exactly as with `q: auto`); given keys are kept; hold and cs-akf (no
// raise) ignore the key; any value but 0 or 1 is an error naming the key.
#include "predvs/predictors/params.h"
#include "predvs/predictors/predictor.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {
namespace {

/// Positions 3 frames ahead of every frame of a noisy circle at 25 Hz, 10 s, 2 channels.
std::vector<double> forecasts(const std::string& name, const Params& params) {
  std::unique_ptr<Predictor> p = makePredictor(name, 2, params);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::vector<double> out;
  Eigen::VectorXd z(2);
  for (int k = 0; k < 250; ++k) {
    const double t = k / 25.0;
    z << 100.0 + 40.0 * std::cos(0.5 * t) + noise(rng), 80.0 + 40.0 * std::sin(0.5 * t) + noise(rng);
    p->update(t, z);
    for (int c = 0; c < 2; ++c) out.push_back(p->predictPosition(c, t + 0.12));
  }
  return out;
}

Params with(std::initializer_list<std::pair<const char*, double>> values, const char* q_word = nullptr) {
  Params p;
  for (const auto& [k, v] : values) p.set(k, v);
  if (q_word) p.setText("q", q_word);
  return p;
}

TEST(ClosedLoopKey, FiltersWithAnAutoQMatchItWhenQIsNotGiven) {
  for (const char* name : {"kf-cv", "kf-ca", "st-akf", "st-akf-pm", "fakf-classic"}) {
    SCOPED_TRACE(name);
    // GIVEN a filter told closed_loop: 1 THEN it runs as with q: auto (covariance matching), not as
    // with its default density and the raise
    const auto told = forecasts(name, with({{"closed_loop", 1.0}}));
    EXPECT_EQ(told, forecasts(name, with({}, "auto")));
    EXPECT_NE(told, forecasts(name, with({})));
    // AND closed_loop: 0 is the default
    EXPECT_EQ(forecasts(name, with({{"closed_loop", 0.0}})), forecasts(name, with({})));
    // AND a q given is kept
    EXPECT_EQ(forecasts(name, with({{"closed_loop", 1.0}, {"q", 500.0}})), forecasts(name, with({{"q", 500.0}})));
  }
}

TEST(ClosedLoopKey, TheOtherFiltersWithARaiseMatchTooUnlessTheirDensityIsGiven) {
  // GIVEN the filters whose density is set by other keys (the CS variance bounds, stkf's q / q_pos /
  // q_vel, imm's q_cv / q_ca) WHEN told closed_loop: 1 THEN their forecasts change, and not when a
  // key that sets the density is given
  struct Case {
    const char* name;
    const char* key;
    double value;
  };
  for (const Case& c : {Case{"cs-akf-adaptive", "sigma_max_sq", 2000.0}, Case{"fakf", "sigma_min_sq", 5.0},
                        Case{"stkf", "q", 500.0}, Case{"imm", "q_cv", 500.0}}) {
    SCOPED_TRACE(c.name);
    EXPECT_NE(forecasts(c.name, with({{"closed_loop", 1.0}})), forecasts(c.name, with({})));
    EXPECT_EQ(forecasts(c.name, with({{"closed_loop", 1.0}, {c.key, c.value}})), forecasts(c.name, with({{c.key, c.value}})));
  }
}

TEST(ClosedLoopKey, EveryPredictorTakesItHoldAndCsAkfIgnoreIt) {
  for (const char* name : {"hold", "cs-akf"}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(forecasts(name, with({{"closed_loop", 1.0}})), forecasts(name, with({})));
  }
  // AND a value that is not 0 or 1 is an error naming the key
  try {
    makePredictor("kf-cv", 2, with({{"closed_loop", 0.5}}));
    FAIL() << "closed_loop: 0.5 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("closed_loop"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace predvs
