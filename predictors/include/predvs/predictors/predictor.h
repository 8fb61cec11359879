// predvs — the predictor interface.
//
// A predictor sits ahead of the servo task: it fuses time-stamped (delayed) feature measurements
// and answers "where will each feature be at time t" so the task can act on where the target will
// be when the command takes effect, not where it was when the image was taken (docs/MODELS.md §0).
//
// Conventions
//  * A predictor tracks `channels()` independent scalar signals (for the servo loop: u and v of
//    every image point; for E6: x_i, y_i, d_x). Each channel has its own Gaussian state
//    [p, v] or [p, v, a] (at most 3 states).
//  * Every measurement carries its acquisition time t_s (seconds). Times passed to update() must
//    be strictly increasing; update() with a time not after the last one throws std::invalid_argument.
//  * update(t, z) predicts to t and fuses z; a NaN entry in z means "this channel was not measured"
//    (predict-only for that channel). update(t) with no z is predict-only for every channel
//    (occlusion, dropped frame).
//  * predict(channel, t) is const: it never changes the filter. It answers for any t at or after the
//    last update time (t before the last update is clamped to the filter time: no smoothing).
//  * Before the first measurement a channel is uninitialised: predict() returns NaN position.
#pragma once

#include "predvs/predictors/params.h"

#include <Eigen/Core>

#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace predvs {

/// State vector of one channel: [p, v] or [p, v, a]; fixed maximum size, no heap allocation.
using ChannelVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1>;
/// Covariance of one channel's state; fixed maximum size 3x3, no heap allocation.
using ChannelMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;

/// Gaussian estimate of one channel at a given time.
struct ChannelEstimate {
  ChannelVector x;  ///< [position, velocity(, acceleration)] in the channel's units (px, px/s, px/s^2)
  ChannelMatrix P;  ///< covariance of x
  double position() const { return x.size() > 0 ? x(0) : std::numeric_limits<double>::quiet_NaN(); }
  double velocity() const { return x.size() > 1 ? x(1) : 0.0; }
  double positionVariance() const { return P.size() > 0 ? P(0, 0) : std::numeric_limits<double>::quiet_NaN(); }
};

/// Innovation of the last update of one channel: eps = z - H x(k|k-1), S = H P(k|k-1) H' + R.
/// `valid` is false when the channel was not measured at the last update.
struct Innovation {
  double eps = 0.0;
  double S = 0.0;
  bool valid = false;
};

/// One parameter that sets a predictor's process or measurement noise, as a noise fit tunes it
/// (calibration/noise_fit.h: positive, on a log scale).
struct NoiseParameter {
  std::string key;  ///< the Params key that sets it, e.g. "q" or "r"
  double lo = 0.0;  ///< bounds of the value itself (not of its log), 0 < lo < hi
  double hi = 0.0;
  double value = 0.0;  ///< the value this instance runs with (may lie outside [lo, hi] if built so)
};

/// One value that can seed (warm-start) a noise fit of a structure from the fit of another
/// predictor on the same rows (calibration/noise_fit.h, NoiseFitOptions::seed_fits):
///   start value of `key` = factor * (fitted value of `from_key` of `from_predictor`)^power.
/// The map is by meaning: the same quantity (e.g. kf-cv's white-acceleration density q seeds the q
/// of a cv structure), or one computed from it (cs-akf's a_max gives the CS variance (4-pi)/pi
/// a_max^2 at zero acceleration).
struct FitSeed {
  std::string key;             ///< this predictor's Params key (one of its noiseParameters())
  std::string from_predictor;  ///< registry name of the fixed predictor whose fitted value is used
  std::string from_key;        ///< that predictor's Params key
  double factor = 1.0;
  double power = 1.0;
  /// Which warm start the value belongs to: the seeds of one structure with the same index form
  /// one start point (one more local fit each, in increasing index), e.g. a CS structure seeded
  /// once from cs-akf (index 0) and once from kf-ca (index 1). Default 0: a single warm start.
  int start = 0;
  /// Only ever raises the key's start value, to max(start value, seeded value): a ceiling lifted to
  /// a floor seeded above it, so that the start point is feasible (cs_akf.cpp, fitSeeds).
  bool raise_only = false;
};

class Predictor {
 public:
  virtual ~Predictor() = default;

  /// Registry name, e.g. "kf-cv".
  virtual std::string name() const = 0;
  /// Number of independent scalar channels.
  int channels() const { return channels_; }

  /// Back to the state after construction: every channel uninitialised, adaptive terms reset.
  virtual void reset() = 0;
  /// Predict to the acquisition time t_s and fuse z (size channels(); NaN = channel not measured).
  virtual void update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) = 0;
  /// Predict-only step to t_s (no measurement at all: occlusion or dropped frame).
  void update(double t_s);
  /// Estimate of `channel` at time t_s (>= last update time), without changing the filter.
  virtual ChannelEstimate predict(int channel, double t_s) const = 0;
  /// Just the position of predict(channel, t_s), the same number (bit for bit). A filter may
  /// override it to skip the covariance (the per-channel Kalman filters do); the default asks predict().
  virtual double predictPosition(int channel, double t_s) const { return predict(channel, t_s).position(); }
  /// Just the velocity of predict(channel, t_s), the same number (bit for bit). As for
  /// predictPosition(), a filter may override it to skip the covariance (the per-channel Kalman
  /// filters and the glitch gate do).
  virtual double predictVelocity(int channel, double t_s) const { return predict(channel, t_s).velocity(); }
  /// The target's velocity at t_s for a feed-forward: what the servo loop feeds a control law in its
  /// `feedforward` mode, and the target rate a task observes there (servo_loop.h). It is the
  /// filter's own velocity, not scaled by the forecast's blend with hold: the blend judges position
  /// forecasts a few frames ahead, where a slow target's velocity is mostly noise, and scales it
  /// towards 0, while a law integrates its feed-forward over its own time constant, which averages
  /// that noise out. The per-channel filters judge it at that time scale instead (docs/MODELS.md §15,
  /// "The feed-forward's velocity"). Default: predictVelocity(), for a predictor without a blend.
  virtual double feedforwardVelocity(int channel, double t_s) const { return predictVelocity(channel, t_s); }
  /// Innovation of the last update on `channel`.
  virtual Innovation innovation(int channel) const = 0;
  /// A copy in the current state, fed the same measurements from here on it gives the same bits
  /// (the glitch gate, glitch_gate.h, keeps one while a measurement is in doubt). nullptr: this
  /// predictor cannot be copied, and is not gated.
  virtual std::unique_ptr<Predictor> clone() const { return nullptr; }

  /// Capabilities the servo loop asks for instead of a name:
  /// whether the predictor forecasts motion at all (false for `hold`, which repeats the last
  /// measurement: the loop then keeps the plain, uncompensated task unless told otherwise) ...
  virtual bool extrapolates() const { return true; }
  /// ... and how many discontinuity-monitor alarms it has raised over all channels since reset()
  /// (0 for a predictor without a monitor).
  virtual int monitorAlarms() const { return 0; }
  /// Named per-channel internals after the last update, for traces (e.g. imm's mode probabilities
  /// "mu_ca_0", ...). Empty for a predictor without any.
  virtual NamedValues diagnostics() const { return {}; }
  /// Counts of events since reset() that a report sums over a run's instances (the glitch gate's
  /// doubts settled each way, glitch_gate.h: "glitches", "steps"). Empty for a predictor without any.
  virtual NamedValues tallies() const { return {}; }
  /// The parameters that set this predictor's process and measurement noise, with bounds wide
  /// enough for 0.1..10 px noise at 1..1000 Hz on targets up to ~1e4 px/s^2, and the values this
  /// instance was built with. Empty: nothing to fit (e.g. `hold`). Each key is a Params key of the
  /// predictor, so makePredictor(name(), n, {key: value}) builds it.
  virtual std::vector<NoiseParameter> noiseParameters() const { return {}; }
  /// Structural variants a noise fit should try besides the configuration it is given: each a
  /// Params override of keys that are not noise levels, e.g. {model: cv} and {model: ca} for a
  /// filter that runs on either motion model. A fit (calibration/noise_fit.h) fits the noise of
  /// every variant and keeps the one with the best objective on the fit data. Empty: one structure.
  /// The variants do not depend on this instance's own parameters.
  virtual std::vector<Params> structuralVariants() const { return {}; }
  /// Which fixed predictors' fitted values can seed a noise fit of THIS structure (built with the
  /// structure's params), and how their keys map to this one's (FitSeed). A fit given those
  /// fitted values (NoiseFitOptions::seed_fits) also starts from them. Empty (the default, and
  /// the fixed KFs kf-cv, kf-ca, cs-akf themselves): nothing seeds it.
  virtual std::vector<FitSeed> fitSeeds() const { return {}; }
  /// Forecast variants a fit under the prediction objective should compare after fitting the
  /// noise: each a Params override of keys that change only the forecast handed out, never the
  /// filter (its innovations, hence the likelihood, are the same), e.g. {hold_blend_frames: 1}
  /// for a filter whose blend with hold learns on two horizons (channel_predictor.h). A fit keeps
  /// the variant whose h-step error on the fit rows is lowest, this instance's own forecast
  /// included (calibration/noise_fit.h). Empty (the default): the forecast has no such choice.
  virtual std::vector<Params> forecastVariants() const { return {}; }

  /// Time of the last update (NaN before the first).
  double time() const { return t_last_; }
  /// Predicted positions of every channel at t_s (convenience over predictPosition()).
  Eigen::VectorXd predictPositions(double t_s) const;
  /// The same into `out` (size channels()), without allocating: the per-frame form for long tracks.
  void predictPositions(double t_s, Eigen::Ref<Eigen::VectorXd> out) const;
  /// Predicted velocities of every channel at t_s (convenience over predictVelocity()).
  Eigen::VectorXd predictVelocities(double t_s) const;
  /// Feed-forward velocities of every channel at t_s (convenience over feedforwardVelocity()).
  Eigen::VectorXd feedforwardVelocities(double t_s) const;

 protected:
  explicit Predictor(int channels);
  /// Checks that t_s is after the last update and records it; returns dt (0 on the first call).
  double advanceClock(double t_s);
  /// The same for an update with measurements z: first checks that z has channels() entries
  /// (std::invalid_argument "NAME: measurement has N entries, expected M").
  double advanceClock(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z);
  void resetClock();

 private:
  int channels_;
  double t_last_;
};

/// One entry of the predictor registry.
struct PredictorInfo {
  std::string name;
  std::string summary;  ///< one line for `predvs list`
};

/// Every registered predictor, in display order.
const std::vector<PredictorInfo>& predictorRegistry();
/// True if `name` is registered.
bool isPredictor(const std::string& name);
/// Builds the predictor `name` for `channels` channels. Throws std::invalid_argument naming the
/// unknown predictor, or the unknown / out-of-range parameter key. Every predictor accepts the
/// caller's keys `glitch_sigmas` (glitch_gate.h), `horizon_frames` (horizonFramesParam) and
/// `closed_loop` (closedLoopParam).
std::unique_ptr<Predictor> makePredictor(const std::string& name, int channels,
                                         const Params& params = {});

/// The `horizon_frames` key: how many frames ahead the caller will ask for forecasts (a number >= 0,
/// need not be whole; 0 or absent = not said). Not a model parameter but a fact about the queries,
/// which `predict`, `track` and `track-study` set from their `--delay-frames` (or `--horizon-s`):
/// a forecast that learns on several horizons sizes its learning by it (the blend with hold learns
/// on the horizons 1..ceil(horizon_frames), channel_predictor.h "The horizons asked for"), the
/// others ignore it. Throws std::invalid_argument naming the key unless finite and >= 0.
double horizonFramesParam(const Params& params);

/// The `closed_loop` key (0 or 1, default 0): the caller's forecasts and velocities drive a control
/// loop every tick (the scenario runs of `predvs servo` and `compare` set it). Not a model parameter
/// but a fact about the use. Every filter with the raise of its process noise (all but hold and
/// cs-akf; process_noise_adapt.h processNoiseRaise) then moves the density until its innovations
/// are white instead (the whitening; stkf matches their spread, as `q: auto`), unless the keys that
/// set its density are given: the maneuvering tracks' density puts noise into the velocity, which
/// reaches the robot on every tick, so it should be as low as the innovations allow; and imm leaves
/// its constant-position mode out unless `cp` is given (imm.h), and the filters coast through a gap
/// more slowly (coast_tau_s 0.5 s instead of 0.2 unless given; channel_predictor.h coastTauParam). (docs/MODELS.md §15, "In a
/// closed loop".) Throws std::invalid_argument naming the key for another value.
bool closedLoopParam(const Params& params);

}  // namespace predvs
