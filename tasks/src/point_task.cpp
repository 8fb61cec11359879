#include "predvs/tasks/point_task.h"

#include <cmath>
#include <stdexcept>

namespace predvs {

PointTask::PointTask(const TaskContext& context) : context_(context), desired_(context.desired_points.uv_px) {
  const int n = context.desired_points.points();
  if (n < 1 || desired_.size() != 2 * n)
    throw std::invalid_argument("task: the desired features have " + std::to_string(desired_.size()) + " entries for " +
                                std::to_string(n) + " points (expected 2 per point, at least one point)");
  if (!desired_.allFinite()) throw std::invalid_argument("task: a desired point is not seen from the desired pose");
}

std::vector<std::string> PointTask::featureNames() const {
  std::vector<std::string> names;
  for (Eigen::Index i = 0; i < desired_.size() / 2; ++i) {
    names.push_back("u" + std::to_string(i));
    names.push_back("v" + std::to_string(i));
  }
  return names;
}

Eigen::MatrixXd PointTask::pixelInteraction(const Eigen::VectorXd& s_px, const Eigen::VectorXd& Z_m,
                                            const CameraIntrinsics& camera) {
  const Eigen::Index n = Z_m.size();
  Eigen::MatrixXd L(2 * n, 6);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = (s_px(2 * i) - camera.u0) / camera.px, y = (s_px(2 * i + 1) - camera.v0) / camera.py;
    const double Z = Z_m(i);
    L.row(2 * i) << -camera.px / Z, 0.0, camera.px * x / Z, camera.px * x * y, -camera.px * (1.0 + x * x), camera.px * y;
    L.row(2 * i + 1) << 0.0, -camera.py / Z, camera.py * y / Z, camera.py * (1.0 + y * y), -camera.py * x * y,
        -camera.py * x;
  }
  return L;
}

double Task::trackingError(const Eigen::VectorXd& s) const {
  const Eigen::VectorXd& sd = desiredFeatures();
  const Eigen::Index pairs = sd.size() / 2;
  double sum = 0.0;
  for (Eigen::Index i = 0; i < pairs; ++i) sum += (s.segment<2>(2 * i) - sd.segment<2>(2 * i)).squaredNorm();
  return std::sqrt(sum / static_cast<double>(pairs));
}

}  // namespace predvs
