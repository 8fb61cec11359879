// predvs calibration — the vision delay of a servo loop estimated from its log: commanded motion
// against observed feature motion (docs/MODELS.md §0, servo/timing_model.h).
//
// Data (LatencyLog): control ticks t_k with the command u_k acting over [t_k, t_{k+1}) (zero-order
// hold, m components: a camera twist, joint speeds, ...), and frames j with their features s_j
// (n channels, NaN = not seen), the time tau_j they were delivered to the controller and, when the
// log stamps it, their acquisition time t_acq_j.
//
// Model (our choice, documented here): the features of a frame are a smooth function of the robot's
// configuration when the frame was taken, and the configuration is the integral of the command,
// p(t) = integral_{t_0}^{t} u dt, with the robot at rest before the first logged tick (p = 0 there,
// true of `predvs servo` logs). The fit uses the start of motion, the first tick t_start with a
// non-zero command: the frames from the start of the log to t_start + max_delay_s + window_s.
// There the features are, for a delay candidate L,
//     s_j,c = a_c . p(tau_j - L) + sum_q b_q,c (tau_j - tau_0)^q + e_j,c     (each channel c)
// (a_c: locally constant Jacobian, on the principal directions of p over the window, those with a
// singular value at least 5 % of the largest, so that barely excited directions cannot fit noise;
// the polynomial, degree time_order, the target's own
// motion), fitted by least squares. The residual sum of squares RSS(L), summed over channels, is
// profiled over a grid of L (0 .. max_delay_s in steps of a tenth of the base period, p linear
// between ticks) and its minimum, refined by a parabola through the three lowest grid points, is
// the estimate: the features stay on their polynomial until L after the start, then bend with
// p. Why only the start: over a whole closed-loop run the command is itself a function of the
// delayed features (u = K(s)), so a regression of features on commands also finds the control
// law's path, and a free local Jacobian absorbs any shift of a smooth command; measured on the
// simulated loop, windowed fits over the whole run (levels, increments, increments with
// instrumental variables) all locked onto that path (about 0.01 s whatever the true delay), while
// the onset fit recovered every delay within 0.01 s. A log must therefore start at rest and then
// move (a constant command is rejected).
// Point model (options.point_model, `--camera` on the command line): when the features are image
// points and the command a camera twist, the feature motion between frames j-1 and j is known up
// to the points' depths: with (x, y) the normalised point at frame j-1, (V, W) the integral of
// (v, w) over [tau_{j-1} - L, tau_j - L] and rho_i = 1/Z_i,
//     du = px (rho_i (-Vx + x Vz) + x y Wx - (1 + x^2) Wy + y Wz) + target_u
//     dv = py (rho_i (-Vy + y Vz) + (1 + y^2) Wx - x y Wy - x Wz) + target_v
// (the interaction matrix of a point, ViSP's convention). Unknowns per window of point_window_s:
// rho_i per point and each channel's target velocity (a polynomial of degree time_order - 1).
// The rotation part has no free parameter and the depths are shared by all of a window's motion,
// so the control law's path (which a free Jacobian absorbed) cannot be fitted: the whole run is
// used, not only the start of motion.
// Uncertainty: the profile-likelihood interval {L : RSS(L) <= RSS_min (1 + 1/dof)} (dof =
// observations - parameters), one standard deviation for Gaussian residuals, taken from the
// lowest to the highest grid delay under that level (a profile with two valleys gives a wide
// interval); its half width is reported as sigma (at least grid step / sqrt(12)). Correlated
// residuals make it optimistic.
// Measured on the simulated default loop (docs/CALIBRATION.md has the table): the start-of-motion
// fit on `hold` runs, 33 of 35 (5 seeds x 7 timings) within one base period, the misses a dual-rate
// case (delta 20 ms, N = 2, 1 px noise) off by 2 and 3 base periods; on a run with the prediction
// path (kf-cv) it read 141 ms for 80. The point model read 7 to 12 ms short of every delay (hold
// and kf-cv), within a base period, with a stated sigma that leaves that bias out.
// What is measured: with delivery times, the total delay D between a command as logged and the
// delivered features that show its effect: the vision latency t_ac + t_p as the controller sees it
// (quantised to its release tick), plus whatever actuation lag lies between the logged command and
// the motion. With acquisition stamps the same fit against t_acq gives that actuation lag A alone
// (commands to camera motion), and the vision delay is D - A. `predvs servo` logs the command as
// applied to the robot (after t_c1 + t_c2), so on its logs A is about 0 and D is the vision delay.
// Units: seconds; features in the log's units (px), commands in theirs.
#pragma once

#include <string>
#include <vector>

namespace predvs {

struct LatencyLog {
  std::vector<double> tick_t_s;                   ///< control ticks, strictly increasing
  std::vector<std::vector<double>> command;       ///< per tick: the m command components acting from it
  std::vector<double> frame_delivery_s;           ///< per frame: delivery time (a tick time), increasing
  std::vector<double> frame_acquisition_s;        ///< per frame: acquisition stamp, or empty when unknown
  std::vector<std::vector<double>> features;      ///< per frame: n channels (NaN = not seen)
};

struct LatencyOptions {
  double max_delay_s = 0.3;  ///< grid upper end (s), > 0; a slower system needs more
  double window_s = 1.0;     ///< frames up to t_start + max_delay_s + window_s enter the fit (s)
  double step_s = 0.0;       ///< grid step (s); 0: a tenth of the median base period
  int time_order = 2;        ///< degree of the polynomial in time for the target's own motion
  /// Point model (below): the features are image points (u, v pairs, px) of a camera driven by a
  /// camera twist (vx vy vz wx wy wz), and the camera's intrinsics are known.
  bool point_model = false;
  double px = 800.0, py = 800.0, u0 = 320.0, v0 = 240.0;  ///< intrinsics for the point model (px)
  double point_window_s = 2.0;  ///< point model: windows over the whole log (s)
};

/// One profiled delay: the estimate, its jackknife standard deviation and the profile itself.
struct DelayEstimate {
  double delay_s = 0.0;
  double sigma_s = 0.0;        ///< half the 1-sigma profile interval (at least grid step / sqrt(12))
  double lo_s = 0.0, hi_s = 0.0;  ///< the profile interval: RSS <= RSS_min (1 + 1 / dof)
  std::vector<double> grid_s;  ///< candidate delays
  std::vector<double> rss;     ///< RSS per candidate (summed over windows and channels)
  int windows = 0;             ///< 1 (the start of motion)
  int frames = 0;              ///< frames that entered the fit
  int directions = 0;          ///< principal directions of the motion regressed on
  /// Fraction of the feature variance (about the polynomial in time) the best fit explains.
  double explained = 0.0;
};

struct LatencyResult {
  double base_period_s = 0.0;   ///< median tick spacing
  double frame_period_s = 0.0;  ///< median spacing of the frame deliveries
  DelayEstimate total;          ///< D: command as logged -> delivered features
  bool has_actuation = false;   ///< true when the log stamps acquisition times
  DelayEstimate actuation;      ///< A: command as logged -> features at their acquisition time
  double stamped_delay_s = 0.0; ///< median of delivery - acquisition stamps (NaN without stamps)
  double vision_delay_s = 0.0;  ///< D - A with stamps, D otherwise
  double vision_sigma_s = 0.0;  ///< its standard deviation (sqrt of the sum of the variances)
};

/// Estimates the delays (model above). Throws std::invalid_argument with a one-line reason when
/// the log cannot carry the information: fewer than 2 ticks or frames, sizes that disagree, times
/// not increasing, commands or features that never change, too few frames around the start of
/// motion, a profile without a minimum inside the grid, or bad options.
LatencyResult estimateLatency(const LatencyLog& log, const LatencyOptions& options = {});

}  // namespace predvs
