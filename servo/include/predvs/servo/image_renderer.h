// predvs — rendering the scene's target into a grey camera image (ViSP vpImageSimulator).
//
// The camera is the pinhole of CameraIntrinsics without distortion; the image is width x height
// pixels, pixel (i, j) is sampled at u = j, v = i (ViSP's convention: the projection u = u0 + px X/Z
// of a point falls on the pixel of index j = u). Each textured planar patch is a vpImageSimulator
// (grey, bilinear interpolation of its texture) posed by cMo, the object frame in the camera
// frame; only the pixels inside a patch are written, over a uniform background.
//
// Patterns (the target's N points oP_i, metres, in the object frame):
//   - Dots: one dark disk of radius dot_radius_m centred on every point, in the plane through the
//     point parallel to the object's x-y plane (its normal is the object's z axis). Each is a
//     square patch of half-side 1.5 r whose 65 x 65 texture holds the disk's coverage of each
//     texel (8 x 8 sub-samples), so the dark-to-background ramp is centred on the circle.
//   - AprilTag: the first four points must be the corners of a square, in order round it (checked:
//     equal sides and diagonals, coplanar); they are the corners of the tag's black square (ViSP's
//     tag size = its side). The texture is the tag's 10 x 10 cells (black border 8 x 8 and one
//     white cell of margin), so the patch is the square scaled by 10/8 about its centre; texture row
//     0 / column 0 is the side p0 -> p1 / p0 -> p3. Cells come from a 10 x 10 PGM (one pixel per
//     cell, 0 black, 255 white); the texture has 16 texels per cell plus one, the texels on a cell
//     boundary holding the mean of the cells they touch, so that the bilinear ramp is centred on
//     the true boundary. The default is data/textures/tag36h11_id0.pgm (how it was made: that
//     directory's README).
//   A patch is drawn only when its front faces the camera: the points must turn so that
//   (p1 - p0) x (p3 - p0) (AprilTag), or the object's +z axis (dots), points away from the camera
//   (true of squarePoints() seen from the scene's default goal, like ViSP's own examples).
//
// Camera effects, in this order: Gaussian blur of standard deviation blur_px (0: none; separable,
// radius ceil(3 sigma), edge pixels repeated), then Gaussian noise of standard deviation
// noise_grey added to every pixel, rounded and clamped to [0, 255]. The noise is read from a pool
// of (pixels + 2^20) samples drawn once from the seeded std::mt19937_64, starting at a uniformly
// drawn offset each frame: independent draws cost about 5 ms per 640 x 480 frame, the pool 0.3 ms.
// Within a frame the samples are independent; from frame to frame a pixel gets the sample of a
// new random offset, so the noise is not frozen, though all frames are windows of one sequence.
// A hidden target (an occlusion window) is the background with the same blur and noise.
#pragma once

#include "predvs/tasks/camera.h"

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImage.h>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

class vpImageSimulator;

namespace predvs {

enum class RenderedPattern { Dots, AprilTag };

struct ImageRendererOptions {
  unsigned width_px = 640;
  unsigned height_px = 480;
  double background_grey = 128.0;  ///< grey level of everything but the target, [0, 255]
  double dot_radius_m = 0.01;      ///< Dots: disk radius
  double dot_grey = 0.0;           ///< Dots: grey level of the disks
  double noise_grey = 0.0;         ///< std dev of the per-pixel Gaussian noise (grey levels)
  double blur_px = 0.0;            ///< std dev of the Gaussian blur (pixels), 0: none
  std::uint64_t seed = 1;          ///< seeds the noise
  std::string tag_cells_path;      ///< AprilTag: the 10 x 10 cell PGM (empty: defaultTagCellsPath())
};

/// dataDir()/textures/tag36h11_id0.pgm (see predvs/servo/data_dir.h for the lookup).
std::string defaultTagCellsPath();
/// The AprilTag texture of a 10 x 10 cell image: (10 k + 1)^2 texels, k per cell, boundary texels
/// the mean of the cells they touch. Throws std::invalid_argument unless cells is 10 x 10.
vpImage<unsigned char> tagTexture(const vpImage<unsigned char>& cells, int texels_per_cell = 16);

class ImageRenderer {
 public:
  /// Throws std::invalid_argument naming what is wrong (an option out of range, AprilTag points
  /// that are not a square, an unreadable cell file).
  ImageRenderer(RenderedPattern pattern, const Eigen::Matrix3Xd& object_points_m, const CameraIntrinsics& camera,
                const ImageRendererOptions& options);
  ~ImageRenderer();
  ImageRenderer(const ImageRenderer&) = delete;
  ImageRenderer& operator=(const ImageRenderer&) = delete;

  /// Renders the target posed at cMo (or only the background when !target_visible) into `image`
  /// (resized to width x height).
  void render(const vpHomogeneousMatrix& cMo, bool target_visible, vpImage<unsigned char>& image);
  /// AprilTag: side of the black square (m); 0 for dots.
  double tagSizeM() const { return tag_size_m_; }
  const ImageRendererOptions& options() const { return options_; }

 private:
  ImageRendererOptions options_;
  vpCameraParameters camera_;
  std::vector<std::unique_ptr<vpImageSimulator>> patches_;
  double tag_size_m_ = 0.0;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::vector<float> noise_pool_;  // noise_grey * N(0, 1)
  std::vector<float> blur_tmp_;

  void blur(vpImage<unsigned char>& image);
};

}  // namespace predvs
