// predvs app — `predvs make-track` (one generated maneuvering track as a predict input CSV) and
// `predvs track-study` (every chosen predictor against `hold` on a grid of generated tracks).
//
// make-track writes FILE with the header t,u,v,u_true,v_true (predict's input format,
// app/track_csv.h): t in s, u, v measured px (empty cell = dropped frame), u_true, v_true the
// truth. The track is servo/maneuver_tracks.h's generateManeuverTrack().
//
// track-study: for every kind x rate x noise x seed it generates the track (seed s of a cell is
// seed + s), runs each predictor as `predvs predict` does (horizon = delay_frames / rate), and
// scores it against the truth (and the measurement). The printed table gives, per predictor,
// on how many tracks it beat hold (RMSE vs truth strictly smaller), the worst and the mean of the
// ratio RMSE / RMSE(hold), and the worst kind/rate/noise. With --fit every predictor except hold
// is first fitted (calibration/noise_fit.h) on the first --fit-split of the track and scored on
// the rest. --out DIR writes DIR/study.csv (one row per track and predictor).
#pragma once

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
  double duration_s = 20.0;
  double drop_prob = 0.02;
  int delay_frames = 2;
  std::vector<std::string> predictors;  ///< empty = all registered
  std::vector<std::string> params;      ///< PREDICTOR.KEY=VALUE (--param)
  bool fit = false;
  double fit_split = 0.5;
  std::string out;                      ///< optional
  std::string command_line;
};

int runTrackStudy(const TrackStudyArgs& a, std::ostream& out, std::ostream& err);

}  // namespace predvs
