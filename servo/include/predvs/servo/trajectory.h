// predvs — 2D target trajectories: position and velocity at any time t (docs/MODELS.md §10, E1–E4, E8, E9).
//
// Unit-agnostic: the same trajectory describes a target in pixels (open-loop prediction, E1–E4)
// or the in-plane translation of the target in metres (closed loop). Every trajectory is built by
// name from predvs::Params; unknown keys are rejected (Params::requireAllUsed). Time in seconds,
// positions in "units", velocities in units/s, frequencies in Hz, angular rates in rad/s.
//
// Names, keys and defaults (defaults are the papers' values where the paper gives one):
//   static      x0 = 0, y0 = 0                          p(t) = (x0, y0)
//   line        x0 = 0, y0 = 0, vx = 10, vy = 10        p(t) = p0 + v t              (E1, paper 000 §6.1)
//   accel-jump  x0 = 0, y0 = 0, vx = 20, vy = 20, ax = 1, ay = 1, t_jump = 14, ax_jump = 30,
//               ay_jump = 30                             constant acceleration a before t_jump and
//               a_jump after it, position and velocity continuous at t_jump (E2, paper 000 §6.1:
//               "the accelerations change to 30 after 14 s")
//   zigzag      x0 = 0, y0 = 0, vx = 1, vy = 10, t_switch = 9, periodic = 0
//               p_x = x0 + vx t; v_y = vy before t_switch and -vy after it (E3). With periodic = 1
//               the sign of v_y flips every t_switch seconds (a triangle wave).
//   circle      cx = 0, cy = 0, radius = 20, omega = 0.15, phase = 0
//               p(t) = c + r (cos(omega t + phase), sin(omega t + phase))  (E4, paper 000 §6.2)
//   sinusoid    x0 = 0, y0 = 0, amp_x = 20, amp_y = 20, freq_x = 0.1, freq_y = 0.15,
//               phase_x = 0, phase_y = 0
//               p_i(t) = i0 + amp_i sin(2 pi freq_i t + phase_i)  (E9: different x/y frequencies)
//   e8-target   x0 = 0, y0 = 0, v0 = 0.15, speed_omega = pi / 20, turn_rate = 5 pi / 72, heading = 0
//               paper 001's eq. 44 target motion in the plane (E8, paper 001 §5.1, §5.3), in metres
//               by its defaults: speed v(t) = v0 cos(speed_omega t) (m/s; it reverses after
//               pi / (2 speed_omega) = 10 s), heading th(t) = heading + turn_rate t (rad, 0 = +x,
//               positive turns LEFT, counter-clockwise seen from +z):
//                   p'(t) = v(t) (cos th(t), sin th(t)),
//               integrated exactly (closed form below). Frames: the paper writes the target's
//               velocity as (v sin th, 0, v cos th) in its world frame x left, y up, z forward (the
//               robot's heading at t = 0, its appendix eq. A.1 and eq. 1); in the predvs world frame
//               (x forward, y left, z up, servo/robot.h) that is v (cos th, sin th, 0): the paper's
//               target turns towards its +x, i.e. to the left of a robot looking along +z.
//               Continuous time: the paper updates v and th once per frame, v(n) = v0 cos(n pi T / 20),
//               th(n) = th(n-1) + T 5 pi / 72, and integrates P(n) = P(n-1) + T V(n-1) (Euler); the
//               curve here takes the same v and th at t = n T and integrates them exactly, so the
//               motion is smooth (the velocity is the derivative everywhere). The paper's Euler
//               samples trail it by about half a frame (under 1 cm over 20 s at T = 0.1 s, see
//               tests/servo/trajectory_test.cpp).
//               Closed form, with a = speed_omega, b = turn_rate and complex positions x + i y:
//                   p(t) = p0 + v0 e^{i heading} (E(b + a, t) + E(b - a, t)) / 2,
//                   E(c, t) = integral_0^t e^{i c s} ds = t e^{i c t / 2} sinc(c t / 2).
#pragma once

#include "predvs/predictors/params.h"

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace predvs {

/// A sudden change of the motion: when it happens and the unit direction of the change (of the
/// velocity for a velocity step, of the acceleration for an acceleration step). A predictor that
/// lags behind the change has an error pointing against `direction`; one that overshoots, along
/// it (metrics.h, computeResponse). No manoeuvre: t_s is NaN.
struct Manoeuvre {
  double t_s = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd direction;
  bool exists() const { return std::isfinite(t_s); }
};

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  /// Registry name, e.g. "circle".
  virtual std::string name() const = 0;
  /// Position at t_s.
  virtual Eigen::Vector2d position(double t_s) const = 0;
  /// Exact time derivative of position() at t_s (right derivative at a switching instant).
  virtual Eigen::Vector2d velocity(double t_s) const = 0;
  /// The trajectory's manoeuvre (line: the start from rest at t = 0 along v; accel-jump: t_jump
  /// along a_jump - a; zigzag: the first switch along -v_y). None for the others: on a circle or a
  /// sinusoid the direction of motion turns, so no fixed direction tells lag from overshoot.
  virtual Manoeuvre manoeuvre() const { return {}; }
};

/// Names accepted by makeTrajectory, in display order.
const std::vector<std::string>& trajectoryNames();
/// Builds trajectory `name` from `params` (keys above; absent keys take the defaults). Throws
/// std::invalid_argument for an unknown name ("unknown trajectory 'x' (known: ...)"), an unknown
/// key ("unknown parameter 'k' for trajectory 'circle'") or an out-of-range value (e.g. negative
/// radius, t_switch <= 0).
std::unique_ptr<Trajectory> makeTrajectory(const std::string& name, const Params& params = {});

}  // namespace predvs
