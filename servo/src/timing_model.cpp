#include "predvs/servo/timing_model.h"

#include "predvs/predictors/named_enum.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

// Relative tolerance when rounding an instant up to a control tick: 0.08 / 0.04 must give tick 2,
// not 3, despite binary rounding.
constexpr double kTickRoundingTolerance = 1e-9;

void requireNonNegative(const char* key, double value) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "timing." << key << " must be a finite value >= 0, got " << value;
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace

namespace {
constexpr EnumName<Pipeline> kPipelines[] = {{Pipeline::Serial, "serial"}, {Pipeline::Parallel, "parallel"}};
}  // namespace

Pipeline parsePipeline(const std::string& name) { return enumFromName(kPipelines, "timing.pipeline", name); }
std::string pipelineName(Pipeline p) { return enumToName(kPipelines, p); }

TimingModel::TimingModel(const TimingConfig& config) : config_(config) {
  if (!(config.base_period_s > 0.0) || !std::isfinite(config.base_period_s)) {
    std::ostringstream msg;
    msg << "timing.base_period_s must be > 0, got " << config.base_period_s;
    throw std::invalid_argument(msg.str());
  }
  if (config.frame_period_n < 1)
    throw std::invalid_argument("timing.frame_period_n must be >= 1, got " + std::to_string(config.frame_period_n));
  requireNonNegative("acquisition_lag_s", config.acquisition_lag_s);
  requireNonNegative("processing_lag_s", config.processing_lag_s);
  requireNonNegative("controller_lag_s", config.controller_lag_s);
  requireNonNegative("servo_lag_s", config.servo_lag_s);
  requireNonNegative("motion_lag_s", config.motion_lag_s);
  const double need = minimumFramePeriod();
  if (framePeriod() < need * (1.0 - kTickRoundingTolerance)) {
    std::ostringstream msg;
    msg << "timing.frame_period_n: frame period T = N * delta = " << framePeriod()
        << " s is shorter than the " << pipelineName(config.pipeline) << " pipeline needs ("
        << (config.pipeline == Pipeline::Serial ? "t_ac + t_p" : "max(t_ac, t_p)") << " = " << need << " s)";
    throw std::invalid_argument(msg.str());
  }
}

double TimingModel::framePeriod() const { return config_.frame_period_n * config_.base_period_s; }
double TimingModel::visionLatency() const { return config_.acquisition_lag_s + config_.processing_lag_s; }
double TimingModel::commandLag() const { return config_.controller_lag_s + config_.servo_lag_s; }

double TimingModel::minimumFramePeriod() const {
  return config_.pipeline == Pipeline::Serial ? visionLatency()
                                              : std::max(config_.acquisition_lag_s, config_.processing_lag_s);
}

double TimingModel::tickTime(long k) const { return static_cast<double>(k) * config_.base_period_s; }

long TimingModel::tickAtOrAfter(double t_s) const {
  const double ticks = t_s / config_.base_period_s;
  return static_cast<long>(std::ceil(ticks - kTickRoundingTolerance * std::max(1.0, std::abs(ticks))));
}

bool TimingModel::isAcquisitionTick(long k) const { return k >= 0 && k % config_.frame_period_n == 0; }

double TimingModel::availableTime(double t_acq_s) const { return t_acq_s + visionLatency(); }
long TimingModel::releaseTick(double t_acq_s) const { return tickAtOrAfter(availableTime(t_acq_s)); }
double TimingModel::releaseTime(double t_acq_s) const { return tickTime(releaseTick(t_acq_s)); }

long TimingModel::commandApplyTick(long k) const { return tickAtOrAfter(tickTime(k) + commandLag()); }

double TimingModel::effectTime(double t_c_s) const {
  return t_c_s + commandLag() + (config_.model_motion_lag ? 0.5 * config_.motion_lag_s : 0.0);
}

double TimingModel::horizon(double t_now_s, double t_acq_s) const {
  if (t_now_s < t_acq_s) {
    std::ostringstream msg;
    msg << "timing: horizon asked at t_now = " << t_now_s << " s before the acquisition t_acq = " << t_acq_s << " s";
    throw std::invalid_argument(msg.str());
  }
  return effectTime(t_now_s) - t_acq_s;
}

double TimingModel::horizonFrames(double t_now_s, double t_acq_s) const {
  return horizon(t_now_s, t_acq_s) / framePeriod();
}

double TimingModel::nominalHorizonFrames() const { return horizonFrames(releaseTime(0.0), 0.0); }

double TimingModel::longestHorizonFrames() const {
  return horizonFrames(releaseTime(0.0) + (config_.frame_period_n - 1) * config_.base_period_s, 0.0);
}

}  // namespace predvs
