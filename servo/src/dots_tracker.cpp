#include "predvs/servo/dots_tracker.h"

#include <visp3/core/vpException.h>
#include <visp3/core/vpImagePoint.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Below this difference of the two class means (grey levels) a region holds no dot: a blank or
/// uniform frame must give no candidate rather than a split of its noise.
constexpr double kMinContrastGrey = 30.0;
/// Surround test of a candidate: kRingSamples points on its ellipse scaled by kRingScale; at most
/// kRingMaxBad of them may be of the dot's class (or outside the image).
constexpr int kRingSamples = 32;
constexpr double kRingScale = 1.6;
constexpr int kRingMaxBad = 2;

/// Otsu's threshold t on the histogram (class 0: grey <= t); the means of the two classes.
int otsuThreshold(const std::array<long, 256>& hist, long total, double& mean0, double& mean1) {
  double sum_all = 0.0;
  for (int g = 0; g < 256; ++g) sum_all += static_cast<double>(g) * hist[g];
  double best = -1.0, sum0 = 0.0;
  long n0 = 0;
  int t_best = 0;
  mean0 = mean1 = 0.0;
  for (int t = 0; t < 255; ++t) {
    n0 += hist[t];
    sum0 += static_cast<double>(t) * hist[t];
    const long n1 = total - n0;
    if (n0 == 0 || n1 == 0) continue;
    const double m0 = sum0 / n0, m1 = (sum_all - sum0) / n1;
    const double between = static_cast<double>(n0) * static_cast<double>(n1) * (m0 - m1) * (m0 - m1);
    if (between > best) {
      best = between;
      t_best = t;
      mean0 = m0;
      mean1 = m1;
    }
  }
  return t_best;
}

}  // namespace

std::vector<DotCandidate> detectDots(const vpImage<unsigned char>& image, const DotDetectionOptions& options,
                                     int u0, int v0, int w, int h, int* polarity_out) {
  std::vector<DotCandidate> out;
  const int W = static_cast<int>(image.getWidth()), H = static_cast<int>(image.getHeight());
  const int ua = std::max(0, u0), va = std::max(0, v0);
  const int ub = std::min(W, u0 + w), vb = std::min(H, v0 + h);
  if (ub - ua < 3 || vb - va < 3) return out;
  const int rw = ub - ua, rh = vb - va;

  std::array<long, 256> hist{};
  for (int v = va; v < vb; ++v)
    for (int u = ua; u < ub; ++u) ++hist[image[v][u]];
  const long total = static_cast<long>(rw) * rh;
  double mean0 = 0.0, mean1 = 0.0;
  const int t = otsuThreshold(hist, total, mean0, mean1);
  if (!(mean1 - mean0 >= kMinContrastGrey)) return out;
  long n_dark = 0;
  for (int g = 0; g <= t; ++g) n_dark += hist[g];
  int polarity = options.polarity;
  if (polarity == 0) polarity = (n_dark <= total - n_dark) ? -1 : +1;
  if (polarity_out) *polarity_out = polarity;
  auto inClass = [&](unsigned char g) { return polarity < 0 ? g <= t : g > t; };

  // 4-connected components of the dot class inside the rectangle.
  std::vector<int> label(static_cast<size_t>(rw) * rh, 0);
  std::vector<std::pair<int, int>> stack, pixels;
  int next_label = 0;
  for (int v = va; v < vb; ++v)
    for (int u = ua; u < ub; ++u) {
      const size_t k = static_cast<size_t>(v - va) * rw + (u - ua);
      if (label[k] != 0 || !inClass(image[v][u])) continue;
      ++next_label;
      label[k] = next_label;
      stack.assign(1, {u, v});
      pixels.clear();
      bool touches_border = false;
      int umin = u, umax = u, vmin = v, vmax = v;
      while (!stack.empty()) {
        const auto [pu, pv] = stack.back();
        stack.pop_back();
        pixels.push_back({pu, pv});
        umin = std::min(umin, pu);
        umax = std::max(umax, pu);
        vmin = std::min(vmin, pv);
        vmax = std::max(vmax, pv);
        if (pu == ua || pu == ub - 1 || pv == va || pv == vb - 1) touches_border = true;
        const int nu[4] = {pu - 1, pu + 1, pu, pu};
        const int nv[4] = {pv, pv, pv - 1, pv + 1};
        for (int n = 0; n < 4; ++n) {
          if (nu[n] < ua || nu[n] >= ub || nv[n] < va || nv[n] >= vb) continue;
          const size_t kn = static_cast<size_t>(nv[n] - va) * rw + (nu[n] - ua);
          if (label[kn] != 0 || !inClass(image[nv[n]][nu[n]])) continue;
          label[kn] = next_label;
          stack.push_back({nu[n], nv[n]});
        }
      }
      const double bw = umax - umin + 1, bh = vmax - vmin + 1;
      const double area = static_cast<double>(pixels.size());
      if (touches_border || bw < options.min_size_px || bh < options.min_size_px || bw > options.max_size_px ||
          bh > options.max_size_px || area < options.min_fill * bw * bh)
        continue;
      DotCandidate c;
      double su = 0.0, sv = 0.0;
      for (const auto& p : pixels) {
        su += p.first;
        sv += p.second;
      }
      c.u_px = su / area;
      c.v_px = sv / area;
      // Ellipse test: a filled ellipse of second central moments C has area 4 pi sqrt(det C).
      double cuu = 0.0, cvv = 0.0, cuv = 0.0;
      for (const auto& p : pixels) {
        const double du = p.first - c.u_px, dv = p.second - c.v_px;
        cuu += du * du;
        cvv += dv * dv;
        cuv += du * dv;
      }
      cuu = cuu / area + 1.0 / 12.0;  // + the variance of a unit pixel
      cvv = cvv / area + 1.0 / 12.0;
      cuv /= area;
      const double det = cuu * cvv - cuv * cuv;
      if (!(det > 0.0)) continue;
      const double ellipticity = area / (4.0 * M_PI * std::sqrt(det));
      if (ellipticity < options.min_ellipticity || ellipticity > 2.0 - options.min_ellipticity) continue;
      // Surround test: the ellipse scaled by kRingScale must lie on the other class (a dot on a
      // plain background, not a bright patch of a cluttered scene). Its boundary is at
      // Mahalanobis distance 2: p = c + 2 k L (cos a, sin a), L L^T = C (Cholesky).
      const double l11 = std::sqrt(cuu), l21 = cuv / l11, l22 = std::sqrt(std::max(cvv - l21 * l21, 0.0));
      int bad = 0;
      for (int a = 0; a < kRingSamples; ++a) {
        const double ca = std::cos(2.0 * M_PI * a / kRingSamples), sa = std::sin(2.0 * M_PI * a / kRingSamples);
        const double ru = c.u_px + 2.0 * kRingScale * (l11 * ca);
        const double rv = c.v_px + 2.0 * kRingScale * (l21 * ca + l22 * sa);
        const int iu = static_cast<int>(std::lround(ru)), iv = static_cast<int>(std::lround(rv));
        if (iu < 0 || iv < 0 || iu >= W || iv >= H || inClass(image[iv][iu])) ++bad;
      }
      if (bad > kRingMaxBad) continue;
      c.width_px = bw;
      c.height_px = bh;
      c.area_px = area;
      double best = std::numeric_limits<double>::infinity();
      for (const auto& p : pixels) {
        const double d = (p.first - c.u_px) * (p.first - c.u_px) + (p.second - c.v_px) * (p.second - c.v_px);
        if (d < best) {
          best = d;
          c.seed_u = p.first;
          c.seed_v = p.second;
        }
      }
      out.push_back(c);
    }
  return out;
}

DotsTracker::DotsTracker(const Params& params, const ImageTrackerContext& /*context*/) {
  expected_points_ = static_cast<int>(params.get("points", 0.0, 0.0, 1000.0));
  if (expected_points_ != params.get("points", 0.0))
    throw std::invalid_argument("dots: parameter 'points' must be an integer (0 = every dot found)");
  const double polarity = params.get("polarity", 0.0, -1.0, 1.0);
  if (polarity != -1.0 && polarity != 0.0 && polarity != 1.0)
    throw std::invalid_argument("dots: parameter 'polarity' must be -1 (dark dots), 0 (minority class) or 1 (bright dots)");
  detection_.polarity = static_cast<int>(polarity);
  grey_precision_ = params.get("grey_precision", 0.85, 0.0, 1.0);
  size_precision_ = params.get("size_precision", 0.65, 0.0, 1.0);
  ellipse_precision_ = params.get("ellipse_precision", 0.65, 0.0, 1.0);
  detection_.min_size_px = params.get("min_size_px", 8.0, 1.0, 10000.0);
  detection_.max_size_px = params.get("max_size_px", 100.0, 1.0, 10000.0);
  if (detection_.max_size_px < detection_.min_size_px)
    throw std::invalid_argument("dots: parameter 'max_size_px' must be >= 'min_size_px'");
  detection_.min_fill = params.get("min_fill", 0.5, 0.0, 1.0);
  detection_.min_ellipticity = params.get("min_ellipticity", 0.8, 0.0, 1.0);
  search_px_ = params.get("search_px", 40.0, 1.0, 100000.0);
  row_tolerance_px_ = params.get("row_tolerance_px", 0.0, 0.0, 100000.0);
  params.requireAllUsed("image tracker 'dots'");
}

std::vector<std::string> DotsTracker::pointNames() const {
  std::vector<std::string> names;
  for (size_t i = 0; i < dots_.size(); ++i) names.push_back("dot" + std::to_string(i));
  return names;
}

void DotsTracker::reset() {
  dots_.clear();
  polarity_ = 0;
}

bool DotsTracker::startDot(Dot& d, const vpImage<unsigned char>& image, const DotCandidate& c) const {
  d.dot = vpDot2();
  d.dot.setGraphics(false);
  d.dot.setGrayLevelPrecision(grey_precision_);
  d.dot.setSizePrecision(size_precision_);
  d.dot.setEllipsoidShapePrecision(ellipse_precision_);
  try {
    d.dot.initTracking(image, vpImagePoint(c.seed_v, c.seed_u));
  } catch (const vpException&) {
    d.tracked = false;
    return false;
  }
  d.tracked = true;
  d.u_px = d.dot.getCog().get_u();
  d.v_px = d.dot.getCog().get_v();
  d.size_px = std::max(d.dot.getWidth(), d.dot.getHeight());
  return true;
}

bool DotsTracker::initialise(const vpImage<unsigned char>& image, const Eigen::VectorXd* hint, std::string& note) {
  int polarity = 0;
  const auto found = detectDots(image, detection_, 0, 0, static_cast<int>(image.getWidth()),
                                static_cast<int>(image.getHeight()), &polarity);
  // Keep the candidates vpDot2 accepts.
  std::vector<Dot> started;
  std::vector<DotCandidate> kept;
  for (const auto& c : found) {
    Dot d;
    if (startDot(d, image, c)) {
      started.push_back(d);
      kept.push_back(c);
    }
  }
  if (hint != nullptr && hint->size() >= 2) {
    const size_t n = static_cast<size_t>(hint->size() / 2);
    dots_.assign(n, Dot());
    for (size_t i = 0; i < n; ++i) {
      dots_[i].u_px = (*hint)(2 * i);
      dots_[i].v_px = (*hint)(2 * i + 1);
    }
    // Greedy assignment, pairs in increasing distance.
    struct Pair {
      double d;
      size_t hint, cand;
    };
    std::vector<Pair> pairs;
    for (size_t i = 0; i < n; ++i)
      for (size_t k = 0; k < started.size(); ++k) {
        const double du = started[k].u_px - (*hint)(2 * i), dv = started[k].v_px - (*hint)(2 * i + 1);
        const double dist = std::hypot(du, dv);
        if (std::isfinite(dist) && dist <= search_px_) pairs.push_back({dist, i, k});
      }
    std::stable_sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.d < b.d; });
    std::vector<bool> hint_used(n, false), cand_used(started.size(), false);
    for (const auto& p : pairs) {
      if (hint_used[p.hint] || cand_used[p.cand]) continue;
      hint_used[p.hint] = cand_used[p.cand] = true;
      dots_[p.hint] = started[p.cand];
    }
    polarity_ = polarity;
    return true;
  }
  if (started.empty() || (expected_points_ > 0 && static_cast<int>(started.size()) < expected_points_)) {
    note = "no dots found to initialise (" + std::to_string(started.size()) + " found" +
           (expected_points_ > 0 ? ", " + std::to_string(expected_points_) + " expected)" : ")");
    return false;
  }
  std::vector<size_t> order(started.size());
  std::iota(order.begin(), order.end(), 0);
  if (expected_points_ > 0 && static_cast<int>(started.size()) > expected_points_) {
    std::vector<double> areas;
    for (const auto& c : kept) areas.push_back(c.area_px);
    std::vector<double> sorted = areas;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return std::fabs(areas[a] - median) < std::fabs(areas[b] - median);
    });
    order.resize(static_cast<size_t>(expected_points_));
  }
  // Rows then columns.
  double tol = row_tolerance_px_;
  if (tol <= 0.0) {
    std::vector<double> heights;
    for (size_t k : order) heights.push_back(started[k].dot.getHeight());
    std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
    tol = heights[heights.size() / 2];
  }
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return started[a].v_px < started[b].v_px; });
  std::vector<std::vector<size_t>> rows;
  double last_v = -std::numeric_limits<double>::infinity();
  for (size_t k : order) {
    if (rows.empty() || started[k].v_px - last_v > tol) rows.emplace_back();
    rows.back().push_back(k);
    last_v = started[k].v_px;
  }
  dots_.clear();
  for (auto& row : rows) {
    std::stable_sort(row.begin(), row.end(), [&](size_t a, size_t b) { return started[a].u_px < started[b].u_px; });
    for (size_t k : row) dots_.push_back(started[k]);
  }
  polarity_ = polarity;
  return true;
}

bool DotsTracker::reacquire(Dot& d, size_t index, const vpImage<unsigned char>& image, const Eigen::VectorXd* hint) {
  double cu = d.u_px, cv = d.v_px;
  if (hint != nullptr && hint->size() >= static_cast<Eigen::Index>(2 * index + 2) && std::isfinite((*hint)(2 * index)) &&
      std::isfinite((*hint)(2 * index + 1))) {
    cu = (*hint)(2 * index);
    cv = (*hint)(2 * index + 1);
  }
  if (!std::isfinite(cu) || !std::isfinite(cv)) return false;
  DotDetectionOptions options = detection_;
  if (polarity_ != 0) options.polarity = polarity_;
  const int half = static_cast<int>(std::ceil(search_px_));
  const auto found = detectDots(image, options, static_cast<int>(std::floor(cu)) - half,
                                static_cast<int>(std::floor(cv)) - half, 2 * half + 1, 2 * half + 1);
  std::vector<size_t> order(found.size());
  std::iota(order.begin(), order.end(), 0);
  auto dist = [&](size_t k) { return std::hypot(found[k].u_px - cu, found[k].v_px - cv); };
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return dist(a) < dist(b); });
  for (size_t k : order) {
    // Not a blob another dot already tracks.
    bool taken = false;
    for (const auto& other : dots_)
      if (&other != &d && other.tracked &&
          std::hypot(other.u_px - found[k].u_px, other.v_px - found[k].v_px) <
              0.5 * std::max(found[k].width_px, found[k].height_px))
        taken = true;
    if (taken) continue;
    Dot trial = d;
    if (startDot(trial, image, found[k])) {
      d = trial;
      return true;
    }
  }
  return false;
}

TrackedPoints DotsTracker::track(const vpImage<unsigned char>& image, const Eigen::VectorXd* hint) {
  TrackedPoints out;
  std::string note;
  if (dots_.empty() && !initialise(image, hint, note)) {
    out.note = note;
    return out;
  }
  const double W = image.getWidth(), H = image.getHeight();
  std::vector<double> prev_u(dots_.size()), prev_v(dots_.size());
  for (size_t i = 0; i < dots_.size(); ++i) {
    Dot& d = dots_[i];
    prev_u[i] = d.u_px;
    prev_v[i] = d.v_px;
    if (!d.tracked) continue;
    try {
      d.dot.track(image);
      const double u = d.dot.getCog().get_u(), v = d.dot.getCog().get_v();
      if (!(u >= 0.0 && v >= 0.0 && u <= W - 1.0 && v <= H - 1.0)) throw vpException(vpException::fatalError, "out");
      d.u_px = u;
      d.v_px = v;
      d.size_px = std::max(d.dot.getWidth(), d.dot.getHeight());
    } catch (const vpException&) {
      d.tracked = false;  // keep the last position for re-acquisition
    }
  }
  // Two dots on one blob: the one that moved more is lost.
  for (size_t i = 0; i < dots_.size(); ++i)
    for (size_t j = i + 1; j < dots_.size(); ++j) {
      Dot &a = dots_[i], &b = dots_[j];
      if (!a.tracked || !b.tracked) continue;
      if (std::hypot(a.u_px - b.u_px, a.v_px - b.v_px) >= 0.5 * std::min(a.size_px, b.size_px)) continue;
      const double ma = std::hypot(a.u_px - prev_u[i], a.v_px - prev_v[i]);
      const double mb = std::hypot(b.u_px - prev_u[j], b.v_px - prev_v[j]);
      Dot& loser = ma > mb ? a : b;
      const size_t k = ma > mb ? i : j;
      loser.tracked = false;
      loser.u_px = prev_u[k];
      loser.v_px = prev_v[k];
    }
  // Re-acquire the dots that were lost before this frame or just now.
  for (size_t i = 0; i < dots_.size(); ++i)
    if (!dots_[i].tracked) reacquire(dots_[i], i, image, hint);

  const size_t n = dots_.size();
  out.points.uv_px = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(2 * n), kNaN);
  out.points.Z_m = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(n), kNaN);
  out.points.seen.assign(n, false);
  int lost = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!dots_[i].tracked) {
      ++lost;
      out.note += (out.note.empty() ? "" : ", ") + std::string("dot ") + std::to_string(i) + " lost";
      continue;
    }
    out.points.uv_px(static_cast<Eigen::Index>(2 * i)) = dots_[i].u_px;
    out.points.uv_px(static_cast<Eigen::Index>(2 * i + 1)) = dots_[i].v_px;
    out.points.seen[i] = true;
  }
  if (n > 0 && lost == static_cast<int>(n)) out.note = "all " + std::to_string(n) + " dots lost";
  return out;
}

}  // namespace predvs
