// The pause of the adaptation on the first measurement after a gap (channel_predictor.h,
// `adapt_after_gap`, docs/MODELS.md §5 and §9): for each predictor that reads the key (st-akf,
// st-akf-pm, fakf-classic, fakf), the key changes the forecasts of a track with gaps while the
// filter coasts, and nothing at all without coasting (the papers' occlusion scenarios) or without
// a gap; every other registered predictor ignores it.
#include "predvs/predictors/predictor.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace predvs {
namespace {

/// 2-frame forecasts of channel 0 on a weaving target (60 Hz, 2 px noise, 12 s, two channels);
/// with gaps, 6-frame gaps every 40 frames.
std::vector<double> forecasts(const std::string& name, const Params& params, bool gaps) {
  auto p = makePredictor(name, 2, params);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 2.0);
  const double T = 1.0 / 60.0;
  std::vector<double> out;
  for (int k = 0; k < 720; ++k) {
    const double t = k * T;
    Eigen::VectorXd z(2);
    z << 300.0 + 120.0 * std::sin(1.3 * t) + 40.0 * t + noise(rng), 200.0 + 80.0 * std::cos(0.9 * t) + noise(rng);
    if (gaps && k % 40 >= 34) z.setConstant(std::nan(""));
    p->update(t, z);
    out.push_back(p->predictPosition(0, t + 2.0 * T));
  }
  return out;
}

TEST(AdaptAfterGap, TheKeyActsWhileCoastingOnGapsOnlyAndOnlyWhereItIsRead) {
  const std::set<std::string> readers = {"st-akf", "st-akf-pm", "fakf-classic", "fakf"};
  for (const auto& info : predictorRegistry()) {
    SCOPED_TRACE(info.name);
    const Params pause{}, adapt{{"adapt_after_gap", 1.0}};
    Params pause_nocoast{{"coast_tau_s", 0.0}}, adapt_nocoast{{"coast_tau_s", 0.0}, {"adapt_after_gap", 1.0}};
    if (info.name == "hold") {  // no velocity to coast: the key is unknown there
      EXPECT_THROW(makePredictor(info.name, 2, adapt), std::invalid_argument);
      continue;
    }
    if (!readers.count(info.name)) {
      // GIVEN a predictor that does not adapt on its innovations THEN the key is not one of its own
      EXPECT_THROW(makePredictor(info.name, 2, adapt), std::invalid_argument);
      continue;
    }
    // GIVEN a predictor that reads it: WHEN the track has gaps and the filter coasts THEN the first
    // measurements after the gaps adapt (1) or not (0, the default): other forecasts
    EXPECT_NE(forecasts(info.name, pause, true), forecasts(info.name, adapt, true));
    // AND without coasting, or without a gap, the key changes nothing, bit for bit
    EXPECT_EQ(forecasts(info.name, pause_nocoast, true), forecasts(info.name, adapt_nocoast, true));
    EXPECT_EQ(forecasts(info.name, pause, false), forecasts(info.name, adapt, false));
  }
}

}  // namespace
}  // namespace predvs
