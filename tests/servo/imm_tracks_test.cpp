// imm against its single models on generated maneuvering tracks (issue 11 item 4: within 10 % of
// the better of kf-cv and kf-ca everywhere, never below hold). The full grid (216 tracks) is
// `predvs track-study` (docs/PERFORMANCE.md "IMM against its single models"); this is the
// test-sized grid of DefaultsThatHold (6 kinds x {10, 60} Hz x {0.5, 3} px, 20 s, seed 7).
#include "predvs/predictors/imm.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/maneuver_tracks.h"

#include "servo/maneuver_track_cell.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace predvs {
namespace {

// Measured with imm's forecast combination (forecast weights from the realised one-frame forecasts,
// docs/MODELS.md §14) against kf-cv and kf-ca with their defaults: imm within 10 % of the better
// single model on 23 of 24 tracks (worst 1.16: smooth, 10 Hz, 0.5 px, where kf-cv is 3.78 px and
// imm 4.39 px: the forecast follows CA, whose one-frame forecasts are the better ones there but
// not its two-frame ones), geometric-mean ratio 1.02, better than hold on all 24. (When the test
// was added, with the forecast combined by the mode probabilities and kf-ca unweighted: 23/24,
// worst 1.12 on the same track, 1.01.) The bounds are those figures with a small margin.
// Since kf-cv's and kf-ca's forecasts are blended with hold (channel_predictor.h, branch wipD; imm's
// is not), the reference is stronger: imm within 10 % on 21 of 24 tracks, worst 1.173, geometric
// mean 1.027, still better than hold on all 24; the bound follows the measurement.
// With the calibrated forecast scores and the blend's step as the combination of the modes' steps
// (imm.h; wipI): 24 of 24, worst 1.085, geometric mean 1.012 (the old code: 23/24, 1.169, 1.025).
// Coasting without the CP mode (imm.h, coast_cp; f8c542f): 24 of 24, worst 1.083, geometric mean 1.006.
constexpr int kMinWithinTenPercent = 24;
constexpr double kMaxRatio = 1.1;
constexpr double kMaxGeometricMeanRatio = 1.02;

TEST(ImmOnTracks, WithinTenPercentOfTheBetterSingleModelAndNeverBelowHold) {
  int within = 0, tracks = 0;
  double worst = 0.0, log_sum = 0.0;
  for (ManeuverKind kind : maneuverKinds())
    for (double rate : {10.0, 60.0})
      for (double noise : {0.5, 3.0}) {
        const ManeuverTrack t = maneuverTrackCell(kind, rate, noise, 20.0, 7);
        const double horizon = 2.0 / rate;
        // kf-cv and kf-ca with their defaults, as imm runs them as its modes (the CA mode's
        // forecast weighted as kf-ca's, channel_predictor.h).
        const auto score = [&](const char* name) {
          auto p = makePredictor(name, 2);
          return scoreOnTrack(t, *p, horizon).rmse_truth_px;
        };
        const double hold = score("hold"), cv = score("kf-cv"), ca = score("kf-ca"), imm = score("imm");
        const double ratio = imm / std::min(cv, ca);
        ++tracks;
        within += ratio <= 1.1 ? 1 : 0;
        worst = std::max(worst, ratio);
        log_sum += std::log(ratio);
        EXPECT_LT(imm, hold) << maneuverKindName(kind) << " " << rate << " Hz " << noise << " px";
        EXPECT_LE(ratio, kMaxRatio) << maneuverKindName(kind) << " " << rate << " Hz " << noise << " px";
      }
  const double mean_ratio = std::exp(log_sum / tracks);
  std::printf("[ imm ] within 10 %% of the better of kf-cv, kf-ca on %d/%d tracks, worst %.3f, geometric mean %.3f\n",
              within, tracks, worst, mean_ratio);
  EXPECT_GE(within, kMinWithinTenPercent);
  EXPECT_LE(mean_ratio, kMaxGeometricMeanRatio);
}

// The tracks of the study grids where imm missed 10 % at main 13b32f0 (docs/PERFORMANCE.md "IMM
// against its single models", "Calibrated forecast scores"): the tuning grid's three 10/15 Hz
// 0.5 px misses, the two of seeds 101-103 (15 s) and the 5 %-drop grid's stops 10 Hz 0.5 px #504.
// Measured at wipI: 1.013, 1.039, 1.016, 1.070, 1.005, 0.998 times the better of kf-cv and kf-ca
// (before 1.121, 1.118, 1.105, 1.178, 1.101, 1.175).
struct MissedCell {
  ManeuverKind kind;
  double rate_hz, noise_px, duration_s;
  std::uint64_t seed;
  double drop_prob;
};
const MissedCell kMissedAtMain[] = {
    {ManeuverKind::Turns, 10.0, 0.5, 20.0, 1, 0.02},   {ManeuverKind::Smooth, 10.0, 0.5, 20.0, 2, 0.02},
    {ManeuverKind::Turns, 15.0, 0.5, 20.0, 1, 0.02},   {ManeuverKind::Smooth, 10.0, 0.5, 15.0, 103, 0.02},
    {ManeuverKind::Turns, 10.0, 0.5, 15.0, 101, 0.02}, {ManeuverKind::Stops, 10.0, 0.5, 10.0, 504, 0.05},
};

/// The track of a cell, scored 2 frames ahead as track-study scores it.
struct CellTrack {
  explicit CellTrack(const MissedCell& m)
      : track(maneuverTrackCell(m.kind, m.rate_hz, m.noise_px, m.duration_s, m.seed, m.drop_prob)),
        horizon(2.0 / m.rate_hz) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s %g Hz %g px #%d", maneuverKindName(m.kind).c_str(), m.rate_hz, m.noise_px,
                  static_cast<int>(m.seed));
    label = buf;
  }
  /// RMSE vs truth of a predictor with these parameters.
  double score(const char* name, const Params& params = Params{}) const {
    auto p = makePredictor(name, 2, params);
    return scoreOnTrack(track, *p, horizon).rmse_truth_px;
  }
  /// The better of kf-cv and kf-ca with their defaults and `params` (imm's single models).
  double bestSingleModel(const Params& params = {}) const {
    return std::min(score("kf-cv", params), score("kf-ca", params));
  }
  ManeuverTrack track;
  double horizon;
  std::string label;
};

TEST(ImmOnTracks, TheStudyMissesOfMainAreWithinTenPercent) {
  for (const MissedCell& m : kMissedAtMain) {
    // GIVEN the track of that cell, 2 frames ahead as track-study scores it
    const CellTrack t(m);
    const double hold = t.score("hold"), best = t.bestSingleModel(), imm = t.score("imm");
    const std::string& cell = t.label;
    std::printf("[ imm ] %s: imm / best %.3f\n", cell.c_str(), imm / best);
    // THEN imm is within 10 % of the better single model and better than hold
    EXPECT_LE(imm, 1.1 * best) << cell;
    EXPECT_LT(imm, hold) << cell;
  }
}

// The tracks of the study grids where imm missed 10 % at main 056b9cd: the tuning grid's smooth
// 60 Hz 3 px #3 and turns 60 Hz 1.5 px #3 (20 s), and hand 60 Hz 1.5 px #103 (15 s). Most of each
// miss is in gaps (smooth #3: an occlusion from 0.2 to 0.43 s while the CP mode carried up to 0.98
// of the forecast), where the CP mode's weight pulled the coasted forecast towards hold a second
// time; imm now coasts without it (imm.h, "Coasting without the CP mode"; coast_cp).
TEST(ImmOnTracks, CoastingWithoutTheCpModeBringsTheMissesOf056b9cdWithinTenPercent) {
  const MissedCell cells[] = {
      {ManeuverKind::Smooth, 60.0, 3.0, 20.0, 3, 0.02},
      {ManeuverKind::Turns, 60.0, 1.5, 20.0, 3, 0.02},
      {ManeuverKind::Hand, 60.0, 1.5, 15.0, 103, 0.02},
  };
  for (const MissedCell& m : cells) {
    // GIVEN the track of that cell, 2 frames ahead as track-study scores it
    const CellTrack t(m);
    // (the single models as they were then: without the raise of q that came after, process_noise_adapt.h,
    // and with the blend's one weight learnt on one-frame forecasts, hold_blend_frames 1 and hold_blend_split 0)
    const double hold = t.score("hold");
    const double best =
        t.bestSingleModel(Params{{"q_raise_ratio", 0.0}, {"hold_blend_frames", 1.0}, {"hold_blend_split", 0.0}});
    // WHEN imm keeps its CP mode's forecast weight through the gaps (before) and coasts without it,
    // both blending the combination with hold as then (blend_per_mode 0, hold_blend_frames 1) and
    // with the whole forecast weights in gaps (gap_weight_power 1); and imm with its defaults,
    // against the single models with theirs
    const double before = t.score("imm", Params{{"coast_cp", 1.0}, {"blend_per_mode", 0.0}, {"hold_blend_frames", 1.0},
                                                {"gap_weight_power", 1.0}, {"hold_blend_split", 0.0}});
    const double imm = t.score("imm", Params{{"blend_per_mode", 0.0}, {"hold_blend_frames", 1.0}, {"gap_weight_power", 1.0},
                                             {"hold_blend_split", 0.0}});
    const double defaults = t.score("imm"), best_now = t.bestSingleModel(Params{});
    const std::string& cell = t.label;
    std::printf("[ imm ] %s: imm / best %.3f (coast_cp 1: %.3f; defaults %.3f of the defaults' best)\n", cell.c_str(),
                imm / best, before / best, defaults / best_now);
    // THEN it was not within 10 % of the better single model and now is, and beats hold; so do
    // the defaults
    EXPECT_GT(before, 1.1 * best) << cell;
    EXPECT_LE(imm, 1.1 * best) << cell;
    EXPECT_LT(imm, hold) << cell;
    EXPECT_LE(defaults, 1.1 * best_now) << cell;
    EXPECT_LT(defaults, hold) << cell;
  }
}

// Two misses of imm on make-track's wide grids at main 4759bec (bursts 60 Hz 0.5 px #608 of
// `--seed 601 --duration-s 12 --drop 0.08`, bursts 60 Hz 1.5 px #409 of `--seed 401
// --duration-s 15`): imm's error in the gaps was nearer the worse single model's, the mode its
// one-frame evidence chose (imm.h, "The forecast weights in a gap").
TEST(ImmOnTracks, TemperedWeightsInGapsBringTwoMissesWithinTenPercentAndLeaveMeasuredFramesAlone) {
  const MissedCell cells[] = {
      {ManeuverKind::Bursts, 60.0, 0.5, 12.0, 608, 0.08},
      {ManeuverKind::Bursts, 60.0, 1.5, 15.0, 409, 0.02},
  };
  for (const MissedCell& m : cells) {
    // GIVEN the track of that cell, 2 frames ahead as track-study scores it
    const CellTrack t(m);
    // (imm and the single models with the blend's one weight, hold_blend_split 0, without the
    // turn share at a gap after a zero crossing, coast_crossing 0, and imm's raise on its combined
    // innovation, q_raise_from_ca 0, as then: with the turn share imm is within 10 % on #608 with
    // either power, with the raise on its CA mode's innovation on #409)
    const Params then{{"hold_blend_split", 0.0}, {"coast_crossing", 0.0}};
    Params imm_then = then;
    imm_then.set("q_raise_from_ca", 0.0);
    const double best = t.bestSingleModel(then), hold = t.score("hold");
    // WHEN imm forecasts a gap with the whole forecast weights (gap_weight_power 1) and tempered
    // (the default)
    Params whole_weights = imm_then;
    whole_weights.set("gap_weight_power", 1.0);
    const double whole = t.score("imm", whole_weights);
    const double tempered = t.score("imm", imm_then);
    std::printf("[ imm ] %s: imm / best %.3f (gap_weight_power 1: %.3f)\n", t.label.c_str(), tempered / best,
                whole / best);
    // THEN it was not within 10 % of the better single model and now is, and beats hold
    EXPECT_GT(whole, 1.1 * best) << t.label;
    EXPECT_LE(tempered, 1.1 * best) << t.label;
    EXPECT_LT(tempered, hold) << t.label;
    // AND every forecast made on a measured frame is the same bits: only a gap's forecasts change
    auto a = makePredictor("imm", 2, Params{{"gap_weight_power", 1.0}});
    auto b = makePredictor("imm", 2);
    int gap_rows = 0, changed = 0;
    for (size_t i = 0; i < t.track.size(); ++i) {
      Eigen::Vector2d z(t.track.u_px[i], t.track.v_px[i]);
      a->update(t.track.t_s[i], z);
      b->update(t.track.t_s[i], z);
      const double ta = t.track.t_s[i] + t.horizon;
      for (int c = 0; c < 2; ++c) {
        const double pa = a->predictPosition(c, ta), pb = b->predictPosition(c, ta);
        if (std::isfinite(z(c))) {
          EXPECT_EQ(std::memcmp(&pa, &pb, sizeof pa), 0) << t.label << " row " << i;
        } else {
          ++gap_rows;
          changed += pa != pb ? 1 : 0;
        }
      }
    }
    EXPECT_GT(changed, gap_rows / 4) << t.label;
  }
}

TEST(ImmOnTracks, CalibratedScoresPickTheModeWithTheSmallerErrorsNotTheSmallerStatedVariance) {
  // GIVEN turns, 10 Hz, 0.5 px #1 of the tuning grid, where kf-cv forecasts better than kf-ca
  // (5.10 against 5.89 px) but the CV mode states a variance about 3.5 times its squared errors
  // and the CA mode about 2 times (imm.h, "Calibration"); imm and kf-cv without the blend's start-up
  // prior, which came after (hold_blend_prior 0; with it kf-cv 5.50 px, imm 5.93 / 5.69)
  const ManeuverTrack t = maneuverTrackCell(ManeuverKind::Turns, 10.0, 0.5, 20.0, 1);
  const double horizon = 0.2;
  const auto run = [&](Params params, double* w_cv) {
    params.set("hold_blend_prior", 0.0);
    ImmPredictor imm(2, params);
    const double rmse = scoreOnTrack(t, imm, horizon).rmse_truth_px;
    *w_cv = 0.5 * (imm.forecastWeight(0, ImmMode::Cv) + imm.forecastWeight(1, ImmMode::Cv));
    return rmse;
  };
  auto cv = makePredictor("kf-cv", 2, {{"hold_blend_prior", 0.0}});
  const double cv_rmse = scoreOnTrack(t, *cv, horizon).rmse_truth_px;
  // WHEN the forecast weights score each mode with its stated variance (before)
  double w_stated = 0.0, w_cal = 0.0;
  const double stated = run(Params{{"forecast_calibration", 0.0}}, &w_stated);
  // AND WHEN with the variance lowered to the realised one (the default)
  const double calibrated = run(Params{}, &w_cal);
  std::printf("[ imm ] turns 10 Hz 0.5 px #1: kf-cv %.3f, imm stated %.3f (CV weight %.2f), calibrated %.3f (%.2f)\n",
              cv_rmse, stated, w_stated, calibrated, w_cal);
  // THEN the stated variances give the CA mode the forecast (measured: CV weight 0.01 at the end,
  // 1.104 times kf-cv), the calibrated ones the CV mode (0.84, 1.013 times kf-cv)
  EXPECT_LT(w_stated, 0.5);
  EXPECT_GT(stated, 1.08 * cv_rmse);
  EXPECT_GT(w_cal, 0.5);
  EXPECT_LE(calibrated, 1.03 * cv_rmse);
}

}  // namespace
}  // namespace predvs
