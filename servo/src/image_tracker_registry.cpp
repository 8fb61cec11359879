// The image-tracker registry: adding a tracker is one entry here.
#include "predvs/predictors/registry.h"
#include "predvs/servo/apriltag_tracker.h"
#include "predvs/servo/dots_tracker.h"
#include "predvs/servo/image_tracker.h"

namespace predvs {

using Trackers = Registry<ImageTracker, const Params&, const ImageTrackerContext&>;

namespace {
const Trackers& trackers() {
  static const Trackers table(
      "image tracker",
      {
          {{"dots", "vpDot2 blobs found automatically (Otsu threshold, size bounds), ordered by rows then columns, "
                    "re-acquired near their last position"},
           Trackers::factory<DotsTracker>()},
          {{"apriltag", "vpDetectorAprilTag: per tag its 4 corners then its centre, tags by increasing id; pose with tag_size"},
           Trackers::factory<AprilTagTracker>()},
      });
  return table;
}
}  // namespace

const std::vector<ImageTrackerInfo>& imageTrackerRegistry() { return trackers().infos(); }
bool isImageTracker(const std::string& name) { return trackers().has(name); }
std::unique_ptr<ImageTracker> makeImageTracker(const std::string& name, const Params& params,
                                               const ImageTrackerContext& context) {
  return trackers().make(name, params, context);
}

}  // namespace predvs
