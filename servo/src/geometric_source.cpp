#include "predvs/servo/geometric_source.h"

#include <limits>
#include <stdexcept>

namespace predvs {
namespace {
const Scene& requireScene(const FeatureSourceContext& c) {
  if (!c.scene) throw std::invalid_argument("feature source: no scene");
  return *c.scene;
}
}  // namespace

GeometricSource::GeometricSource(const Params& params, const FeatureSourceContext& context)
    : scene_(requireScene(context)),
      camera_(context.camera),
      noise_(context.noise, context.seed),
      occlusions_(context.occlusions) {
  params.requireAllUsed("feature source 'geometric'");
}

FeatureFrame GeometricSource::acquire(double t_acq_s, const vpHomogeneousMatrix& wMc) {
  FeatureFrame f;
  f.t_acq_s = t_acq_s;
  f.points = scene_.project(t_acq_s, wMc, camera_);
  bool hidden = false;
  for (const auto& o : occlusions_) hidden = hidden || (t_acq_s >= o.start_s && t_acq_s < o.end_s);
  for (int i = 0; i < f.points.points(); ++i) {
    if (hidden) f.points.seen[static_cast<size_t>(i)] = false;
    if (!f.points.seen[static_cast<size_t>(i)]) {
      f.points.uv_px(2 * i) = f.points.uv_px(2 * i + 1) = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    f.points.uv_px(2 * i) = noise_.apply(f.points.uv_px(2 * i));
    f.points.uv_px(2 * i + 1) = noise_.apply(f.points.uv_px(2 * i + 1));
  }
  return f;
}

}  // namespace predvs
