// predvs app — `predvs make-track` (one generated maneuvering track as a predict input CSV) and
// `predvs track-study` (every chosen predictor against `hold` on a grid of generated tracks).
//
// make-track writes FILE with the header t,u,v,u_true,v_true (predict's input format,
// app/track_csv.h): t in s, u, v measured px (empty cell = dropped frame), u_true, v_true the
// truth. The track is servo/maneuver_tracks.h's generateManeuverTrack().
//
// track-study: for every kind x rate x noise x seed it generates the track (seed s of a cell is
// seed + s; with --draws N, N tracks of that motion, draws 0..N-1 of the noise and the dropped
// frames, named #seed/dD for D > 0), runs each predictor as `predvs predict` does (horizon =
// delay_frames / rate), and scores it against the truth (and the measurement). The printed table gives, per predictor,
// on how many tracks it beat hold (RMSE vs truth strictly smaller), the worst and the mean of the
// ratio RMSE / RMSE(hold), and the worst kind/rate/noise. With --fit every predictor except hold
// is first fitted (calibration/noise_fit.h) on the first --fit-split of the track and scored on
// the rest; by default (--fit-objective prediction) on the squared error of the prediction
// delay_frames ahead against the fit part's own later measurements (the score is what is
// fitted; the truth is never used), or on the innovation likelihood. A second table gives, per
// adaptive predictor (every one but hold, kf-cv, kf-ca, cs-akf), on how many tracks its RMSE vs
// truth is within 10 % of the best of the fixed KFs kf-cv, kf-ca, cs-akf run on the same track,
// the geometric-mean and worst ratio, and the worst track. --jobs N computes N tracks at once (the
// results do not depend on N). --out DIR writes DIR/study.csv (one row per track and predictor).
#pragma once

#include "predvs/calibration/noise_fit.h"

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

struct MakeTrackArgs {
  std::string kind = "turns";
  double rate_hz = 30.0;
  double noise_px = 1.0;
  double duration_s = 20.0;
  double drop_prob = 0.02;
  long seed = 1;
  long draw = 0;  ///< --draw D: the draw of the noise and the drops (ManeuverTrackConfig::draw)
  double glitch_prob = 0.0;  ///< --glitch P (ManeuverTrackConfig::glitch_prob)
  double glitch_px = 15.0;   ///< --glitch-px G
  std::string out;
};

/// Writes the track (to a temporary file renamed into place: no half-written output).
int runMakeTrack(const MakeTrackArgs& a, std::ostream& out);

struct TrackStudyArgs {
  std::vector<std::string> kinds;       ///< empty = all
  std::vector<double> rates_hz = {10, 15, 30, 60};
  std::vector<double> noises_px = {0.5, 1.5, 3.0};
  int seeds = 3;
  long seed = 1;
  int draws = 1;  ///< --draws N: each motion with the draws 0..N-1 of its noise and drops
  double duration_s = 20.0;
  double drop_prob = 0.02;
  double glitch_prob = 0.0;  ///< --glitch P
  double glitch_px = 15.0;   ///< --glitch-px G
  double glitch_sigmas = 0.0;  ///< --glitch-sigmas G (setGlitchSigmas, predict_command.h)
  int delay_frames = 2;
  std::vector<std::string> predictors;  ///< empty = all registered
  std::vector<std::string> params;      ///< PREDICTOR.KEY=VALUE (--param)
  bool fit = false;
  double fit_split = 0.5;
  std::string fit_objective = "prediction";  ///< --fit-objective likelihood | prediction
  int fit_starts = 1;                        ///< --fit-starts N
  double fit_select = NoiseFitOptions{}.select_holdout;  ///< --fit-select-holdout F
  bool no_warm_start = false;  ///< --no-warm-start: no fit seeded by the fixed KFs' (noise_fit.h)
  int jobs = 1;                              ///< --jobs N: tracks in parallel
  std::string out;                      ///< optional
  std::string command_line;
};

int runTrackStudy(const TrackStudyArgs& a, std::ostream& out, std::ostream& err);

}  // namespace predvs
