// predvs tests — a small dual-rate plant for the control laws of paper 003: a free-flying camera
// looking at static points, a camera that acquires a frame every N base periods and delivers it
// `latency_ticks` later, and a law called every base period (as the servo loop calls a task,
// servo/servo_loop.h, with the `hold` predictor: in.used = in.measured = the latest delivered
// frame). The command acts over [t, t + delta) at once (no command lag).
#pragma once

#include "predvs/tasks/task.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <utility>
#include <vector>

namespace predvs {
namespace testing_plant {

/// Points in the camera frame (m); a twist (v, w) moves them as dP/dt = -v - w x P, integrated in
/// substeps that are each an exact rigid motion, so the point set never deforms.
struct FreeCamera {
  CameraIntrinsics camera;
  std::vector<Eigen::Vector3d> P;

  PointFeatures features() const {
    PointFeatures f;
    const Eigen::Index n = static_cast<Eigen::Index>(P.size());
    f.uv_px.resize(2 * n);
    f.Z_m.resize(n);
    f.seen.assign(P.size(), true);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector3d& p = P[static_cast<size_t>(i)];
      f.uv_px(2 * i) = camera.u0 + camera.px * p.x() / p.z();
      f.uv_px(2 * i + 1) = camera.v0 + camera.py * p.y() / p.z();
      f.Z_m(i) = p.z();
    }
    return f;
  }
  double minDepth() const {
    double z = std::numeric_limits<double>::infinity();
    for (const auto& p : P) z = std::min(z, p.z());
    return z;
  }
  void apply(const Eigen::VectorXd& twist, double dt, int substeps = 4) {
    const Eigen::Vector3d v = twist.head<3>(), w = twist.tail<3>();
    const double h = dt / substeps;
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    if (w.norm() > 0.0) R = Eigen::AngleAxisd(-h * w.norm(), w.normalized()).toRotationMatrix();
    for (int k = 0; k < substeps; ++k)
      for (auto& p : P) p = R * p - h * v;
  }
};

/// The corners of a square of side `side_m`, centred on the optical axis at depth Z_m, seen from
/// a camera rotated by `angle_rad` about its optical axis from the pose where the square's edges
/// are aligned with the image axes.
inline std::vector<Eigen::Vector3d> rotatedSquare(double side_m, double Z_m, double angle_rad) {
  const double a = side_m / 2;
  // A camera rotated by +angle sees the points rotated by -angle.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3d> P;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(-a, -a, Z_m), Eigen::Vector3d(a, -a, Z_m),
                                   Eigen::Vector3d(a, a, Z_m), Eigen::Vector3d(-a, a, Z_m)})
    P.push_back(R * p);
  return P;
}

struct PlantTiming {
  double delta_s = 0.01;   ///< base period
  int frame_ticks = 8;     ///< N
  int latency_ticks = 8;   ///< acquisition to delivery (one frame: N)
};

struct RunOutcome {
  std::vector<double> error_px;  ///< RMS over points of the pixel error, per tick
  double peak_command = 0.0;     ///< max |u|
  double min_depth_m = std::numeric_limits<double>::infinity();
  bool crossed = false;          ///< a point reached the camera plane (the run stopped there)
  double final_error_px() const { return error_px.empty() ? std::numeric_limits<double>::quiet_NaN() : error_px.back(); }
  /// First time after which the error stays below `tol_px`, NaN if it never does.
  double convergenceTime(double tol_px, double delta_s) const {
    if (crossed || error_px.empty() || !(error_px.back() < tol_px)) return std::numeric_limits<double>::quiet_NaN();
    size_t k = error_px.size();
    while (k > 0 && error_px[k - 1] < tol_px) --k;
    return static_cast<double>(k) * delta_s;
  }
};

/// The context a task is built with for this plant (desired = the points at `desired`).
inline TaskContext makeContext(const FreeCamera& desired, const PlantTiming& timing,
                               CommandSpace space = {"camera-twist", {"vx", "vy", "vz", "wx", "wy", "wz"}}) {
  TaskContext c;
  c.camera = desired.camera;
  c.desired_points = desired.features();
  c.command_space = std::move(space);
  c.base_period_s = timing.delta_s;
  c.frame_period_s = timing.frame_ticks * timing.delta_s;
  c.nominal_delay_frames = static_cast<double>(timing.latency_ticks) / timing.frame_ticks;
  return c;
}

/// Runs `task` on `plant` for `duration_s`; `task.trackingError` of the true features is the error.
/// The command u moves the camera with the twist robot_jacobian u (6 x m; identity: the
/// free-flying camera; a constant invertible matrix stands in for an arm's Jacobian). The run
/// stops when a point comes within min_depth_m of the camera plane (the camera went through the
/// object plane) or the command is not finite.
inline RunOutcome run(Task& task, FreeCamera plant, const PlantTiming& timing, double duration_s,
                      const Eigen::MatrixXd& robot_jacobian = Eigen::MatrixXd::Identity(6, 6),
                      double min_depth_m = 0.01) {
  struct Frame {
    long release;
    double t_acq;
    PointFeatures f;
  };
  RunOutcome out;
  std::deque<Frame> pending;
  bool have = false;
  double t_acq = 0.0;
  Eigen::VectorXd measured, depths;
  const Eigen::Index m = robot_jacobian.cols();
  const Eigen::VectorXd state = Eigen::VectorXd::Zero(m), no_rate;
  const Eigen::MatrixXd no_truth;
  const long ticks = std::lround(duration_s / timing.delta_s);
  for (long k = 0; k < ticks; ++k) {
    const double t = k * timing.delta_s;
    const PointFeatures truth = plant.features();
    out.error_px.push_back(task.trackingError(truth.uv_px));
    if (k % timing.frame_ticks == 0) pending.push_back({k + timing.latency_ticks, t, truth});
    while (!pending.empty() && pending.front().release <= k) {
      measured = pending.front().f.uv_px;
      depths = pending.front().f.Z_m;
      t_acq = pending.front().t_acq;
      have = true;
      pending.pop_front();
    }
    Eigen::VectorXd u = Eigen::VectorXd::Zero(m);
    if (have) {
      const TaskInput in{t, t_acq, measured, measured, no_rate, depths, robot_jacobian, state, no_truth};
      u = task.computeCommand(in);
    }
    out.peak_command = std::max(out.peak_command, u.norm());
    plant.apply(robot_jacobian * u, timing.delta_s);
    out.min_depth_m = std::min(out.min_depth_m, plant.minDepth());
    if (!(plant.minDepth() > min_depth_m) || !u.allFinite()) {
      out.crossed = true;
      out.error_px.push_back(std::numeric_limits<double>::infinity());
      break;
    }
  }
  return out;
}

}  // namespace testing_plant
}  // namespace predvs
