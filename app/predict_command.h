// predvs app — `predvs predict`: open-loop prediction of a recorded feature track.
//
// For every row i of the track (time t_i, measurement z_i, possibly empty), each predictor is
// updated with (t_i, z_i) (predict-only for empty cells) and then asked, without changing its
// state, for the feature position at t_i + horizon. This is x(k+h|k) of METHODS §0/§1.
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
//   rmse_px = sqrt(mean(du^2 + dv^2)),  rmse_u_px = sqrt(mean(du^2)),  rmse_v_px likewise.
#pragma once

#include "track_csv.h"

#include "predvs/predictors/params.h"

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

class StagedOutputDir;

/// A predictor name with its parameters.
struct PredictorSpec {
  std::string name;
  Params params;
};

/// RMSE of predictions against a reference (see file comment). NaN when n == 0.
struct PredictionErrors {
  double rmse_px = 0.0;
  double rmse_u_px = 0.0;
  double rmse_v_px = 0.0;
  int n = 0;
};

/// One predictor's predictions along the track.
struct PredictionRun {
  PredictorSpec spec;
  std::vector<double> u_pred_px, v_pred_px;  ///< prediction made at row i for t_i + horizon
  PredictionErrors vs_measurement;
  PredictionErrors vs_truth;  ///< n == 0 when the track has no truth
};

struct PredictionReport {
  double horizon_s = 0.0;
  std::vector<PredictionRun> runs;
};

/// Runs every predictor along the track. Throws std::invalid_argument for an unknown predictor or
/// parameter (message names them) or a non-positive horizon.
PredictionReport predictTrack(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors,
                              double horizon_s);

/// RMSE of (u_pred, v_pred) made at rows t against (u_ref, v_ref) interpolated at t + horizon.
PredictionErrors predictionErrors(const std::vector<double>& t_s, const std::vector<double>& u_pred,
                                  const std::vector<double>& v_pred, double horizon_s,
                                  const std::vector<double>& u_ref, const std::vector<double>& v_ref);

/// Writes predictions.csv, summary.json and (if plots) predictions.png + its gnuplot script/data.
///  predictions.csv: t,u,v,t_target,NAME.u_pred,NAME.v_pred[,...] (one column pair per predictor;
///                   empty cell = no measurement / no prediction yet), times in s, positions in px.
///  summary.json:    {"command", "input", "rows", "horizon_s", "delay_frames", "frame_period_s",
///                    "error_reference", "predictors": [{"name", "params", "vs_measurement":
///                    {"rmse_px","rmse_u_px","rmse_v_px","n"}, "vs_truth": {...} or null}]}
void writePredictionOutputs(const FeatureTrack& track, const PredictionReport& report, int delay_frames,
                            const std::string& command_line, bool plots, StagedOutputDir& dir);

/// The aligned table printed on the terminal.
void printPredictionTable(const PredictionReport& report, bool has_truth, std::ostream& out);

}  // namespace predvs
