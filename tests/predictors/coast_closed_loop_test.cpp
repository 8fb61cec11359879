// Coasting in a closed loop (channel_predictor.h coastTauParam; docs/PERFORMANCE.md "Coasting in a
// closed loop"): told `closed_loop: 1`, every filter that coasts through a gap does so with
// coast_tau_s 0.5 s instead of 0.2 s, unless the key is given; imm too.
#include "predvs/predictors/channel_predictor.h"
#include "predvs/predictors/predictor.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <random>
#include <string>
#include <vector>

namespace predvs {
namespace {

/// `name` (1 channel, `params`) on a 40 px/s ramp at 25 Hz with 0.5 px of noise, 0.6 s of frames
/// missing at 3 s: the 2-frame forecasts after every frame, measured or not.
std::vector<double> throughAGap(const std::string& name, const Params& params) {
  auto p = makePredictor(name, 1, params);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::vector<double> out;
  const double T = 0.04;
  for (int k = 0; k < 150; ++k) {
    const double t = k * T;
    const bool gap = t >= 3.0 && t < 3.6;
    if (gap)
      p->update(t);
    else
      p->update(t, Eigen::VectorXd::Constant(1, 50.0 + 40.0 * t + noise(rng)));
    out.push_back(p->predictPosition(0, t + 2 * T));
  }
  return out;
}

TEST(CoastClosedLoop, AClosedLoopCoastsOverHalfASecond) {
  EXPECT_EQ(kDefaultClosedLoopCoastTauS, 0.5);
  for (const char* name : {"kf-cv", "kf-ca", "cs-akf-adaptive", "st-akf", "imm"}) {
    SCOPED_TRACE(name);
    // GIVEN the filter told it serves a closed loop, and the same filter with coast_tau_s given
    const std::vector<double> loop = throughAGap(name, Params{{"closed_loop", 1.0}});
    // THEN through the gap it coasts as with coast_tau_s 0.5, not as with the open loop's 0.2
    EXPECT_EQ(loop, throughAGap(name, Params{{"closed_loop", 1.0}, {"coast_tau_s", 0.5}}));
    EXPECT_NE(loop, throughAGap(name, Params{{"closed_loop", 1.0}, {"coast_tau_s", kDefaultCoastTauS}}));
    // AND in the open loop the default is still 0.2 s
    EXPECT_EQ(throughAGap(name, Params{}), throughAGap(name, Params{{"coast_tau_s", kDefaultCoastTauS}}));
  }
}

}  // namespace
}  // namespace predvs
