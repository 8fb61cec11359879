#include "predvs/calibration/noise_fit.h"

#include "predvs/predictors/noise_estimate.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/sampled_signal.h"

#include <ceres/ceres.h>
#include <ceres/covariance.h>

#include <Eigen/Core>

#include <algorithm>
#include <iterator>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kLog2Pi = 1.8378770664093453;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Central-difference step in theta = log(value), likelihood objective.
constexpr double kLogStep = 1e-4;
/// Central-difference step in theta, prediction objective (clamps and windows: a wider step).
constexpr double kPredictionLogStep = 1e-3;
/// Decades by which start j >= 1 moves the process-noise keys (file comment of noise_fit.h).
constexpr double kStartDecades[] = {2.0, -2.0, 1.0, -1.0, 3.0, -3.0};

/// One h-step target of the prediction objective: after the update of `frame`, channel `channel`
/// predicted at t_target is compared with z (the channel's measurement interpolated at t_target).
struct PredictionTarget {
  size_t frame;
  int channel;
  double t_target;
  double z;
};

/// The targets of every frame >= burn_in (sorted by frame): the measurement of each channel
/// interpolated linearly at t_k + h between its nearest measured rows, inside its measured span
/// (servo/sampled_signal.h, the rule `predvs predict` scores with).
std::vector<PredictionTarget> predictionTargets(const FitTrack& track, double horizon_s, int burn_in) {
  const int n = static_cast<int>(track.channels.size());
  std::vector<std::vector<double>> at(static_cast<size_t>(n));
  for (int c = 0; c < n; ++c)
    at[static_cast<size_t>(c)] = interpolateShifted(track.t_s, track.channels[static_cast<size_t>(c)], horizon_s);
  std::vector<PredictionTarget> out;
  for (size_t k = static_cast<size_t>(std::max(burn_in, 0)); k < track.t_s.size(); ++k)
    for (int c = 0; c < n; ++c) {
      const double value = at[static_cast<size_t>(c)][k];
      if (std::isfinite(value)) out.push_back({k, c, track.t_s[k] + horizon_s, value});
    }
  return out;
}

/// Runs the predictor over the track and calls f(eps, S) for every innovation after the burn-in.
/// Returns false when an innovation is not finite or S <= 0.
template <class F>
bool forEachInnovation(Predictor& p, const FitTrack& track, int burn_in, F&& f) {
  const int n = static_cast<int>(track.channels.size());
  Eigen::VectorXd z(n);
  for (size_t i = 0; i < track.t_s.size(); ++i) {
    for (int c = 0; c < n; ++c) z(c) = track.channels[static_cast<size_t>(c)][i];
    p.update(track.t_s[i], z);
    if (static_cast<int>(i) < burn_in) continue;
    for (int c = 0; c < n; ++c) {
      const Innovation in = p.innovation(c);
      if (!in.valid) continue;
      if (!(in.S > 0.0) || !std::isfinite(in.S) || !std::isfinite(in.eps)) return false;
      f(in.eps, in.S);
    }
  }
  return true;
}

/// The fitting problem: predictor, fixed params, fitted keys, track.
struct Model {
  std::string predictor;
  Params base;
  std::vector<NoiseParameter> keys;
  const FitTrack* track = nullptr;
  int burn_in = 10;

  Params paramsAt(const double* theta) const {
    Params p = base;
    for (size_t i = 0; i < keys.size(); ++i) p.set(keys[i].key, std::exp(theta[i]));
    return p;
  }
  /// -log L at theta (log values); NaN when the filter fails.
  double negLogLik(const double* theta) const {
    std::unique_ptr<Predictor> pred;
    try {
      pred = makePredictor(predictor, static_cast<int>(track->channels.size()), paramsAt(theta));
    } catch (const std::invalid_argument&) {
      return kNaN;  // an inconsistent combination (e.g. sigma_min_sq > sigma_max_sq): infeasible
    }
    double s = 0.0;
    if (!forEachInnovation(*pred, *track, burn_in,
                           [&](double eps, double S) { s += 0.5 * (kLog2Pi + std::log(S) + eps * eps / S); }))
      return kNaN;
    return s;
  }

  /// Prediction objective: out[i] = p(t_target; theta) - z of targets[i]. False when the
  /// predictor cannot be built or a prediction is not finite.
  std::vector<PredictionTarget> targets;
  bool predictionResiduals(const double* theta, double* out) const {
    std::unique_ptr<Predictor> pred;
    try {
      pred = makePredictor(predictor, static_cast<int>(track->channels.size()), paramsAt(theta));
    } catch (const std::invalid_argument&) {
      return false;
    }
    const int n = static_cast<int>(track->channels.size());
    Eigen::VectorXd z(n);
    size_t next = 0;
    for (size_t i = 0; i < track->t_s.size() && next < targets.size(); ++i) {
      for (int c = 0; c < n; ++c) z(c) = track->channels[static_cast<size_t>(c)][i];
      pred->update(track->t_s[i], z);
      for (; next < targets.size() && targets[next].frame == i; ++next) {
        const double p = pred->predict(targets[next].channel, targets[next].t_target).position();
        if (!std::isfinite(p)) return false;
        out[next] = p - targets[next].z;
      }
    }
    return next == targets.size();
  }
  /// 1/2 sum of squared h-step errors; NaN when the predictor fails.
  double halfSquaredError(const double* theta) const {
    std::vector<double> r(targets.size());
    if (!predictionResiduals(theta, r.data())) return kNaN;
    double s = 0.0;
    for (double x : r) s += x * x;
    return 0.5 * s;
  }
};

/// d r / d theta into jac (n x k, row-major) by central differences of `step` in each theta_j.
/// Where one side cannot be evaluated, the one-sided difference from r0 = r(theta) if `one_sided`;
/// false when that is not allowed or neither side can be evaluated.
template <class ResidualsAt>
bool differenceJacobian(const double* theta, size_t k, size_t n, double step, bool one_sided, const double* r0,
                        const ResidualsAt& residualsAt, double* jac) {
  std::vector<double> rp(n), rm(n);
  for (size_t j = 0; j < k; ++j) {
    std::vector<double> tp(theta, theta + k), tm(theta, theta + k);
    tp[j] += step;
    tm[j] -= step;
    const bool okp = residualsAt(tp.data(), rp.data());
    const bool okm = (okp || one_sided) && residualsAt(tm.data(), rm.data());
    if (okp && okm) {
      for (size_t r = 0; r < n; ++r) jac[r * k + j] = (rp[r] - rm[r]) / (2.0 * step);
    } else if (one_sided && okp) {
      for (size_t r = 0; r < n; ++r) jac[r * k + j] = (rp[r] - r0[r]) / step;
    } else if (one_sided && okm) {
      for (size_t r = 0; r < n; ++r) jac[r * k + j] = (r0[r] - rm[r]) / step;
    } else {
      return false;
    }
  }
  return true;
}

/// The prediction objective's residuals as a Ceres cost, Jacobian by central differences in theta
/// (one-sided where one side fails).
class PredictionResiduals : public ceres::CostFunction {
 public:
  explicit PredictionResiduals(const Model& m) : m_(m) {
    mutable_parameter_block_sizes()->push_back(static_cast<int>(m.keys.size()));
    set_num_residuals(static_cast<int>(m.targets.size()));
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* theta = parameters[0];
    if (!m_.predictionResiduals(theta, residuals)) return false;
    if (jacobians && jacobians[0])
      return differenceJacobian(theta, m_.keys.size(), static_cast<size_t>(num_residuals()), kPredictionLogStep, true,
                                residuals, [this](const double* t, double* r) { return m_.predictionResiduals(t, r); },
                                jacobians[0]);
    return true;
  }

 private:
  const Model& m_;
};

/// theta = lo + (hi - lo) sigmoid(phi), in log values.
struct BoundMap {
  std::vector<double> lo, hi;
  double theta(size_t i, double phi) const { return lo[i] + (hi[i] - lo[i]) / (1.0 + std::exp(-phi)); }
  double dtheta(size_t i, double phi) const {
    const double s = 1.0 / (1.0 + std::exp(-phi));
    return (hi[i] - lo[i]) * s * (1.0 - s);
  }
  double phi(size_t i, double theta) const {
    const double s = std::clamp((theta - lo[i]) / (hi[i] - lo[i]), 1e-9, 1.0 - 1e-9);
    return std::log(s / (1.0 - s));
  }
};

class NegLogLikFunction : public ceres::FirstOrderFunction {
 public:
  NegLogLikFunction(const Model& m, const BoundMap& b) : m_(m), b_(b) {}
  int NumParameters() const override { return static_cast<int>(m_.keys.size()); }
  bool Evaluate(const double* phi, double* cost, double* gradient) const override {
    const size_t k = m_.keys.size();
    std::vector<double> theta(k);
    for (size_t i = 0; i < k; ++i) theta[i] = b_.theta(i, phi[i]);
    const double f = m_.negLogLik(theta.data());
    if (!std::isfinite(f)) return false;
    *cost = f;
    if (gradient) {
      for (size_t i = 0; i < k; ++i) {
        std::vector<double> tp = theta, tm = theta;
        tp[i] += kLogStep;
        tm[i] -= kLogStep;
        const double fp = m_.negLogLik(tp.data()), fm = m_.negLogLik(tm.data());
        double g;
        if (std::isfinite(fp) && std::isfinite(fm))
          g = (fp - fm) / (2.0 * kLogStep);
        else if (std::isfinite(fp))
          g = (fp - f) / kLogStep;
        else if (std::isfinite(fm))
          g = (f - fm) / kLogStep;
        else
          return false;
        gradient[i] = g * b_.dtheta(i, phi[i]);
      }
    }
    return true;
  }

 private:
  const Model& m_;
  const BoundMap& b_;
};

/// Residuals {eps/sqrt(S), log(S)/2} per innovation, Jacobian by central differences in theta.
class FisherResiduals : public ceres::CostFunction {
 public:
  FisherResiduals(const Model& m, int innovations) : m_(m) {
    mutable_parameter_block_sizes()->push_back(static_cast<int>(m.keys.size()));
    set_num_residuals(2 * innovations);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const double* theta = parameters[0];
    if (!residualsAt(theta, residuals)) return false;
    if (jacobians && jacobians[0])
      return differenceJacobian(theta, m_.keys.size(), static_cast<size_t>(num_residuals()), kLogStep, false, residuals,
                                [this](const double* t, double* r) { return residualsAt(t, r); }, jacobians[0]);
    return true;
  }

 private:
  bool residualsAt(const double* theta, double* out) const {
    std::unique_ptr<Predictor> pred;
    try {
      pred = makePredictor(m_.predictor, static_cast<int>(m_.track->channels.size()), m_.paramsAt(theta));
    } catch (const std::invalid_argument&) {
      return false;
    }
    size_t i = 0;
    const auto n = static_cast<size_t>(num_residuals());
    const bool ok = forEachInnovation(*pred, *m_.track, m_.burn_in, [&](double eps, double S) {
      if (i + 2 <= n) {
        out[i++] = eps / std::sqrt(S);
        out[i++] = 0.5 * std::log(S);
      } else {
        i += 2;
      }
    });
    if (!ok || i != n) return false;  // the set of innovations must not depend on theta
    return true;
  }
  const Model& m_;
};

}  // namespace

namespace {
/// Only the words of `p` (e.g. model: ca, r: auto): what selects a predictor's structure.
Params textsOf(const Params& p) {
  Params t;
  for (const auto& kv : p.texts()) t.setText(kv.first, kv.second);
  return t;
}
}  // namespace

std::vector<NoiseParameter> fitParameters(const std::string& predictor, const Params& structure) {
  std::vector<NoiseParameter> keys = makePredictor(predictor, 1, structure)->noiseParameters();
  if (keys.empty()) throw std::invalid_argument("predictor '" + predictor + "' has no parameters to fit");
  return keys;
}

double innovationLogLikelihood(const std::string& predictor, const Params& params, const FitTrack& track,
                               int burn_in_frames, int* n) {
  auto p = makePredictor(predictor, static_cast<int>(track.channels.size()), params);
  double s = 0.0;
  int count = 0;
  const bool ok = forEachInnovation(*p, track, burn_in_frames, [&](double eps, double S) {
    s -= 0.5 * (kLog2Pi + std::log(S) + eps * eps / S);
    ++count;
  });
  if (n) *n = count;
  return ok ? s : kNaN;
}

std::string fitObjectiveName(FitObjective o) { return o == FitObjective::Prediction ? "prediction" : "likelihood"; }

FitObjective parseFitObjective(const std::string& text) {
  if (text == "likelihood") return FitObjective::Likelihood;
  if (text == "prediction") return FitObjective::Prediction;
  throw std::invalid_argument("unknown fit objective '" + text + "' (expected likelihood or prediction)");
}

double predictionRmse(const std::string& predictor, const Params& params, const FitTrack& track, double horizon_s,
                      int burn_in_frames, int* n) {
  makePredictor(predictor, static_cast<int>(track.channels.size()), params);  // throws on bad params
  Model m;
  m.predictor = predictor;
  m.base = params;
  m.track = &track;
  m.burn_in = burn_in_frames;
  m.targets = predictionTargets(track, horizon_s, burn_in_frames);
  if (n) *n = static_cast<int>(m.targets.size());
  if (m.targets.empty()) return kNaN;
  const double h = m.halfSquaredError(nullptr);
  return std::sqrt(2.0 * h / static_cast<double>(m.targets.size()));
}

namespace {

/// One fit of the predictor's noise with its structure as `base` gives it (fitNoise, below, runs
/// this once per structural variant).
NoiseFitResult fitOneStructure(const std::string& predictor, const Params& base, const FitTrack& track,
                               const NoiseFitOptions& options) {
  if (track.channels.empty()) throw std::invalid_argument("noise fit: the track has no channel");
  for (const auto& ch : track.channels)
    if (ch.size() != track.t_s.size()) throw std::invalid_argument("noise fit: the channels and t have different lengths");
  if (!(options.horizon_s >= 0.0)) throw std::invalid_argument("noise fit: expected a horizon >= 0 s");
  Model m;
  m.predictor = predictor;
  m.keys = fitParameters(predictor, textsOf(base));
  m.track = &track;
  m.burn_in = options.burn_in_frames;
  int measured = 0;
  for (size_t i = 0; i < track.t_s.size(); ++i) measured += std::isfinite(track.channels.front()[i]) ? 1 : 0;
  if (measured < 4 * std::max(options.burn_in_frames, 5))
    throw std::invalid_argument("noise fit: the track has " + std::to_string(measured) + " measured rows, need at least " +
                                std::to_string(4 * std::max(options.burn_in_frames, 5)) + " (4 x the burn-in of " +
                                std::to_string(std::max(options.burn_in_frames, 5)) + " rows)");

  // Fixed keys: everything in base except the fitted ones.
  for (const auto& kv : base.values()) m.base.set(kv.first, kv.second);
  for (const auto& kv : base.texts())
    if (kv.first != "r") m.base.setText(kv.first, kv.second);

  // Start values: base, else the start-up noise estimate (r), else the predictor's default.
  std::vector<StartupNoiseEstimator> estimators(track.channels.size(), StartupNoiseEstimator(1.0, 50));
  for (size_t c = 0; c < track.channels.size(); ++c)
    for (size_t i = 0; i < track.t_s.size(); ++i) estimators[c].push(track.t_s[i], track.channels[c][i]);
  double mean_variance = 0.0;
  for (const auto& e : estimators) mean_variance += e.variance() / static_cast<double>(estimators.size());
  // Start values; under the prediction objective r is held at its start value (see the header).
  const bool hold_r = options.objective == FitObjective::Prediction && !options.prediction_fits_r;
  std::vector<FittedValue> held;
  {
    std::vector<NoiseParameter> fitted;
    for (NoiseParameter fp : m.keys) {
      double v = fp.value;
      if (base.values().count(fp.key))
        v = base.values().at(fp.key);
      else if (fp.key == "r")
        v = mean_variance;
      fp.value = std::clamp(v, fp.lo * 1.01, fp.hi / 1.01);
      if (hold_r && fp.key == "r") {
        m.base.set("r", fp.value);
        FittedValue h;
        h.key = "r";
        h.initial = h.value = h.lo95 = h.hi95 = fp.value;
        h.std_log = kNaN;
        h.held = true;
        held.push_back(h);
      } else {
        fitted.push_back(fp);
      }
    }
    m.keys = fitted;
  }
  if (m.keys.empty()) throw std::invalid_argument("noise fit: no parameter left to fit (r is held)");
  const size_t k = m.keys.size();
  BoundMap b;
  std::vector<double> theta0(k);
  for (size_t i = 0; i < k; ++i) {
    theta0[i] = std::log(m.keys[i].value);
    b.lo.push_back(std::log(m.keys[i].lo));
    b.hi.push_back(std::log(m.keys[i].hi));
  }

  NoiseFitResult res;
  res.predictor = predictor;
  res.objective = options.objective;
  res.horizon_s = options.horizon_s;
  const bool by_prediction = options.objective == FitObjective::Prediction;
  if (by_prediction) {
    m.targets = predictionTargets(track, options.horizon_s, m.burn_in);
    if (m.targets.size() < 2 * k + 2)
      throw std::invalid_argument("noise fit: " + std::to_string(m.targets.size()) +
                                  " h-step targets inside the track, too few for the prediction objective");
  }
  // The objective to minimise at theta: -log L, or 1/2 sum of squared h-step errors.
  const auto objective = [&](const double* th) { return by_prediction ? m.halfSquaredError(th) : m.negLogLik(th); };
  int n0 = 0;
  const double f0 = objective(theta0.data());
  if (!std::isfinite(f0))
    throw std::invalid_argument(std::string("noise fit: the ") + (by_prediction ? "h-step prediction error" : "likelihood") +
                                " is not finite at the starting values");
  res.loglik_before = innovationLogLikelihood(predictor, m.paramsAt(theta0.data()), track, m.burn_in, &n0);
  res.innovations = n0;
  res.residuals = static_cast<int>(m.targets.size());

  // One local fit from theta_start: returns the end point and its objective.
  const auto solveFrom = [&](const std::vector<double>& theta_start, double* f_end, int* iterations,
                             std::string* message) {
    std::vector<double> th = theta_start;
    if (by_prediction) {
      ceres::Problem::Options popt;
      ceres::Problem problem(popt);
      problem.AddResidualBlock(new PredictionResiduals(m), nullptr, th.data());
      for (size_t i = 0; i < k; ++i) {
        problem.SetParameterLowerBound(th.data(), static_cast<int>(i), b.lo[i]);
        problem.SetParameterUpperBound(th.data(), static_cast<int>(i), b.hi[i]);
      }
      ceres::Solver::Options opt;
      opt.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
      opt.linear_solver_type = ceres::DENSE_QR;
      opt.max_num_iterations = options.max_iterations;
      opt.logging_type = ceres::SILENT;
      opt.function_tolerance = 1e-8;
      opt.parameter_tolerance = 1e-6;
      opt.num_threads = 1;
      ceres::Solver::Summary summary;
      ceres::Solve(opt, &problem, &summary);
      *iterations = static_cast<int>(summary.iterations.size());
      *message = summary.message;
    } else {
      std::vector<double> phi(k);
      for (size_t i = 0; i < k; ++i) phi[i] = b.phi(i, th[i]);
      ceres::GradientProblem problem(new NegLogLikFunction(m, b));
      ceres::GradientProblemSolver::Options opt;
      opt.line_search_direction_type = ceres::LBFGS;
      opt.max_num_iterations = options.max_iterations;
      opt.logging_type = ceres::SILENT;
      opt.function_tolerance = 1e-9;
      opt.gradient_tolerance = 1e-8;
      ceres::GradientProblemSolver::Summary summary;
      ceres::Solve(opt, problem, phi.data(), &summary);
      for (size_t i = 0; i < k; ++i) th[i] = b.theta(i, phi[i]);
      *iterations = static_cast<int>(summary.iterations.size());
      *message = summary.message;
    }
    *f_end = objective(th.data());
    return th;
  };

  if (options.starts < 1) throw std::invalid_argument("noise fit: expected at least one starting point");
  // Warm starts (header): the start values with the keys this structure's fitSeeds() map from
  // options.seed_fits replaced, one start point per FitSeed::start index (increasing); each is
  // tried after the m starts when it moves a fitted key.
  std::map<int, std::vector<double>> warm;  // by FitSeed::start
  std::map<int, bool> warm_moved;
  if (!options.seed_fits.empty()) {
    std::vector<FitSeed> seeds;
    try {
      seeds = makePredictor(predictor, 1, m.base)->fitSeeds();
    } catch (const std::invalid_argument&) {
      // built with the start values below (theta0 passed above), so this does not happen
    }
    const double margin = std::log(1.01);
    for (const FitSeed& s : seeds) {
      const auto src = options.seed_fits.find(s.from_predictor);
      if (src == options.seed_fits.end() || !src->second.values().count(s.from_key)) continue;
      const double v = s.factor * std::pow(src->second.values().at(s.from_key), s.power);
      if (!(v > 0.0) || !std::isfinite(v)) continue;
      std::vector<double>& w = warm.emplace(s.start, theta0).first->second;
      bool& moved = warm_moved[s.start];
      for (size_t i = 0; i < k; ++i)
        if (m.keys[i].key == s.key) {
          const double seeded = std::clamp(std::log(v), b.lo[i] + margin, b.hi[i] - margin);
          w[i] = s.raise_only ? std::max(w[i], seeded) : seeded;
          moved = moved || w[i] != theta0[i];
        }
    }
  }
  std::vector<std::vector<double>> warm_starts;
  for (const auto& kv : warm)
    if (warm_moved[kv.first]) warm_starts.push_back(kv.second);
  std::vector<double> theta = theta0;
  double f1 = f0;
  res.starts = 0;
  const int tries = options.starts + static_cast<int>(warm_starts.size());
  for (int j = 0; j < tries; ++j) {
    std::vector<double> start = theta0;
    const bool is_warm = j >= options.starts;
    if (is_warm) {
      start = warm_starts[static_cast<size_t>(j - options.starts)];
      if (!std::isfinite(objective(start.data()))) continue;
      res.warm_start = true;
    } else if (j > 0) {
      const double decades = kStartDecades[static_cast<size_t>(j - 1) % std::size(kStartDecades)] *
                             (1.0 + static_cast<double>((j - 1) / static_cast<int>(std::size(kStartDecades))));
      bool moved = false;
      for (size_t i = 0; i < k; ++i) {
        if (m.keys[i].key == "r") continue;
        const double margin = std::log(1.01);
        start[i] = std::clamp(theta0[i] + decades * std::log(10.0), b.lo[i] + margin, b.hi[i] - margin);
        moved = moved || start[i] != theta0[i];
      }
      if (!moved || !std::isfinite(objective(start.data()))) continue;
    }
    double fj = kNaN;
    int iterations = 0;
    std::string message;
    const std::vector<double> th = solveFrom(start, &fj, &iterations, &message);
    ++res.starts;
    res.iterations += iterations;
    if (j == 0) res.termination = message;
    if (std::isfinite(fj) && fj < f1) {  // never return something worse than the start values
      theta = th;
      f1 = fj;
      res.best_start = j;  // >= options.starts: a warm start (options.starts + its rank)
      res.warm_start_kept = is_warm;
      res.termination = message;
    }
  }
  res.params = m.paramsAt(theta.data());
  res.loglik_after = innovationLogLikelihood(predictor, res.params, track, m.burn_in);
  if (by_prediction) {
    res.rmse_before_px = std::sqrt(2.0 * f0 / static_cast<double>(m.targets.size()));
    res.rmse_after_px = std::sqrt(2.0 * f1 / static_cast<double>(m.targets.size()));
  } else {
    res.rmse_before_px = predictionRmse(predictor, m.paramsAt(theta0.data()), track, options.horizon_s, m.burn_in);
    res.rmse_after_px = predictionRmse(predictor, res.params, track, options.horizon_s, m.burn_in);
  }

  // Uncertainty: inverse Fisher information (likelihood) or the Gauss-Newton covariance of the
  // h-step least squares (prediction), by ceres::Covariance.
  std::vector<double> std_log(k, kNaN);
  {
    ceres::Problem::Options popt;
    ceres::Problem lsq(popt);
    std::vector<double> block = theta;
    if (by_prediction)
      lsq.AddResidualBlock(new PredictionResiduals(m), nullptr, block.data());
    else
      lsq.AddResidualBlock(new FisherResiduals(m, n0), nullptr, block.data());
    ceres::Covariance::Options copt;
    copt.algorithm_type = ceres::DENSE_SVD;
    copt.null_space_rank = -1;
    copt.min_reciprocal_condition_number = 1e-14;
    ceres::Covariance cov(copt);
    std::vector<std::pair<const double*, const double*>> blocks = {{block.data(), block.data()}};
    // Ceres' dense SVD does not survive a non-finite Jacobian (an adaptive filter whose numeric
    // derivative blows up at a clamp): check it first and report no covariance then.
    double cost = 0.0;
    ceres::CRSMatrix jac;
    bool finite = lsq.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, &jac) && std::isfinite(cost);
    for (double x : jac.values) finite = finite && std::isfinite(x);
    // Prediction: the residuals are not normalised, scale (J'J)^-1 by s^2 = 2 J / (n - p).
    const double scale = by_prediction ? 2.0 * cost / std::max(1.0, static_cast<double>(m.targets.size() - k)) : 1.0;
    if (finite && cov.Compute(blocks, &lsq)) {
      std::vector<double> C(k * k);
      if (cov.GetCovarianceBlock(block.data(), block.data(), C.data())) {
        res.covariance_ok = true;
        for (size_t i = 0; i < k; ++i) std_log[i] = std::sqrt(std::max(0.0, scale * C[i * k + i]));
      }
    }
  }
  for (size_t i = 0; i < k; ++i) {
    FittedValue v;
    v.key = m.keys[i].key;
    v.initial = std::exp(theta0[i]);
    v.value = std::exp(theta[i]);
    v.std_log = std_log[i];
    v.lo95 = v.value * std::exp(-1.96 * std_log[i]);
    v.hi95 = v.value * std::exp(1.96 * std_log[i]);
    v.at_bound = (theta[i] - b.lo[i]) < 0.01 * (b.hi[i] - b.lo[i]) || (b.hi[i] - theta[i]) < 0.01 * (b.hi[i] - b.lo[i]);
    res.values.push_back(v);
  }
  res.values.insert(res.values.end(), held.begin(), held.end());
  return res;
}

/// `base` with a variant's overrides (texts and numbers) set on it.
Params withVariant(Params base, const Params& v) {
  base.setAll(v);
  return base;
}

/// True when `base` gives one of the keys the variants override (it pins the choice among them).
bool pinsVariantKey(const Params& base, const std::vector<Params>& variants) {
  for (const auto& v : variants) {
    for (const auto& kv : v.texts())
      if (base.has(kv.first)) return true;
    for (const auto& kv : v.values())
      if (base.has(kv.first)) return true;
  }
  return false;
}

/// "key=value,key=value" of a variant's overrides (texts and numbers).
std::string describeVariant(const Params& v) {
  std::ostringstream o;
  o.precision(10);
  const char* sep = "";
  for (const auto& kv : v.texts()) {
    o << sep << kv.first << "=" << kv.second;
    sep = ",";
  }
  for (const auto& kv : v.values()) {
    o << sep << kv.first << "=" << kv.second;
    sep = ",";
  }
  return o.str();
}

}  // namespace

std::set<std::string> fitSeedSources(const std::string& predictor, const Params& structure) {
  const Params texts = textsOf(structure);
  std::vector<Params> structures = {structure};
  for (const Params& v : makePredictor(predictor, 1, texts)->structuralVariants())
    structures.push_back(withVariant(structure, v));
  std::set<std::string> out;
  for (const Params& p : structures) {
    std::unique_ptr<Predictor> inst;
    try {
      inst = makePredictor(predictor, 1, p);
    } catch (const std::invalid_argument&) {
      continue;  // a variant the given params contradict: fitNoise does not fit it either
    }
    for (const FitSeed& s : inst->fitSeeds()) out.insert(s.from_predictor);
  }
  return out;
}

std::vector<size_t> fitOrder(const std::vector<std::string>& predictors, const std::vector<Params>& structures) {
  std::vector<size_t> first, then;
  for (size_t i = 0; i < predictors.size(); ++i) {
    const Params p = i < structures.size() ? structures[i] : Params{};
    (fitSeedSources(predictors[i], p).empty() ? first : then).push_back(i);
  }
  first.insert(first.end(), then.begin(), then.end());
  return first;
}

namespace {

/// The structure and its noise (fitNoise without the forecast's choice): fitOneStructure, once
/// per structural variant unless `base` pins one.
NoiseFitResult fitStructures(const std::string& predictor, const Params& base, const FitTrack& track,
                             const NoiseFitOptions& options) {
  // The structural variants the predictor offers, unless `base` already pins one of their keys.
  const std::vector<Params> variants = makePredictor(predictor, 1, textsOf(base))->structuralVariants();
  if (variants.empty() || pinsVariantKey(base, variants)) return fitOneStructure(predictor, base, track, options);

  const bool by_prediction = options.objective == FitObjective::Prediction;
  if (!validSelectHoldout(options.select_holdout))
    throw std::invalid_argument("noise fit: expected a structure hold-out fraction in [0, 0.9]");
  // The rows before the held-out part (select_holdout > 0), and the track cut there.
  const size_t rows = track.t_s.size();
  const size_t head = options.select_holdout > 0.0
                          ? static_cast<size_t>(std::lround((1.0 - options.select_holdout) * static_cast<double>(rows)))
                          : rows;
  FitTrack head_track;
  if (head < rows) {
    head_track.t_s.assign(track.t_s.begin(), track.t_s.begin() + static_cast<long>(head));
    for (const auto& ch : track.channels) head_track.channels.emplace_back(ch.begin(), ch.begin() + static_cast<long>(head));
  }
  // Lower is better: RMSE, or -log L.
  const auto score = [&](const NoiseFitResult& r) { return by_prediction ? r.rmse_after_px : -r.loglik_after; };

  NoiseFitResult best;
  double best_score = kNaN;
  bool have = false;
  std::vector<VariantFit> tried;
  std::string first_error;
  for (const auto& v : variants) {
    const Params pv = withVariant(base, v);
    NoiseFitResult r;
    try {
      r = fitOneStructure(predictor, pv, track, options);
    } catch (const std::invalid_argument& e) {
      if (first_error.empty()) first_error = e.what();
      continue;  // this structure cannot run on the track (e.g. too few targets for its keys)
    }
    VariantFit f;
    f.variant = describeVariant(v);
    f.objective_before = by_prediction ? r.rmse_before_px : r.loglik_before;
    f.objective_after = by_prediction ? r.rmse_after_px : r.loglik_after;
    double s = score(r);
    if (head < rows) {
      // Out of sample: fitted on the head, judged on the rows after it.
      try {
        const NoiseFitResult h = fitOneStructure(predictor, pv, head_track, options);
        const int burn = static_cast<int>(head);
        const double o = by_prediction ? predictionRmse(predictor, h.params, track, options.horizon_s, burn)
                                       : innovationLogLikelihood(predictor, h.params, track, burn);
        if (std::isfinite(o)) {
          f.objective_holdout = o;
          s = by_prediction ? o : -o;
        }
      } catch (const std::invalid_argument&) {
        // the head is too short for this structure: judged in sample (the header)
      }
    }
    tried.push_back(f);
    if (!have || s < best_score) {
      best = r;
      best.variant = f.variant;
      best_score = s;
      have = true;
    }
  }
  if (!have) throw std::invalid_argument(first_error);
  best.variants = tried;
  return best;
}

/// fitNoise() once `base` says the horizon (or there is none to say): the structures, then the
/// forecast variants.
NoiseFitResult fitNoiseAsked(const std::string& predictor, const Params& base, const FitTrack& track,
                             const NoiseFitOptions& options) {
  NoiseFitResult best = fitStructures(predictor, base, track, options);
  if (options.objective != FitObjective::Prediction) return best;  // the forecast does not change log L
  // The forecast variants of the kept structure (Predictor::forecastVariants()), unless `base`
  // pins one of their keys: each run with the fitted noise, on the same rows and targets as the
  // fit; the lowest h-step RMSE is kept (the fitted values are the same for all).
  const std::vector<Params> forecasts = makePredictor(predictor, 1, best.params)->forecastVariants();
  if (forecasts.empty() || pinsVariantKey(base, forecasts)) return best;
  best.rmse_own_forecast_px = best.rmse_after_px;
  for (const auto& v : forecasts) {
    const Params pv = withVariant(best.params, v);
    VariantFit f;
    f.variant = describeVariant(v);
    f.objective_before = f.objective_after = predictionRmse(predictor, pv, track, options.horizon_s, options.burn_in_frames);
    best.forecast_variants.push_back(f);
    if (f.objective_after < best.rmse_after_px) {
      best.rmse_after_px = f.objective_after;
      best.params = pv;
      best.forecast_variant = f.variant;
    }
  }
  return best;
}

}  // namespace

NoiseFitResult fitNoise(const std::string& predictor, const Params& base, const FitTrack& track,
                        const NoiseFitOptions& options) {
  // The fit's horizon (the prediction objective's, and the h-step RMSE's it reports), told to the
  // predictor (horizon_frames) unless the caller told it; not handed back in the params, since it
  // is the caller's to say.
  // (medianPeriod: the frame period predict and fit-noise measure their horizon in)
  if (base.has("horizon_frames") || !(options.horizon_s > 0.0) || track.t_s.size() < 2)
    return fitNoiseAsked(predictor, base, track, options);
  const double period = medianPeriod(track.t_s);
  if (!(period > 0.0)) return fitNoiseAsked(predictor, base, track, options);
  Params told = base;
  told.set("horizon_frames", options.horizon_s / period);
  NoiseFitResult res = fitNoiseAsked(predictor, told, track, options);
  res.params.erase("horizon_frames");
  return res;
}

}  // namespace predvs
