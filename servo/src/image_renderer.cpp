#include "predvs/servo/image_renderer.h"

#include "predvs/servo/data_dir.h"

#include <visp3/core/vpColVector.h>
#include <visp3/io/vpImageIo.h>
#include <visp3/robot/vpImageSimulator.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>


namespace predvs {
namespace {

constexpr int kDotTexels = 65;           // dot texture side (texels)
constexpr double kDotPatchHalfSide = 1.5;  // patch half-side / disk radius
constexpr int kCoverageSamples = 8;      // per texel axis, for the disk's coverage
constexpr size_t kNoisePoolExtra = size_t{1} << 20;  // pool = image size + this many samples

void requireRange(const std::string& what, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi)) {
    std::ostringstream msg;
    msg << what << " = " << v << " is out of range [" << lo << ", " << hi << "]";
    throw std::invalid_argument(msg.str());
  }
}

std::unique_ptr<vpImageSimulator> makePatch(const vpImage<unsigned char>& texture, const Eigen::Vector3d corners[4]) {
  auto sim = std::make_unique<vpImageSimulator>(vpImageSimulator::GRAY_SCALED);
  sim->setInterpolationType(vpImageSimulator::BILINEAR_INTERPOLATION);
  vpColVector X[4];
  for (int k = 0; k < 4; ++k) {
    X[k].resize(3);
    for (unsigned r = 0; r < 3; ++r) X[k][r] = corners[k](r);
  }
  sim->init(texture, X);
  return sim;
}

/// The disk's coverage of each texel of a kDotTexels^2 patch of half-side 1.5 r: 0 = disk
/// (dot grey), 1 = background.
vpImage<unsigned char> dotTexture(double dot_grey, double background_grey) {
  vpImage<unsigned char> t(kDotTexels, kDotTexels);
  const double step = 2.0 * kDotPatchHalfSide / (kDotTexels - 1);  // texel pitch in radii
  for (int i = 0; i < kDotTexels; ++i)
    for (int j = 0; j < kDotTexels; ++j) {
      int inside = 0;
      for (int a = 0; a < kCoverageSamples; ++a)
        for (int b = 0; b < kCoverageSamples; ++b) {
          const double y = -kDotPatchHalfSide + step * (i - 0.5 + (a + 0.5) / kCoverageSamples);
          const double x = -kDotPatchHalfSide + step * (j - 0.5 + (b + 0.5) / kCoverageSamples);
          inside += x * x + y * y <= 1.0;
        }
      const double cover = static_cast<double>(inside) / (kCoverageSamples * kCoverageSamples);
      t[static_cast<unsigned>(i)][static_cast<unsigned>(j)] =
          static_cast<unsigned char>(std::lround(cover * dot_grey + (1.0 - cover) * background_grey));
    }
  return t;
}

}  // namespace

std::string defaultTagCellsPath() { return dataDir() + "/textures/tag36h11_id0.pgm"; }

vpImage<unsigned char> tagTexture(const vpImage<unsigned char>& cells, int k) {
  if (cells.getWidth() != 10 || cells.getHeight() != 10)
    throw std::invalid_argument("tag cells: expected a 10 x 10 image (one pixel per cell), got " +
                                std::to_string(cells.getWidth()) + " x " + std::to_string(cells.getHeight()));
  if (k < 1) throw std::invalid_argument("tag texture: texels per cell must be >= 1");
  const int n = 10 * k + 1;
  // The cells a texel centre touches along one axis: one inside a cell, two on a boundary.
  auto span = [k](int i, int& lo, int& hi) {
    lo = hi = std::min(i / k, 9);
    if (i % k == 0 && i > 0) lo = std::min(i / k - 1, 9);
    if (i / k > 9) lo = hi = 9;
  };
  vpImage<unsigned char> t(static_cast<unsigned>(n), static_cast<unsigned>(n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      int r0, r1, c0, c1;
      span(i, r0, r1);
      span(j, c0, c1);
      double sum = 0.0;
      int count = 0;
      for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c) {
          sum += cells[static_cast<unsigned>(r)][static_cast<unsigned>(c)];
          ++count;
        }
      t[static_cast<unsigned>(i)][static_cast<unsigned>(j)] = static_cast<unsigned char>(std::lround(sum / count));
    }
  return t;
}

ImageRenderer::ImageRenderer(RenderedPattern pattern, const Eigen::Matrix3Xd& oP, const CameraIntrinsics& camera,
                             const ImageRendererOptions& options)
    : options_(options), rng_(options.seed) {
  requireRange("image width", options.width_px, 1, 1e5);
  requireRange("image height", options.height_px, 1, 1e5);
  requireRange("background", options.background_grey, 0.0, 255.0);
  requireRange("dot_grey", options.dot_grey, 0.0, 255.0);
  requireRange("image_noise", options.noise_grey, 0.0, 255.0);
  requireRange("blur", options.blur_px, 0.0, 50.0);
  camera_.initPersProjWithoutDistortion(camera.px, camera.py, camera.u0, camera.v0);

  if (pattern == RenderedPattern::Dots) {
    requireRange("dot_radius", options.dot_radius_m, 1e-6, 1e3);
    const vpImage<unsigned char> texture = dotTexture(options.dot_grey, options.background_grey);
    const double a = kDotPatchHalfSide * options.dot_radius_m;
    for (Eigen::Index i = 0; i < oP.cols(); ++i) {
      const Eigen::Vector3d c = oP.col(i);
      const Eigen::Vector3d corners[4] = {c + Eigen::Vector3d(-a, -a, 0), c + Eigen::Vector3d(a, -a, 0),
                                          c + Eigen::Vector3d(a, a, 0), c + Eigen::Vector3d(-a, a, 0)};
      patches_.push_back(makePatch(texture, corners));
    }
    return;
  }

  // AprilTag: the first four points are the black square's corners, in order round it.
  if (oP.cols() < 4) throw std::invalid_argument("apriltag rendering: the target needs 4 points (the tag's corners)");
  const Eigen::Vector3d p[4] = {oP.col(0), oP.col(1), oP.col(2), oP.col(3)};
  const double side = (p[1] - p[0]).norm();
  const double tol = 1e-6 * std::max(side, 1e-9);
  bool square = side > 0.0;
  for (int k = 0; k < 4; ++k) square = square && std::abs((p[(k + 1) % 4] - p[k]).norm() - side) <= tol;
  square = square && std::abs((p[2] - p[0]).norm() - (p[3] - p[1]).norm()) <= tol;
  const Eigen::Vector3d normal = (p[1] - p[0]).cross(p[3] - p[0]);
  square = square && std::abs(normal.normalized().dot(p[2] - p[0])) <= tol;
  if (!square)
    throw std::invalid_argument(
        "apriltag rendering: target.points 0-3 must be the corners of a square, in order round it (the tag's "
        "black square)");
  tag_size_m_ = side;
  vpImage<unsigned char> cells;
  const std::string path = options.tag_cells_path.empty() ? defaultTagCellsPath() : options.tag_cells_path;
  try {
    vpImageIo::read(cells, path);
  } catch (const std::exception& e) {
    throw std::invalid_argument("apriltag rendering: cannot read the tag cells '" + path + "': " + e.what());
  }
  const vpImage<unsigned char> texture = tagTexture(cells);
  const Eigen::Vector3d centre = (p[0] + p[1] + p[2] + p[3]) / 4.0;
  Eigen::Vector3d corners[4];
  for (int k = 0; k < 4; ++k) corners[k] = centre + (p[k] - centre) * (10.0 / 8.0);
  patches_.push_back(makePatch(texture, corners));
}

ImageRenderer::~ImageRenderer() = default;

void ImageRenderer::render(const vpHomogeneousMatrix& cMo, bool target_visible, vpImage<unsigned char>& image) {
  const unsigned char bg = static_cast<unsigned char>(std::lround(options_.background_grey));
  image.resize(options_.height_px, options_.width_px, bg);
  std::fill(image.bitmap, image.bitmap + image.getSize(), bg);
  if (target_visible)
    for (auto& patch : patches_) {
      patch->setCameraPosition(cMo);
      patch->getImage(image, camera_);
    }
  if (options_.blur_px > 0.0) blur(image);
  if (options_.noise_grey > 0.0) {
    // A window of the seeded pool at a random offset (see the header).
    const size_t n = image.getSize();
    if (noise_pool_.size() < n + kNoisePoolExtra) {
      noise_pool_.resize(n + kNoisePoolExtra);
      for (auto& x : noise_pool_) x = static_cast<float>(options_.noise_grey * normal_(rng_));
    }
    const size_t offset = std::uniform_int_distribution<size_t>(0, noise_pool_.size() - n)(rng_);
    const float* z = noise_pool_.data() + offset;
    for (size_t i = 0; i < n; ++i) {
      const float v = static_cast<float>(image.bitmap[i]) + z[i];  // rounded half up, clamped
      image.bitmap[i] = static_cast<unsigned char>(std::min(255.0f, std::max(0.0f, v + 0.5f)));
    }
  }
}

void ImageRenderer::blur(vpImage<unsigned char>& image) {
  // Separable Gaussian, radius ceil(3 sigma), borders clamped (the edge pixel repeats).
  const int r = static_cast<int>(std::ceil(3.0 * options_.blur_px));
  std::vector<float> w(static_cast<size_t>(2 * r + 1));
  double sum = 0.0;
  for (int k = -r; k <= r; ++k)
    sum += w[static_cast<size_t>(k + r)] = static_cast<float>(std::exp(-0.5 * k * k / (options_.blur_px * options_.blur_px)));
  for (auto& x : w) x = static_cast<float>(x / sum);
  const int W = static_cast<int>(image.getWidth()), H = static_cast<int>(image.getHeight());
  const size_t Ws = static_cast<size_t>(W);
  blur_tmp_.resize(Ws * static_cast<size_t>(H));
  std::vector<float> line(static_cast<size_t>(std::max(W, H) + 2 * r));
  // Rows: the row padded by r repeated edge pixels on each side, then a plain convolution.
  for (int i = 0; i < H; ++i) {
    const unsigned char* row = image.bitmap + static_cast<size_t>(i) * Ws;
    for (int j = -r; j < W + r; ++j) line[static_cast<size_t>(j + r)] = row[std::clamp(j, 0, W - 1)];
    float* out = blur_tmp_.data() + static_cast<size_t>(i) * Ws;
    for (int j = 0; j < W; ++j) {
      const float* x = line.data() + j;
      float acc = 0.0f;
      for (int k = 0; k <= 2 * r; ++k) acc += w[static_cast<size_t>(k)] * x[k];
      out[j] = acc;
    }
  }
  // Columns: accumulate whole rows (contiguous), clamped row indices.
  std::vector<float> acc(Ws);
  for (int i = 0; i < H; ++i) {
    std::fill(acc.begin(), acc.end(), 0.0f);
    for (int k = -r; k <= r; ++k) {
      const float wk = w[static_cast<size_t>(k + r)];
      const float* src = blur_tmp_.data() + static_cast<size_t>(std::clamp(i + k, 0, H - 1)) * Ws;
      for (size_t j = 0; j < Ws; ++j) acc[j] += wk * src[j];
    }
    unsigned char* dst = image.bitmap + static_cast<size_t>(i) * Ws;
    for (size_t j = 0; j < Ws; ++j) dst[j] = static_cast<unsigned char>(std::min(255.0f, std::max(0.0f, acc[j] + 0.5f)));
  }
}

}  // namespace predvs
