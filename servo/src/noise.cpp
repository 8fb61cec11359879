#include "predvs/servo/noise.h"

#include "predvs/predictors/named_enum.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace predvs {

namespace {
constexpr EnumName<NoiseKind> kNoiseKinds[] = {
    {NoiseKind::None, "none"}, {NoiseKind::Gaussian, "gaussian"}, {NoiseKind::Uniform, "uniform"}};
}  // namespace

NoiseKind parseNoiseKind(const std::string& name) { return enumFromName(kNoiseKinds, "noise.model", name); }
std::string noiseKindName(NoiseKind kind) { return enumToName(kNoiseKinds, kind); }

NoiseConfig makeNoiseConfig(const std::string& name, const Params& params) {
  NoiseConfig c;
  c.kind = parseNoiseKind(name);
  c.sigma = params.get("sigma", 0.5);
  const double round = params.get("round", 0.0);
  if (round != 0.0 && round != 1.0) {
    std::ostringstream msg;
    msg << "noise.round must be 0 or 1, got " << round;
    throw std::invalid_argument(msg.str());
  }
  c.round_to_integer = round == 1.0;
  params.requireAllUsed("noise model '" + name + "'");
  return c;
}

NoiseModel::NoiseModel(const NoiseConfig& config, std::uint64_t seed) : config_(config), rng_(seed) {
  if (!(config.sigma >= 0.0) || !std::isfinite(config.sigma)) {
    std::ostringstream msg;
    msg << "noise.sigma must be >= 0, got " << config.sigma;
    throw std::invalid_argument(msg.str());
  }
}

double NoiseModel::sample() {
  switch (config_.kind) {
    case NoiseKind::None: return 0.0;
    case NoiseKind::Gaussian: return config_.sigma * normal_(rng_);
    case NoiseKind::Uniform: return config_.sigma * (2.0 * uniform_(rng_) - 1.0);
  }
  return 0.0;
}

double NoiseModel::apply(double value) {
  const double noisy = value + sample();
  return config_.round_to_integer ? std::round(noisy) : noisy;
}

void NoiseModel::apply(Eigen::Ref<Eigen::VectorXd> values) {
  for (Eigen::Index i = 0; i < values.size(); ++i) values(i) = apply(values(i));
}

double NoiseModel::standardDeviation() const {
  switch (config_.kind) {
    case NoiseKind::None: return 0.0;
    case NoiseKind::Gaussian: return config_.sigma;
    case NoiseKind::Uniform: return config_.sigma / std::sqrt(3.0);
  }
  return 0.0;
}

}  // namespace predvs
