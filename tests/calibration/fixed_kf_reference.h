// Test helper: a generated track fitted and scored in sample as `track-study --fit --fit-split 1`
// does, with the fixed KFs (kf-cv, kf-ca, cs-akf) fitted first: the reference of issue 11 item 3's
// `--fit` criterion and the seeds of the warm start (tests/calibration/*warm_start_test.cpp).
#pragma once

#include "predvs/calibration/noise_fit.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/maneuver_tracks.h"

#include <algorithm>
#include <string>

namespace predvs {

struct FixedKfReference {
  ManeuverTrack truth;   ///< the generated track, with its truth
  FitTrack track;        ///< its measurements, as the fit sees them
  NoiseFitOptions o;     ///< prediction objective, 2 frames ahead, in sample (no burn-in)
  NoiseFitOptions seeded;  ///< o with the fixed KFs' fitted values as seed_fits
  double best_fixed_px = 0.0;  ///< the smallest truth RMSE of the three fitted fixed KFs
  bool fixed_warm_started = false;  ///< whether any fixed KF's fit tried a warm start (none should)

  /// `structure`: keys every fixed KF is fitted with (none: their defaults).
  FixedKfReference(const ManeuverTrack& g, double rate_hz, const Params& structure = {})
      : truth(g), track{g.t_s, {g.u_px, g.v_px}} {
    o.objective = FitObjective::Prediction;
    o.horizon_s = 2.0 / rate_hz;
    o = inSampleFitOptions(o);
    seeded = o;
    best_fixed_px = 1e300;
    for (const std::string name : {"kf-cv", "kf-ca", "cs-akf"}) {
      const NoiseFitResult f = fitNoise(name, structure, track, o);
      fixed_warm_started = fixed_warm_started || f.warm_start;
      best_fixed_px = std::min(best_fixed_px, truthRmse(name, f.params));
      seeded.seed_fits[name] = f.params;
    }
  }

  /// RMSE against the truth [px] of `name` with `params`, 2 frames ahead, every row scored.
  double truthRmse(const std::string& name, const Params& params) const {
    auto p = makePredictor(name, 2, params);
    return scoreOnTrack(truth, *p, o.horizon_s).rmse_truth_px;
  }
};

}  // namespace predvs
