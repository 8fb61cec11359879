// predvs app — `predvs predict`: open-loop prediction of a recorded feature track.
//
// For every frame i of the track (time t_i, the N points' measurements z_i, possibly empty), each
// predictor (one instance with 2N channels: u and v of every point, channel 2p and 2p + 1) is
// updated with (t_i, z_i) (predict-only for empty cells, a point missing from a long-format frame)
// and then asked, without changing its state, for every position at t_i + horizon. This is
// x(k+h|k) of docs/MODELS.md §0/§1. The channels are independent, so a point's predictions are those a
// 2-channel predictor fed that point alone would make.
//
// Horizon. --horizon-s S gives it in seconds. --delay-frames H gives it in frames:
//   horizon = H * median(t_{i+1} - t_i) over all rows (the median so that a few dropped or late
//   frames do not change the nominal frame period).
//
// Error reference (choice). The prediction made at t_i is compared with the measurement at
// t_i + horizon, linearly interpolated between the two nearest later/earlier measured rows
// (rows with an empty cell are skipped). On a uniformly sampled track with --delay-frames this is
// exactly the measurement H rows later. Predictions whose target time lies outside the measured
// span, and predictions made before the predictor has seen a measurement, are left out (n counts
// the rows used). The same rule against u_true/v_true gives the error against the truth.
//   rmse_px = sqrt(mean(du^2 + dv^2)),  rmse_u_px = sqrt(mean(du^2)),  rmse_v_px likewise,
// per point over its scored frames, and overall over every scored (frame, point) pair (for N = 1
// the overall figures are the point's).
#pragma once

#include "track_csv.h"

#include "predvs/predictors/params.h"

#include <cstddef>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

namespace predvs {

class StagedOutputDir;

/// A predictor name with its parameters, and the label it is shown under (`predict --predictor
/// kf-cv,kf-cv-r5=kf-cv:r=5`: the same predictor twice, each with its parameters; empty = name).
struct PredictorSpec {
  std::string name;  ///< the registry name (predictor.h)
  Params params;
  std::string label{};  ///< the name in predictions.csv, summary.json, the plot and the table; empty = name
  const std::string& shownName() const { return label.empty() ? name : label; }
};

/// Throws std::invalid_argument "OPTION: unknown predictor 'NAME' (known: ...)" unless NAME is registered.
void requirePredictor(const std::string& option, const std::string& name);

/// The predictors of a command line (`predict` and `track` --predictor, `track-study` --predictors):
/// `items` is the comma list split, either {"all"} (every registered predictor) or elements
/// [LABEL=]TYPE[:KEY=VALUE...], compare's syntax (parsePredictorChoice, predictor_choice.h): the registry
/// predictor TYPE shown as LABEL with those parameters, so one predictor can run with several
/// parameter sets side by side. Throws std::invalid_argument "OPTION: ..." for an empty list, 'all'
/// in a list, an unknown TYPE, a malformed element or a name shown twice.
std::vector<PredictorSpec> parsePredictorSpecs(const std::string& option, const std::vector<std::string>& items);
/// `--glitch-sigmas G` of predict, track and track-study: sets the key glitch_sigmas to G (the glitch
/// gate, glitch_gate.h) on every spec that does not set it itself. Throws std::invalid_argument
/// "--glitch-sigmas: ..." unless G >= 0.
void setGlitchSigmas(std::vector<PredictorSpec>& specs, double g);
/// The command's horizon in frames (`--delay-frames`, or `--horizon-s` over the frame period) as the
/// key horizon_frames (predictor.h horizonFramesParam) on every spec that does not set it itself: the
/// predictors whose forecast learns on several horizons learn on the ones they will be asked for.
void setHorizonFrames(std::vector<PredictorSpec>& specs, double frames);

/// RMSE of predictions against a reference (see file comment). NaN when n == 0.
struct PredictionErrors {
  double rmse_px = 0.0;
  double rmse_u_px = 0.0;
  double rmse_v_px = 0.0;
  int n = 0;
};

/// One point's predictions along the track.
struct PointPrediction {
  std::vector<double> u_pred_px, v_pred_px;  ///< prediction made at frame i for t_i + horizon
  PredictionErrors vs_measurement;
  PredictionErrors vs_truth;  ///< n == 0 when the track has no truth
};

/// One predictor's predictions along the track.
struct PredictionRun {
  PredictorSpec spec;
  std::vector<PointPrediction> points;  ///< one per FeatureTrack point, in its order
  PredictionErrors vs_measurement;      ///< overall: every scored (frame, point) pair
  PredictionErrors vs_truth;            ///< overall; n == 0 when the track has no truth
  /// Predictor::tallies() summed over the run's instances (one per channel), by name in the order
  /// they first appear; empty when the predictor keeps none (the glitch gate's "glitches", "steps").
  NamedValues tallies;
};

struct PredictionReport {
  double horizon_s = 0.0;
  std::vector<PredictionRun> runs;
};

/// Rows of the track a run takes at a time (predictTrack, predictToFiles): the predictions of one
/// block of rows are written, scored and handed on before the next block's are made, so nothing of
/// the track's size is allocated for them. Only the speed and the memory depend on it.
constexpr size_t kPredictBlockRows = 65536;

/// Runs every predictor along the track. Throws std::invalid_argument for an unknown predictor or
/// parameter (message names them) or a non-positive horizon.
/// jobs: threads (>= 1; the caller's thread is one of them). The predictors are independent, and
/// so are a predictor's channels (predictor.h): each channel of each predictor runs as a 1-channel
/// instance, block_rows rows at a time, on the thread it was given at the start; the report is the
/// same, bit for bit, for any jobs and block_rows.
PredictionReport predictTrack(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors,
                              double horizon_s, int jobs = 1, size_t block_rows = kPredictBlockRows);

/// RMSE of (u_pred, v_pred) made at rows t against (u_ref, v_ref) interpolated at t + horizon.
PredictionErrors predictionErrors(const std::vector<double>& t_s, const std::vector<double>& u_pred,
                                  const std::vector<double>& v_pred, double horizon_s,
                                  const std::vector<double>& u_ref, const std::vector<double>& v_ref);

/// The plot data (predictions_plot.dat, hence predictions.png) of a long track is thinned: beyond
/// kMaxPlotRows rows it is the envelope of kPlotSlices equal time slices (plotEnvelope(), plots.h:
/// per slice two rows, the first and last time, every other column's min and max), which draws the
/// ink of every row at the PNG's resolution (1200 px wide: a slice is at most one pixel column of
/// the plot); up to kMaxPlotRows rows (11 min at 30 Hz) every row is drawn, as it is.
/// predictions.csv and every error figure keep every row.
constexpr size_t kMaxPlotRows = 20000;
constexpr size_t kPlotSlices = 1200;

/// What predictToFiles writes besides the predictions, and which rows it scores.
struct PredictionFiles {
  int delay_frames = -1;     ///< the horizon in frames, for summary.json and the plot's title (-1: given in s)
  std::string command_line;  ///< for summary.json
  bool plots = true;         ///< predictions.png, its gnuplot script and data
  size_t score_from = 0;     ///< rows before it are predicted and written, not scored (--fit-split)
  size_t block_rows = kPredictBlockRows;
  /// The track's median frame period (s) when the caller has measured it (medianPeriod, for the
  /// horizon in frames): summary.json's "frame_period_s" then reuses it instead of a second median of
  /// every row's period, on one thread after the predictors (docs/PERFORMANCE.md, "Eleventh pass").
  /// NaN: measured there.
  double frame_period_s = std::numeric_limits<double>::quiet_NaN();
};

/// predictTrack streamed to the output files: the predictions of each block of rows are written to
/// predictions.csv, scored and thinned for the plot while the predictors go on with the next block,
/// and no column of the track's size is kept (the returned report has the errors and the specs, no
/// prediction columns). The files are the same, byte for byte, for any jobs and block_rows
/// (tests/app/predict_throughput_test.cpp). Errors are those of predictTrack, then std::runtime_error
/// naming a file that could not be written.
///  predictions.csv, summary.json and (if plots) predictions.png + its gnuplot script/data:
///  predictions.csv: one point: t,u,v,t_target,NAME.u_pred,NAME.v_pred[,...] (one column pair per
///                   predictor; empty cell = no measurement / no prediction yet), times in s,
///                   positions in px; N > 1 points: the long layout t,point,u,v,t_target,NAME.u_pred,
///                   NAME.v_pred[,...], one row per frame and point.
///  summary.json:    {"command", "input", "format", "points" (names), "ignored_columns", "rows"
///                    (frames), "horizon_s", "delay_frames", "frame_period_s", "error_reference",
///                    "predictors": [{"name", "params", "vs_measurement":
///                    {"rmse_px","rmse_u_px","rmse_v_px","n"}, "vs_truth": {...} or null (both
///                    overall), "per_point": [{"point", "vs_measurement", "vs_truth"}]}]}
///  predictions.png: u and v versus time of the first point (for N > 1 its title says so; every
///                   point is in predictions.csv and its errors in summary.json); the envelope of
///                   kPlotSlices time slices beyond kMaxPlotRows rows (its title then says so); under
///                   them each predictor's RMS error (vs truth when the track has it, else vs the
///                   measurement; every point, the rows scored) per equal time slice of about 8 frames,
///                   at most 200 slices, from predictions_errors.dat. Drawn by predictions.gp from
///                   predictions_plot.bin: the numbers of the text predictions_plot.dat (same rows
///                   and columns: t_s u_px v_px t_target_s u_true_px v_true_px, then u_pred v_pred
///                   per predictor) as doubles in the machine's byte order (NaN for "NaN"), which
///                   gnuplot reads once per series without parsing text; predictions.gp says how
///                   to draw from the text instead (the same PNG).
///  jobs:            threads (predictTrack's), which also format predictions.csv (written in row
///                   order: the same file for any jobs).
PredictionReport predictToFiles(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors,
                                double horizon_s, const PredictionFiles& files, StagedOutputDir& dir, int jobs = 1);

/// The aligned table printed on the terminal: overall errors per predictor, and for N > 1 points
/// the RMSE against the measurement (and the truth) per point.
void printPredictionTable(const PredictionReport& report, const FeatureTrack& track, std::ostream& out);

}  // namespace predvs
