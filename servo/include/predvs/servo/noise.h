// predvs — seeded measurement-noise models (docs/MODELS.md §10: E6 noise study, default scenario).
//
//   none      n = 0
//   gaussian  n ~ N(0, sigma^2)                                    (variance sigma^2)
//   uniform   n = sigma (2 w - 1), w ~ U[0, 1] (paper 001 §5.2)     (variance sigma^2 / 3)
// Optionally the noisy value is rounded to the nearest integer (pixel quantisation, paper 001 §5.2).
// Every model draws from its own std::mt19937_64 seeded with the scenario seed, so a run is
// reproducible bit for bit on one platform and two runs with the same seed see the same noise.
#pragma once

#include "predvs/predictors/params.h"

#include <Eigen/Core>

#include <cstdint>
#include <random>
#include <string>

namespace predvs {

enum class NoiseKind { None, Gaussian, Uniform };

/// "none" | "gaussian" | "uniform"; throws std::invalid_argument naming noise.model otherwise.
NoiseKind parseNoiseKind(const std::string& name);
std::string noiseKindName(NoiseKind kind);

/// Plain configuration (YAML: `noise.<key>`).
struct NoiseConfig {
  NoiseKind kind = NoiseKind::Gaussian;  ///< noise.model
  double sigma = 0.5;                    ///< noise.sigma >= 0, in the measurement's units (px)
  bool round_to_integer = false;         ///< noise.round
};

/// Builds a NoiseConfig from a model name and Params with keys `sigma` (default 0.5) and `round`
/// (0 or 1, default 0); unknown keys are rejected.
NoiseConfig makeNoiseConfig(const std::string& name, const Params& params = {});

class NoiseModel {
 public:
  /// Throws std::invalid_argument ("noise.sigma must be >= 0, got -1") on a bad config.
  NoiseModel(const NoiseConfig& config, std::uint64_t seed);
  const NoiseConfig& config() const { return config_; }
  /// One noise sample n (before rounding).
  double sample();
  /// value + n, rounded to the nearest integer if configured.
  double apply(double value);
  /// Applies apply() to every entry, in order.
  void apply(Eigen::Ref<Eigen::VectorXd> values);
  /// Theoretical standard deviation of n: sigma (gaussian), sigma / sqrt(3) (uniform), 0 (none).
  double standardDeviation() const;

 private:
  NoiseConfig config_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

}  // namespace predvs
