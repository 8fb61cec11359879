#include "predvs/servo/paper_trajectories.h"

#include "trajectory_params.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kPi = 3.14159265358979323846;

using detail::finiteParam;
using detail::positiveParam;

/// A planar Trajectory seen as 2 channels (x, y).
class PlanarChannels : public ChannelTrajectory {
 public:
  explicit PlanarChannels(std::unique_ptr<Trajectory> t) : t_(std::move(t)) {}
  std::string name() const override { return t_->name(); }
  const std::vector<std::string>& channelNames() const override {
    static const std::vector<std::string> names = {"x", "y"};
    return names;
  }
  Eigen::VectorXd position(double t_s) const override { return t_->position(t_s); }
  Eigen::VectorXd velocity(double t_s) const override { return t_->velocity(t_s); }
  Manoeuvre manoeuvre() const override { return t_->manoeuvre(); }

 private:
  std::unique_ptr<Trajectory> t_;
};

class OnsetSinusoid : public ChannelTrajectory {
 public:
  explicit OnsetSinusoid(const Params& p)
      : x0_(finiteParam(p, "onset-sinusoid", "x0", 0.0)),
        amplitude_(finiteParam(p, "onset-sinusoid", "amplitude", 2000.0)),
        period_s_(positiveParam(p, "onset-sinusoid", "period", 3.0)),
        t_start_s_(finiteParam(p, "onset-sinusoid", "t_start", 1.0)) {}
  std::string name() const override { return "onset-sinusoid"; }
  const std::vector<std::string>& channelNames() const override {
    static const std::vector<std::string> names = {"x"};
    return names;
  }
  Eigen::VectorXd position(double t) const override {
    Eigen::VectorXd x(1);
    x(0) = t < t_start_s_ ? x0_ : x0_ + amplitude_ * std::sin(2.0 * kPi * (t - t_start_s_) / period_s_);
    return x;
  }
  Eigen::VectorXd velocity(double t) const override {
    const double w = 2.0 * kPi / period_s_;
    Eigen::VectorXd v(1);
    v(0) = t < t_start_s_ ? 0.0 : amplitude_ * w * std::cos(w * (t - t_start_s_));
    return v;
  }
  double onsetTime() const override { return t_start_s_; }
  Manoeuvre manoeuvre() const override {
    Manoeuvre m;
    if (amplitude_ == 0.0) return m;
    m.t_s = t_start_s_;
    m.direction = Eigen::VectorXd::Constant(1, amplitude_ > 0.0 ? 1.0 : -1.0);
    return m;
  }

 private:
  double x0_, amplitude_, period_s_, t_start_s_;
};

E6TargetConfig e6ConfigFrom(const Params& p) {
  const std::string n = "e6-target";
  E6TargetConfig c;
  c.period_s = positiveParam(p, n, "period_s", c.period_s);
  c.fx_px = positiveParam(p, n, "fx", c.fx_px);
  c.fy_px = positiveParam(p, n, "fy", c.fy_px);
  c.width_cm = positiveParam(p, n, "width_cm", c.width_cm);
  c.v0_cm_s = finiteParam(p, n, "v0_cm_s", c.v0_cm_s);
  c.turn_rate_rad_s = finiteParam(p, n, "turn_rate_rad_s", c.turn_rate_rad_s);
  c.x0_cm = finiteParam(p, n, "x0_cm", c.x0_cm);
  c.y0_cm = finiteParam(p, n, "y0_cm", c.y0_cm);
  c.z0_cm = positiveParam(p, n, "z0_cm", c.fx_px * c.width_cm / 35.0);
  return c;
}

}  // namespace

double ChannelTrajectory::onsetTime() const { return std::numeric_limits<double>::quiet_NaN(); }

E6TargetTrajectory::E6TargetTrajectory(const E6TargetConfig& c) : config_(c) {
  for (const auto& kv : {std::make_pair("period_s", c.period_s), std::make_pair("fx", c.fx_px),
                         std::make_pair("fy", c.fy_px), std::make_pair("width_cm", c.width_cm),
                         std::make_pair("z0_cm", c.z0_cm)})
    if (!(kv.second > 0.0) || !std::isfinite(kv.second))
      throw std::invalid_argument(std::string("trajectory 'e6-target': parameter '") + kv.first + "' must be > 0");
  P_cm_.emplace_back(c.x0_cm, c.y0_cm, c.z0_cm);
}

const std::vector<std::string>& E6TargetTrajectory::channelNames() const {
  static const std::vector<std::string> names = {"x_i", "y_i", "d_x"};
  return names;
}

size_t E6TargetTrajectory::segment(double t_s) const {
  const double T = config_.period_s;
  // 1e-9 relative tolerance so that t = n T computed as n * T lands on sample n.
  const double k = std::floor(t_s / T + 1e-9);
  const size_t n = k <= 0.0 ? 0 : static_cast<size_t>(k);
  while (V_cm_s_.size() <= n) {
    const size_t m = V_cm_s_.size();  // computing V(m), then P(m + 1)
    const double speed = config_.v0_cm_s * std::cos(static_cast<double>(m) * kPi * T / 20.0);
    V_cm_s_.emplace_back(-speed * std::sin(heading_rad_), 0.0, speed * std::cos(heading_rad_));  // x right: the paper's x is left
    P_cm_.push_back(P_cm_[m] + T * V_cm_s_[m]);
    heading_rad_ += T * config_.turn_rate_rad_s;
  }
  return n;
}

Eigen::Vector3d E6TargetTrajectory::targetPositionCm(double t_s) const {
  const size_t n = segment(t_s);
  return P_cm_[n] + (t_s - static_cast<double>(n) * config_.period_s) * V_cm_s_[n];
}

Eigen::Vector3d E6TargetTrajectory::targetVelocityCmS(double t_s) const { return V_cm_s_[segment(t_s)]; }

Eigen::VectorXd E6TargetTrajectory::position(double t_s) const {
  const Eigen::Vector3d P = targetPositionCm(t_s);
  Eigen::VectorXd X(3);
  X << config_.fx_px * P.x() / P.z(), config_.fy_px * P.y() / P.z(), config_.fx_px * config_.width_cm / P.z();
  return X;
}

Eigen::VectorXd E6TargetTrajectory::velocity(double t_s) const {
  const Eigen::Vector3d P = targetPositionCm(t_s), V = targetVelocityCmS(t_s);
  const double Z2 = P.z() * P.z();
  Eigen::VectorXd Xdot(3);
  Xdot << config_.fx_px * (V.x() * P.z() - P.x() * V.z()) / Z2, config_.fy_px * (V.y() * P.z() - P.y() * V.z()) / Z2,
      -config_.fx_px * config_.width_cm * V.z() / Z2;
  return Xdot;
}

std::vector<std::string> channelTrajectoryNames() {
  std::vector<std::string> names = {"e6-target", "onset-sinusoid"};
  for (const auto& n : trajectoryNames()) names.push_back(n);
  return names;
}

std::unique_ptr<ChannelTrajectory> makeChannelTrajectory(const std::string& name, const Params& params) {
  std::unique_ptr<ChannelTrajectory> t;
  if (name == "e6-target") {
    t = std::make_unique<E6TargetTrajectory>(e6ConfigFrom(params));
  } else if (name == "onset-sinusoid") {
    t = std::make_unique<OnsetSinusoid>(params);
  } else {
    bool planar = false;
    for (const auto& n : trajectoryNames()) planar = planar || n == name;
    if (!planar) {
      std::string known;
      for (const auto& n : channelTrajectoryNames()) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown trajectory '" + name + "' (known: " + known + ")");
    }
    return std::make_unique<PlanarChannels>(makeTrajectory(name, params));
  }
  params.requireAllUsed("trajectory '" + name + "'");
  return t;
}

}  // namespace predvs
