// predvs — fuzzy adaptive Kalman filters (docs/MODELS.md §3, paper 000 §4).
//
// Both filters watch the innovation sequence of each channel over a sliding window of N_w frames,
//   E'(k) = (1/N_w) sum eps(i),   C(k) = (1/N_w) sum eps(i)^2,   i = k-N_w+1 .. k,
// and compare the actual innovation power C with the filter's own S(k) = P(k|k-1)(0,0) + R(k-1).
// When the filter matches the data, E' ~ 0 and C ~ S. The windowed statistics include the current
// innovation, and R(k) is adapted BEFORE the measurement update of frame k, so that update already
// uses the new R (as in Escamilla-Ambrosio & Mort and paper 000: R(k) is then used in K(k)).
// Adaptation starts once the window is full (the first N_w innovations only fill it), so a few
// noisy innovations after initialisation do not swing R.
//
// R is kept finite and positive for every input: after each adaptation R is clamped to
// [r_min, r_max] (parameters, px^2; defaults r/100 and 100 r; fakf with `r: auto`: within a factor
// r_band = 1.5 of the start-up estimate, kDefaultFakfRBand). This is what the property suite
// relies on (no NaN, P PSD), and it also bounds a known weakness of the innovation-driven rules:
// a persistent model error (a lagging filter on a curved path) makes C > S, and in the improved
// rule also E' > 0, which raises R, which makes the filter lag more. Without a ceiling that loop
// runs away (measured: fakf with sigma_min_sq = 0.01 on a 200 px circle at 0.15 rad/s drove R to
// 1e4 px^2 and the error to ~100 px); two decades around the nominal R keep the adaptation useful
// for a mis-specified noise level while bounding the damage (same case: ~5 px).
#pragma once

#include "predvs/predictors/channel_predictor.h"
#include "predvs/predictors/cs_akf.h"
#include "predvs/predictors/fuzzy.h"

#include <memory>
#include <vector>

namespace predvs {

/// Sliding window of the last N_w innovations of one channel: E' (mean) and C (mean square).
class InnovationWindow {
 public:
  explicit InnovationWindow(int length = 10);
  void push(double eps);
  void clear();
  int length() const { return static_cast<int>(buf_.size()); }
  int count() const { return count_; }
  bool full() const { return count_ == length(); }
  /// E' = mean of the stored innovations (0 when empty).
  double mean() const;
  /// C = mean of the squared stored innovations (0 when empty).
  double meanSquare() const;
  /// E' and C from one pass over the window (same sums, same order, so bit-identical to mean()
  /// and meanSquare(); half the loop overhead on the filter's hot path).
  struct Moments {
    double mean = 0.0, mean_square = 0.0;
  };
  Moments moments() const;

 private:
  std::vector<double> buf_;
  int next_ = 0;
  int count_ = 0;
};

/// Default white-jerk density of fakf-classic with `model: ca`, px^2/s^5: kf-ca's (kDefaultQCa),
/// so that fakf-classic on CA is kf-ca plus the fuzzy R adaptation, as on CV it is kf-cv plus it.
/// It beats hold on 208/216 generated tracks (kf-ca: 214; q 1e5: 173, 5e5: 208, 1e6: 206; it loses
/// on bursts and zigzag at 3 px); docs/PERFORMANCE.md "Defaults that hold", subsection "st-akf,
/// st-akf-pm and fakf-classic on either motion model".
inline constexpr double kDefaultQFakfClassicCa = 3e5;

/// Default `shrink_sigmas` of fakf-classic (cv, ca; shrink_v_sigmas defaults to it):
/// channel_predictor.h, significance-weighted forecast; docs/MODELS.md §15. cv: 0.5, the smallest
/// n that beats hold on the 216 tracks of `predvs track-study` and both held-out grids (0 and 0.25
/// lose hand 10 Hz 3 px #101, x1.023 / x1.009; mean ratio 0.542 -> 0.543); ca: 3 (2: 214 / 215).
inline constexpr double kDefaultShrinkSigmasFakfClassic = 0.5;
inline constexpr double kDefaultShrinkSigmasFakfClassicCa = 3.0;

/// `fakf-classic`: the traditional fuzzy adaptive KF of Escamilla-Ambrosio & Mort, the baseline
/// paper 000 compares against (docs/MODELS.md §3). Motion model (`model`, a word): `cv` (default,
/// the paper's) x = [p, v] per channel with kf-cv's model and defaults (white-acceleration density
/// q, px^2/s^3), or `ca`: x = [p, v, a] with kf-ca's model and defaults (white-jerk density q,
/// px^2/s^5). A template on the state size N (2 = cv, 3 = ca); makeFakfClassicPredictor() reads
/// `model`. No CS model, no P inflation. Per frame, once the window is full:
///   DoM(k) = C(k) - S(k)                  (actual minus theoretical innovation power)
///   dR(k)  = fuzzy(DoM): N -> decrease, ZE -> keep, P -> increase (fuzzy::makeFakfDomSystem)
///   R(k)   = clamp(R(k-1) + dR(k), r_min, r_max)
/// The adaptation only sees the innovation and S, so it is the same on both models.
/// Parameters: model (cv | ca, default cv), q (cv: 1e4 px^2/s^3 = kDefaultQCv; ca: 3e5 px^2/s^5 =
/// kDefaultQFakfClassicCa; raised as kf-cv's when not given, q_raise_ratio (default 2; 0 = no
/// raise); `auto`: adapted both ways; process_noise_adapt.h), r (initial R, px^2, default `auto`),
/// p0_vel ((px/s)^2, 1e4),
/// p0_acc ((px/s^2)^2, 1e4; choice: accepted and unused on cv, so that one configuration runs on
/// either model, e.g. a noise fit's structural variants that change `model` alone), window (N_w,
/// 10), dom_range (DoM universe half-width, 10 px^2), dr_max (dR universe half-width, 0.5 px^2 per
/// frame; choice: the original paper's ranges are not in paper 000), r_min (r/100 px^2),
/// r_max (100 r px^2), coast_tau_s (s, 0.2, channel_predictor.h), adapt_after_gap (0 | 1,
/// default 0: while coasting, the first measured frame after a gap neither enters the window nor
/// adapts R; channel_predictor.h), shrink_sigmas (significance
/// weight of the forecast, default kDefaultShrinkSigmasFakfClassic = 0.5 on cv, 3 on ca; 0 = the
/// unweighted filter) and shrink_v_sigmas (velocity, default shrink_sigmas), channel_predictor.h;
/// adaptation (on | off, default on; off: R stays at r, kalman_math.h adaptationParam);
/// q also takes `auto` (process_noise_adapt.h). q and r default to kf-cv's (kf-ca's on ca), so
/// with equal shrink_sigmas the only difference is the adaptation.
template <int N>
class FakfClassicPredictor : public ChannelPredictor<N> {
  using Base = ChannelPredictor<N>;

 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<FakfClassicPredictor>(*this); }
  FakfClassicPredictor(int channels, const Params& params);
  std::string name() const override { return "fakf-classic"; }
  /// q (white-acceleration density on cv, white-jerk density on ca) and r (the initial R).
  std::vector<NoiseParameter> noiseParameters() const override {
    return {motionDensityParameter<N>("q", q_), this->measurementNoiseParameter()};
  }
  /// {model: cv} and {model: ca}, each also with `adaptation: off` (R fixed at r).
  std::vector<Params> structuralVariants() const override;
  /// q from kf-cv's fitted q (cv) or kf-ca's (ca): the same density (kalman_math.h motionDensitySeed).
  std::vector<FitSeed> fitSeeds() const override { return {motionDensitySeed<N>("q")}; }

  /// Current (adapted) measurement variance of channel c, px^2.
  double adaptedR(int c) const { return measurementNoise(c); }

 protected:
  Mat<N> transition(int, double dt) const override { return motionTransition<N>(dt); }
  Mat<N> processNoise(int c, double dt) const override {
    return motionProcessNoise<N>(q_ * this->processNoiseScale(c), dt);
  }
  double measurementNoise(int c) const override { return r_.at(static_cast<size_t>(c)); }
  void resetAdaptation() override;
  void step(int c, double dt, double z) override;

 private:
  double q_;
  double r_min_, r_max_;
  bool relative_bounds_ = true;  ///< r_min / r_max not given: with auto R they are 0.01 / 100 x the estimate
  int window_length_;
  bool adapt_;  ///< `adaptation` on (default) / off: R stays at r (kalman_math.h adaptationParam)
  fuzzy::MamdaniSystem dom_;
  std::vector<double> r_;
  std::vector<InnovationWindow> window_;
};

extern template class FakfClassicPredictor<2>;
extern template class FakfClassicPredictor<3>;

/// The registry's factory: reads `model` (cv | ca, default cv) and builds FakfClassicPredictor<2>
/// or <3>. Another word is a std::invalid_argument naming `model`.
std::unique_ptr<Predictor> makeFakfClassicPredictor(int channels, const Params& params);


/// Default `r_band` of fakf: with `r: auto` and no r_min / r_max given, the fuzzy R stays within
/// [r_est / r_band, r_band r_est] of the start-up noise estimate r_est (px^2; see FakfPredictor).
/// 100 before issue 11. Why 1.5: with `r: auto` the noise is measured, so the fuzzy R only has to
/// correct the estimate's own error (about +-25 % from 53 frames), not a wrong guess by decades;
/// and on maneuvering tracks the fuzzy R walks away from the noise in both directions (C > S on
/// a manoeuvre pushes it up, the downward drift noted below pulls it down), which is what made
/// fakf worse than cs-akf-adaptive (which is fakf without the fuzzy layer): measured on the 216
/// tracks of `predvs track-study` with shrink_sigmas 2 (cs_akf.h), r_band 1 / 1.5 / 2 / 100: all
/// 216 beat hold on the tuning grid (geometric-mean ratio 0.537 / 0.539 / 0.541 / 0.549), and on
/// the held-out seeds 101-103 216 / 216 / 215 / 215 (hand 10 Hz 3 px #101: x1.001, x1.002).
/// 1.5 keeps a fuzzy R at little cost (r_band 1 is cs-akf-adaptive plus the P inflation).
inline constexpr double kDefaultFakfRBand = 1.5;

/// `fakf`: the improved fuzzy adaptive KF of paper 000 §4 (docs/MODELS.md §3), built on the adaptive CS
/// filter (cs-akf-adaptive: state [p, v, a], Singer Q with the adapted acceleration variance).
/// At every measured frame k of a channel, after the time update and before the measurement update:
///
///   eps(k) = z(k) - p(k|k-1),  S(k) = P(k|k-1)(0,0) + R(k-1),  window <- eps(k)
///   R adaptation (once the window is full):
///     E'(k) = mean eps,  dP'(k) = C(k) - S(k),  beta(k) = fuzzy(E', dP')  (fuzzy::makeFakfBetaSystem)
///     R(k) = clamp(beta(k) R(k-1), r_min, r_max)
///   P inflation, every `inflation_period` measured frames (paper: every 10), window full:
///     dE(k) = |E'(k) - E'(k - period)|
///     gamma = fuzzy(dE) (fuzzy::makeFakfGammaSystem) if dE > |E'(k - period)| and dE >= de_min,
///     gamma = 1 otherwise;  P(k|k-1) <- gamma P(k|k-1)
///
/// Choice (documented deviation from a literal reading): the paper's rule "dE > |E'(k-N)|" alone
/// fires on about half of the checks on pure noise (two window means of zero-mean noise), and the
/// gamma map clamps every dE below its universe to gamma(de_min) = 175, so a literal filter would
/// multiply P by 175 every couple of seconds on a straight line. We read the universe [2, 50] px as
/// the range where a change of motion is considered at all: a dE below de_min gives gamma = 1.
/// (`inflate_below_de_min` = 1 restores the literal rule.)
/// Second choice (issue 11): the universe is in px, fitted to the paper's 1 px noise. Under noise
/// alone E' is a mean of N_w innovations of variance S, so dE = |E'(k) - E'(k - period)| has
/// standard deviation sqrt(2 S / N_w) (about 1.4 px at 3 px noise and N_w = 10, where de_min = 2 px
/// was crossed on ~15 % of the checks and each crossing multiplied P by >= 100: the gain went to 1,
/// the velocity and acceleration followed the noise). A change is therefore also required to be
/// significant: dE >= de_sigma sqrt(2 S / N_w) (de_sigma = 3, a 3-sigma change; 0 = the paper's
/// fixed threshold only). At 1 px noise that bound (~1.5 px) is below de_min, so the paper's
/// scenarios are unaffected.
///
/// Order inside a frame: R is adapted with the S of R(k-1) first, then P is inflated, then the
/// Joseph update uses R(k) and the inflated P; the CS variance adaptation of the base class runs
/// after the update as usual. A frame where the channel is not measured changes nothing here.
///
/// Parameters (besides those of cs-akf-adaptive: alpha, r, p0_vel, p0_acc, sigma_min_sq,
/// sigma_max_sq): window (N_w, 10), inflation_period (10 frames), e_range (0.5 px),
/// dp_range (10 px^2), beta_min (0.8), beta_max (1.2), de_min (2 px), de_max (50 px),
/// gamma_min (100), gamma_max (1000), r_min (r/100 px^2), r_max (100 r px^2) when r is a number,
/// r_band (1.5, kDefaultFakfRBand: with `r: auto` R stays within a factor r_band of the estimate),
/// inflate_below_de_min (0), de_sigma (3, see above), adapt_after_gap (0 | 1, default 0: while
/// coasting, the first measured frame after a gap neither enters the window nor adapts R or
/// inflates P; channel_predictor.h). The CS parameters default to cs-akf-adaptive's, so `fakf` is exactly
/// that filter plus the fuzzy layer; its CS variance floor sigma_min_sq decides the smooth-motion
/// error (tests/predictors/fakf_test.cpp reports the figures).
///
/// Measured behaviour worth knowing (1 px noise, T = 0.1 s, tests/predictors/fakf_test.cpp):
///   * with the paper's universes R settles below the true variance when the noise matches
///     (0.55 .. 0.8 px^2 for a true 1 px^2): E' is a 10-sample mean of unit noise, so it crosses
///     +-0.5 often and beta does a multiplicative random walk whose log drifts down, while dP'
///     on a +-10 px^2 universe pulls back only weakly at this noise scale;
///   * the improvement over kf-cv / fakf-classic comes from the CS model; on E1-E4 the fuzzy layer
///     itself is within about +-15 % of cs-akf-adaptive alone, not consistently better.
class FakfPredictor : public CsAkfAdaptivePredictor {
 public:
  std::unique_ptr<Predictor> clone() const override { return std::make_unique<FakfPredictor>(*this); }
  FakfPredictor(int channels, const Params& params);
  std::string name() const override { return "fakf"; }
  /// alpha, the CS variance bounds sigma_min_sq and sigma_max_sq, and r (the initial R): the
  /// keys of cs-akf-adaptive (issue 11 item 1: the variance bounds of the CS models).
  std::vector<NoiseParameter> noiseParameters() const override { return CsAkfAdaptivePredictor::noiseParameters(); }

  /// Current (adapted) measurement variance of channel c, px^2.
  double adaptedR(int c) const { return measurementNoise(c); }
  /// gamma applied at the last measured frame of channel c (1 when not inflated).
  double lastGamma(int c) const { return chan_.at(static_cast<size_t>(c)).gamma; }
  /// Number of P inflations (gamma > 1) on channel c since the last reset.
  int inflations(int c) const { return chan_.at(static_cast<size_t>(c)).inflations; }

 protected:
  double measurementNoise(int c) const override { return chan_.at(static_cast<size_t>(c)).r; }
  void resetAdaptation() override;
  /// Remembers z for inflatePrior (the base hook does not receive it), then runs the CS cycle.
  void step(int c, double dt, double z) override;
  /// R adaptation and P inflation on the prior of frame k (see the class comment).
  void inflatePrior(int c, double dt) override;

 private:
  struct Channel {
    double r = 1.0;
    InnovationWindow window;
    double e_ref = 0.0;  ///< E' at the previous inflation check
    bool has_ref = false;
    int measured = 0;    ///< measured frames since the window filled
    double gamma = 1.0;
    int inflations = 0;
  };
  int window_length_;
  int inflation_period_;
  double r_min_, r_max_;
  bool relative_bounds_ = true;
  double de_min_;
  double de_sigma_;
  double r_band_;
  bool inflate_below_de_min_;
  fuzzy::MamdaniSystem beta_;
  fuzzy::MamdaniSystem gamma_;
  std::vector<Channel> chan_;
  double pending_z_ = 0.0;  ///< z of the frame being processed by step()
};

}  // namespace predvs
