// predvs — `geometric`: features from the scene's geometry (no image).
//
// Every acquired frame is the exact pinhole projection of the target's N points (Scene::project)
// plus seeded measurement noise on each coordinate, drawn in the order u_0, v_0, u_1, v_1, ...
// (NoiseModel). Depths are the true ones (depth assumed known, as in ViSP's simulated IBVS
// tutorials). A point behind the camera, or any frame inside an occlusion window, is lost
// (status false, NaN features); no noise is drawn for a lost point.
#pragma once

#include "predvs/servo/feature_source.h"

namespace predvs {

class GeometricSource : public FeatureSource {
 public:
  /// No parameters of its own (unknown keys are rejected).
  GeometricSource(const Params& params, const FeatureSourceContext& context);
  std::string name() const override { return "geometric"; }
  int points() const override { return scene_.points(); }
  FeatureFrame acquire(double t_acq_s, const vpHomogeneousMatrix& wMc) override;

 private:
  const Scene& scene_;
  CameraIntrinsics camera_;
  NoiseModel noise_;
  std::vector<OcclusionInterval> occlusions_;
};

}  // namespace predvs
