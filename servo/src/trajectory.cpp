#include "predvs/servo/trajectory.h"

#include "trajectory_params.h"

#include <cmath>
#include <complex>
#include <functional>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

using detail::finiteParam;
using detail::positiveParam;

/// A manoeuvre at t_s along `change` (none when the change is zero).
Manoeuvre manoeuvreAlong(double t_s, const Eigen::Vector2d& change) {
  Manoeuvre m;
  if (change.norm() == 0.0) return m;
  m.t_s = t_s;
  m.direction = change.normalized();
  return m;
}

class StaticTrajectory : public Trajectory {
 public:
  explicit StaticTrajectory(const Params& p) : p0_(finiteParam(p, "static", "x0", 0), finiteParam(p, "static", "y0", 0)) {}
  std::string name() const override { return "static"; }
  Eigen::Vector2d position(double) const override { return p0_; }
  Eigen::Vector2d velocity(double) const override { return Eigen::Vector2d::Zero(); }

 private:
  Eigen::Vector2d p0_;
};

class LineTrajectory : public Trajectory {
 public:
  explicit LineTrajectory(const Params& p)
      : p0_(finiteParam(p, "line", "x0", 0), finiteParam(p, "line", "y0", 0)),
        v_(finiteParam(p, "line", "vx", 10), finiteParam(p, "line", "vy", 10)) {}
  std::string name() const override { return "line"; }
  Eigen::Vector2d position(double t) const override { return p0_ + v_ * t; }
  Eigen::Vector2d velocity(double) const override { return v_; }
  Manoeuvre manoeuvre() const override { return manoeuvreAlong(0.0, v_); }

 private:
  Eigen::Vector2d p0_, v_;
};

class AccelJumpTrajectory : public Trajectory {
 public:
  explicit AccelJumpTrajectory(const Params& p)
      : p0_(finiteParam(p, "accel-jump", "x0", 0), finiteParam(p, "accel-jump", "y0", 0)),
        v0_(finiteParam(p, "accel-jump", "vx", 20), finiteParam(p, "accel-jump", "vy", 20)),
        a0_(finiteParam(p, "accel-jump", "ax", 1), finiteParam(p, "accel-jump", "ay", 1)),
        t_jump_(positiveParam(p, "accel-jump", "t_jump", 14)),
        a1_(finiteParam(p, "accel-jump", "ax_jump", 30), finiteParam(p, "accel-jump", "ay_jump", 30)) {}
  std::string name() const override { return "accel-jump"; }
  Eigen::Vector2d position(double t) const override {
    if (t < t_jump_) return p0_ + v0_ * t + 0.5 * a0_ * t * t;
    const double s = t - t_jump_;
    return position1() + velocity1() * s + 0.5 * a1_ * s * s;
  }
  Eigen::Vector2d velocity(double t) const override {
    if (t < t_jump_) return v0_ + a0_ * t;
    return velocity1() + a1_ * (t - t_jump_);
  }
  Manoeuvre manoeuvre() const override { return manoeuvreAlong(t_jump_, a1_ - a0_); }

 private:
  Eigen::Vector2d position1() const { return p0_ + v0_ * t_jump_ + 0.5 * a0_ * t_jump_ * t_jump_; }
  Eigen::Vector2d velocity1() const { return v0_ + a0_ * t_jump_; }
  Eigen::Vector2d p0_, v0_, a0_;
  double t_jump_;
  Eigen::Vector2d a1_;
};

class ZigzagTrajectory : public Trajectory {
 public:
  explicit ZigzagTrajectory(const Params& p)
      : p0_(finiteParam(p, "zigzag", "x0", 0), finiteParam(p, "zigzag", "y0", 0)),
        vx_(finiteParam(p, "zigzag", "vx", 1)),
        vy_(finiteParam(p, "zigzag", "vy", 10)),
        t_switch_(positiveParam(p, "zigzag", "t_switch", 9)),
        periodic_(finiteParam(p, "zigzag", "periodic", 0) != 0.0) {}
  std::string name() const override { return "zigzag"; }
  Eigen::Vector2d position(double t) const override { return {p0_.x() + vx_ * t, p0_.y() + yOffset(t)}; }
  Eigen::Vector2d velocity(double t) const override { return {vx_, vy_ * sign(t)}; }
  Manoeuvre manoeuvre() const override { return manoeuvreAlong(t_switch_, {0.0, -vy_}); }

 private:
  // Sign of v_y on the segment containing t (right-continuous at the switches).
  double sign(double t) const {
    if (t < t_switch_) return 1.0;
    if (!periodic_) return -1.0;
    const long seg = static_cast<long>(std::floor(t / t_switch_));
    return seg % 2 == 0 ? 1.0 : -1.0;
  }
  // Integral of v_y from 0 to t.
  double yOffset(double t) const {
    if (t <= t_switch_) return vy_ * t;
    if (!periodic_) return vy_ * t_switch_ - vy_ * (t - t_switch_);
    const long seg = static_cast<long>(std::floor(t / t_switch_));
    const double base = (seg % 2 == 0) ? 0.0 : vy_ * t_switch_;  // triangle: 0 at even, peak at odd
    return base + sign(t) * vy_ * (t - seg * t_switch_);
  }
  Eigen::Vector2d p0_;
  double vx_, vy_, t_switch_;
  bool periodic_;
};

class CircleTrajectory : public Trajectory {
 public:
  explicit CircleTrajectory(const Params& p)
      : c_(finiteParam(p, "circle", "cx", 0), finiteParam(p, "circle", "cy", 0)),
        r_(finiteParam(p, "circle", "radius", 20)),
        w_(finiteParam(p, "circle", "omega", 0.15)),
        phi_(finiteParam(p, "circle", "phase", 0)) {
    if (r_ < 0.0) throw std::invalid_argument("trajectory 'circle': parameter 'radius' must be >= 0, got " + std::to_string(r_));
  }
  std::string name() const override { return "circle"; }
  Eigen::Vector2d position(double t) const override {
    const double a = w_ * t + phi_;
    return c_ + r_ * Eigen::Vector2d(std::cos(a), std::sin(a));
  }
  Eigen::Vector2d velocity(double t) const override {
    const double a = w_ * t + phi_;
    return r_ * w_ * Eigen::Vector2d(-std::sin(a), std::cos(a));
  }

 private:
  Eigen::Vector2d c_;
  double r_, w_, phi_;
};

class SinusoidTrajectory : public Trajectory {
 public:
  explicit SinusoidTrajectory(const Params& p)
      : p0_(finiteParam(p, "sinusoid", "x0", 0), finiteParam(p, "sinusoid", "y0", 0)),
        amp_(finiteParam(p, "sinusoid", "amp_x", 20), finiteParam(p, "sinusoid", "amp_y", 20)),
        w_(kTwoPi * finiteParam(p, "sinusoid", "freq_x", 0.1), kTwoPi * finiteParam(p, "sinusoid", "freq_y", 0.15)),
        phi_(finiteParam(p, "sinusoid", "phase_x", 0), finiteParam(p, "sinusoid", "phase_y", 0)) {}
  std::string name() const override { return "sinusoid"; }
  Eigen::Vector2d position(double t) const override {
    return p0_ + Eigen::Vector2d(amp_.x() * std::sin(w_.x() * t + phi_.x()), amp_.y() * std::sin(w_.y() * t + phi_.y()));
  }
  Eigen::Vector2d velocity(double t) const override {
    return {amp_.x() * w_.x() * std::cos(w_.x() * t + phi_.x()), amp_.y() * w_.y() * std::cos(w_.y() * t + phi_.y())};
  }

 private:
  Eigen::Vector2d p0_, amp_, w_, phi_;
};

/// Paper 001's eq. 44 target motion in the plane (header: e8-target).
class E8Target : public Trajectory {
 public:
  explicit E8Target(const Params& p)
      : p0_(finiteParam(p, "e8-target", "x0", 0), finiteParam(p, "e8-target", "y0", 0)),
        v0_(finiteParam(p, "e8-target", "v0", 0.15)),
        speed_omega_(finiteParam(p, "e8-target", "speed_omega", kPi / 20.0)),
        turn_rate_(finiteParam(p, "e8-target", "turn_rate", 5.0 * kPi / 72.0)),
        heading_(finiteParam(p, "e8-target", "heading", 0.0)) {}
  std::string name() const override { return "e8-target"; }
  Eigen::Vector2d position(double t) const override {
    using C = std::complex<double>;
    const C d = v0_ * std::polar(1.0, heading_) *
                (integralOfPhase(turn_rate_ + speed_omega_, t) + integralOfPhase(turn_rate_ - speed_omega_, t)) / 2.0;
    return p0_ + Eigen::Vector2d(d.real(), d.imag());
  }
  Eigen::Vector2d velocity(double t) const override {
    const double speed = v0_ * std::cos(speed_omega_ * t), th = heading_ + turn_rate_ * t;
    return speed * Eigen::Vector2d(std::cos(th), std::sin(th));
  }

 private:
  // E(c, t) = integral_0^t e^{i c s} ds = t e^{i c t / 2} sinc(c t / 2), exact at c = 0.
  static std::complex<double> integralOfPhase(double c, double t) {
    const double half = c * t / 2.0;
    const double sinc = std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : std::sin(half) / half;
    return t * sinc * std::polar(1.0, half);
  }
  Eigen::Vector2d p0_;
  double v0_, speed_omega_, turn_rate_, heading_;
};

using Factory = std::function<std::unique_ptr<Trajectory>(const Params&)>;

template <class T>
Factory factory() {
  return [](const Params& p) { return std::make_unique<T>(p); };
}

const std::vector<std::pair<std::string, Factory>>& entries() {
  static const std::vector<std::pair<std::string, Factory>> table = {
      {"static", factory<StaticTrajectory>()},     {"line", factory<LineTrajectory>()},
      {"accel-jump", factory<AccelJumpTrajectory>()}, {"zigzag", factory<ZigzagTrajectory>()},
      {"circle", factory<CircleTrajectory>()},     {"sinusoid", factory<SinusoidTrajectory>()},
      {"e8-target", factory<E8Target>()},
  };
  return table;
}

}  // namespace

const std::vector<std::string>& trajectoryNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& e : entries()) out.push_back(e.first);
    return out;
  }();
  return names;
}

std::unique_ptr<Trajectory> makeTrajectory(const std::string& name, const Params& params) {
  for (const auto& e : entries()) {
    if (e.first != name) continue;
    auto t = e.second(params);
    params.requireAllUsed("trajectory '" + name + "'");
    return t;
  }
  std::string known;
  for (const auto& e : entries()) known += (known.empty() ? "" : ", ") + e.first;
  throw std::invalid_argument("unknown trajectory '" + name + "' (known: " + known + ")");
}

}  // namespace predvs
