// The closed loop through rendered images (issue 9 item 3): cost per frame of rendering the target
// (ImageRenderer: vpImageSimulator, blur, noise), of tracking it (dots / apriltag trackers) and of
// a whole acquisition of the rendered-image sources (render + track + identification), on the
// ibvs-rendered-* set-up: 640 x 480, the 10 cm square 0.5 m in front of the camera, slightly
// tilted. Every iteration is one frame; the camera moves a little between frames so that the
// trackers really track.
#include "predvs/servo/feature_source.h"
#include "predvs/servo/image_renderer.h"
#include "predvs/servo/image_tracker.h"
#include "predvs/servo/scene.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <string>

namespace {

using namespace predvs;

vpHomogeneousMatrix view(long k) {
  const double s = 0.002 * std::sin(0.05 * static_cast<double>(k));
  return vpHomogeneousMatrix(0.01 + s, -0.005, 0.5, 0.05, 0.03 + s, 0.02);
}

ImageRendererOptions cameraEffects(bool effects) {
  ImageRendererOptions o;
  if (effects) {
    o.noise_grey = 2.0;  // as in data/scenarios/ibvs-rendered-*.yaml
    o.blur_px = 0.5;
  }
  return o;
}

// BM_Render/<pattern 0 dots, 1 apriltag>/<camera effects 0 off, 1 blur 0.5 px + noise 2>
void BM_Render(benchmark::State& state) {
  const auto pattern = state.range(0) ? RenderedPattern::AprilTag : RenderedPattern::Dots;
  ImageRenderer renderer(pattern, squarePoints(0.1), CameraIntrinsics{}, cameraEffects(state.range(1) != 0));
  vpImage<unsigned char> I;
  long k = 0;
  for (auto _ : state) {
    renderer.render(view(k++), true, I);
    benchmark::DoNotOptimize(I.bitmap);
  }
}
BENCHMARK(BM_Render)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond);

// BM_Track/<tracker 0 dots, 1 apriltag>/<apriltag decimation>, on rendered frames with the camera
// effects (rendered outside the timed region).
void BM_Track(benchmark::State& state) {
  const bool tag = state.range(0) != 0;
  if (!tag && !isImageTracker("dots")) {
    state.SkipWithError("the dots tracker is not registered in this build");
    return;
  }
  ImageRenderer renderer(tag ? RenderedPattern::AprilTag : RenderedPattern::Dots, squarePoints(0.1), CameraIntrinsics{},
                         cameraEffects(true));
  Params params;
  if (tag) params.set("decimation", static_cast<double>(state.range(1)));
  auto tracker = makeImageTracker(tag ? "apriltag" : "dots", params, ImageTrackerContext{CameraIntrinsics{}, true});
  vpImage<unsigned char> I;
  long k = 0;
  for (auto _ : state) {
    state.PauseTiming();
    renderer.render(view(k++), true, I);
    state.ResumeTiming();
    benchmark::DoNotOptimize(tracker->track(I));
  }
}
BENCHMARK(BM_Track)->Args({0, 1})->Args({1, 1})->Args({1, 2})->Unit(benchmark::kMillisecond);

// BM_RenderedSourceAcquire/<0 dots, 1 apriltag>: one acquisition of the source as the loop calls it
// (render + track + identification), the scenario's source keys (image_noise 2, blur 0.5, and
// decimation 2 for apriltag).
void BM_RenderedSourceAcquire(benchmark::State& state) {
  const std::string name = state.range(0) ? "apriltag" : "dots";
  if (name == "dots" && !isImageTracker("dots")) {
    state.SkipWithError("the dots tracker is not registered in this build");
    return;
  }
  SceneConfig sc;
  sc.trajectory = "static";
  sc.trajectory_params = Params{};
  const Scene scene(sc);
  FeatureSourceContext ctx;
  ctx.scene = &scene;
  Params keys{{"image_noise", 2.0}, {"blur", 0.5}};  // data/scenarios/ibvs-rendered-*.yaml
  if (name == "apriltag") keys.set("decimation", 2.0);
  auto source = makeFeatureSource(name, keys, ctx);
  const vpHomogeneousMatrix wMo = scene.objectPose(0.0);
  long k = 0;
  for (auto _ : state) {
    const vpHomogeneousMatrix wMc = wMo * view(k).inverse();
    benchmark::DoNotOptimize(source->acquire(0.04 * static_cast<double>(k++), wMc));
  }
}
BENCHMARK(BM_RenderedSourceAcquire)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
