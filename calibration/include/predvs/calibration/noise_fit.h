// predvs — offline noise fitting of a predictor on a recorded track, with Ceres (issue 11 item 1).
//
// Two objectives (NoiseFitOptions::objective):
//
// 1. `likelihood` (fit-noise's default): maximise the innovation log-likelihood. The predictor
// runs over the track; every measured update of every channel after a burn-in gives an innovation
// eps_k = z_k - H x(k|k-1) and its predicted variance S_k, read through Predictor::innovation(c),
// which every predictor already implements (no change to the interface was needed: it is the
// least invasive capability, and adaptive filters report the S they actually used). Then
//   log L(theta) = -1/2 sum_k [ log(2 pi S_k) + eps_k^2 / S_k ],
// the exact log-likelihood for a linear Gaussian filter (the prediction-error decomposition), a
// quasi-likelihood for the adaptive ones, and for imm the moment-matched Gaussian of its mixture.
// The first `burn_in_frames` rows are left out (initial transient with P0).
//
// 2. `prediction` (the default of `predict --fit` and `track-study --fit`: what they score): minimise
// the mean squared h-step-ahead prediction error against the track's own later measurements (a
// user has no truth). For every frame k >= burn_in and every channel c, after the update of frame
// k the const prediction p_c(t_k + h) is compared with the measurement of channel c interpolated
// linearly at t_k + h between its nearest measured rows (exactly the measurement of frame k + d
// when h = d frame periods and that frame was measured); targets outside the measured span of the
// channel are left out. The set of residuals depends on the track only, not on theta:
//   J(theta) = 1/2 sum_(k,c) (p_c(t_k + h; theta) - z_c(t_k + h))^2,   MSE = 2 J / n.
// r is held at its start value by default (NoiseFitOptions::prediction_fits_r = false): the
// predicted mean of a linear Kalman filter depends on the ratios q/r only, so the h-step errors
// cannot tell r from q (a flat valley: fitted freely, r runs to a bound with the same predictions),
// and for the adaptive filters nearly so; the start value (base, else the track's start-up noise
// estimate) measures r directly. The result lists r as held (FittedValue::held).
// Note that the target carries the measurement noise, so the minimum MSE is about the truth MSE
// plus r (and the covariance of its estimate); the arg-min is the same in expectation.
// Solved as a bounded least-squares problem (ceres::Problem, Levenberg-Marquardt, bounds
// [log lo_i, log hi_i] on theta = log value set on the parameter block), the Jacobian by central
// differences of step 1e-3 in theta (0.1 % relative: the adaptive filters' clamps and windows make
// a smaller step noisy).
//
// Parameters. Each predictor names the keys to fit (Predictor::noiseParameters()), all positive
// and fitted on a log scale: theta_i = log(value_i), bounded in [log lo_i, log hi_i]. For the
// likelihood the bounds are the smooth map theta = lo + (hi - lo) / (1 + exp(-phi)) with phi free,
// so the solver sees no bound at all; minimised: -log L(theta(phi)) with ceres::GradientProblemSolver
// (L-BFGS, Armijo/Wolfe line search). Derivatives are numeric (central differences of step 1e-4 in
// theta = log value, i.e. a relative step of 0.01 %): the adaptive filters are not differentiable in
// closed form (windows, clamps, fuzzy rules), and a fit costs a few hundred passes over the track,
// well under a second for 2,000 frames.
//
// Several starting points (NoiseFitOptions::starts = m > 1): the fit is run from the start values
// and from m - 1 more points, start j moving every process-noise key (all but r) by
// 10^(+2, -2, +1, -1, +3, -3, ...)[j-1] within its bounds (r keeps its start: the data pin it);
// the best objective wins. The adaptive filters' objectives are not convex (clamps, windows).
//
// Warm start (NoiseFitOptions::seed_fits): the fitted params of other predictors on the same rows
// (in practice the fixed KFs kf-cv, kf-ca, cs-akf, fitted first: fitOrder()). Each structure asks
// its predictor which of those values seed it (Predictor::fitSeeds(): the map by meaning, e.g.
// kf-cv's q for a white-acceleration cv structure, cs-akf's alpha and (4 - pi)/pi a_max^2 for a CS
// one) and, when one of its fitted keys gets a value that way, the fit is also run from the start
// values with those keys replaced (clamped into their bounds; the other keys keep their start,
// r under the prediction objective stays held): one start more, after the m above, and the best
// objective wins as above. A structure may ask for several warm starts (FitSeed::start: the seeds
// with one index form one start point, tried in increasing index), e.g. a CS structure from
// cs-akf's fit and, separately, from kf-ca's (cs_akf.h). A warm start that cannot run (an infeasible combination, e.g.
// sigma_min_sq above sigma_max_sq) is skipped. Why: an adaptive structure that contains a fixed
// KF (its adaptive layer off, or weak) has that KF's fitted noise near one of its own minima; the
// start values alone can lead the solver to a worse local minimum (docs/PERFORMANCE.md, "Warm
// start"). A predictor without fitSeeds() (the fixed KFs) or a run without seed_fits fits exactly
// as before, bit for bit.
//
// Uncertainty. Likelihood: at the optimum, ceres::Covariance is evaluated on the least-squares
// problem whose residuals are, per innovation, r_a = eps_k / sqrt(S_k) and r_b = log(S_k) / 2.
// Their J'J has as expectation the Fisher information of the innovation likelihood,
//   I(theta) = sum_k [ (d eps_k)^2 / S_k + 1/2 (d log S_k)^2 ],
// so its inverse is the Cramer-Rao covariance of theta = log(value). Prediction: ceres::Covariance
// of the prediction least-squares problem itself, (J'J)^-1 scaled by the residual variance
// s^2 = 2 J / (n - p) (the Gauss-Newton covariance of a nonlinear least-squares estimate). The
// h-step errors of neighbouring frames are correlated (overlapping horizons, shared filter state),
// which this formula ignores: read it as a lower bound. Reported: std_log (the standard deviation of
// log(value), i.e. roughly the relative standard error) and the 95 % interval
// value * exp(-+1.96 std_log). A parameter that ends within 1 % (in log) of a bound is flagged.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/predictors/predictor.h"

#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace predvs {

/// The keys fitted for `predictor`: the noiseParameters() of the predictor built with its
/// defaults and the words of `structure` (e.g. {model: ca}: the keys depend on the structure);
/// their `value` is the default, the starting value when neither `base` nor the track gives one.
/// Throws std::invalid_argument for an unknown predictor, or one with nothing to fit (`hold`).
std::vector<NoiseParameter> fitParameters(const std::string& predictor, const Params& structure = {});

/// A track to fit on: frame times and any number of measured channels (u_0, v_0, u_1, v_1, ...),
/// [channel][frame], NaN where not measured. One predictor with that many channels runs over it;
/// the likelihood sums every channel's innovations.
struct FitTrack {
  std::vector<double> t_s;
  std::vector<std::vector<double>> channels;
};

/// What fitNoise optimises (see the file comment).
enum class FitObjective { Likelihood, Prediction };
/// "likelihood" / "prediction".
std::string fitObjectiveName(FitObjective o);
/// Parses "likelihood" / "prediction"; throws std::invalid_argument naming the expected words.
FitObjective parseFitObjective(const std::string& text);

/// True when f is a valid NoiseFitOptions::select_holdout: a fraction in [0, 0.9] (NaN is not).
inline bool validSelectHoldout(double f) { return f >= 0.0 && f <= 0.9; }

struct NoiseFitOptions {
  int burn_in_frames = 10;
  int max_iterations = 200;
  FitObjective objective = FitObjective::Likelihood;
  double horizon_s = 0.0;  ///< prediction objective: h, seconds ahead of each frame (>= 0)
  int starts = 1;          ///< starting points (>= 1), see the file comment
  bool prediction_fits_r = false;  ///< prediction objective: fit r too (default: held at its start value)
  /// Structural variants: the fraction of the track's rows, at its end, held out to choose the
  /// structure (in [0, 0.9]; 0 = choose on the fit's own objective over the whole track). See fitNoise.
  double select_holdout = 0.0;
  /// Warm start: the fitted params of other predictors on the same rows, by registry name (e.g.
  /// {"kf-cv": {q: 812, r: 0.26}}); see the file comment. Empty: no warm start.
  std::map<std::string, Params> seed_fits;
};

/// The registry names whose fitted params can seed a fit of `predictor` in any of its structures
/// (the one `structure` gives and its structuralVariants(): Predictor::fitSeeds()). Empty for the
/// fixed KFs. Throws std::invalid_argument for an unknown predictor.
std::set<std::string> fitSeedSources(const std::string& predictor, const Params& structure = {});

/// The order in which to fit `predictors` (indices into it) so that every predictor comes after
/// those that can seed it (fitSeedSources): first those that take no seed, in their order, then
/// the others, in their order. (No predictor both takes a seed and gives one today; a chain would
/// need a topological sort.) `structures[i]`, if given, is predictor i's params.
std::vector<size_t> fitOrder(const std::vector<std::string>& predictors, const std::vector<Params>& structures = {});

/// The options of a fit whose rows are then scored from the first one on (`predict --fit`
/// without --fit-split, `track-study --fit --fit-split 1`: fitted and scored in sample): under
/// the prediction objective no burn-in (burn_in_frames = 0), so the fit sees the start-up
/// transient that the score counts. Choice: on the generated tracks the filter starts at rest
/// behind a moving target, and at 10 Hz the first 10 frames can hold half of a track's squared
/// 2-frame error (zigzag 10 Hz 0.5 px #3: cs-akf-adaptive fitted without them scored 1.18 times
/// cs-akf, with them 1.03; docs/PERFORMANCE.md "--fit on the whole track"). The likelihood keeps
/// its burn-in (the transient of P0 is not a property of the noise). A fit scored on later rows
/// only (--fit-split F < 1) keeps the burn-in too: the transient is not in what is scored.
inline NoiseFitOptions inSampleFitOptions(NoiseFitOptions o) {
  if (o.objective == FitObjective::Prediction) o.burn_in_frames = 0;
  return o;
}

struct FittedValue {
  std::string key;
  double initial = 0.0;  ///< value the fit started from
  double value = 0.0;    ///< fitted value
  double std_log = 0.0;  ///< standard deviation of log(value) (NaN if the covariance failed)
  double lo95 = 0.0, hi95 = 0.0;
  bool at_bound = false;
  bool held = false;  ///< not fitted: kept at `initial` (r under the prediction objective)
};

/// One structural variant a fit tried (Predictor::structuralVariants()): its overrides and the
/// objective at its start values and after its fit (h-step RMSE in px for the prediction
/// objective, lower is better; log-likelihood for the likelihood objective, higher is better).
struct VariantFit {
  std::string variant;  ///< "key=value,...", e.g. "model=ca"
  double objective_before = 0.0;
  double objective_after = 0.0;
  /// With NoiseFitOptions::select_holdout > 0: the same objective on the held-out rows, the
  /// variant fitted on the rows before them (what chose the structure); NaN otherwise.
  double objective_holdout = std::numeric_limits<double>::quiet_NaN();
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
  FitObjective objective = FitObjective::Likelihood;
  double horizon_s = 0.0;          ///< prediction objective: h
  int residuals = 0;               ///< prediction objective: number of h-step errors
  double rmse_before_px = 0.0;     ///< h-step RMSE vs the later measurements at the start (both objectives)
  double rmse_after_px = 0.0;      ///< ... at the fitted values
  int starts = 1;                  ///< starting points tried (the warm start included)
  int best_start = 0;              ///< the one kept (0 = the start values; from options.starts on: the warm starts, in FitSeed::start order)
  bool warm_start = false;         ///< a warm start from NoiseFitOptions::seed_fits was tried
  bool warm_start_kept = false;    ///< ... and it gave the result
  std::string variant;             ///< the structural variant kept, "key=value,..." (empty: none offered)
  std::vector<VariantFit> variants;  ///< every variant fitted, in the predictor's order (empty: none)
  /// The forecast variant kept (Predictor::forecastVariants(), prediction objective only), e.g.
  /// "hold_blend_frames=1"; empty: the structure's own forecast (its h-step RMSE is rmse_after_px
  /// unless a variant did better).
  std::string forecast_variant;
  /// Each forecast variant compared, with its h-step RMSE on the fit rows (objective_after; no fit of
  /// its own, so objective_before is the same); empty when none was compared.
  std::vector<VariantFit> forecast_variants;
  /// The h-step RMSE of the structure's own forecast at the fitted noise (px; what rmse_after_px
  /// was before the forecast variants were compared); NaN when none was compared.
  double rmse_own_forecast_px = std::numeric_limits<double>::quiet_NaN();
};

/// Innovation log-likelihood of `predictor` with `params` over the track (rows >= burn_in_frames);
/// n receives the number of innovations. Throws std::invalid_argument for a bad predictor/params.
double innovationLogLikelihood(const std::string& predictor, const Params& params, const FitTrack& track,
                               int burn_in_frames, int* n = nullptr);

/// Root-mean-square h-step prediction error of `predictor` with `params` against the track's
/// interpolated later measurements (the prediction objective, rows >= burn_in_frames); n receives
/// the number of errors. NaN when the predictor fails. Throws std::invalid_argument for bad params.
double predictionRmse(const std::string& predictor, const Params& params, const FitTrack& track, double horizon_s,
                      int burn_in_frames, int* n = nullptr);

/// Fits the keys of `predictor` (fitParameters) on the track. When the predictor offers
/// structural variants (Predictor::structuralVariants(), e.g. its motion model) and `base` sets
/// none of their keys, every variant is fitted in turn (each as below) and the one with the best
/// objective on the track is kept: the result's params carry its keys (e.g. model: ca), `variant`
/// names it and `variants` lists every variant's objective; before/after fields are the kept
/// variant's. A variant that cannot be fitted on the track is skipped (the first error is thrown
/// if none can). With options.select_holdout = f > 0 the structure is chosen out of sample
/// instead: each variant is fitted on the first 1 - f of the rows and run over the whole track,
/// its objective (h-step RMSE, or log-likelihood) taken on the last f of the rows only; the best
/// there is then fitted again on the whole track, which gives the result. Choice: an adaptive
/// structure fitted on the same rows it is judged on tends to win in sample and lose after; the
/// rows nearest the future stand in for it (if the held-out part is too short for a variant, it
/// is judged in sample). When `base` pins a variant key, only that structure is fitted. Starting values: the value in `base`
/// if given, else for r the start-up noise estimate of the track (noise_estimate.h), else the
/// predictor's default; each clamped into its bounds. Other keys of `base` are kept fixed. Under the
/// prediction objective the kept structure's forecast variants (Predictor::forecastVariants(), e.g.
/// the blend with hold on one horizon instead of two) are then run with the fitted noise on the same
/// rows, and the one with the lowest h-step RMSE is kept (`forecast_variant`; none when `base` pins
/// one of their keys): they change the forecast only, so the noise need not be fitted again. This
/// choice is made on the whole track also with select_holdout (one pass per variant at the fitted
/// noise, nothing fitted on it). The predictor is also told the fit's horizon (options.horizon_s:
/// the prediction objective's, and the h-step RMSE's reported under either objective) over the
/// track's median frame period, as the key horizon_frames (predictor.h), unless `base` gives it; a
/// key added so is not in the result's params (whoever runs them says its own horizon; imm's
/// filter, hence its likelihood, depends on it too). Throws std::invalid_argument
/// (bad predictor, fewer than 4 * burn_in measured rows, no finite objective at the start, no h-step
/// target for the prediction objective, horizon < 0, starts < 1).
NoiseFitResult fitNoise(const std::string& predictor, const Params& base, const FitTrack& track,
                        const NoiseFitOptions& options = {});

}  // namespace predvs
