// predvs — `apriltag`: an image tracker on ViSP's vpDetectorAprilTag (ViSP 3.5).
//
// Every image is searched for tags of one family (detection, not frame-to-frame tracking: a tag
// is found or not, independently in each image). Points: per tag, its 4 corners in the
// detector's order (vpDetectorAprilTag::getTagsCorners(); in the frame of the pose it returns,
// ViSP's default with z not aligned with the camera, the corners (-s/2, -s/2, 0), (s/2, -s/2, 0),
// (s/2, s/2, 0), (-s/2, s/2, 0), s the tag size, as getTagsPoints3D()), then its
// centre, so 5 points per tag, tags in increasing id order. The centre is the intersection of
// the two diagonals of the detected corners: the image of the square's centre under any
// perspective, unlike the mean of the corners.
//
// Pixel convention: ViSP's (the centre of pixel (i, j) is u = j, v = i, as in u = u0 + px X/Z and
// vpDot2). The AprilTag library inside vpDetectorAprilTag puts pixel centres at x + 0.5 and ViSP
// passes its corners on unchanged, so 0.5 px is subtracted from both coordinates (tested on a tag
// rendered at a known pose: within 0.3 px after, about 0.5 px off along both axes before). The
// pose comes from vpDetectorAprilTag on the library's corners: its x and y translation carry that
// half pixel, about Z * 0.5 / px (0.3 mm at 0.5 m for px = 800), which is below what the depths
// here are used for.
//
// Which tags: the `ids` parameter (one id, or a text list "8,9,10"), otherwise the ids of the
// first image where at least one tag is found (initialisation). A listed tag that is not found in
// an image has its 5 points lost (NaN pixels, seen = false); tags not listed are ignored. The
// hint of track() is not used: tag ids identify the points.
//
// Pose: with `tag_size` (m, the side of the black square, ViSP's convention) > 0 and the camera
// known (ImageTrackerContext::camera_known), every found tag's pose cMo is estimated
// (HOMOGRAPHY_VIRTUAL_VS), its points get their depths Z_m = (cMo oP)_z, and TrackedPoints::cMo
// is the pose of the first listed tag that was found. Otherwise Z_m is NaN and pose_valid false.
//
// Parameters: family (text: 36h11 (default), 25h9, 16h5, circle21h7), decimation (quad decimate,
// default 1: full resolution; 2 halves the image for the quad search, about 3x faster, corners are
// still refined on the full image), threads (default 1), tag_size (m, default 0: no pose), ids.
#pragma once

#include "predvs/servo/image_tracker.h"

#include <visp3/core/vpCameraParameters.h>
#include <visp3/detection/vpDetectorAprilTag.h>

#include <memory>
#include <string>
#include <vector>

namespace predvs {

class AprilTagTracker : public ImageTracker {
 public:
  /// Throws std::invalid_argument naming the parameter.
  AprilTagTracker(const Params& params, const ImageTrackerContext& context);
  std::string name() const override { return "apriltag"; }
  int points() const override { return 5 * static_cast<int>(ids_.size()); }
  std::vector<std::string> pointNames() const override;
  TrackedPoints track(const vpImage<unsigned char>& image, const Eigen::VectorXd* hint = nullptr) override;
  void reset() override;
  /// The tag ids, in point order (empty until initialised without `ids`).
  const std::vector<int>& ids() const { return ids_; }

 private:
  std::unique_ptr<vpDetectorAprilTag> detector_;
  vpCameraParameters camera_;
  bool pose_ = false;
  double tag_size_m_ = 0.0;
  std::vector<int> ids_;        // tags followed, increasing
  std::vector<int> fixed_ids_;  // the `ids` parameter (empty: from the first detection)
};

}  // namespace predvs
