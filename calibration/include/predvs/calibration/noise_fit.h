// predvs — offline noise fitting of a predictor on a recorded track, with Ceres (issue 11 item 1).
//
// Objective (choice: the innovation log-likelihood, not the h-step prediction error). The predictor
// runs over the track; every measured update of every channel after a burn-in gives an innovation
// eps_k = z_k - H x(k|k-1) and its predicted variance S_k, read through Predictor::innovation(c),
// which every predictor already implements (no change to the interface was needed: it is the
// least invasive capability, and adaptive filters report the S they actually used). Then
//   log L(theta) = -1/2 sum_k [ log(2 pi S_k) + eps_k^2 / S_k ],
// the exact log-likelihood for a linear Gaussian filter (the prediction-error decomposition), a
// quasi-likelihood for the adaptive ones, and for imm the moment-matched Gaussian of its mixture.
// The first `burn_in_frames` rows are left out (initial transient with P0).
//
// Parameters. Each predictor names the keys to fit (Predictor::noiseParameters()), all positive
// and fitted on a log scale: theta_i = log(value_i), bounded in [log lo_i, log hi_i] by the smooth
// map theta = lo + (hi - lo) / (1 + exp(-phi)) with phi free, so the solver sees no bound at all.
// Minimised: -log L(theta(phi)) with ceres::GradientProblemSolver (L-BFGS, Armijo/Wolfe line search).
// Derivatives are numeric (central differences of step 1e-4 in theta = log value, i.e. a relative
// step of 0.01 %): the adaptive filters are not differentiable in closed form (windows, clamps,
// fuzzy rules), and a fit costs a few hundred passes over the track, well under a second for
// 2,000 frames.
//
// Uncertainty. At the optimum, ceres::Covariance is evaluated on the least-squares problem whose
// residuals are, per innovation, r_a = eps_k / sqrt(S_k) and r_b = log(S_k) / 2. Their J'J has as
// expectation the Fisher information of the innovation likelihood,
//   I(theta) = sum_k [ (d eps_k)^2 / S_k + 1/2 (d log S_k)^2 ],
// so its inverse is the Cramer-Rao covariance of theta = log(value). Reported: std_log (the standard
// deviation of log(value), i.e. roughly the relative standard error) and the 95 % interval
// value * exp(-+1.96 std_log). A parameter that ends within 1 % (in log) of a bound is flagged.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/predictors/predictor.h"

#include <string>
#include <vector>

namespace predvs {

/// The keys fitted for `predictor`: the noiseParameters() of the predictor built with its
/// defaults (their `value` is the default, the starting value when neither `base` nor the track
/// gives one). Throws std::invalid_argument for an unknown predictor, or one with nothing to fit
/// (`hold`).
std::vector<NoiseParameter> fitParameters(const std::string& predictor);

/// A track to fit on: frame times and any number of measured channels (u_0, v_0, u_1, v_1, ...),
/// [channel][frame], NaN where not measured. One predictor with that many channels runs over it;
/// the likelihood sums every channel's innovations.
struct FitTrack {
  std::vector<double> t_s;
  std::vector<std::vector<double>> channels;
};

struct NoiseFitOptions {
  int burn_in_frames = 10;
  int max_iterations = 200;
};

struct FittedValue {
  std::string key;
  double initial = 0.0;  ///< value the fit started from
  double value = 0.0;    ///< fitted value
  double std_log = 0.0;  ///< standard deviation of log(value) (NaN if the covariance failed)
  double lo95 = 0.0, hi95 = 0.0;
  bool at_bound = false;
};

struct NoiseFitResult {
  std::string predictor;
  Params params;  ///< the base params with the fitted keys set: what predict/servo/compare use
  std::vector<FittedValue> values;
  double loglik_before = 0.0;  ///< log L at the starting values
  double loglik_after = 0.0;   ///< log L at the fitted values
  int innovations = 0;         ///< number of innovations in log L
  int iterations = 0;
  std::string termination;     ///< Ceres' termination message
  bool covariance_ok = false;
};

/// Innovation log-likelihood of `predictor` with `params` over the track (rows >= burn_in_frames);
/// n receives the number of innovations. Throws std::invalid_argument for a bad predictor/params.
double innovationLogLikelihood(const std::string& predictor, const Params& params, const FitTrack& track,
                               int burn_in_frames, int* n = nullptr);

/// Fits the keys of `predictor` (fitParameters) on the track. Starting values: the value in `base`
/// if given, else for r the start-up noise estimate of the track (noise_estimate.h), else the
/// predictor's default; each clamped into its bounds. Other keys of `base` are kept fixed. Throws std::invalid_argument
/// (bad predictor, fewer than 4 * burn_in measured rows, no finite likelihood at the start).
NoiseFitResult fitNoise(const std::string& predictor, const Params& base, const FitTrack& track,
                        const NoiseFitOptions& options = {});

}  // namespace predvs
