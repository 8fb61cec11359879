#include "predvs/tasks/vtc_task.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

namespace predvs {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double positive(const Params& params, const std::string& key, double fallback) {
  const double value = params.get(key, fallback);
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "task vtc: parameter '" << key << "' must be > 0, got " << value;
    throw std::invalid_argument(msg.str());
  }
  return value;
}

}  // namespace

VtcTask::VtcTask(const Params& params, const TaskContext& context) : context_(context) {
  if (context.command_space.kind != "unicycle-tilt")
    throw std::invalid_argument("task 'vtc' drives a 'unicycle-tilt' robot, not a '" + context.command_space.kind +
                                "' one (robot)");
  kg_ << positive(params, "kg_x", 0.5), positive(params, "kg_y", 0.75), positive(params, "kg_d", 1.0 / 3.0);

  true_.fx_px = context.camera.px;
  true_.fy_px = context.camera.py;
  true_.width_m = positive(params, "target_width_m", 0.12);
  true_.camera_offset_y_m = params.get("camera_offset_y_m", 0.10, -10.0, 10.0);
  singular_tolerance_ = params.get("singular_tolerance", 0.02, 0.0, 0.999);

  // Parameter errors (paper eq. 43), drawn once per run from the run's seed.
  const double amplitude = params.get("param_error", 0.0, 0.0, 0.9);
  const bool common = params.get("param_error_common", 0.0, 0.0, 1.0) != 0.0;
  double rho[4] = {0.0, 0.0, 0.0, 0.0};
  if (amplitude > 0.0) {
    std::mt19937_64 rng(context.seed);
    std::uniform_real_distribution<double> draw(-amplitude, amplitude);
    for (double& r : rho) r = draw(rng);
    if (common) rho[1] = rho[2] = rho[3] = rho[0];
  }
  const char* keys[4] = {"rho_fx", "rho_fy", "rho_W", "rho_dy"};
  for (int i = 0; i < 4; ++i) rho[i] = params.get(keys[i], rho[i], -0.9, 0.9);
  estimated_.fx_px = true_.fx_px * (1.0 + rho[0]);
  estimated_.fy_px = true_.fy_px * (1.0 + rho[1]);
  estimated_.width_m = true_.width_m * (1.0 + rho[2]);
  estimated_.camera_offset_y_m = true_.camera_offset_y_m * (1.0 + rho[3]);

  const std::string width = params.text("width", "range");
  if (width != "range" && width != "spread")
    throw std::invalid_argument("task vtc: 'width' must be range or spread, got '" + width + "'");
  width_spread_ = width == "spread";
  const std::string source = params.text("desired_source", "params");
  const double dx = params.get("desired_x_px", 0.0, -1e5, 1e5);
  const double dyp = params.get("desired_y_px", 0.0, -1e5, 1e5);
  const double dd = params.get("desired_d_px", 35.0, 0.0, 1e5);
  params.requireAllUsed("task 'vtc'");
  if (source == "params") {
    if (!(dd > 0.0)) throw std::invalid_argument("task vtc: 'desired_d_px' must be > 0");
    desired_ = Eigen::Vector3d(dx, dyp, dd);
  } else if (source == "points") {
    desired_ = features(context.desired_points);
    if (!desired_.allFinite() || !(desired_(2) > 0.0))
      throw std::invalid_argument("task vtc: 'desired_source' points: the desired points are missing or lost");
  } else {
    throw std::invalid_argument("task vtc: 'desired_source' must be params or points, got '" + source + "'");
  }
}

Eigen::VectorXd VtcTask::features(const PointFeatures& points) const {
  const int n = points.points();
  Eigen::VectorXd X = Eigen::Vector3d::Constant(kNaN);
  if (n < 2 || points.uv_px.size() != 2 * n) return X;
  double su = 0.0, sv = 0.0, umin = std::numeric_limits<double>::infinity(), umax = -umin;
  for (int k = 0; k < n; ++k) {
    const double u = points.uv_px(2 * k), v = points.uv_px(2 * k + 1);
    if (!points.seen[static_cast<size_t>(k)] || !std::isfinite(u) || !std::isfinite(v)) return X;
    su += u;
    sv += v;
    umin = std::min(umin, u);
    umax = std::max(umax, u);
  }
  double width = umax - umin;
  if (width_spread_) {
    const double mean_u = su / n;
    double deviation = 0.0;
    for (int k = 0; k < n; ++k) deviation += std::abs(points.uv_px(2 * k) - mean_u);
    width = 2.0 * deviation / n;
  }
  X << su / n - context_.camera.u0, sv / n - context_.camera.v0, width;
  return X;
}

Eigen::Matrix3d VtcTask::robotImageJacobian(const Eigen::Vector3d& X, double tilt_rad, const VtcModel& m) {
  const double s = std::sin(tilt_rad), c = std::cos(tilt_rad), dy = m.camera_offset_y_m;
  const double xi = X(0), yi = X(1), d = X(2);
  const double k = d / (m.fx_px * m.width_m);  // 1 / Z
  const double x = xi / m.fx_px, y = yi / m.fy_px;
  Eigen::Matrix3d B;
  B << xi * c * k, m.fx_px * ((y - dy * k) * s + (1.0 + x * x) * c), xi * (y - dy * k),  //
      m.fy_px * k * (y * c - s), m.fy_px * x * (y * c - s), m.fy_px * (1.0 + y * y - dy * k * y),  //
      d * c * k, d * x * c, d * (y - dy * k);
  return B;
}

double VtcTask::singularityIndicator(const Eigen::Vector3d& X, double tilt_rad, const VtcModel& m) {
  const double Z = m.fx_px * m.width_m / X(2);
  const Eigen::Vector3d PC(X(0) / m.fx_px * Z, X(1) / m.fy_px * Z - m.camera_offset_y_m, Z);  // P - C, camera frame
  return (Z * std::cos(tilt_rad) + PC(1) * std::sin(tilt_rad)) / PC.norm();
}

Eigen::VectorXd VtcTask::computeCommand(const TaskInput& in) {
  if (in.robot_state.size() < 4)
    throw std::invalid_argument("task 'vtc': needs the robot state (x, y, heading, tilt), got " +
                                std::to_string(in.robot_state.size()) + " values (robot)");
  ++ticks_;
  const double tilt = in.robot_state(3);
  Eigen::Vector3d rate = Eigen::Vector3d::Zero();
  if (in.target_rate.size() == 3 && in.target_rate.allFinite()) rate = in.target_rate;

  stopped_ = true;
  lyap_f_ = lyap_bound_ = lyap_f_bar_ = kNaN;
  const bool usable = in.used.size() == 3 && in.used.allFinite() && in.used(2) > 0.0;
  if (!usable) return Eigen::Vector3d::Zero();  // lost target: stop, keep the last B_i

  const Eigen::Vector3d X = in.used;
  B_ = robotImageJacobian(X, tilt, estimated_);
  const Eigen::Vector3d Xe = desired_ - X;
  if (std::abs(singularityIndicator(X, tilt, estimated_)) < singular_tolerance_) return Eigen::Vector3d::Zero();

  const Eigen::Matrix3d B_bar = B_;
  const Eigen::Vector3d u = B_bar.fullPivLu().solve(kg_.asDiagonal() * Xe - rate);
  stopped_ = false;
  ++control_ticks_;

  const Eigen::Matrix3d B_exact = robotImageJacobian(X, tilt, true_);
  lyap_f_bar_ = Xe.dot(rate + B_bar * u);
  const double delta_f = Xe.dot((B_bar - B_exact) * u);
  lyap_f_ = lyap_f_bar_ - delta_f;
  lyap_bound_ = kg_.minCoeff() * Xe.squaredNorm() - delta_f;
  if (lyap_bound_ > 0.0) ++bound_positive_;
  if (lyap_f_ > 0.0) ++f_positive_;
  return u;
}

double VtcTask::trackingError(const Eigen::VectorXd& s) const {
  return std::sqrt((s.head<3>() - desired_).squaredNorm() / 3.0);
}

NamedValues VtcTask::diagnostics() const {
  return {{"lyap_f", lyap_f_}, {"lyap_bound", lyap_bound_}, {"lyap_f_bar", lyap_f_bar_}, {"stopped", stopped_ ? 1.0 : 0.0}};
}

NamedValues VtcTask::runSummary() const {
  const double n = static_cast<double>(control_ticks_);
  return {{"lyap_bound_positive_fraction", control_ticks_ > 0 ? bound_positive_ / n : kNaN},
          {"lyap_f_positive_fraction", control_ticks_ > 0 ? f_positive_ / n : kNaN},
          {"stopped_fraction", ticks_ > 0 ? static_cast<double>(ticks_ - control_ticks_) / ticks_ : kNaN}};
}

}  // namespace predvs
