// predvs app — `predvs calibrate camera` and `predvs calibrate latency` (calibration/ does the
// work; this reads the inputs, prints, and writes the outputs through a StagedOutputDir, so a
// failure leaves no output directory).
//
// predvs calibrate camera --images PATTERN|DIR --pattern circles|chessboard|apriltag
//                         [--rows R --cols C --spacing M] [--diameter M] [--tag-size M]
//                         [--name NAME] [--out DIR=out/calibration/camera] [--no-plots]
//   Images: a directory (every .pgm .ppm .png .jpg .jpeg .bmp .tif .tiff in it, sorted by name),
//   a glob pattern (quoted: 'dir/grid36-*.pgm') or one file. Every image must be readable and of
//   the same size (else an error); an image where the pattern is not found is rejected by name
//   and left out; fewer than 3 remaining is an error. Defaults: 6 x 6, spacing 0.03 m (ViSP's
//   grid2d.pdf, the grid36 images); --diameter of the dots (circles; default 2/3 of the spacing);
//   --tag-size (apriltag; default 0.8 of the spacing).
//   Writes camera.xml (ViSP, camera NAME (default "camera") with perspectiveProjWithoutDistortion
//   and perspectiveProjWithDistortion models: `--camera DIR/camera.xml` of servo and compare),
//   camera.yaml (OpenCV: camera_matrix, distortion_coefficients k1 k2 p1 p2 k3), residuals.csv
//   (image, point, u_px, v_px, du_px, dv_px of the full model), summary.json (the three models,
//   RMS per image, rejected images, the command line) and residuals.png (one panel per image:
//   every point with its residual vector magnified, with its gnuplot script and data).
//   Prints the per-image and overall RMS and the three models.
//
// predvs calibrate latency --log LOG.csv [--predictor NAME] [--commands A,B,...]
//                          [--camera FILE [--camera-name NAME] | --intrinsics PX,PY,U0,V0]
//                          [--max-delay-s S=0.3] [--window-s S=1] [--out DIR=out/calibration/latency]
//                          [--no-plots]
//   Without intrinsics: the generic fit around the start of motion; with them (image points and a
//   camera twist): the point model over the whole run (calibration/latency_estimation.h).
//   The log: `predvs servo`'s log.csv (docs/CALIBRATION.md, "The servo log"): columns t_s,
//   t_acq_s (optional), meas_<f>... (features), the command columns (default: those of vx vy vz
//   wx wy wz present; --commands names others, e.g. a joint-speed robot's), and `predictor` (the
//   run used: --predictor, default the first in the file). A frame is a row whose t_acq_s differs
//   from the previous row's (without t_acq_s: whose features differ).
//   Writes timing.yaml (a scenario fragment for `--set-file`: timing.base_period_s,
//   frame_period_n, acquisition_lag_s = processing_lag_s = half the vision delay rounded to the
//   nearest base period, delay_frames removed; controller_lag_s when the log has acquisition
//   stamps), latency.json (the estimates, their uncertainty, the profile) and profile.png (the
//   fit's residual sum of squares versus the delay).
#pragma once

#include <ostream>
#include <string>

namespace predvs {

struct CalibrateCameraOptions {
  std::string images;
  std::string pattern = "circles";
  int rows = 6, cols = 6;
  double spacing_m = 0.03;
  double diameter_m = 0.0;  ///< circles; 0 = not given (2/3 of the spacing)
  double tag_size_m = 0.0;  ///< apriltag; 0 = not given (0.8 of the spacing)
  std::string name = "camera";
  std::string out_dir = "out/calibration/camera";
  bool plots = true;
  std::string command_line;
};

struct CalibrateLatencyOptions {
  std::string log;
  std::string predictor;
  std::string commands;  ///< comma-separated; empty: the camera-twist names present
  double max_delay_s = 0.3;
  double window_s = 1.0;
  std::string camera;       ///< ViSP XML: the point model with its intrinsics (latency_estimation.h)
  std::string camera_name;
  std::string intrinsics;   ///< "px,py,u0,v0": the point model with these intrinsics
  std::string out_dir = "out/calibration/latency";
  bool plots = true;
  std::string command_line;
};

void runCalibrateCamera(const CalibrateCameraOptions& options, std::ostream& out, std::ostream& err);
void runCalibrateLatency(const CalibrateLatencyOptions& options, std::ostream& out, std::ostream& err);

}  // namespace predvs
