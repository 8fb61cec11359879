#include "predvs/calibration/noise_fit.h"

#include "predvs/predictors/noise_estimate.h"
#include "predvs/predictors/predictor.h"

#include <ceres/ceres.h>
#include <ceres/covariance.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kLog2Pi = 1.8378770664093453;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Central-difference step in theta = log(value).
constexpr double kLogStep = 1e-4;

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
    if (jacobians && jacobians[0]) {
      const size_t k = m_.keys.size();
      const auto n = static_cast<size_t>(num_residuals());
      std::vector<double> rp(n), rm(n);
      for (size_t j = 0; j < k; ++j) {
        std::vector<double> tp(theta, theta + k), tm(theta, theta + k);
        tp[j] += kLogStep;
        tm[j] -= kLogStep;
        if (!residualsAt(tp.data(), rp.data()) || !residualsAt(tm.data(), rm.data())) return false;
        for (size_t r = 0; r < n; ++r) jacobians[0][r * k + j] = (rp[r] - rm[r]) / (2.0 * kLogStep);
      }
    }
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

std::vector<NoiseParameter> fitParameters(const std::string& predictor) {
  std::vector<NoiseParameter> keys = makePredictor(predictor, 1)->noiseParameters();
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

NoiseFitResult fitNoise(const std::string& predictor, const Params& base, const FitTrack& track,
                        const NoiseFitOptions& options) {
  if (track.channels.empty()) throw std::invalid_argument("noise fit: the track has no channel");
  for (const auto& ch : track.channels)
    if (ch.size() != track.t_s.size()) throw std::invalid_argument("noise fit: the channels and t have different lengths");
  Model m;
  m.predictor = predictor;
  m.keys = fitParameters(predictor);
  m.track = &track;
  m.burn_in = options.burn_in_frames;
  int measured = 0;
  for (size_t i = 0; i < track.t_s.size(); ++i) measured += std::isfinite(track.channels.front()[i]) ? 1 : 0;
  if (measured < 4 * std::max(options.burn_in_frames, 5))
    throw std::invalid_argument("noise fit: the track has " + std::to_string(measured) + " measured rows, need at least " +
                                std::to_string(4 * std::max(options.burn_in_frames, 5)));

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
  const size_t k = m.keys.size();
  BoundMap b;
  std::vector<double> theta0(k);
  for (size_t i = 0; i < k; ++i) {
    const NoiseParameter& fp = m.keys[i];
    double v = fp.value;
    if (base.values().count(fp.key))
      v = base.values().at(fp.key);
    else if (fp.key == "r")
      v = mean_variance;
    v = std::clamp(v, fp.lo * 1.01, fp.hi / 1.01);
    theta0[i] = std::log(v);
    b.lo.push_back(std::log(fp.lo));
    b.hi.push_back(std::log(fp.hi));
  }

  NoiseFitResult res;
  res.predictor = predictor;
  int n0 = 0;
  const double f0 = m.negLogLik(theta0.data());
  if (!std::isfinite(f0)) throw std::invalid_argument("noise fit: the likelihood is not finite at the starting values");
  innovationLogLikelihood(predictor, m.paramsAt(theta0.data()), track, m.burn_in, &n0);
  res.loglik_before = -f0;
  res.innovations = n0;

  std::vector<double> phi(k);
  for (size_t i = 0; i < k; ++i) phi[i] = b.phi(i, theta0[i]);
  ceres::GradientProblem problem(new NegLogLikFunction(m, b));
  ceres::GradientProblemSolver::Options opt;
  opt.line_search_direction_type = ceres::LBFGS;
  opt.max_num_iterations = options.max_iterations;
  opt.logging_type = ceres::SILENT;
  opt.function_tolerance = 1e-9;
  opt.gradient_tolerance = 1e-8;
  ceres::GradientProblemSolver::Summary summary;
  ceres::Solve(opt, problem, phi.data(), &summary);
  res.iterations = static_cast<int>(summary.iterations.size());
  res.termination = summary.message;

  std::vector<double> theta(k);
  for (size_t i = 0; i < k; ++i) theta[i] = b.theta(i, phi[i]);
  double f1 = m.negLogLik(theta.data());
  if (!(f1 <= f0)) {  // never return something worse than the start
    theta = theta0;
    f1 = f0;
  }
  res.loglik_after = -f1;
  res.params = m.paramsAt(theta.data());

  // Uncertainty: inverse Fisher information by ceres::Covariance.
  std::vector<double> std_log(k, kNaN);
  {
    ceres::Problem::Options popt;
    ceres::Problem lsq(popt);
    std::vector<double> block = theta;
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
    if (finite && cov.Compute(blocks, &lsq)) {
      std::vector<double> C(k * k);
      if (cov.GetCovarianceBlock(block.data(), block.data(), C.data())) {
        res.covariance_ok = true;
        for (size_t i = 0; i < k; ++i) std_log[i] = std::sqrt(std::max(0.0, C[i * k + i]));
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
  return res;
}

}  // namespace predvs
