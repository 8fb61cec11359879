// predvs app — `predvs track`: track features through a recorded image sequence or video, and
// score every predictor's H-frame-ahead prediction of each tracked point.
//
//   predvs track --images PATTERN|DIR|IMAGE|VIDEO [--source dots|apriltag|...] [--predictor
//                NAME|all|a,b] [--delay-frames H] [--fps F] [--set KEY=VALUE]... [--strip-frames K]
//                [--max-frames N] [--out DIR] [--no-plots]
//
// Frames (servo/image_sequence.h) are stamped t = (index - first) / fps. Each readable frame goes
// through the image tracker named by --source (servo/image_tracker.h, `predvs list`); its
// parameters come from --set KEY=VALUE. A skipped frame (missing, corrupt, other size) is logged
// on stderr, one line each, and counted: it is a row whose points are all unmeasured. A frame
// where the tracker loses every point is logged as well (and when points come back).
//
// Prediction. For each predictor and each point, a 2-channel predictor (u, v) runs along the
// rows (predvs predict's predictTrack(): update with the measurement, predict-only for an empty
// one) and is asked at row r for the position at t_r + H / fps. The error of that prediction is
// its pixel distance to the measurement of the same point at row r + H (the frame H frames
// later: rows are uniform in time, skipped frames included), when both exist. Per point and over
// all points pooled: rmse_px = sqrt(mean e^2), median_px, max_px, n (number of scored pairs).
// The leaderboard sorts the predictors by the pooled RMSE.
//
// Outputs in DIR (staged: nothing is left behind on error, output_dir.h):
//   tracks.csv        t,point,u,v          one row per frame and point (empty u,v: not measured)
//   tracks_wide.csv   t,u0,v0,u1,v1,...    one row per frame
//   predictions.csv   t,point,u,v,t_target,NAME.u_pred,NAME.v_pred,...  (prediction made at t)
//   leaderboard.csv   predictor,point,rmse_px,median_px,max_px,n  (point "all" = pooled)
//   leaderboard.json  the same, with the definitions
//   strip.png         K frames side by side: tracked points (green +, numbered) and, as circles,
//                     each predictor's prediction of that frame made H frames earlier
//   tracks.png, errors.png (+ .gp, .dat)  gnuplot: u and v of every point versus time; the
//                     prediction error (mean over the points seen) versus time per predictor
//   summary.json      command, images, source and its parameters, frames read / skipped (with
//                     the reasons), points, lost counts, predictors and their errors, timing
#pragma once

#include "predict_command.h"

#include "predvs/predictors/params.h"

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

struct TrackOptions {
  std::string images;                  ///< pattern, directory, image or video
  std::string source = "dots";         ///< image tracker name
  Params source_params;                ///< --set KEY=VALUE
  std::vector<PredictorSpec> predictors;
  int delay_frames = 2;                ///< H
  double fps = 30.0;                   ///< frames per second of the recording (time stamps)
  long max_frames = -1;                ///< -1: all
  int strip_frames = 4;                ///< frames in strip.png (0: no strip)
  std::string out_dir = "out/track";
  bool plots = true;                   ///< gnuplot figures
  bool progress = false;               ///< a progress line on stderr (a terminal)
  std::string command_line;
};

/// Error statistics of one predictor on one point (or pooled), pixels. NaN when n == 0.
struct TrackErrorStats {
  double rmse_px = 0.0, median_px = 0.0, max_px = 0.0;
  int n = 0;
};

/// Statistics of the distances `e` (finite values only).
TrackErrorStats trackErrorStats(std::vector<double> e);

/// Everything `predvs track` computed (also what the tests check).
struct TrackResult {
  std::string images_description;
  unsigned width = 0, height = 0;
  double frame_period_s = 0.0;
  std::vector<double> t_s;                  ///< per row (frame)
  std::vector<long> frame_index;            ///< per row
  std::vector<bool> frame_ok;               ///< false: skipped
  std::vector<std::string> point_names;     ///< N
  std::vector<std::vector<double>> u_px, v_px;  ///< [point][row], NaN when not measured
  struct Skip {
    long index;
    std::string origin, reason;
  };
  std::vector<Skip> skips;
  long frames_all_lost = 0;                 ///< readable frames after initialisation with no point
  long frames_before_init = 0;              ///< readable frames before the tracker had its points
  double read_s = 0.0, track_s = 0.0;       ///< wall time spent reading, tracking
  struct Prediction {
    PredictorSpec spec;
    std::vector<std::vector<double>> u_pred_px, v_pred_px;  ///< [point][row]: made at t_row
    std::vector<TrackErrorStats> per_point;
    TrackErrorStats pooled;
    NamedValues tallies;  ///< PredictionRun::tallies (the glitch gate's doubts settled each way)
  };
  std::vector<Prediction> predictions;      ///< in leaderboard order (pooled RMSE)
  size_t rows() const { return t_s.size(); }
};

/// Reads, tracks and scores (no file written). Logs skips and total losses on `log`. Throws
/// std::invalid_argument for a bad option, an unopenable sequence or a tracker that found no
/// point in any frame.
TrackResult runTracking(const TrackOptions& options, std::ostream& log);

/// Runs `predvs track`: runTracking(), then writes DIR, prints the leaderboard on `out`.
void runTrackCommand(const TrackOptions& options, std::ostream& out, std::ostream& err);

}  // namespace predvs
