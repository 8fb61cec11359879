// predvs — the glitch gate: a measurement a tracker got wrong for one frame
// kept out of a predictor (docs/MODELS.md §16).
//
// An image tracker now and then reports a point far from where it is for a
// single frame (vpDot2 catching a neighbouring blob, a tag corner detected on
// the wrong edge), and now and then jumps to a new place and stays there
// (re-acquisition after a loss). A filter fed the glitch takes it for motion:
// the forecast it makes on that frame extrapolates the jump, and is further off
// than repeating the measurement would be. Neither can be told from the other
// on the frame itself; the next frame tells them apart.
//
// Detection, per channel: the distance d of a measurement from the straight
// line through the two measured frames before it, tested only when the three
// frames are consecutive at a steady period (their two intervals within a
// factor kGlitchPeriodRatio of each other; so the first two frames after a
// gap are never tested: a point re-acquired elsewhere goes straight in, and
// so would a glitch on one of them), against s, the mean of d^2 with
// forgetting (time constant kGlitchScaleTauS; each sample clipped at
// kGlitchClip^2 s so that one jump does not inflate it). There is no test over
// the first kGlitchWarmup samples; s then starts at the mean of all but their
// kGlitchTrimmed largest, over kGlitchTrimmedMean: a glitch, which spoils the
// sample of its frame and of the two after it (it is a point of their lines),
// does not count, and a tracker whose resting positions repeat to the bit does
// not make s zero as a median would. s has a floor of
// (kGlitchFloor m)^2, m^2 the mean square step between frames (the same
// forgetting), so that a track without noise is not tested against nothing.
// |d| > g sqrt(s), g = `glitch_sigmas` (default 0 = off; `predvs track`, which
// runs an image tracker, uses kTrackerGlitchSigmas), puts the channel *in
// doubt* on that frame.
//
// Two hypotheses until the next frame. The predictor is fed the frame as it is
// (A: a step or a manoeuvre); a copy of it made before the frame
// (Predictor::clone()) is fed the frame without the channels in doubt (B: a
// glitch, the channels coast). The forecast of a channel in doubt is
// p f_B + (1 - p) f_A, p the share of glitches among the doubts settled so far on this
// predictor, (n_glitch + 1) / (n_settled + 2). The next update settles the
// doubt: when its measurements of the channels in doubt lie closer (summed
// squares) to B's one-step forecasts than to A's, it was a glitch and B goes on
// as the predictor (the glitch never entered it); otherwise A goes on, the
// predictor exactly as without the gate. A frame that measures none of them
// settles for A.
//
// Cost: the test on every measured frame of every channel (an exponential, a
// division and a few flops, about 100 instructions) and an indirection on every
// update and forecast; a copy of the predictor and one more update on a frame in
// doubt. On `predict --predictor all` that is 10 % more instructions
// (docs/PERFORMANCE.md "Tracker glitches").
#pragma once

#include "predvs/predictors/predictor.h"

#include <array>
#include <memory>
#include <vector>

namespace predvs {

/// The gate is off unless `glitch_sigmas` is given: on tracks without glitches
/// its doubts are manoeuvres (a start from rest at 10 Hz, say), and the
/// forecast made on a doubted frame costs a little (docs/PERFORMANCE.md
/// "Tracker glitches").
inline constexpr double kDefaultGlitchSigmas = 0.0;
/// g where the measurements come from an image tracker (`predvs track
/// --glitch-sigmas`, default).
inline constexpr double kTrackerGlitchSigmas = 8.0;
/// The two intervals of a test within this factor of each other (a steady
/// period, jitter allowed).
inline constexpr double kGlitchPeriodRatio = 1.5;
/// Time constant of the forgetting means s and m^2 (s).
inline constexpr double kGlitchScaleTauS = 2.0;
/// Samples of d^2 before the first test (file comment).
inline constexpr int kGlitchWarmup = 10;
/// Of the first kGlitchWarmup samples, the largest kGlitchTrimmed are left out of s's start.
inline constexpr int kGlitchTrimmed = 3;
/// The expected mean of the 7 smallest of 10 chi-square variables of one degree of freedom
/// (400,000 simulated sets), which s's start divides by so as to estimate their variance.
inline constexpr double kGlitchTrimmedMean = 0.372;
/// A sample of d^2 enters s clipped at kGlitchClip^2 s.
inline constexpr double kGlitchClip = 3.0;
/// Floor of sqrt(s) as a fraction of the rms step between frames.
inline constexpr double kGlitchFloor = 0.1;

/// The `glitch_sigmas` parameter g (>= 0, default kDefaultGlitchSigmas = 0: no
/// gate).
double glitchSigmasParam(const Params& params);

/// A predictor behind the glitch gate (file comment). name() and every
/// capability are the inner predictor's (glitches() and steps() count the
/// doubts settled each way).
class GlitchGate : public Predictor {
 public:
  /// inner must support clone(); g > 0.
  GlitchGate(std::unique_ptr<Predictor> inner, double g);
  std::unique_ptr<Predictor> clone() const override;

  std::string name() const override { return inner_->name(); }
  void reset() override;
  void update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) override;
  using Predictor::update;
  ChannelEstimate predict(int channel, double t_s) const override;
  double predictPosition(int channel, double t_s) const override;
  double predictVelocity(int channel, double t_s) const override;
  double feedforwardVelocity(int channel, double t_s) const override;
  Innovation innovation(int channel) const override { return inner_->innovation(channel); }
  bool extrapolates() const override { return inner_->extrapolates(); }
  int monitorAlarms() const override { return inner_->monitorAlarms(); }
  NamedValues diagnostics() const override { return inner_->diagnostics(); }
  /// The inner predictor's, then "glitches" and "steps" (glitches(), steps()).
  NamedValues tallies() const override;
  std::vector<NoiseParameter> noiseParameters() const override { return inner_->noiseParameters(); }
  std::vector<Params> structuralVariants() const override { return inner_->structuralVariants(); }
  std::vector<FitSeed> fitSeeds() const override { return inner_->fitSeeds(); }
  std::vector<Params> forecastVariants() const override { return inner_->forecastVariants(); }

  /// Doubts settled as glitches / as steps since reset().
  int glitches() const { return n_glitch_; }
  int steps() const { return n_step_; }
  /// True while the last update left a channel in doubt.
  bool inDoubt() const { return static_cast<bool>(coasted_); }

 private:
  /// One channel's line test (file comment).
  struct Line {
    double t1 = 0.0, z1 = 0.0, t2 = 0.0, z2 = 0.0;  ///< the last two measured frames kept (1 = newest)
    int kept = 0;                                   ///< how many of them are valid (0..2)
    double s = 0.0, m2 = 0.0;                       ///< forgetting means of d^2 and of the step^2
    double keep_h = -1.0, keep_factor = 0.0;        ///< exp(-keep_h / kGlitchScaleTauS), cached
    int samples = 0;
    std::array<double, kGlitchWarmup> warm{};  ///< the first samples of d^2
    bool doubt = false;
    double t_doubt = 0.0, z_doubt = 0.0;
    void keep(double t, double z) {
      t2 = t1;
      z2 = z1;
      t1 = t;
      z1 = z;
      kept = kept < 2 ? kept + 1 : 2;
    }
  };
  /// True when z at t on channel c is in doubt; otherwise the line learns the
  /// frame.
  bool test(Line& line, double t, double z) const;
  /// Settles the doubt of the last update with this update's measurements.
  void settle(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z);
  /// The glitch share p (file comment).
  double glitchShare() const { return (n_glitch_ + 1.0) / (n_glitch_ + n_step_ + 2.0); }
  /// One number of a forecast (`of`: Predictor::predictPosition, predictVelocity or
  /// feedforwardVelocity) of channel c at t_s: A's, or while c is in doubt the glitch share's mix of
  /// B's and A's, as predict() mixes them.
  double mixed(double (Predictor::*of)(int, double) const, int c, double t_s) const;

  std::unique_ptr<Predictor> inner_;    ///< A: fed every measurement
  std::unique_ptr<Predictor> coasted_;  ///< B, while a doubt is open: fed the
                                        ///< frame without its doubted channels
  double g_;
  std::vector<Line> lines_;
  int n_glitch_ = 0, n_step_ = 0;
};

/// inner behind a glitch gate of g sigmas when g > 0 and inner can be copied;
/// inner itself otherwise.
std::unique_ptr<Predictor> withGlitchGate(std::unique_ptr<Predictor> inner, double g);

}  // namespace predvs
