// predvs — the feature-source interface and its registry.
//
// A feature source delivers, for every acquired frame, the image features of the target's N
// points with a status per point (seen / lost), stamped with the acquisition time. The loop asks
// for a frame at every acquisition tick of the timing model and delays it by the vision latency.
// `geometric` projects the scene's points exactly and adds seeded measurement noise; image
// trackers (vpDot2 blobs, AprilTags on rendered or recorded images) plug in here.
//
// Registry: makeFeatureSource(name, params, context) builds a source by name;
// featureSourceRegistry() lists them (`predvs list`). A new source is one file plus one registry
// line in servo/src/feature_source_registry.cpp.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/predictors/registry.h"
#include "predvs/servo/noise.h"
#include "predvs/servo/prediction_experiment.h"
#include "predvs/servo/scene.h"
#include "predvs/tasks/camera.h"
#include "predvs/tasks/task.h"

#include <visp3/core/vpHomogeneousMatrix.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace predvs {

/// What a source is built with (besides its own parameters).
struct FeatureSourceContext {
  const Scene* scene = nullptr;  ///< outlives the source
  CameraIntrinsics camera;       ///< the true intrinsics
  NoiseConfig noise;             ///< measurement noise (px)
  std::uint64_t seed = 1;
  std::vector<OcclusionInterval> occlusions;  ///< frames acquired in [start_s, end_s) see no point
  double image_width_px = 640.0;   ///< image size (camera.width/height): the rendered-image sources' images
  double image_height_px = 480.0;
};

/// One acquired frame.
struct FeatureFrame {
  double t_acq_s = 0.0;
  PointFeatures points;
};

class FeatureSource {
 public:
  virtual ~FeatureSource() = default;
  virtual std::string name() const = 0;
  /// Number of points N it reports.
  virtual int points() const = 0;
  /// The frame acquired at t_acq with the camera at wMc.
  virtual FeatureFrame acquire(double t_acq_s, const vpHomogeneousMatrix& wMc) = 0;
};

using FeatureSourceInfo = RegistryInfo;

const std::vector<FeatureSourceInfo>& featureSourceRegistry();
bool isFeatureSource(const std::string& name);
/// Builds source `name`. Throws std::invalid_argument "unknown feature source 'x' (known: ...)"
/// or naming the parameter.
std::unique_ptr<FeatureSource> makeFeatureSource(const std::string& name, const Params& params,
                                                 const FeatureSourceContext& context);

}  // namespace predvs
