// predvs — `dots`: blob tracking with ViSP's vpDot2, initialised automatically (no clicks).
//
// Detection (first image, and re-acquisition). The grey image is binarised at Otsu's threshold
// (the grey level that maximises the between-class variance of the histogram); the dots are the
// MINORITY class (fewer pixels), i.e. dark dots on a light target or bright dots on a dark one,
// unless `polarity` forces it (-1 dark, +1 bright, 0 minority). Candidates are the 4-connected
// components of that class whose bounding box is between `min_size_px` and `max_size_px` wide
// and high, that fill at least `min_fill` of their bounding box (a disc fills pi/4 = 0.785) and
// do not touch the border of the searched region, whose area over that of the ellipse of the same
// second moments C, area / (4 pi sqrt(det C)), is within [min_ellipticity, 2 - min_ellipticity]
// (1 for a filled ellipse: irregular patches of a cluttered scene fall below), and whose
// surround is plain: of 32 points on that ellipse scaled by 1.6, at most 2 are of the dots'
// class. A region whose two Otsu classes differ by less than 30 grey levels (a blank or uniform
// frame) has no candidate. Each candidate starts a vpDot2 at its pixel nearest to its
// centroid (vpDot2::initTracking: grey bounds from that pixel and `grey_precision`, ViSP's rule).
//
// Points and order. Without a hint, N = the dots found on the first image with any (or, with
// `points` = K > 0, the first image with at least K candidates, keeping the K whose areas are
// closest to the median area). They are ordered by rows then columns: sorted by v; a dot whose v
// is within `row_tolerance_px` (default: the median dot height) of the previous dot's v joins its
// row; each row is sorted by u. With a hint (2N pixels), N = hint points and each hint point takes
// the nearest unclaimed candidate (pairs taken in increasing distance), within `search_px`.
//
// Tracking. Each frame, every tracked dot runs vpDot2::track() (it follows the blob contour from
// the previous centre of gravity, and searches a window of 5x its size when that fails). The
// pixel position is the centre of gravity of the blob (sub-pixel, from its moments). A dot is
// lost when vpDot2 throws, when its centre leaves the image, or when it lands within half a dot
// size of another tracked dot (two dots on one blob: the one that moved more is lost).
//
// Re-acquisition rule. A lost dot is searched each frame by the detection above, in a square of
// half-side `search_px` centred on the hint point when a hint is given, else on its last tracked
// position; the nearest candidate not already tracked by another dot is taken. A dot is never
// re-initialised elsewhere than near where it was (or where the hint says): N and the order
// never change after initialisation.
//
// Parameters (`--set KEY=VALUE` of `predvs track`, `source:` keys in a scenario):
//   points (0 = all found on the first image), polarity (0), grey_precision (0.85, vpDot2's
//   setGrayLevelPrecision), size_precision (0.65), ellipse_precision (0.65, 0 disables the shape
//   test), min_size_px (8), max_size_px (100), min_fill (0.5), min_ellipticity (0.8), search_px (40),
//   row_tolerance_px (0 = the median dot height).
// Units: pixels (u right, v down, origin at the top-left pixel's centre as in ViSP).
#pragma once

#include "predvs/servo/image_tracker.h"

#include <visp3/blob/vpDot2.h>

#include <vector>

namespace predvs {

/// One blob found by detectDots(): centroid, bounding box size, pixel count and the pixel of the
/// blob nearest to its centroid (where vpDot2 starts).
struct DotCandidate {
  double u_px = 0.0, v_px = 0.0;
  double width_px = 0.0, height_px = 0.0;
  double area_px = 0.0;
  int seed_u = 0, seed_v = 0;
};

struct DotDetectionOptions {
  int polarity = 0;           ///< -1 dark dots, +1 bright dots, 0 the minority class
  double min_size_px = 8.0;   ///< bounding box width and height bounds
  double max_size_px = 100.0;
  double min_fill = 0.5;      ///< area / bounding box area
  double min_ellipticity = 0.8;  ///< area / (4 pi sqrt(det C)) within [e, 2 - e] (1: a filled ellipse)
};

/// The candidates in the rectangle [u0, u0+w) x [v0, v0+h) (clipped to the image), Otsu threshold
/// computed on that rectangle. `threshold_out` (optional) receives the threshold and the polarity
/// used (+1/-1). Candidates in detection order (scan order of their first pixel).
std::vector<DotCandidate> detectDots(const vpImage<unsigned char>& image, const DotDetectionOptions& options,
                                     int u0, int v0, int w, int h, int* polarity_out = nullptr);

class DotsTracker : public ImageTracker {
 public:
  /// Reads the parameters above; throws std::invalid_argument naming a bad or unknown key.
  DotsTracker(const Params& params, const ImageTrackerContext& context);
  std::string name() const override { return "dots"; }
  int points() const override { return static_cast<int>(dots_.size()); }
  std::vector<std::string> pointNames() const override;
  TrackedPoints track(const vpImage<unsigned char>& image, const Eigen::VectorXd* hint = nullptr) override;
  void reset() override;

 private:
  struct Dot {
    vpDot2 dot;
    bool tracked = false;
    double u_px = 0.0, v_px = 0.0;  ///< last tracked position
    double size_px = 0.0;           ///< max(width, height) at the last successful track
  };
  bool initialise(const vpImage<unsigned char>& image, const Eigen::VectorXd* hint, std::string& note);
  bool startDot(Dot& d, const vpImage<unsigned char>& image, const DotCandidate& c) const;
  bool reacquire(Dot& d, size_t index, const vpImage<unsigned char>& image, const Eigen::VectorXd* hint);

  DotDetectionOptions detection_;
  int expected_points_ = 0;
  double grey_precision_ = 0.85;
  double size_precision_ = 0.65;
  double ellipse_precision_ = 0.65;
  double search_px_ = 40.0;
  double row_tolerance_px_ = 0.0;
  int polarity_ = 0;  ///< the polarity found at initialisation (+1/-1), used when re-acquiring
  std::vector<Dot> dots_;
};

}  // namespace predvs
