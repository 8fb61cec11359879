// predvs — error metrics shared by the open-loop prediction experiment and the closed loop
// (the figures the papers' experiments report, docs/MODELS.md §10: RMSE, final error, peak error,
// convergence time, integrated absolute error, control effort).
//
// Input: a scalar error e(t_i) >= 0 per step on a uniform or non-uniform time grid (open loop:
// the Euclidean prediction error in the target's units; closed loop: the RMS over the four points
// of the pixel distance between the true and the desired features), and optionally the camera
// velocity command v(t_i) (closed loop).
//
// Definitions (choices, documented):
//  * steady window: t >= t_0 + steady_start_fraction * (t_end - t_0) (default: the second half of
//    the run), so the initial transient (filter initialisation, visual-servo convergence) does
//    not enter the steady-state figures. rmse_px and max_error_px are over this window.
//  * final_error: mean of e over the last 10 % of the run (t >= t_0 + 0.9 (t_end - t_0)).
//  * iae: integral of e dt over the whole run (rectangle rule with the step to the next sample).
//  * settling_time_s: on the trailing mean m(t) of e over settling_smoothing_s (0.5 s by default;
//    0 = raw e), the first time after which m stays at or below
//        m_final + max(settling_band * (m_peak - m_final), 3 sd_final),  settling_band = 0.05,
//    measured from t_0, where m_peak is the maximum of m over the run, m_final and sd_final the
//    mean and standard deviation of m over the final window; NaN if m ends above it. (A band
//    relative to the excursion, because the tracking error of a moving target does not go to
//    zero; the smoothing and the 3-sigma floor keep measurement noise from deciding it.)
//  * control_effort: sum of ||u||^2 dt over the whole run, u the applied command in the robot's
//    command space ((m/s)^2 s + (rad/s)^2 s mixed as ViSP's 6-vector for a camera twist); NaN
//    when no command is given (open loop).
#pragma once

#include "predvs/predictors/params.h"

#include <Eigen/Core>

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace predvs {

struct MetricsOptions {
  double steady_start_fraction = 0.5;  ///< start of the steady window, fraction of the run (metrics.steady_start_fraction)
  double final_fraction = 0.1;         ///< length of the final window, fraction of the run (metrics.final_fraction)
  double settling_band = 0.05;         ///< settling band, fraction of (e_peak - e_final) (metrics.settling_band)
  double settling_smoothing_s = 0.5;   ///< trailing-mean window for the settling time, s (metrics.settling_smoothing_s)
  /// Window after a manoeuvre over which the response's lag and overshoot are taken, s
  /// (metrics.response_window_s, > 0; see ResponseMetrics). 3 s: long enough for every predictor
  /// of E1-E3 to react to the change, short enough that the measurement noise of the rest of a
  /// 20 s run does not decide the maxima.
  double response_window_s = 3.0;
  /// Closed loop: also report every feature's own error e_f = s_f - s*_f over the steady window
  /// (metrics.per_feature; see featureErrorValues()).
  bool per_feature = false;
  /// Closed loop: the outcome of a positioning run, converged / failed (metrics.outcome; see
  /// Outcome below). Off by default, so that the figures of a scenario that does not ask for it
  /// are exactly those it had before (no added names, no early stop).
  bool outcome = false;
  double converge_px = 1.0;         ///< convergence threshold on e (metrics.converge_px), > 0
  double converge_hold_s = 1.0;     ///< least time e stays at or below it before the end (metrics.converge_hold_s), >= 0
  bool fail_outside_image = true;   ///< a true point outside the image is a failure (metrics.fail_outside_image)
  bool fail_robot_limit = true;     ///< the robot at a hard limit is a failure (metrics.fail_robot_limit)
};

struct Metrics {
  double rmse = std::numeric_limits<double>::quiet_NaN();             ///< sqrt(mean e^2) over the steady window
  double final_error = std::numeric_limits<double>::quiet_NaN();      ///< mean e over the final window
  double max_error = std::numeric_limits<double>::quiet_NaN();        ///< max e over the steady window
  double peak_error = std::numeric_limits<double>::quiet_NaN();       ///< max e over the whole run
  double iae = std::numeric_limits<double>::quiet_NaN();              ///< integral of e dt, whole run
  double settling_time_s = std::numeric_limits<double>::quiet_NaN();  ///< see header comment
  double control_effort = std::numeric_limits<double>::quiet_NaN();   ///< sum ||v||^2 dt (closed loop)
  int steady_samples = 0;                                             ///< samples in the steady window
};

/// Computes the metrics of e(t) (NaN entries of e are skipped: e.g. before the first prediction).
/// `t_s` and `error` must have the same size (std::invalid_argument otherwise); `velocity`, when
/// not null, holds one command vector per sample. Options out of (0, 1) throw std::invalid_argument
/// naming metrics.<key>.
Metrics computeMetrics(const std::vector<double>& t_s, const std::vector<double>& error,
                       const MetricsOptions& options = {},
                       const std::vector<Eigen::VectorXd>* velocity = nullptr);

/// Per-feature error figures over the steady window (same window as rmse): for every feature f of
/// `names`, mean_e_<f> (signed mean of s_f - s*_f: a steady offset), rms_e_<f> and max_e_<f> (largest
/// |s_f - s*_f|). `features` holds one feature vector per sample (NaN entries skipped).
NamedValues featureErrorValues(const std::vector<double>& t_s, const std::vector<Eigen::VectorXd>& features,
                               const Eigen::VectorXd& desired, const std::vector<std::string>& names,
                               const MetricsOptions& options = {});

/// Figures of a run with occlusions, from the error e and, per sample, whether the latest
/// delivered frame was lost: occl_rmse, occl_max (RMS / max of e while it is lost),
/// occl_end_error (e at the last tick before a frame is delivered again), reacq_error (e at the
/// first tick after) and reacq_1s_rmse (RMS of e over the 1 s from there); the last three are
/// means over the occlusions of the run. NaN entries of e are skipped.
NamedValues occlusionValues(const std::vector<double>& t_s, const std::vector<double>& e, const std::vector<bool>& lost);
/// {"lost_policy_s", T}: T = the time (s) during which the lost-feature policy held or dropped at
/// least one channel (lost_feature_policy.h): the number of samples flagged in `expired` times the
/// sample period `period_s`. 0 with lost.action extrapolate.
std::pair<std::string, double> lostPolicyValue(const std::vector<bool>& expired, double period_s);

/// The metrics as named values, the names every report uses (predvs servo and compare):
/// rmse, final, max, peak, iae, settling_s, effort (the fields above, in that order).
NamedValues metricValues(const Metrics& m);

/// The outcome of a closed-loop positioning run (metrics.outcome; paper 003 §4.1, docs/MODELS.md §10 E10:
/// "converges where ... fails", the reachable region over (lambda, frame period)).
///
/// Failure (divergence), checked by the loop on the TRUE state after every control step (and at
/// t = 0), first match wins:
///   behind     some target point has depth Z <= 0 in the camera frame (the camera came through the
///              object plane: the failure of docs/MODELS.md §11 E10);
///   image      with fail_outside_image, some point's true projection (u, v) is outside the image
///              0 <= u < width, 0 <= v < height (camera.width / camera.height, servo_loop.h);
///   robot      with fail_robot_limit, the robot reports that it is at a hard limit (Robot::atLimit():
///              an arm joint against its stop; robots without hard limits never are).
/// The run stops at the first failing state: its trace ends at the last tick before it, and
/// failure_time_s is the time of that state (0 when the initial pose already fails). A failed run
/// has no steady state: its steady-window figures (rmse, final, max, settling_s and the per-feature
/// errors) are NaN, while peak, iae and effort cover the run up to the failure. Aggregates over runs
/// skip NaN, so a median rmse over runs is the median over the runs that did not fail (its n says
/// how many).
///
/// Convergence: the run did not fail, and from some sample time t_c to the end of the run every
/// error sample is at or below converge_px, with t_end - t_c >= converge_hold_s (the run's duration
/// is the time limit; the hold keeps a dip at the last tick from counting). convergence_time_s =
/// t_c - t_0, the start of that final stretch below the threshold (NaN when not converged). The
/// error is of the true features (the loop's tracking error), so image noise does not make it cross
/// the threshold by itself.
enum class FailureKind { None, Behind, OutsideImage, RobotLimit };

struct Outcome {
  bool converged = false;
  double convergence_time_s = std::numeric_limits<double>::quiet_NaN();
  FailureKind failure = FailureKind::None;
  double failure_time_s = std::numeric_limits<double>::quiet_NaN();
  bool failed() const { return failure != FailureKind::None; }
};

/// The outcome of a run from its error samples e(t_i) (t_s increasing; NaN counts as above the
/// threshold) and the failure the loop detected (None, or the kind and its time). Throws
/// std::invalid_argument naming metrics.converge_px / metrics.converge_hold_s when out of range,
/// or when t_s and error differ in size.
Outcome computeOutcome(const std::vector<double>& t_s, const std::vector<double>& error, FailureKind failure,
                       double failure_time_s, const MetricsOptions& options);

/// The outcome as named values, in this order: converged (1/0), convergence_time_s (NaN unless
/// converged), failed (1/0), failure_time_s (NaN unless failed), fail_behind, fail_image,
/// fail_robot (1 for the kind of failure, else 0: their means over runs are the fraction of runs
/// failing that way).
NamedValues outcomeValues(const Outcome& outcome);

/// The metrics of a failed run: the steady-window figures (rmse, final, max, settling_s) set to
/// NaN, the others kept (see Outcome).
Metrics withoutSteadyState(Metrics m);

/// Response of a predictor to a manoeuvre, the figures paper 000 §6.1 compares on E1-E3 ("fastest
/// response, smallest overshoot"). Input per sample: |e_i| and the signed error along the unit
/// direction d of the change, s_i = (x_hat_i - x_i) . d, negative while the estimate lags behind the
/// change and positive when it overshoots it. Both are judged over the window [t_change_s,
/// t_change_s + options.response_window_s] (3 s by default), on trailing means over
/// options.settling_smoothing_s of the samples from t_change_s on (so that one noisy sample does
/// not decide them, and the rest of a long run, where only noise is left, does not either):
///  * max_lag     largest -mean(s) (>= 0) in the window, the worst lag behind the change;
///  * overshoot   largest +mean(s) (>= 0) in the window, the worst overshoot past it;
///  * mean_after  mean of |e| over [t_change, t_change + window_s];
///  * response_s  settling time (header definition, options.settling_band) of |e| restricted to
///                t >= t_change, measured from t_change: how long the predictor takes to follow.
/// NaN fields when no finite sample lies at or after t_change.
struct ResponseMetrics {
  double max_lag = std::numeric_limits<double>::quiet_NaN();
  double overshoot = std::numeric_limits<double>::quiet_NaN();
  double mean_after = std::numeric_limits<double>::quiet_NaN();
  double response_s = std::numeric_limits<double>::quiet_NaN();
};

/// Default window of ResponseMetrics::mean_after (s): the 3 s after the change.
constexpr double kResponseWindowS = 3.0;

/// Computes ResponseMetrics (t_s, error and signed_error of equal size, std::invalid_argument
/// otherwise; NaN entries are skipped).
ResponseMetrics computeResponse(const std::vector<double>& t_s, const std::vector<double>& error,
                                const std::vector<double>& signed_error, double t_change_s,
                                const MetricsOptions& options = {}, double window_s = kResponseWindowS);

}  // namespace predvs
