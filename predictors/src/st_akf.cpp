#include "predvs/predictors/st_akf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace predvs {

StAkfPredictor::StAkfPredictor(int channels, const Params& params)
    : ChannelPredictor<3>(channels, measurementNoiseParam(params, 1.0), params.get("p0_vel", 1e4, 0.0, 1e12),
                          params.get("p0_acc", 1e4, 0.0, 1e12)),
      q_(processNoiseParam(params, "q", kDefaultQStAkf, 0.0, 1e15)),
      rho_(params.get("rho", 0.95, 0.0, 1.0)),
      beta_(params.get("beta", 5.0, 1.0, 1e6)),
      ext_(static_cast<size_t>(channels)) {
  readCoastParam(params);
  if (isAutoProcessNoise(params, "q")) enableAutoProcessNoise();
  a_ << params.get("a1", 1.0, 1.0, 1e6), params.get("a2", 1.0, 1.0, 1e6), params.get("a3", 1.0, 1.0, 1e6);
  if (isAutoMeasurementNoise(params)) enableAutoNoise();
}

void StAkfPredictor::resetAdaptation() {
  for (auto& e : ext_) e = Extra{};
}

void StAkfPredictor::restartChannel(int c, double z) {
  initialize(c, z);
  ext_[static_cast<size_t>(c)] = Extra{};
}

void StAkfPredictor::step(int c, double dt, double z) {
  ChannelState& s = state_[static_cast<size_t>(c)];
  Extra& ex = ext_[static_cast<size_t>(c)];
  const Mat<3> F = transition(c, dt);
  const Mat<3> Q = processNoise(c, dt);
  if (!isMeasured(z)) {  // predict only: no innovation, so no fading information
    timeUpdate(s.g, F, Q);
    return;
  }
  const double R = measurementNoise(c);
  const Vec<3> x_pred = F * s.g.x;
  const Mat<3> FPFt = F * s.g.P * F.transpose();
  const double gamma = z - x_pred(0);
  ex.V0 = ex.has_V0 ? (rho_ * ex.V0 + gamma * gamma) / (1.0 + rho_) : gamma * gamma;
  ex.has_V0 = true;
  const double N = ex.V0 - Q(0, 0) - beta_ * R;
  const double M = a_(0) * FPFt(0, 0);
  // No fading while R is still the start-up estimate (r: auto, its first ~53 frames): an innovation
  // power above the filter's then only says that the prior R was too small, not that the target
  // manoeuvres, and fading on it sets the gain to ~1 and the acceleration to the noise.
  const double cf = M > 0.0 && nominalNoiseFinal(c) ? N / M : 0.0;
  for (int i = 0; i < 3; ++i) ex.lambda(i) = std::max(1.0, a_(i) * cf);
  ex.s_unfaded = FPFt(0, 0) + Q(0, 0) + R;
  const Vec<3> sqrt_l = ex.lambda.cwiseSqrt();
  s.g.x = x_pred;
  s.g.P = sqrt_l.asDiagonal() * FPFt * sqrt_l.asDiagonal();
  s.g.P += Q;
  symmetrize(s.g.P);
  s.innovation = measurementUpdate(s.g, z, R);  // Joseph form
}

SteadyStateCa steadyStateCa(double q, double r, double dt) {
  const Mat<3> F = caTransition(dt);
  const Mat<3> Q = caProcessNoise(q, dt);
  Gaussian<3> g;
  g.P.setZero();
  SteadyStateCa out;
  for (out.iterations = 1; out.iterations <= 100000; ++out.iterations) {
    const Mat<3> P_prev = g.P;
    timeUpdate(g, F, Q);
    out.K = g.P.col(0) / (g.P(0, 0) + r);
    measurementUpdate(g, 0.0, r);
    if ((g.P - P_prev).cwiseAbs().maxCoeff() <= 1e-13 * g.P.cwiseAbs().maxCoeff()) break;
  }
  out.P_post = g.P;
  return out;
}

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

StAkfPmPredictor::StAkfPmPredictor(int channels, const Params& params)
    : StAkfPredictor(channels, params),
      on_alarm_steady_(params.get("pm_on_alarm", 0.0, 0.0, 1.0) != 0.0),
      ss_frames_(static_cast<int>(params.get("pm_ss_frames", 25.0, 1.0, 1e6))),
      monitors_(static_cast<size_t>(channels), DiscontinuityMonitor(monitorConfig(params))),
      history_(static_cast<size_t>(channels)),
      ss_left_(static_cast<size_t>(channels), 0) {}

const SteadyStateCa& StAkfPmPredictor::steadyState(double dt) {
  if (!(std::abs(dt - ss_dt_) <= 1e-9 * dt)) {  // same period up to round-off: reuse
    ss_ = steadyStateCa(q(), measurementNoise(0), dt);
    ss_dt_ = dt;
  }
  return ss_;
}

int StAkfPmPredictor::monitorAlarms() const {
  int n = 0;
  for (const auto& m : monitors_) n += m.alarms();
  return n;
}

void StAkfPmPredictor::resetAdaptation() {
  StAkfPredictor::resetAdaptation();
  for (auto& m : monitors_) m.reset();
  for (auto& h : history_) h = History{};
  for (auto& n : ss_left_) n = 0;
}

void StAkfPmPredictor::initialize(int c, double z) {
  StAkfPredictor::initialize(c, z);
  History& h = history_[static_cast<size_t>(c)];
  h = History{};
  h.push(state_[static_cast<size_t>(c)].g, time());
}

void StAkfPmPredictor::step(int c, double dt, double z) {
  const size_t i = static_cast<size_t>(c);
  History& h = history_[i];
  DiscontinuityMonitor& mon = monitors_[i];
  const double t_now = time();  // the clock was advanced before step()
  if (ss_left_[i] > 0) {
    // Steady-state phase after an alarm: fixed gain, no fading, no monitoring.
    const SteadyStateCa& ss = steadyState(dt);
    ChannelState& s = state_[i];
    s.g.x = transition(c, dt) * s.g.x;
    if (isMeasured(z)) {
      const double eps = z - s.g.x(0);
      s.g.x += ss.K * eps;
      s.innovation = Innovation{eps, measurementNoise(c) / (1.0 - ss.K(0)), true};  // S = r / (1 - K_0)
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
    dxp = z - (transition(c, t_now - p.t_s) * p.g.x)(0);
  }
  StAkfPredictor::step(c, dt, z);
  if (isMeasured(z)) {
    const Innovation& in = state_[i].innovation;
    const bool alarm = mon.config().statistic == MonitorConfig::Statistic::kChiSquare
                           ? mon.observe(t_now, in.eps, unfadedS(c))
                           : mon.observe(t_now, dxp);
    if (alarm) {
      restartChannel(c, z);  // calls initialize(): history restarts at this measurement
      mon.restart();
      if (on_alarm_steady_) {
        ss_left_[i] = ss_frames_;
        state_[i].g.P = steadyState(dt).P_post;
      }
      return;
    }
  }
  h.push(state_[i].g, t_now);
}

}  // namespace predvs
