// predvs app — `predvs fit-noise` and the predictor parameter file it writes (`--params FILE`).
//
// Parameter file (YAML), the same shape as a scenario's `predictors:` list:
//   # comment lines: what was fitted, on which track, the likelihood before/after
//   predictors:
//     - {name: kf-cv, params: {q: 123.4, r: 2.25}}
// Every name must be a registered predictor and every value a number (or `auto` for r); a key the
// predictor does not know is reported when the predictor is built. `predict --params FILE` sets
// these params on the predictors it runs with those names (--param given on the command line
// wins); `servo` and `compare --params FILE` turn each entry into the override
// `--set predictors.NAME.params.KEY=VALUE` (so a predictor the scenario lacks is added).
//
// fit-noise: reads a track (predict's CSV), fits the predictor's noise parameters with
// calibration/noise_fit.h (--objective likelihood, the default: innovation log-likelihood, L-BFGS;
// --objective prediction: mean squared h-step prediction error against the track's own
// measurements interpolated at t + h, h = --horizon-frames x the median frame period, bounded
// Levenberg-Marquardt; log-scale bounded parameters, numeric derivatives, uncertainty from
// ceres::Covariance), writes DIR/params.yaml and DIR/fit.json, and prints each fitted value with
// its 95 % interval, the log-likelihood and the h-step RMSE before and after. --starts N runs the
// fit from N starting points and keeps the best.
#pragma once

#include "predict_command.h"
#include "predvs/calibration/noise_fit.h"

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

struct NoiseFitResult;
struct FitTrack;

/// A parameter file given by path, or by the name of one of the data directory's params/ (predvs
/// list's data; `--params pre-issue-11` is params/pre-issue-11.yaml, wherever predvs is installed).
/// A path with a '/' or a file that exists is taken as it is.
std::string resolveParamsFile(const std::string& name_or_path);
/// Reads a parameter file (format above; calibration/param_file.h reads it), given as
/// resolveParamsFile() takes it. Throws std::invalid_argument "FILE: ..." on any defect.
std::vector<PredictorSpec> readParamsFile(const std::string& path);
/// The YAML text of a parameter file for `specs`, with `comment` lines first (calibration/param_file.h).
std::string paramsFileText(const std::vector<PredictorSpec>& specs, const std::vector<std::string>& comment);
/// Every point's u and v columns of the track as a fit input (channels u_0, v_0, u_1, ...), rows [0, rows).
FitTrack fitTrackOf(const FeatureTrack& track, size_t rows);
/// Prints one fit: "KEY  VALUE  [LO95, HI95]" rows and the log-likelihood line.
void printFit(const NoiseFitResult& fit, std::ostream& out);

struct FitNoiseArgs {
  std::string input;
  std::string predictor;
  std::vector<std::string> params;  ///< KEY=VALUE fixed or start values
  std::string params_file;
  int burn_in = 10;
  std::string objective = "likelihood";  ///< --objective likelihood | prediction
  int horizon_frames = 2;                ///< --horizon-frames N: h = N x median frame period
  int starts = 1;                        ///< --starts N
  double select_holdout = NoiseFitOptions{}.select_holdout;  ///< --select-holdout F
  std::string out;
  std::string command_line;
};

int runFitNoise(const FitNoiseArgs& a, std::ostream& out);

}  // namespace predvs
