// predvs — image trackers: from an image to the N point features, and their registry.
//
// A tracker turns each grey image into the pixel positions of N points with a status per point.
// It is the image-processing half of an image feature source: `predvs track` runs one on a
// recorded sequence; the `dots` and `apriltag` feature sources of the closed loop run one on
// images rendered from the scene. Trackers:
//   - `dots`: vpDot2 blobs, initialised automatically (no clicks) and then tracked frame to frame;
//   - `apriltag`: vpDetectorAprilTag; per tag, its 4 corners then its centre (5 points per tag),
//     tags in increasing id order; with the camera and the tag size known, the tag's pose too.
// N is fixed at initialisation (the first frame, or the `points`/`ids` parameters). A point the
// tracker cannot find is lost (seen = false, NaN pixels): a status, never an exception; the
// tracker tries to re-acquire it on later frames.
//
// Registry: makeImageTracker(name, params, context); imageTrackerRegistry() lists them
// (`predvs list`). A new tracker is one file plus one line in servo/src/image_tracker_registry.cpp.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/predictors/registry.h"
#include "predvs/tasks/camera.h"
#include "predvs/tasks/task.h"

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImage.h>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace predvs {

/// What a tracker is built with (besides its own parameters).
struct ImageTrackerContext {
  CameraIntrinsics camera;     ///< intrinsics of the images
  bool camera_known = false;   ///< true when `camera` is the real one (pose estimation possible)
};

/// The tracker's answer for one image.
struct TrackedPoints {
  PointFeatures points;      ///< N points: pixels (NaN when lost), Z_m (NaN unless a pose gives it), seen
  bool pose_valid = false;   ///< cMo below is an estimate (apriltag with camera and tag size)
  vpHomogeneousMatrix cMo;   ///< object (first tag) pose in the camera frame
  std::string note;          ///< why points were lost, for logs ("dot 3 lost", "no tag found")
};

class ImageTracker {
 public:
  virtual ~ImageTracker() = default;
  virtual std::string name() const = 0;
  /// N; 0 until initialised.
  virtual int points() const = 0;
  /// Labels of the N points ("dot0", "tag8.c0" ... "tag8.centre"), for tracks and plots.
  virtual std::vector<std::string> pointNames() const = 0;
  /// Tracks one image. `hint` (optional, 2N pixels, NaN where unknown) is where the points are
  /// expected: it orders the points at initialisation and guides re-acquisition. Without it the
  /// tracker orders the points itself (documented per tracker).
  virtual TrackedPoints track(const vpImage<unsigned char>& image, const Eigen::VectorXd* hint = nullptr) = 0;
  /// Forgets every point: the next image initialises again.
  virtual void reset() = 0;
};

using ImageTrackerInfo = RegistryInfo;

const std::vector<ImageTrackerInfo>& imageTrackerRegistry();
bool isImageTracker(const std::string& name);
/// Builds tracker `name`. Throws std::invalid_argument "unknown image tracker 'x' (known: ...)"
/// or naming the parameter.
std::unique_ptr<ImageTracker> makeImageTracker(const std::string& name, const Params& params,
                                               const ImageTrackerContext& context);

}  // namespace predvs
