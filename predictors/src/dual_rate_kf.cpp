#include "predvs/predictors/dual_rate_kf.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace predvs {

namespace {
void requireAll(const Eigen::VectorXd& v, Eigen::Index n, bool allow_zero, const char* what) {
  if (v.size() != n)
    throw std::invalid_argument(std::string("DualRateKf: ") + what + " has " + std::to_string(v.size()) +
                                " entries, expected " + std::to_string(n));
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isfinite(v(i)) || v(i) < 0.0 || (!allow_zero && v(i) == 0.0))
      throw std::invalid_argument(std::string("DualRateKf: ") + what + " of channel " + std::to_string(i) +
                                  (allow_zero ? " must be >= 0" : " must be > 0"));
}
}  // namespace

DualRateKf::DualRateKf(const DualRateKfConfig& config) : config_(config) {
  if (!(config.base_period_s > 0.0) || !std::isfinite(config.base_period_s))
    throw std::invalid_argument("DualRateKf: the base period must be > 0");
  if (config.frame_ticks < 1) throw std::invalid_argument("DualRateKf: the frame must have N >= 1 ticks");
  const Eigen::Index n = config.accel_std.size();
  requireAll(config.accel_std, n, true, "accel_std");
  requireAll(config.measurement_std, n, false, "measurement_std");
  requireAll(config.initial_velocity_std, n, false, "initial_velocity_std");

  // The scalar constant-velocity model at delta (eqs. 4-5), noise input every tick, position read
  // at the frame instant; lifted over the frame (Appendix A).
  const double d = config.base_period_s;
  LinearSystem cv;
  cv.A = (Eigen::Matrix2d() << 1.0, d, 0.0, 1.0).finished();
  cv.B = (Eigen::Vector2d() << 0.5 * d * d, d).finished();
  cv.C = (Eigen::RowVector2d() << 1.0, 0.0).finished();
  cv.D = Eigen::MatrixXd::Zero(1, 1);
  const int N = config.frame_ticks;
  lifted_ = liftSystem(cv, N, sampledEveryTick(N, 1), sampledAtFrameStart(N, 1));
  A_bar_ = lifted_.A;
  const Mat<2> BBt = lifted_.B * lifted_.B.transpose();
  for (Eigen::Index c = 0; c < n; ++c) Q_bar_.push_back(config.accel_std(c) * config.accel_std(c) * BBt);
  channels_.resize(static_cast<size_t>(n));
  reset();
}

void DualRateKf::reset() {
  initialised_.assign(channels_.size(), false);
  for (auto& g : channels_) {
    g.x.setZero();
    g.P.setIdentity();
  }
}

bool DualRateKf::initialised() const {
  for (bool b : initialised_)
    if (!b) return false;
  return true;
}

void DualRateKf::predict() {
  for (size_t c = 0; c < channels_.size(); ++c)
    if (initialised_[c]) timeUpdate(channels_[c], A_bar_, Q_bar_[c]);
}

void DualRateKf::update(const Eigen::VectorXd& s) {
  if (s.size() != channels())
    throw std::invalid_argument("DualRateKf: measurement has " + std::to_string(s.size()) + " entries, expected " +
                                std::to_string(channels()));
  for (size_t c = 0; c < channels_.size(); ++c) {
    const double z = s(static_cast<Eigen::Index>(c));
    if (!isMeasured(z)) continue;
    const double r = config_.measurement_std(static_cast<Eigen::Index>(c));
    if (!initialised_[c]) {
      const double v0 = config_.initial_velocity_std(static_cast<Eigen::Index>(c));
      channels_[c].x << z, 0.0;
      channels_[c].P << r * r, 0.0, 0.0, v0 * v0;
      initialised_[c] = true;
      continue;
    }
    measurementUpdate(channels_[c], z, r * r);
  }
}

Eigen::VectorXd DualRateKf::predictTicks(double i) const {
  Eigen::VectorXd out(channels());
  const double dt = i * config_.base_period_s;
  for (size_t c = 0; c < channels_.size(); ++c)
    out(static_cast<Eigen::Index>(c)) = initialised_[c] ? channels_[c].x(0) + dt * channels_[c].x(1)
                                                        : std::numeric_limits<double>::quiet_NaN();
  return out;
}

Eigen::VectorXd DualRateKf::velocities() const {
  Eigen::VectorXd out(channels());
  for (size_t c = 0; c < channels_.size(); ++c)
    out(static_cast<Eigen::Index>(c)) = initialised_[c] ? channels_[c].x(1) : std::numeric_limits<double>::quiet_NaN();
  return out;
}

}  // namespace predvs
