// The feature-source registry: adding a source is one entry here.
#include "predvs/predictors/registry.h"
#include "predvs/servo/feature_source.h"
#include "predvs/servo/geometric_source.h"
#include "predvs/servo/rendered_image_source.h"

namespace predvs {

using Sources = Registry<FeatureSource, const Params&, const FeatureSourceContext&>;

namespace {
const Sources& sources() {
  static const Sources table(
      "feature source",
      {
          {{"geometric", "exact projection of the scene's points plus seeded pixel noise; occlusion windows"},
           Sources::factory<GeometricSource>()},
          {{"dots", "rendered images (a dark disk on every point, image noise, blur) tracked by the dots tracker"},
           [](const Params& p, const FeatureSourceContext& c) { return std::make_unique<RenderedImageSource>("dots", p, c); }},
          {{"apriltag", "rendered images (an AprilTag on the first four points) tracked by the apriltag tracker; depth from its pose"},
           [](const Params& p, const FeatureSourceContext& c) {
             return std::make_unique<RenderedImageSource>("apriltag", p, c);
           }},
      });
  return table;
}
}  // namespace

const std::vector<RegistryInfo>& featureSourceRegistry() { return sources().infos(); }
bool isFeatureSource(const std::string& name) { return sources().has(name); }
std::unique_ptr<FeatureSource> makeFeatureSource(const std::string& name, const Params& params,
                                                 const FeatureSourceContext& context) {
  return sources().make(name, params, context);
}

}  // namespace predvs
