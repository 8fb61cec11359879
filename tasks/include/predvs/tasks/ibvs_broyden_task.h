// predvs — `ibvs-broyden`: uncalibrated IBVS of image points with an online Jacobian estimate
// and optional delay compensation (docs/MODELS.md §7, §10 E9; paper 002 §2-3, after Piepmeier et al.).
//
// Uncalibrated: the law uses no camera model, no depth and no robot Jacobian. Its model is the
// estimate J (2N features x m commands) of ds/du, learnt by a JacobianEstimator (rls or broyden)
// from what the robot actually did. With e = s - s* and ft the target's own image rate,
// de/dt = J u + ft, so the law
//     u = J^+ (-K e - ft)
// makes e decay as exp(-K t) when J is right. J^+ is a damped least-squares inverse:
//     J^+ r = V diag(sigma_i / (sigma_i^2 + mu^2)) U' r,   mu = damping * sigma_max(J),
// so a singular or badly estimated J gives a bounded command, never an exception (J = 0, e.g.
// before anything was learnt, gives u = 0). Lost features (NaN) drop their rows from the law.
//
// Learning (docs/MODELS.md §7, "pairing under delay"): observe() pairs each MEASURED feature increment
// between two consecutive delivered measurements with the increment of the command integral p
// (TaskMeasurement::command_integral) between the SAME acquisition times; the image is old but p
// at its acquisition time is known, so the pair is consistent whatever the delay. Predicted
// features are never fed to the estimator (a prediction already contains J dp: the update would
// feed on itself). The target term of the update is ft dt with dt the time between the two
// acquisitions and ft the mean of the predictor's target rates at them
// (TaskMeasurement::target_rate, the filtered velocity of s - E once each frame is fused), i.e. the
// target's own motion over the increment itself; zero when the loop gives none or when delay
// compensation is off. (An earlier version used its latest forecast at the effect time, about the
// delay later than the increment; docs/REPRODUCTION.md, E9, says what the change bought.)
//
// Delay compensation (`delay_compensation`, 1 = on, default): act on in.used (the loop's forecast
// of the features at the effect time) and feed forward in.target_rate. 0 = off, the uncompensated
// baseline of paper 002: act on in.measured (the latest, delayed image), no feed-forward, and ft = 0
// in the update too, so the baseline uses no predictor information at all.
//
// Initial estimate (`init`):
//  * `explore` (default): fully uncalibrated. From the first tick the robot makes small probe
//    moves, one input axis after the other: +probe_speed for probe_frames vision periods, then
//    -probe_speed as long (back to the start), starting from J = 0 with P0 = p0 I; the estimator
//    learns from these increments through observe() like from any other. The law takes over once
//    a measurement acquired at least one frame after the last probe has been observed (so the
//    last axis has been seen despite the vision delay). Chosen as default because it is what a
//    real uncalibrated system does (paper 002's ref. [3] also uses trial moves) and it needs no
//    ground truth. Cost: 2 m probe_frames frames plus the delay before servoing starts.
//    Exploration and the target term: increments observed while probing are learnt with ft = 0,
//    in both modes. A probe pair (+dp then -dp, one frame each) cancels a target moving at a
//    steady rate by itself: least squares over the pair gives J dp = (df+ - df-) / 2, in which the
//    two ft T terms cancel (up to the change of ft over one frame). The loop's forecast rate, on
//    the other hand, is then contaminated by the probes themselves: it is the rate of f - E with
//    E = integral of J u, and J is still (close to) zero, so the probe motion is not compensated
//    and part of it would be subtracted from the very increment that should teach it (measured on
//    e9-broyden when the choice was made: a worse median error and final Jacobian error with it).
//  * `model`: EXPERIMENTAL initialisation for studies only. J0 = J_true .* (1 + model_error U),
//    U uniform in [-1, 1] per entry (seeded with the context seed), J_true = in.true_point_jacobian
//    of the first tick. TaskInput calls that matrix ground truth for diagnostics; this is the one
//    documented exception, for experiments such as "started from the truth, does it stay there"
//    (docs/MODELS.md §11 E9). Increments observed before the first tick are not learnt.
//
// Parameters (task.<key>): gain (K, 1/s, > 0, default 1), method (rls | broyden, default rls),
// lambda (forgetting, (0, 1], default 0.99: a memory of ~100 increments), min_dp (skip threshold on
// |dp| in p's units, default 1e-3: 1 mm or 1 mrad per frame, ~1.6 px at 0.5 m and f = 800 px,
// above the 0.5 px noise; below it an increment teaches noise), p0 (P0 = p0 I, default 1e6: the
// first probe increment of 5e-3 gets weight p0 |dp|^2 = 25 against the prior, i.e. it is ~96 %
// believed), damping (mu / sigma_max, default 1e-2), delay_compensation (0 | 1, default 1),
// init (explore | model), probe_speed (command units, default 0.05), probe_frames (>= 1, default 1),
// model_error (>= 0, default 0.2; init = model only).
// lambda and damping defaults were chosen on an E9-like run (free camera 0.5 m from a 10 cm
// square moving on 5 cm sinusoids at 0.1 / 0.15 Hz, T = 0.1 s, 2-frame delay, 0.5 px noise, perfect
// forecast, 3 seeds, K = 1..6 /s): lambda 0.95 or damping 1e-3 let the estimate wind up in the
// directions the tracking motion does not excite and some runs diverged at K = 4..6 /s;
// lambda 0.99 with damping 1e-2 converged in every run (steady RMS 3.6 px at K = 1 down to 0.9 px
// at K = 6 with compensation; 15-78 px without, which diverges beyond K T ~ 0.6).
// Diagnostics per tick: jacobian_error = ||J_hat - J_true||_F / ||J_true||_F (J_true from
// in.true_point_jacobian, NaN when absent), updated (1 when an update happened since the last
// command), exploring (1 while probing). Run summary: jacobian_error_final (mean over the last 10 %
// of ticks, NaN ticks ignored), jacobian_updates.
#pragma once

#include "predvs/predictors/params.h"
#include "predvs/tasks/jacobian_estimator.h"
#include "predvs/tasks/point_task.h"

#include <Eigen/Core>

#include <limits>
#include <string>
#include <vector>

namespace predvs {

class IbvsBroydenTask : public PointTask {
 public:
  enum class Init { Explore, Model };

  /// Throws std::invalid_argument naming the key in quotes ("parameter 'gain' must be > 0, got 0":
  /// the app points a quoted key at its line in the scenario file) on a bad or unknown parameter,
  /// or on an empty command space.
  IbvsBroydenTask(const Params& params, const TaskContext& context);

  std::string name() const override { return "ibvs-broyden"; }
  void observe(const TaskMeasurement& m) override;
  Eigen::VectorXd computeCommand(const TaskInput& in) override;
  /// The current estimate J_hat (2N x m).
  const Eigen::MatrixXd& featureJacobian() const override { return estimator_.jacobian(); }
  /// NaN rows of the error (dropped features) are left out of the damped solve.
  bool canDropFeatures() const override { return true; }
  NamedValues diagnostics() const override;
  bool needsTrueJacobian() const override { return true; }
  NamedValues runSummary() const override;

  const JacobianEstimator& estimator() const { return estimator_; }
  bool exploring() const { return exploring_; }

  /// u = J^+ r with the damped pseudo-inverse above (rows of r that are not finite are dropped).
  static Eigen::VectorXd dampedSolve(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, double damping);

 private:
  Eigen::VectorXd probeCommand(double t_s) const;

  double gain_;
  double damping_;
  bool compensation_;
  Init init_;
  double probe_speed_;
  int probe_frames_;
  double model_error_;
  double p0_;
  int inputs_;
  JacobianEstimator estimator_;

  bool started_ = false;       // first computeCommand() seen
  bool learning_ = false;      // observe() may update the estimator
  bool exploring_ = false;
  double t0_s_ = 0.0;
  double last_t_acq_s_ = -1e300;
  bool has_prev_ = false;
  double prev_t_acq_s_ = 0.0;
  Eigen::VectorXd prev_features_, prev_p_;
  Eigen::VectorXd prev_rate_;  // TaskMeasurement::target_rate of the previous observed frame
  bool updated_since_command_ = false;
  bool updated_ = false;
  double jacobian_error_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> jacobian_errors_;
};

}  // namespace predvs
