// The CS structures of cs-akf-adaptive and fakf against kf-ca on a track where kf-ca's fitted
// white-jerk density is high (FIT4: bursts 60 Hz 0.5 px #1 of the tuning grid), and their second
// warm start from kf-ca's fit (cs_akf.h CsAkfAdaptivePredictor::fitSeeds, FitSeed::start).
#include "predvs/calibration/noise_fit.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/maneuver_tracks.h"
#include "calibration/fixed_kf_reference.h"
#include "servo/maneuver_track_cell.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace predvs {
namespace {

TEST(CsWarmStart, CsStructureReachesKfCaOnBursts60Hz) {
  // GIVEN the tuning grid's track bursts 60 Hz 0.5 px #1 (20 s, 2 % drops), fitted and scored on
  // the whole track as `track-study --fit --fit-split 1` does
  // (every filter with the blend weight learnt on one-frame forecasts, hold_blend_frames 1, as when
  // this test was written: with the default since 2026-12-03, the smaller of the one- and two-frame
  // weights, kf-ca's fit gains more on this track than cs-akf-adaptive's, and the ratio is 1.12;
  // docs/PERFORMANCE.md "The blend on two horizons")
  // (and without the turn share of a gap after a zero crossing, coast_crossing 0, since 2026-12-04:
  // with it the start values win here, 0.991 times the best fixed KF, and no warm start is kept)
  Params one_frame;
  one_frame.set("hold_blend_frames", 1.0);
  one_frame.set("coast_crossing", 0.0);
  const double rate_hz = 60.0;
  const FixedKfReference ref(maneuverTrackCell(ManeuverKind::Bursts, rate_hz, 0.5, 20.0, 1), rate_hz, one_frame);
  const NoiseFitOptions& seeded = ref.seeded;
  // kf-ca's density is above what the old bound of sigma_min_sq (1e8) gave at alpha = 1/s (2e8)
  EXPECT_GT(seeded.seed_fits.at("kf-ca").get("q", 0.0), 2e8);
  // WHEN cs-akf-adaptive is fitted in the structure the study keeps there (CS mean, unweighted),
  // with both warm starts
  Params structure;
  structure.setText("mean", "current");
  structure.set("shrink_sigmas", 0.0);
  structure.set("hold_blend_frames", 1.0);
  structure.set("coast_crossing", 0.0);
  const NoiseFitResult f = fitNoise("cs-akf-adaptive", structure, ref.track, seeded);
  // THEN the start values and both warm starts run: cs-akf's too, its floor 0.27 a_max^2 = 2.6e7
  // being above the default ceiling 1e6, which the seed lifts to it (FitSeed::raise_only; before,
  // that start was infeasible and skipped: 2 starts, kf-ca's kept, 1.08 times the best fixed KF);
  // a warm start is kept, and the fit is within the 10 % of the best fitted fixed KF
  const double ratio = ref.truthRmse("cs-akf-adaptive", f.params) / ref.best_fixed_px;
  std::printf("[ cs warm start ] starts %d, kept %d, cs-akf-adaptive / best fixed KF %.3f\n", f.starts,
              f.best_start, ratio);
  EXPECT_TRUE(f.warm_start);
  EXPECT_EQ(f.starts, 3);
  EXPECT_TRUE(f.warm_start_kept);
  EXPECT_GE(f.best_start, 1);  // o.starts (1) + rank: a warm start
  EXPECT_LT(ratio, 1.10);
}

TEST(CsWarmStart, KfCaSeedsTheFloorAsDensityOverTwoAlpha) {
  // GIVEN cs-akf-adaptive at alpha 2/s, adaptation on and off
  Params on, off;
  on.set("alpha", 2.0);
  off.set("alpha", 2.0);
  off.setText("adaptation", "off");
  // WHEN asked for its seeds THEN start 1 maps kf-ca's q to sigma_min_sq = q / (2 alpha), and
  // with the adaptation on also the ceiling (off: no ceiling is fitted)
  for (const bool adapt : {true, false}) {
    const Params& p = adapt ? on : off;
    int kf_ca_keys = 0;
    int lifted_ceilings = 0;
    for (const FitSeed& s : makePredictor("cs-akf-adaptive", 1, p)->fitSeeds()) {
      if (s.from_predictor != "kf-ca") {
        EXPECT_EQ(s.start, 0);
        // start 0's ceiling, with the adaptation on: lifted to cs-akf's floor, never lowered
        if (s.key == "sigma_max_sq") {
          EXPECT_TRUE(s.raise_only);
          ++lifted_ceilings;
        }
        continue;
      }
      ++kf_ca_keys;
      EXPECT_EQ(s.start, 1);
      EXPECT_EQ(s.from_key, "q");
      EXPECT_DOUBLE_EQ(s.factor, 0.25);
      EXPECT_TRUE(s.key == "sigma_min_sq" || s.key == "sigma_max_sq");
    }
    EXPECT_EQ(kf_ca_keys, adapt ? 2 : 1);
    EXPECT_EQ(lifted_ceilings, adapt ? 1 : 0);
  }
  // AND with the adaptation off the (unused) ceiling no longer bounds the floor
  Params high = off;
  high.set("sigma_min_sq", 4.5e8);
  EXPECT_NO_THROW(makePredictor("fakf", 1, high));
  Params high_on = on;
  high_on.set("sigma_min_sq", 4.5e8);
  EXPECT_THROW(makePredictor("fakf", 1, high_on), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
