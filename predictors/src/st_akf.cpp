#include "predvs/predictors/st_akf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace predvs {

namespace {

/// The state size of the motion model named by `model` (cv: 2, ca: 3; absent: `fallback`).
int motionModelStates(const Params& params, const std::string& fallback, const std::string& who) {
  const std::string word = params.text("model", fallback);
  if (word == "cv") return 2;
  if (word == "ca") return 3;
  throw std::invalid_argument("predictor '" + who + "': parameter 'model' must be cv or ca, got '" + word + "'");
}

constexpr const char* kDefaultModel = "ca";  // paper 004's filter

}  // namespace

template <int N>
StAkfPredictor<N>::StAkfPredictor(int channels, const Params& params)
    : Base(channels, measurementNoiseParam(params, 1.0), params.get("p0_vel", 1e4, 0.0, 1e12),
           params.get("p0_acc", 1e4, 0.0, 1e12)),
      q_(processNoiseParam(params, "q", N == 2 ? kDefaultQStAkfCv : kDefaultQStAkf, 0.0, N == 2 ? 1e12 : 1e15)),
      rho_(params.get("rho", 0.95, 0.0, 1.0)),
      beta_(params.get("beta", 5.0, 1.0, 1e6)),
      adapt_(adaptationParam(params, "st-akf")),
      ext_(static_cast<size_t>(channels)) {
  // Built directly (tests) the template argument is the model; a `model` given must agree with it.
  if (params.has("model") && motionModelStates(params, kDefaultModel, "st-akf") != N)
    throw std::invalid_argument("st-akf: parameter 'model' does not match the state size of the filter built");
  this->readCoastParam(params);
  this->readAdaptAfterGapParam(params);
  this->readShrinkParams(params, N == 2 ? kDefaultShrinkSigmasStAkfCv : kDefaultShrinkSigmasStAkf, kDefaultShrinkVelocityStAkf);
  this->readProcessNoiseAdaptation(params, N == 3 ? kDefaultQWhiteRhoAcceleration : kDefaultQWhiteRho);
  const double a1 = params.get("a1", 1.0, 1.0, 1e6), a2 = params.get("a2", 1.0, 1.0, 1e6);
  const double a3 = params.get("a3", 1.0, 1.0, 1e6);  // read on cv too, unused there (header)
  if constexpr (N == 2)
    a_ << a1, a2;
  else
    a_ << a1, a2, a3;
  if (isAutoMeasurementNoise(params)) this->enableAutoNoise();
}

template <int N>
std::vector<Params> StAkfPredictor<N>::structuralVariants() const {
  return withAdaptationOff(motionModelVariants());
}

template <int N>
void StAkfPredictor<N>::resetAdaptation() {
  for (auto& e : ext_) e = Extra{};
}

template <int N>
void StAkfPredictor<N>::restartChannel(int c, double z) {
  this->initialize(c, z);
  ext_[static_cast<size_t>(c)] = Extra{};
}

template <int N>
void StAkfPredictor<N>::step(int c, double dt, double z) {
  typename Base::ChannelState& s = this->state_[static_cast<size_t>(c)];
  Extra& ex = ext_[static_cast<size_t>(c)];
  const Mat<N> F = transition(c, dt);
  const Mat<N> Q = processNoise(c, dt);
  if (!isMeasured(z)) {  // predict only: no innovation, so no fading information
    timeUpdate(s.g, F, Q);
    return;
  }
  // The first measurement after a gap, while coasting (channel_predictor.h): its innovation holds
  // the coast's own departure from the model over the gap, not a one-step misfit of the model,
  // so it neither enters V0 nor fades P (adapt_after_gap: 1 restores both). Without coasting (the
  // papers' occlusion scenarios E7 and E8 pin coast_tau_s = 0) every measured frame fades, as in
  // the paper.
  const bool paused = this->adaptationPausedAfterGap(c);
  const double R = this->measurementNoise(c);
  const Vec<N> x_pred = F * s.g.x;
  const Mat<N> FPFt = F * s.g.P * F.transpose();
  if (!paused) {
    const double gamma = z - x_pred(0);
    ex.V0 = ex.has_V0 ? (rho_ * ex.V0 + gamma * gamma) / (1.0 + rho_) : gamma * gamma;
    ex.has_V0 = true;
  }
  const double Nv = ex.V0 - Q(0, 0) - beta_ * R;
  const double M = a_(0) * FPFt(0, 0);
  // No fading while R is still the start-up estimate (r: auto, its first ~53 frames): an innovation
  // power above the filter's then only says that the prior R was too small, not that the target
  // manoeuvres, and fading on it sets the gain to ~1 and the acceleration to the noise.
  const double cf = !paused && adapt_ && M > 0.0 && this->nominalNoiseFinal(c) ? Nv / M : 0.0;
  for (int i = 0; i < N; ++i) ex.lambda(i) = std::max(1.0, a_(i) * cf);
  ex.s_unfaded = FPFt(0, 0) + Q(0, 0) + R;
  s.g.x = x_pred;
  if ((ex.lambda.array() == 1.0).all()) {  // no fading (most frames): sqrt(1) scales by 1, the same bits
    s.g.P = FPFt;
  } else {
    const Vec<N> sqrt_l = ex.lambda.cwiseSqrt();
    s.g.P = sqrt_l.asDiagonal() * FPFt * sqrt_l.asDiagonal();
  }
  s.g.P += Q;
  symmetrize(s.g.P);
  s.innovation = measurementUpdate(s.g, z, R);  // Joseph form
}

template <int N>
SteadyStateKf<N> steadyStateKf(double q, double r, double dt) {
  Mat<N> F, Q;
  if constexpr (N == 2) {
    F = cvTransition(dt);
    Q = cvProcessNoise(q, dt);
  } else {
    F = caTransition(dt);
    Q = caProcessNoise(q, dt);
  }
  Gaussian<N> g;
  g.P.setZero();
  SteadyStateKf<N> out;
  for (out.iterations = 1; out.iterations <= 100000; ++out.iterations) {
    const Mat<N> P_prev = g.P;
    timeUpdate(g, F, Q);
    out.K = g.P.col(0) / (g.P(0, 0) + r);
    measurementUpdate(g, 0.0, r);
    if ((g.P - P_prev).cwiseAbs().maxCoeff() <= 1e-13 * g.P.cwiseAbs().maxCoeff()) break;
  }
  out.P_post = g.P;
  return out;
}

template SteadyStateKf<2> steadyStateKf<2>(double, double, double);
template SteadyStateKf<3> steadyStateKf<3>(double, double, double);

// ---------------------------------------------------------------------------------------------

namespace {

MonitorConfig monitorConfig(const Params& params) {
  MonitorConfig m;
  m.statistic = params.get("monitor", 0.0, 0.0, 1.0) != 0.0 ? MonitorConfig::Statistic::kChiSquare
                                                             : MonitorConfig::Statistic::kBand;
  const double n = params.get("pm_window", 20.0, 2.0, 1000.0);
  if (n != static_cast<int>(n))
    throw std::invalid_argument("predictor parameter 'pm_window' must be an integer, got " + std::to_string(n));
  m.window = static_cast<int>(n);
  m.band_factor = params.get("pm_band", 6.0, 1e-6, 1e6);
  m.band_floor = params.get("pm_floor", 1e-6, 0.0, 1e12);
  m.chi2_threshold = params.get("pm_chi2", 15.13, 1e-6, 1e12);
  return m;
}

}  // namespace

template <int N>
StAkfPmPredictor<N>::StAkfPmPredictor(int channels, const Params& params)
    : Base(channels, params),
      monitor_on_(adaptationParam(params, "st-akf-pm")),
      on_alarm_steady_(params.get("pm_on_alarm", 0.0, 0.0, 1.0) != 0.0),
      ss_frames_(static_cast<int>(params.get("pm_ss_frames", 25.0, 1.0, 1e6))),
      monitors_(static_cast<size_t>(channels), DiscontinuityMonitor(monitorConfig(params))),
      history_(static_cast<size_t>(channels)),
      ss_left_(static_cast<size_t>(channels), 0) {}

template <int N>
const SteadyStateKf<N>& StAkfPmPredictor<N>::steadyState(double dt) {
  if (!(std::abs(dt - ss_dt_) <= 1e-9 * dt)) {  // same period up to round-off: reuse
    ss_ = steadyStateKf<N>(this->q(), this->measurementNoise(0), dt);
    ss_dt_ = dt;
  }
  return ss_;
}

template <int N>
int StAkfPmPredictor<N>::monitorAlarms() const {
  int n = 0;
  for (const auto& m : monitors_) n += m.alarms();
  return n;
}

template <int N>
void StAkfPmPredictor<N>::resetAdaptation() {
  Base::resetAdaptation();
  for (auto& m : monitors_) m.reset();
  for (auto& h : history_) h = History{};
  for (auto& n : ss_left_) n = 0;
}

template <int N>
void StAkfPmPredictor<N>::initialize(int c, double z) {
  Base::initialize(c, z);
  History& h = history_[static_cast<size_t>(c)];
  h = History{};
  h.push(this->state_[static_cast<size_t>(c)].g, this->time());
}

template <int N>
void StAkfPmPredictor<N>::step(int c, double dt, double z) {
  const size_t i = static_cast<size_t>(c);
  History& h = history_[i];
  DiscontinuityMonitor& mon = monitors_[i];
  const double t_now = this->time();  // the clock was advanced before step()
  if (ss_left_[i] > 0) {
    // Steady-state phase after an alarm: fixed gain, no fading, no monitoring.
    const SteadyStateKf<N>& ss = steadyState(dt);
    auto& s = this->state_[i];
    s.g.x = this->transition(c, dt) * s.g.x;
    if (isMeasured(z)) {
      const double eps = z - s.g.x(0);
      s.g.x += ss.K * eps;
      s.innovation = Innovation{eps, this->measurementNoise(c) / (1.0 - ss.K(0)), true};  // S = r / (1 - K_0)
      --ss_left_[i];
    }
    s.g.P = ss.P_post;
    h.push(s.g, t_now);
    if (ss_left_[i] == 0) mon.restart();
    return;
  }
  double dxp = std::numeric_limits<double>::quiet_NaN();
  if (isMeasured(z) && h.count == 2) {
    // Two-step prediction x(k|k-2) from the estimate kept two updates ago.
    const Past& p = h.past[0];
    dxp = z - (this->transition(c, t_now - p.t_s) * p.g.x)(0);
  }
  Base::step(c, dt, z);
  if (isMeasured(z) && monitor_on_) {
    const Innovation& in = this->state_[i].innovation;
    const bool alarm = mon.config().statistic == MonitorConfig::Statistic::kChiSquare
                           ? mon.observe(t_now, in.eps, this->unfadedS(c))
                           : mon.observe(t_now, dxp);
    if (alarm) {
      this->restartChannel(c, z);  // calls initialize(): history restarts at this measurement
      mon.restart();
      if (on_alarm_steady_) {
        ss_left_[i] = ss_frames_;
        this->state_[i].g.P = steadyState(dt).P_post;
      }
      return;
    }
  }
  h.push(this->state_[i].g, t_now);
}

template class StAkfPredictor<2>;
template class StAkfPredictor<3>;
template class StAkfPmPredictor<2>;
template class StAkfPmPredictor<3>;

std::unique_ptr<Predictor> makeStAkfPredictor(int channels, const Params& params) {
  if (motionModelStates(params, kDefaultModel, "st-akf") == 2) return std::make_unique<StAkfPredictor<2>>(channels, params);
  return std::make_unique<StAkfPredictor<3>>(channels, params);
}

std::unique_ptr<Predictor> makeStAkfPmPredictor(int channels, const Params& params) {
  if (motionModelStates(params, kDefaultModel, "st-akf-pm") == 2)
    return std::make_unique<StAkfPmPredictor<2>>(channels, params);
  return std::make_unique<StAkfPmPredictor<3>>(channels, params);
}

}  // namespace predvs
