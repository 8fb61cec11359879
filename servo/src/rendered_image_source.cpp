#include "predvs/servo/rendered_image_source.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const Scene& requireScene(const FeatureSourceContext& c) {
  if (!c.scene) throw std::invalid_argument("feature source: no scene");
  return *c.scene;
}

unsigned imageSide(const std::string& key, double v) {
  if (!(v >= 1.0 && v <= 1e5) || v != std::floor(v))
    throw std::invalid_argument(key + " = " + std::to_string(v) + ": a rendered image needs a whole number of pixels");
  return static_cast<unsigned>(v);
}

double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

RenderedImageSource::RenderedImageSource(const std::string& tracker, const Params& params,
                                         const FeatureSourceContext& context)
    : tracker_name_(tracker), scene_(requireScene(context)), camera_(context.camera), occlusions_(context.occlusions) {
  const std::string what = "feature source '" + tracker + "'";
  ImageRendererOptions o;
  o.width_px = imageSide("camera.width", context.image_width_px);
  o.height_px = imageSide("camera.height", context.image_height_px);
  o.background_grey = params.get("background", o.background_grey, 0.0, 255.0);
  o.dot_radius_m = params.get("dot_radius", o.dot_radius_m, 1e-6, 1e3);
  o.dot_grey = params.get("dot_grey", o.dot_grey, 0.0, 255.0);
  o.noise_grey = params.get("image_noise", o.noise_grey, 0.0, 255.0);
  o.blur_px = params.get("blur", o.blur_px, 0.0, 50.0);
  o.tag_cells_path = params.text("tag_cells", "");
  o.seed = context.seed;
  match_px_ = params.get("match_px", match_px_, 0.0, 1e6);
  const RenderedPattern pattern = tracker == "apriltag" ? RenderedPattern::AprilTag : RenderedPattern::Dots;
  if (tracker != "apriltag" && tracker != "dots")
    throw std::invalid_argument("rendered image source: unknown pattern '" + tracker + "' (known: dots, apriltag)");
  try {
    renderer_ = std::make_unique<ImageRenderer>(pattern, scene_.objectPoints(), camera_, o);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(what + ": " + e.what());
  }

  // Every key the renderer does not know goes to the tracker.
  static const std::set<std::string> kRendererKeys = {"background", "dot_radius", "dot_grey", "image_noise",
                                                       "blur",       "tag_cells",  "match_px"};
  Params tracker_params;
  for (const auto& kv : params.values())
    if (!kRendererKeys.count(kv.first)) tracker_params.set(kv.first, kv.second);
  for (const auto& kv : params.texts())
    if (!kRendererKeys.count(kv.first)) tracker_params.setText(kv.first, kv.second);
  if (pattern == RenderedPattern::AprilTag && !tracker_params.has("tag_size"))
    tracker_params.set("tag_size", renderer_->tagSizeM());
  ImageTrackerContext tctx;
  tctx.camera = camera_;
  tctx.camera_known = true;
  try {
    tracker_ = makeImageTracker(tracker, tracker_params, tctx);
    tracker_params.requireAllUsed(what);
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    throw std::invalid_argument(msg.find(what) == std::string::npos ? what + ": " + msg : msg);
  }
  match_.assign(static_cast<size_t>(scene_.points()), -1);
}

FeatureFrame RenderedImageSource::acquire(double t_acq_s, const vpHomogeneousMatrix& wMc) {
  const auto t0 = std::chrono::steady_clock::now();
  // The truth, for identification only (hint and matching) and the depth fallback.
  const PointFeatures truth = scene_.project(t_acq_s, wMc, camera_);
  bool hidden = false;
  for (const auto& o : occlusions_) hidden = hidden || (t_acq_s >= o.start_s && t_acq_s < o.end_s);
  const vpHomogeneousMatrix cMo = wMc.inverse() * scene_.objectPose(t_acq_s);
  renderer_->render(cMo, !hidden, image_);
  const auto t1 = std::chrono::steady_clock::now();

  // The hint: the true projections in the tracker's point order, only to initialise or re-acquire.
  const int n = scene_.points();
  Eigen::VectorXd hint;
  if (tracker_->points() == 0) {
    hint = truth.uv_px;
  } else if (any_lost_) {
    hint = Eigen::VectorXd::Constant(2 * tracker_->points(), kNaN);
    for (int i = 0; i < n; ++i)
      if (match_[static_cast<size_t>(i)] >= 0) hint.segment<2>(2 * match_[static_cast<size_t>(i)]) = truth.uv_px.segment<2>(2 * i);
  }
  tracked_ = tracker_->track(image_, hint.size() ? &hint : nullptr);
  const auto t2 = std::chrono::steady_clock::now();

  // Identification: each unmatched scene point takes the nearest seen, unclaimed tracked point
  // within match_px of its true projection.
  const PointFeatures& m = tracked_.points;
  const int nt = m.points();
  std::vector<bool> claimed(static_cast<size_t>(nt), false);
  for (int i = 0; i < n; ++i)
    if (match_[static_cast<size_t>(i)] >= 0 && match_[static_cast<size_t>(i)] < nt) claimed[static_cast<size_t>(match_[static_cast<size_t>(i)])] = true;
  for (int i = 0; i < n; ++i) {
    if (match_[static_cast<size_t>(i)] >= 0 || !truth.seen[static_cast<size_t>(i)]) continue;
    int best = -1;
    double best_d = match_px_;
    for (int j = 0; j < nt; ++j) {
      if (claimed[static_cast<size_t>(j)] || !m.seen[static_cast<size_t>(j)]) continue;
      const double d = std::hypot(m.uv_px(2 * j) - truth.uv_px(2 * i), m.uv_px(2 * j + 1) - truth.uv_px(2 * i + 1));
      if (d <= best_d) {
        best_d = d;
        best = j;
      }
    }
    if (best >= 0) {
      match_[static_cast<size_t>(i)] = best;
      claimed[static_cast<size_t>(best)] = true;
    }
  }

  FeatureFrame f;
  f.t_acq_s = t_acq_s;
  f.points.uv_px = Eigen::VectorXd::Constant(2 * n, kNaN);
  f.points.Z_m = Eigen::VectorXd::Constant(n, kNaN);
  f.points.seen.assign(static_cast<size_t>(n), false);
  any_lost_ = false;
  for (int i = 0; i < n; ++i) {
    const int j = match_[static_cast<size_t>(i)];
    if (j < 0 || j >= nt || !m.seen[static_cast<size_t>(j)]) {
      any_lost_ = true;
      continue;
    }
    f.points.seen[static_cast<size_t>(i)] = true;
    f.points.uv_px.segment<2>(2 * i) = m.uv_px.segment<2>(2 * j);
    f.points.Z_m(i) = std::isfinite(m.Z_m(j)) ? m.Z_m(j) : truth.Z_m(i);
  }
  render_s_ += seconds(t0, t1);
  track_s_ += seconds(t1, t2);
  ++frames_;
  return f;
}

}  // namespace predvs
