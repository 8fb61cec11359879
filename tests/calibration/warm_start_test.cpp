// Warm start of a noise fit from the fixed KFs' fitted values (noise_fit.h "Warm start",
// NoiseFitOptions::seed_fits, Predictor::fitSeeds, fitOrder).
#include "predvs/calibration/noise_fit.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/maneuver_tracks.h"
#include "calibration/fixed_kf_reference.h"
#include "servo/maneuver_track_cell.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace predvs {
namespace {

TEST(WarmStart, ImmOnSmooth12HzLeavesItsLocalMinimumWithTheFixedKfsValues) {
  // GIVEN the 12/20/45 Hz grid's track smooth 12 Hz 2.5 px #202 (10 s, 2 % drops), fitted and
  // scored on the whole track as `track-study --fit --fit-split 1` does
  const double rate_hz = 12.0;
  // WHEN the fixed KFs are fitted first, then imm with one start, and with their values as a warm start
  const FixedKfReference ref(maneuverTrackCell(ManeuverKind::Smooth, rate_hz, 2.5, 10.0, 202, 0.02), rate_hz);
  // (imm blending its combination with hold, as when this was measured: with each mode blended on
  // its own, the default since, one start already finds 1.02 here)
  const Params combined_blend{{"blend_per_mode", 0.0}};
  const NoiseFitResult cold = fitNoise("imm", combined_blend, ref.track, ref.o);
  const NoiseFitResult warm = fitNoise("imm", combined_blend, ref.track, ref.seeded);
  // THEN one start stops in a local minimum 1.32 times the best fitted fixed KF (kf-ca), the warm
  // start is tried, kept, and within the 10 % (1.06). (Before imm's calibrated forecast
  // scores, smooth 45 Hz of the same seed showed it, 1.18 -> 1.03; since, one start finds 1.03 there.)
  EXPECT_FALSE(ref.fixed_warm_started);  // nothing seeds a fixed KF
  EXPECT_FALSE(cold.warm_start);
  EXPECT_TRUE(warm.warm_start);
  EXPECT_TRUE(warm.warm_start_kept);
  EXPECT_EQ(warm.starts, 2);
  EXPECT_LT(warm.rmse_after_px, cold.rmse_after_px);
  EXPECT_GT(ref.truthRmse("imm", cold.params) / ref.best_fixed_px, 1.10);
  EXPECT_LT(ref.truthRmse("imm", warm.params) / ref.best_fixed_px, 1.10);
}

TEST(WarmStart, FixedKfsComeFirstAndSeedTheAdaptiveOnes) {
  // GIVEN a study's predictor list in its own order
  const std::vector<std::string> names = {"hold", "stkf", "kf-cv", "imm", "cs-akf-adaptive", "kf-ca", "cs-akf"};
  // WHEN ordered for fitting THEN those that take no seed come first, in their order, then the rest
  const std::vector<size_t> order = fitOrder(names);
  std::vector<std::string> got;
  for (size_t i : order) got.push_back(names[i]);
  EXPECT_EQ(got, (std::vector<std::string>{"hold", "kf-cv", "kf-ca", "cs-akf", "stkf", "imm", "cs-akf-adaptive"}));
  // AND the sources are found over every structure of the predictor
  EXPECT_EQ(fitSeedSources("stkf"), (std::set<std::string>{"kf-cv", "kf-ca"}));
  EXPECT_EQ(fitSeedSources("imm"), (std::set<std::string>{"kf-cv", "kf-ca"}));
  EXPECT_EQ(fitSeedSources("fakf"), (std::set<std::string>{"cs-akf", "kf-ca"}));  // two warm starts (cs_akf.h)
  EXPECT_TRUE(fitSeedSources("kf-ca").empty());
}

TEST(WarmStart, WithoutSeedsTheFitIsUnchangedToTheBit) {
  // GIVEN a short track and st-akf fitted with no seed_fits and with seeds of a predictor it
  // does not map (only cs-akf's values: st-akf takes kf-cv's / kf-ca's q)
  const double rate_hz = 30.0;
  const ManeuverTrack g = maneuverTrackCell(ManeuverKind::Turns, rate_hz, 1.5, 6.0, 4);
  const FitTrack track{g.t_s, {g.u_px, g.v_px}};
  NoiseFitOptions o;
  o.objective = FitObjective::Prediction;
  o.horizon_s = 2.0 / rate_hz;
  Params structure;
  structure.setText("model", "cv");
  const NoiseFitResult plain = fitNoise("st-akf", structure, track, o);
  NoiseFitOptions other = o;
  other.seed_fits["cs-akf"] = fitNoise("cs-akf", {}, track, o).params;
  const NoiseFitResult unmapped = fitNoise("st-akf", structure, track, other);
  // THEN no warm start is tried and the fitted values are the same bits
  EXPECT_FALSE(unmapped.warm_start);
  EXPECT_EQ(unmapped.starts, plain.starts);
  EXPECT_EQ(unmapped.params.values(), plain.params.values());
}

}  // namespace
}  // namespace predvs
