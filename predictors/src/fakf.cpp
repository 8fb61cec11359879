#include "predvs/predictors/fakf.h"
#include "predvs/predictors/kalman_baselines.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace predvs {

InnovationWindow::InnovationWindow(int length) {
  if (length < 1) throw std::invalid_argument("innovation window length must be >= 1");
  buf_.assign(static_cast<size_t>(length), 0.0);
}

void InnovationWindow::push(double eps) {
  buf_[static_cast<size_t>(next_)] = eps;
  next_ = (next_ + 1) % length();
  count_ = std::min(count_ + 1, length());
}

void InnovationWindow::clear() {
  std::fill(buf_.begin(), buf_.end(), 0.0);
  next_ = 0;
  count_ = 0;
}

// Sums are recomputed over the (short) window rather than kept as running sums, which would
// accumulate rounding over long runs.
double InnovationWindow::mean() const {
  if (count_ == 0) return 0.0;
  double s = 0.0;
  for (int i = 0; i < count_; ++i) s += buf_[static_cast<size_t>(i)];
  return s / count_;
}

double InnovationWindow::meanSquare() const {
  if (count_ == 0) return 0.0;
  double s = 0.0;
  for (int i = 0; i < count_; ++i) s += buf_[static_cast<size_t>(i)] * buf_[static_cast<size_t>(i)];
  return s / count_;
}

InnovationWindow::Moments InnovationWindow::moments() const {
  Moments m;
  if (count_ == 0) return m;
  double s = 0.0, s2 = 0.0;
  for (int i = 0; i < count_; ++i) {
    const double e = buf_[static_cast<size_t>(i)];
    s += e;
    s2 += e * e;
  }
  m.mean = s / count_;
  m.mean_square = s2 / count_;
  return m;
}

namespace {

fuzzy::DomSystemConfig domConfig(const Params& p) {
  fuzzy::DomSystemConfig c;
  c.dom_range = p.get("dom_range", c.dom_range, 1e-9, 1e9);
  c.dr_max = p.get("dr_max", c.dr_max, 1e-12, 1e9);
  return c;
}

/// The state size of the motion model named by `model` (cv: 2, ca: 3; absent: cv, the paper's).
int fakfClassicModelStates(const Params& params) {
  const std::string word = params.text("model", "cv");
  if (word == "cv") return 2;
  if (word == "ca") return 3;
  throw std::invalid_argument("predictor 'fakf-classic': parameter 'model' must be cv or ca, got '" + word + "'");
}

}  // namespace

template <int N>
FakfClassicPredictor<N>::FakfClassicPredictor(int channels, const Params& params)
    : Base(channels, measurementNoiseParam(params, 1.0), params.get("p0_vel", 1e4, 0.0, 1e12),
           params.get("p0_acc", 1e4, 0.0, 1e12)),  // read on cv too, unused there (header)
      q_(processNoiseParam(params, "q", N == 2 ? kDefaultQCv : kDefaultQFakfClassicCa, 0.0, N == 2 ? 1e12 : 1e15)),
      r_min_(params.get("r_min", 0.01 * this->r0_, 1e-12, 1e12)),
      r_max_(params.get("r_max", 100.0 * this->r0_, 1e-12, 1e12)),
      window_length_(static_cast<int>(params.get("window", 10.0, 2.0, 1000.0))),
      adapt_(adaptationParam(params, "fakf-classic")),
      dom_(fuzzy::makeFakfDomSystem(domConfig(params))) {
  // Built directly (tests) the template argument is the model; a `model` given must agree with it.
  if (params.has("model") && fakfClassicModelStates(params) != N)
    throw std::invalid_argument("fakf-classic: parameter 'model' does not match the state size of the filter built");
  this->readCoastParam(params);
  this->readAdaptAfterGapParam(params);
  this->readShrinkParams(params, N == 2 ? kDefaultShrinkSigmasFakfClassic : kDefaultShrinkSigmasFakfClassicCa, true);
  this->readProcessNoiseAdaptation(params);
  if (!(r_min_ <= this->r0_ && this->r0_ <= r_max_))
    throw std::invalid_argument("fakf-classic: need r_min <= r <= r_max");
  relative_bounds_ = !params.has("r_min") && !params.has("r_max");
  if (isAutoMeasurementNoise(params)) this->enableAutoNoise();
  resetAdaptation();
}

template <int N>
std::vector<Params> FakfClassicPredictor<N>::structuralVariants() const {
  return withAdaptationOff(motionModelVariants());
}

template <int N>
void FakfClassicPredictor<N>::resetAdaptation() {
  r_.assign(static_cast<size_t>(this->channels()), this->r0_);
  window_.assign(static_cast<size_t>(this->channels()), InnovationWindow(window_length_));
}

template <int N>
void FakfClassicPredictor<N>::step(int c, double dt, double z) {
  typename Base::ChannelState& s = this->state_[static_cast<size_t>(c)];
  timeUpdate(s.g, transition(c, dt), processNoise(c, dt));
  if (!isMeasured(z)) return;
  double& R = r_[static_cast<size_t>(c)];
  InnovationWindow& win = window_[static_cast<size_t>(c)];
  const double eps = z - s.g.x(0);
  if (!this->nominalNoiseFinal(c)) R = this->nominalNoise(c);  // start-up estimate: adapt from it once frozen
  const double S = s.g.P(0, 0) + R;  // theoretical innovation power with R(k-1)
  // The first measurement after a gap while coasting is the coast's own error: it neither enters
  // the window nor adapts R (channel_predictor.h).
  if (!this->adaptationPausedAfterGap(c)) {
    win.push(eps);
    if (adapt_ && win.full() && this->nominalNoiseFinal(c)) {
      const double dom = win.meanSquare() - S;
      const double lo = this->autoNoise() && relative_bounds_ ? 0.01 * this->nominalNoise(c) : r_min_;
      const double hi = this->autoNoise() && relative_bounds_ ? 100.0 * this->nominalNoise(c) : r_max_;
      R = std::clamp(R + dom_.evaluate(dom), lo, hi);
    }
  }
  s.innovation = measurementUpdate(s.g, z, R);
}

template class FakfClassicPredictor<2>;
template class FakfClassicPredictor<3>;

std::unique_ptr<Predictor> makeFakfClassicPredictor(int channels, const Params& params) {
  if (fakfClassicModelStates(params) == 2) return std::make_unique<FakfClassicPredictor<2>>(channels, params);
  return std::make_unique<FakfClassicPredictor<3>>(channels, params);
}


namespace {

fuzzy::BetaSystemConfig betaConfig(const Params& p) {
  fuzzy::BetaSystemConfig c;
  c.e_range = p.get("e_range", c.e_range, 1e-9, 1e9);
  c.dp_range = p.get("dp_range", c.dp_range, 1e-9, 1e9);
  c.beta_min = p.get("beta_min", c.beta_min, 1e-3, 1.0 - 1e-9);
  c.beta_max = p.get("beta_max", c.beta_max, 1.0 + 1e-9, 1e3);
  return c;
}

fuzzy::GammaSystemConfig gammaConfig(const Params& p) {
  fuzzy::GammaSystemConfig c;
  c.de_min = p.get("de_min", c.de_min, 0.0, 1e9);
  c.de_max = p.get("de_max", c.de_max, 0.0, 1e9);
  c.gamma_min = p.get("gamma_min", c.gamma_min, 1.0, 1e12);
  c.gamma_max = p.get("gamma_max", c.gamma_max, 1.0, 1e12);
  return c;
}

}  // namespace

FakfPredictor::FakfPredictor(int channels, const Params& params)
    : CsAkfAdaptivePredictor(channels, params),
      window_length_(static_cast<int>(params.get("window", 10.0, 2.0, 1000.0))),
      inflation_period_(static_cast<int>(params.get("inflation_period", 10.0, 1.0, 1000.0))),
      r_min_(params.get("r_min", 0.01 * r0_, 1e-12, 1e12)),
      r_max_(params.get("r_max", 100.0 * r0_, 1e-12, 1e12)),
      de_min_(params.get("de_min", 2.0, 0.0, 1e9)),
      de_sigma_(params.get("de_sigma", 3.0, 0.0, 1e3)),
      r_band_(params.get("r_band", kDefaultFakfRBand, 1.0, 1e6)),
      inflate_below_de_min_(params.get("inflate_below_de_min", 0.0, 0.0, 1.0) != 0.0),
      beta_(fuzzy::makeFakfBetaSystem(betaConfig(params))),
      gamma_(fuzzy::makeFakfGammaSystem(gammaConfig(params))) {
  if (!(r_min_ <= r0_ && r0_ <= r_max_)) throw std::invalid_argument("fakf: need r_min <= r <= r_max");
  relative_bounds_ = !params.has("r_min") && !params.has("r_max");
  readAdaptAfterGapParam(params);
  FakfPredictor::resetAdaptation();
}

void FakfPredictor::resetAdaptation() {
  CsAkfAdaptivePredictor::resetAdaptation();
  Channel init;
  init.r = r0_;
  init.window = InnovationWindow(window_length_);
  chan_.assign(static_cast<size_t>(channels()), init);
}

void FakfPredictor::step(int c, double dt, double z) {
  pending_z_ = z;
  CsAkfAdaptivePredictor::step(c, dt, z);
}

void FakfPredictor::inflatePrior(int c, double dt) {
  CsAkfAdaptivePredictor::inflatePrior(c, dt);
  Channel& ch = chan_[static_cast<size_t>(c)];
  ch.gamma = 1.0;
  if (!isMeasured(pending_z_)) return;
  if (!adapt_) {  // adaptation: off: R is r (or its start-up estimate), P as predicted
    ch.r = nominalNoise(c);
    return;
  }
  Gaussian<3>& g = channelGaussian(c);
  const double eps = pending_z_ - g.x(0);
  if (!nominalNoiseFinal(c)) ch.r = nominalNoise(c);  // start-up estimate: adapt from it once frozen
  const double S = g.P(0, 0) + ch.r;  // theoretical innovation power with R(k-1)
  if (adaptationPausedAfterGap(c)) return;  // the coast's own error: not in the window (channel_predictor.h)
  ch.window.push(eps);
  if (!ch.window.full() || !nominalNoiseFinal(c)) return;

  // R(k) = beta(E', dP') R(k-1)
  const InnovationWindow::Moments m = ch.window.moments();
  const double e_mean = m.mean;
  const double x[2] = {e_mean, m.mean_square - S};
  const double lo = autoNoise() && relative_bounds_ ? nominalNoise(c) / r_band_ : r_min_;
  const double hi = autoNoise() && relative_bounds_ ? r_band_ * nominalNoise(c) : r_max_;
  ch.r = std::clamp(beta_.evaluate(x) * ch.r, lo, hi);

  // P(k|k-1) <- gamma P(k|k-1), decided every inflation_period measured frames.
  if (ch.measured++ % inflation_period_ != 0) return;
  if (ch.has_ref) {
    const double dE = std::abs(e_mean - ch.e_ref);
    const double de_noise = de_sigma_ * std::sqrt(2.0 * S / window_length_);  // 3-sigma of dE under noise
    if (dE > std::abs(ch.e_ref) && (inflate_below_de_min_ || dE >= de_min_) && dE >= de_noise) {
      ch.gamma = gamma_.evaluate(dE);
      g.P *= ch.gamma;
      ++ch.inflations;
    }
  }
  ch.e_ref = e_mean;
  ch.has_ref = true;
}

}  // namespace predvs
