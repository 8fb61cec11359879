// The caller's key `closed_loop` (predictor.h closedLoopParam): every filter with the raise of q
// adapts its density to its innovations instead when the keys that set the density are not given
// (the whitening, process_noise_adapt.h; stkf the spread, as `q: auto`); given keys are kept; imm
// leaves its CP mode out unless `cp` is given; hold and cs-akf (no raise) ignore the key; any value
// but 0 or 1 is an error naming the key.
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

TEST(ClosedLoopKey, FiltersWithAnAutoQWhitenTheirInnovationsWhenQIsNotGiven) {
  for (const char* name : {"kf-cv", "kf-ca", "st-akf", "st-akf-pm", "fakf-classic"}) {
    SCOPED_TRACE(name);
    // GIVEN a filter told closed_loop: 1 THEN it runs neither with its default density and the
    // raise nor as with q: auto (covariance matching): its density is whitened (q_whitening_test.cpp)
    const auto told = forecasts(name, with({{"closed_loop", 1.0}}));
    EXPECT_NE(told, forecasts(name, with({}, "auto")));
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
    // (imm's `cp` given too: in a closed loop its CP mode is left out by default, below)
    const double cp = std::string(c.name) == "imm" ? 1.0 : -1.0;
    Params told = with({{"closed_loop", 1.0}, {c.key, c.value}}), given = with({{c.key, c.value}});
    if (cp > 0.0) told.set("cp", cp), given.set("cp", cp);
    EXPECT_EQ(forecasts(c.name, told), forecasts(c.name, given));
  }
}

/// True when imm built with `params` reports mode probabilities of mode `mode` ("cp", "cv", "ca").
bool immHasMode(const Params& params, const std::string& mode) {
  std::unique_ptr<Predictor> p = makePredictor("imm", 2, params);
  Eigen::VectorXd z(2);
  z << 1.0, 2.0;
  p->update(0.0, z);
  for (const auto& [name, value] : p->diagnostics())
    if (name.rfind("mu_" + mode + "_", 0) == 0) return true;
  return false;
}

TEST(ClosedLoopKey, ImmLeavesItsConstantPositionModeOutUnlessCpIsGiven) {
  // GIVEN imm told closed_loop: 1 THEN it has the CV and CA modes only
  EXPECT_FALSE(immHasMode(with({{"closed_loop", 1.0}}), "cp"));
  EXPECT_TRUE(immHasMode(with({{"closed_loop", 1.0}}), "cv"));
  EXPECT_TRUE(immHasMode(with({{"closed_loop", 1.0}}), "ca"));
  // AND all three with cp: 1, and without the key (the open loop's default)
  EXPECT_TRUE(immHasMode(with({{"closed_loop", 1.0}, {"cp", 1.0}}), "cp"));
  EXPECT_TRUE(immHasMode(with({}), "cp"));
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
