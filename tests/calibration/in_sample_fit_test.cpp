// inSampleFitOptions (calibration/noise_fit.h): a fit scored on every row of its track
// (`predict --fit`, `track-study --fit --fit-split 1`) counts the start-up rows too.
#include "predvs/calibration/noise_fit.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/maneuver_tracks.h"
#include "servo/maneuver_track_cell.h"

#include <gtest/gtest.h>

namespace predvs {
namespace {

TEST(InSampleFit, PredictionObjectiveHasNoBurnInLikelihoodKeepsIt) {
  NoiseFitOptions o;
  o.objective = FitObjective::Prediction;
  EXPECT_EQ(inSampleFitOptions(o).burn_in_frames, 0);
  o.objective = FitObjective::Likelihood;
  EXPECT_EQ(inSampleFitOptions(o).burn_in_frames, NoiseFitOptions{}.burn_in_frames);
}

TEST(InSampleFit, StartUpRowsInTheObjectiveBringCsAkfAdaptiveWithin10PercentOfCsAkf) {
  // GIVEN the track-study track zigzag 10 Hz 0.5 px #3 (20 s, 2 % drops): the filters start at rest
  // behind a fast target, and the first frames hold much of the squared 2-frame error
  const double rate_hz = 10.0;
  const ManeuverTrack g = maneuverTrackCell(ManeuverKind::Zigzag, rate_hz, 0.5, 20.0, 3, 0.02);
  const FitTrack track{g.t_s, {g.u_px, g.v_px}};
  NoiseFitOptions o;
  o.objective = FitObjective::Prediction;
  o.horizon_s = 2.0 / rate_hz;
  // (the blend learnt on one-frame forecasts only and without its start-up prior, as when this test
  // was written: the defaults, two horizons and hold_blend_prior 4, each also rescue the burnt-in
  // fit, 1.03, which is the next assertion's contrast)
  Params structure;
  structure.set("hold_blend_frames", 1.0);
  structure.set("hold_blend_prior", 0.0);
  const auto truthRmse = [&](const std::string& name, const NoiseFitOptions& opt) {
    auto p = makePredictor(name, 2, fitNoise(name, structure, track, opt).params);
    return scoreOnTrack(g, *p, o.horizon_s).rmse_truth_px;  // every row scored, as track-study --fit-split 1
  };
  // WHEN cs-akf and cs-akf-adaptive are fitted on the whole track, with and without its first 10 rows
  const double reference = truthRmse("cs-akf", inSampleFitOptions(o));
  const double in_sample = truthRmse("cs-akf-adaptive", inSampleFitOptions(o));
  const double burnt_in = truthRmse("cs-akf-adaptive", o);
  // THEN with the start-up rows cs-akf-adaptive is within the 10 % of cs-akf (measured
  // 1.03), and without them it is not (1.18: the fit picks a structure that starts badly)
  EXPECT_LT(in_sample / reference, 1.10);
  EXPECT_GT(burnt_in / reference, 1.10);
  EXPECT_LT(in_sample, burnt_in);
}

}  // namespace
}  // namespace predvs
