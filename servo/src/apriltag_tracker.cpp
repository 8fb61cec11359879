#include "predvs/servo/apriltag_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// The AprilTag library puts the centre of pixel (x, y) at (x + 0.5, y + 0.5) (its bilinear
/// sampler reads at px - 0.5), ViSP at (x, y); vpDetectorAprilTag passes the library's corners on
/// unchanged. Added to them, this gives ViSP's convention, the one of the pinhole u = u0 + px X/Z.
constexpr double kLibraryToViSPPx = -0.5;

vpDetectorAprilTag::vpAprilTagFamily parseFamily(const std::string& name) {
  if (name == "36h11") return vpDetectorAprilTag::TAG_36h11;
  if (name == "25h9") return vpDetectorAprilTag::TAG_25h9;
  if (name == "16h5") return vpDetectorAprilTag::TAG_16h5;
  if (name == "circle21h7") return vpDetectorAprilTag::TAG_CIRCLE21h7;
  throw std::invalid_argument("parameter 'family' = '" + name + "': expected 36h11, 25h9, 16h5 or circle21h7");
}

/// `ids`: one number, or a text list "8, 9, 10".
std::vector<int> parseIds(const Params& params) {
  std::vector<int> ids;
  if (!params.has("ids")) return ids;
  if (params.values().count("ids")) {
    const double v = params.get("ids", -1.0, 0.0, 1e6);
    if (v != std::floor(v)) throw std::invalid_argument("parameter 'ids': expected whole tag ids");
    ids.push_back(static_cast<int>(v));
  } else {
    std::string list = params.text("ids", "");
    std::replace(list.begin(), list.end(), ',', ' ');
    std::istringstream in(list);
    std::string word;
    while (in >> word) {
      char* end = nullptr;
      const long id = std::strtol(word.c_str(), &end, 10);
      if (*end != '\0' || id < 0) throw std::invalid_argument("parameter 'ids': '" + word + "' is not a tag id");
      ids.push_back(static_cast<int>(id));
    }
    if (ids.empty()) throw std::invalid_argument("parameter 'ids': expected tag ids, e.g. \"8,9\"");
  }
  std::sort(ids.begin(), ids.end());
  if (std::adjacent_find(ids.begin(), ids.end()) != ids.end())
    throw std::invalid_argument("parameter 'ids': an id is listed twice");
  return ids;
}

/// Intersection of the diagonals p0-p2 and p1-p3 (pixels u, v).
bool diagonalsCentre(const std::vector<vpImagePoint>& c, double& u, double& v) {
  const double x1 = c[0].get_u(), y1 = c[0].get_v(), x2 = c[2].get_u(), y2 = c[2].get_v();
  const double x3 = c[1].get_u(), y3 = c[1].get_v(), x4 = c[3].get_u(), y4 = c[3].get_v();  // any origin
  const double den = (x1 - x2) * (y3 - y4) - (y1 - y2) * (x3 - x4);
  if (std::abs(den) < 1e-12) return false;
  const double a = x1 * y2 - y1 * x2, b = x3 * y4 - y3 * x4;
  u = (a * (x3 - x4) - (x1 - x2) * b) / den;
  v = (a * (y3 - y4) - (y1 - y2) * b) / den;
  return true;
}

}  // namespace

AprilTagTracker::AprilTagTracker(const Params& params, const ImageTrackerContext& context) {
  const auto family = parseFamily(params.text("family", "36h11"));
  const double decimation = params.get("decimation", 1.0, 1.0, 8.0);
  const double threads = params.get("threads", 1.0, 1.0, 64.0);
  tag_size_m_ = params.get("tag_size", 0.0, 0.0, 100.0);
  fixed_ids_ = parseIds(params);
  params.requireAllUsed("image tracker 'apriltag'");
  detector_ = std::make_unique<vpDetectorAprilTag>(family, vpDetectorAprilTag::HOMOGRAPHY_VIRTUAL_VS);
  detector_->setAprilTagQuadDecimate(static_cast<float>(decimation));
  detector_->setAprilTagNbThreads(static_cast<int>(threads));
  camera_.initPersProjWithoutDistortion(context.camera.px, context.camera.py, context.camera.u0, context.camera.v0);
  pose_ = tag_size_m_ > 0.0 && context.camera_known;
  ids_ = fixed_ids_;
}

std::vector<std::string> AprilTagTracker::pointNames() const {
  std::vector<std::string> names;
  for (int id : ids_) {
    const std::string tag = "tag" + std::to_string(id);
    for (int c = 0; c < 4; ++c) names.push_back(tag + ".c" + std::to_string(c));
    names.push_back(tag + ".centre");
  }
  return names;
}

void AprilTagTracker::reset() { ids_ = fixed_ids_; }

TrackedPoints AprilTagTracker::track(const vpImage<unsigned char>& image, const Eigen::VectorXd* /*hint*/) {
  std::vector<vpHomogeneousMatrix> cMo;
  if (pose_)
    detector_->detect(image, tag_size_m_, camera_, cMo);
  else
    detector_->detect(image);
  const std::vector<int> found_ids = detector_->getTagsId();
  const std::vector<std::vector<vpImagePoint>> corners = detector_->getTagsCorners();

  // First detection of each id (a duplicate id is ignored).
  std::map<int, size_t> where;
  for (size_t k = 0; k < found_ids.size(); ++k) where.emplace(found_ids[k], k);
  if (ids_.empty())
    for (const auto& kv : where) ids_.push_back(kv.first);  // increasing (map order)

  TrackedPoints out;
  const int n = points();
  out.points.uv_px = Eigen::VectorXd::Constant(2 * n, kNaN);
  out.points.Z_m = Eigen::VectorXd::Constant(n, kNaN);
  out.points.seen.assign(static_cast<size_t>(n), false);
  const double h = tag_size_m_ / 2.0;
  // The corners in the frame of the pose vpDetectorAprilTag returns (its default, z not aligned
  // with the camera: getTagsPoints3D()).
  const double oP[5][2] = {{-h, -h}, {h, -h}, {h, h}, {-h, h}, {0.0, 0.0}};
  std::string missing;
  for (size_t t = 0; t < ids_.size(); ++t) {
    const auto it = where.find(ids_[t]);
    if (it == where.end() || corners[it->second].size() != 4) {
      missing += (missing.empty() ? "" : ", ") + std::to_string(ids_[t]);
      continue;
    }
    const std::vector<vpImagePoint>& c = corners[it->second];
    double uc = 0.0, vc = 0.0;
    if (!diagonalsCentre(c, uc, vc)) {
      missing += (missing.empty() ? "" : ", ") + std::to_string(ids_[t]);
      continue;
    }
    const int base = 5 * static_cast<int>(t);
    for (int j = 0; j < 5; ++j) {
      const int i = base + j;
      out.points.uv_px(2 * i) = (j < 4 ? c[static_cast<size_t>(j)].get_u() : uc) + kLibraryToViSPPx;
      out.points.uv_px(2 * i + 1) = (j < 4 ? c[static_cast<size_t>(j)].get_v() : vc) + kLibraryToViSPPx;
      out.points.seen[static_cast<size_t>(i)] = true;
      if (pose_ && it->second < cMo.size()) {
        const vpHomogeneousMatrix& M = cMo[it->second];
        out.points.Z_m(i) = M[2][0] * oP[j][0] + M[2][1] * oP[j][1] + M[2][3];
      }
    }
    if (pose_ && it->second < cMo.size() && !out.pose_valid) {
      out.pose_valid = true;
      out.cMo = cMo[it->second];
    }
  }
  if (ids_.empty())
    out.note = "no tag found";
  else if (!missing.empty())
    out.note = "tag " + missing + " not found";
  return out;
}

}  // namespace predvs
