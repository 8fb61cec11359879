// predvs — `dots` and `apriltag` feature sources: the closed loop through rendered images.
//
// At every acquisition the scene's target is rendered into a grey camera image at the camera's
// pose (ImageRenderer, image_renderer.h: `dots` draws a dark disk on every point, `apriltag` an
// AprilTag on the square of the first four points), and an image tracker of the same name
// (image_tracker.h) measures the points in it. The frame is stamped with the acquisition time
// and goes through the loop's timing model, predictors and tasks like any other source.
//
// What comes from the image and what from the scene:
//   - pixels: from the tracker only. A point the tracker does not find is lost (status false,
//     NaN pixels); the scenario's pixel noise (`noise:`) is not added: the noise is the image's
//     (`image_noise`, grey levels) as seen through the tracker.
//   - which tracked point is which scene point: the true projection is used, as a real system
//     knows its own pattern, for identification only. It is the tracker's hint at
//     initialisation and whenever a point is lost (re-acquisition: `dots` searches near it;
//     `apriltag` ignores hints, tag ids identify its points); and each scene point is matched
//     once to the nearest tracked point within `match_px` (default 10 px) of its true
//     projection, the first time that point is seen, and keeps it (an AprilTag's centre is a
//     tracked point: a 4-point scene leaves it unmatched, a 5-point scene whose fifth point is
//     the centre uses it).
//   - depth Z: the tracker's (apriltag: from the tag's pose, camera known, tag size = the side of
//     the rendered square unless `tag_size` is given) when it has one, else the scene's true
//     depth of the point, as the geometric source (ViSP's simulated IBVS tutorials).
//   - occlusion windows: frames acquired inside one are rendered without the target (background
//     and noise only), so the tracker really loses it and has to re-acquire it afterwards.
//
// Parameters: the renderer's background (grey, default 128), dot_radius (m, 0.01), dot_grey (0),
// image_noise (grey levels, std dev, 0), blur (px, std dev, 0), tag_cells (text: a 10 x 10 PGM,
// default data/textures/tag36h11_id0.pgm), match_px (10); every other key goes to the tracker
// (dots: see dots_tracker.h; apriltag: family, decimation, threads, tag_size, ids). The image is
// camera.width x camera.height pixels (FeatureSourceContext).
#pragma once

#include "predvs/servo/feature_source.h"
#include "predvs/servo/image_renderer.h"
#include "predvs/servo/image_tracker.h"

#include <memory>
#include <string>
#include <vector>

namespace predvs {

class RenderedImageSource : public FeatureSource {
 public:
  /// `tracker`: "dots" or "apriltag" (the pattern drawn and the tracker run). Throws
  /// std::invalid_argument naming the parameter.
  RenderedImageSource(const std::string& tracker, const Params& params, const FeatureSourceContext& context);
  std::string name() const override { return tracker_name_; }
  int points() const override { return scene_.points(); }
  FeatureFrame acquire(double t_acq_s, const vpHomogeneousMatrix& wMc) override;

  /// The last rendered image, and the last tracker answer (for logs and tests).
  const vpImage<unsigned char>& lastImage() const { return image_; }
  const TrackedPoints& lastTracked() const { return tracked_; }
  /// Wall time spent rendering and tracking so far (s), and the number of frames.
  double renderSeconds() const { return render_s_; }
  double trackSeconds() const { return track_s_; }
  long frames() const { return frames_; }

 private:
  std::string tracker_name_;
  const Scene& scene_;
  CameraIntrinsics camera_;
  std::vector<OcclusionInterval> occlusions_;
  std::unique_ptr<ImageRenderer> renderer_;
  std::unique_ptr<ImageTracker> tracker_;
  double match_px_ = 10.0;
  std::vector<int> match_;   // scene point -> tracker point (-1: not yet matched)
  bool any_lost_ = true;     // last frame lost a point (or nothing yet): give the hint
  vpImage<unsigned char> image_;
  TrackedPoints tracked_;
  double render_s_ = 0.0, track_s_ = 0.0;
  long frames_ = 0;
};

}  // namespace predvs
