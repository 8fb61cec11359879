// predvs — the timing and delay model of a (dual-rate) visual servo loop (docs/MODELS.md §0;
// paper 000 §2, paper 002 §2, paper 003 §2.1).
//
// One explicit object decides every time in the loop:
//  * the controller ticks every base period delta (t_k = k * delta);
//  * the camera acquires a frame every T = N * delta, at the ticks k = 0, N, 2N, ...;
//  * a frame acquired at t_acq is usable at t_acq + t_ac + t_p (acquisition + processing lag),
//    i.e. from the first control tick at or after that instant (its release tick);
//  * a command computed at t_c starts acting on the robot at t_c + t_c1 + t_c2 (controller output
//    lag + joint-servo lag), from the first control tick at or after that instant; the motion it
//    causes then takes t_m (motion lag), whose midpoint t_m / 2 is added when it is modelled;
//  * the predictor must therefore forecast a feature measured at t_acq over the horizon
//        h(t_now, t_acq) = (t_now - t_acq) + t_c1 + t_c2 (+ t_m / 2),
//    i.e. to the effect time t_now + t_c1 + t_c2 (+ t_m / 2). In frames (paper 002) this is the
//    forecast x(k + h | k) with h = horizon / T (not necessarily an integer in the dual-rate case).
//
// Pipelines (paper 000 Fig. 1): `serial` processes a frame after it is acquired, so a new frame
// can start only every t_ac + t_p; `parallel` (double-buffered) acquires the next frame while the
// previous one is processed, so the frame period only needs max(t_ac, t_p) while the latency stays
// t_ac + t_p. The constructor rejects a frame period T shorter than the pipeline allows.
#pragma once

#include <string>

namespace predvs {

/// How image acquisition and processing overlap (paper 000 Fig. 1).
enum class Pipeline {
  Serial,    ///< acquire, then process: minimum frame period t_ac + t_p
  Parallel,  ///< double-buffered: minimum frame period max(t_ac, t_p), latency still t_ac + t_p
};

/// "serial" / "parallel" (case-sensitive); throws std::invalid_argument naming timing.pipeline.
Pipeline parsePipeline(const std::string& name);
std::string pipelineName(Pipeline p);

/// Plain configuration, filled by the app. Keys (YAML: `timing.<key>`) and defaults: the default
/// scenario of predvs, delta = T = 40 ms and a two-frame vision latency of 80 ms, no command lag.
struct TimingConfig {
  double base_period_s = 0.04;      ///< delta, control period (timing.base_period_s), > 0
  int frame_period_n = 1;           ///< N >= 1, vision period T = N * delta (timing.frame_period_n)
  double acquisition_lag_s = 0.04;  ///< t_ac >= 0 (timing.acquisition_lag_s)
  double processing_lag_s = 0.04;   ///< t_p >= 0 (timing.processing_lag_s)
  double controller_lag_s = 0.0;    ///< t_c1 >= 0 (timing.controller_lag_s)
  double servo_lag_s = 0.0;         ///< t_c2 >= 0 (timing.servo_lag_s)
  double motion_lag_s = 0.0;        ///< t_m >= 0 (timing.motion_lag_s)
  bool model_motion_lag = false;    ///< add t_m / 2 to the horizon (timing.model_motion_lag)
  Pipeline pipeline = Pipeline::Parallel;  ///< (timing.pipeline: serial | parallel)
};

class TimingModel {
 public:
  /// Validates the configuration: throws std::invalid_argument with a message naming the key,
  /// e.g. "timing.frame_period_n must be >= 1, got 0", or, for an infeasible pipeline,
  /// "timing.frame_period_n: frame period T = 0.04 s is shorter than the serial pipeline needs
  /// (t_ac + t_p = 0.08 s)".
  explicit TimingModel(const TimingConfig& config = {});

  const TimingConfig& config() const { return config_; }
  double basePeriod() const { return config_.base_period_s; }       ///< delta (s)
  int framePeriodTicks() const { return config_.frame_period_n; }   ///< N
  double framePeriod() const;                                       ///< T = N * delta (s)
  /// Vision latency t_ac + t_p (s).
  double visionLatency() const;
  /// Command lag t_c1 + t_c2 (s).
  double commandLag() const;
  /// Minimum frame period the pipeline allows: t_ac + t_p (serial) or max(t_ac, t_p) (parallel).
  double minimumFramePeriod() const;

  /// Time of control tick k: k * delta.
  double tickTime(long k) const;
  /// Index of the first control tick at or after t_s (a 1e-9 relative tolerance absorbs rounding).
  long tickAtOrAfter(double t_s) const;
  /// True when a frame is acquired at tick k (k multiple of N).
  bool isAcquisitionTick(long k) const;

  /// Instant a frame acquired at t_acq becomes usable: t_acq + t_ac + t_p.
  double availableTime(double t_acq_s) const;
  /// Control tick from which the frame acquired at t_acq is delivered (first tick at or after
  /// availableTime(t_acq)).
  long releaseTick(double t_acq_s) const;
  /// tickTime(releaseTick(t_acq)).
  double releaseTime(double t_acq_s) const;

  /// Control tick from which a command computed at tick k acts: first tick at or after
  /// t_k + t_c1 + t_c2.
  long commandApplyTick(long k) const;
  /// Time the command computed at t_c takes effect, i.e. the time the predictor aims at:
  /// t_c + t_c1 + t_c2 (+ t_m / 2 if the motion lag is modelled).
  double effectTime(double t_c_s) const;
  /// Prediction horizon for a measurement acquired at t_acq used by a command computed at t_now:
  /// (t_now - t_acq) + t_c1 + t_c2 (+ t_m / 2). Throws std::invalid_argument if t_now < t_acq.
  double horizon(double t_now_s, double t_acq_s) const;
  /// The same horizon in frames, h in x(k + h | k): horizon / T.
  double horizonFrames(double t_now_s, double t_acq_s) const;
  /// Horizon in frames of the freshest measurement at an acquisition-aligned release, i.e. with
  /// t_now = releaseTime(t_acq): the constant h of paper 002 for this configuration.
  double nominalHorizonFrames() const;
  /// The longest horizon in frames the loop asks of the freshest measurement: at the last control
  /// tick before the next frame's release, nominalHorizonFrames() + (N - 1) / N.
  double longestHorizonFrames() const;

 private:
  TimingConfig config_;
};

}  // namespace predvs
