#include "predvs/predictors/imm.h"

#include "predvs/predictors/cs_akf.h"
#include "predvs/predictors/kalman_baselines.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

constexpr double kLog2Pi = 1.8378770664093453;
/// Floor of a mode probability after an update: keeps every mode recoverable after a long stretch
/// dominated by the others (renormalised afterwards).
constexpr double kMuFloor = 1e-6;
/// Default forgetting time of the forecast weights' evidence (s): docs/MODELS.md §14.
constexpr double kDefaultForecastTauS = 30.0;
/// Default factor on the CP mode's forecast weight on a frame without a measurement, while coasting
/// (imm.h, "Coasting without the CP mode"; docs/MODELS.md §14).
constexpr double kDefaultCoastCp = 0.0;
/// Default power of the forecast weights on a frame without a measurement (imm.h, "The forecast
/// weights in a gap"; docs/MODELS.md §14).
constexpr double kDefaultGapWeightPower = 0.5;
/// Default floor of a forecast weight relative to the largest (docs/MODELS.md §14).
constexpr double kDefaultForecastFloor = 0.01;
/// Default power of the raise of q on the CV mode's density (imm.h, "The raise of q on each mode").
constexpr double kDefaultQRaiseCvExponent = 0.5;
/// Default time constant (s) of the low-pass by which the feed-forward's weights compare the modes'
/// steps with the measured ones (`ff_weight_tau_s`; imm.h, "The feed-forward's velocity").
constexpr double kDefaultFeedforwardWeightTauS = 2.0;
/// Lowest calibration factor of a forecast variance (imm.h, "Calibration"): keeps v_j > 0 where a
/// mode's forecasts are exact for long (a still target without noise: its mean ratio e^2 / s can
/// reach 0), where log 0 and 0 / 0 would make its score NaN (which the floor's std::max then turns
/// into the floor: the exact mode would get the least weight). Far below the factors on the
/// generated tracks: the study grids give the same bits with and without it.
constexpr double kMinForecastCalibration = 1e-12;

/// std::exp(x) without the call for x = 0 (+0 or -0), whose exp is exactly 1: the same bits.
inline double expOrOne(double x) { return x == 0.0 ? 1.0 : std::exp(x); }

// The mode-matched filters of the CP and CV modes on their own states. Their state is the common
// [p, v, a] with the states the model lacks at zero (mixInto leaves them 0, their F zeroes them),
// and these are timeUpdate<3> / measurementUpdate<3> (kalman_math.h) written out for that pattern:
// every product or sum they skip has a zero factor or term, and every sum they keep has at most two
// non-zero terms, so the order of Eigen's sums does not matter and the results are the same bits
// (up to the sign of a zero). The CA mode uses the generic ones.

/// CP: F = diag(1, 0, 0), Q = diag(q, 0, 0): x unchanged, P(0, 0) += q.
inline void timeUpdateCp(Gaussian<3>& g, const Mat<3>& Q) { g.P(0, 0) = g.P(0, 0) + Q(0, 0); }

/// CV: F = [[1, T, 0], [0, 1, 0], [0, 0, 0]]:  x0 += T x1;  P <- F P F' + Q on the 2x2 block.
inline void timeUpdateCv(Gaussian<3>& g, const Mat<3>& F, const Mat<3>& Q) {
  const double T = F(0, 1);
  g.x(0) = g.x(0) + T * g.x(1);
  const double p00 = g.P(0, 0), p01 = g.P(0, 1), p10 = g.P(1, 0), p11 = g.P(1, 1);
  const double fp00 = p00 + T * p10, fp01 = p01 + T * p11;  // row 0 of F P; row 1 is (p10, p11)
  const double n00 = fp00 + fp01 * T + Q(0, 0);
  const double n01 = fp01 + Q(0, 1);            // (F P F')(0, 1) = fp00 * 0 + fp01 * 1
  const double n10 = p10 + p11 * T + Q(1, 0);   // (F P F')(1, 0) = p10 * 1 + p11 * T
  const double n11 = p11 + Q(1, 1);
  g.P(0, 0) = n00;
  g.P(0, 1) = g.P(1, 0) = 0.5 * (n01 + n10);
  g.P(1, 1) = n11;
}

/// CP: the scalar Joseph update of p: K = P00 / S.
inline Innovation measurementUpdateCp(Gaussian<3>& g, double z, double R) {
  Innovation in;
  in.eps = z - g.x(0);
  in.S = g.P(0, 0) + R;
  in.valid = true;
  const double k0 = g.P(0, 0) / in.S;
  g.x(0) += k0 * in.eps;
  const double a = 1.0 - k0;
  g.P(0, 0) = (a * g.P(0, 0)) * a + (R * k0) * k0;
  return in;
}

/// CV: the Joseph update on the 2x2 block, I - K H = [[1 - k0, 0], [-k1, 1]]:
///   P <- A P A' + (R K) K', then (0, 1) and (1, 0) averaged (symmetrize).
inline Innovation measurementUpdateCv(Gaussian<3>& g, double z, double R) {
  Innovation in;
  in.eps = z - g.x(0);
  in.S = g.P(0, 0) + R;
  in.valid = true;
  const double p00 = g.P(0, 0), p01 = g.P(0, 1), p10 = g.P(1, 0), p11 = g.P(1, 1);
  const double k0 = p00 / in.S, k1 = p10 / in.S;
  g.x(0) += k0 * in.eps;
  g.x(1) += k1 * in.eps;
  const double a00 = 1.0 - k0, a10 = -k1;
  const double ap00 = a00 * p00, ap01 = a00 * p01;              // row 0 of A P
  const double ap10 = a10 * p00 + p10, ap11 = a10 * p01 + p11;  // row 1 of A P
  const double n00 = ap00 * a00 + (R * k0) * k0;
  const double n01 = (ap00 * a10 + ap01) + (R * k0) * k1;
  const double n10 = ap10 * a00 + (R * k1) * k0;
  const double n11 = (ap10 * a10 + ap11) + (R * k1) * k1;
  g.P(0, 0) = n00;
  g.P(0, 1) = g.P(1, 0) = 0.5 * (n01 + n10);
  g.P(1, 1) = n11;
  return in;
}

}  // namespace

const char* immModeName(ImmMode m) {
  switch (m) {
    case ImmMode::Cp: return "cp";
    case ImmMode::Cv: return "cv";
    case ImmMode::Ca: return "ca";
  }
  return "?";
}

ImmPredictor::ImmPredictor(int channels, const Params& params)
    : Predictor(channels),
      q_cp_(params.get("q_cp", 2.0, 0.0, 1e12)),
      q_cv_(params.get("q_cv", kDefaultQCv, 0.0, 1e12)),
      q_ca_(params.get("q_ca", kDefaultQCa, 0.0, 1e15)),
      alpha_(params.get("alpha", 0.0, 0.0, 1e3)),
      r_(1.0),
      p0_vel_(params.get("p0_vel", 1e4, 0.0, 1e12)),
      p0_acc_(params.get("p0_acc", 1e4, 0.0, 1e12)),
      coast_tau_s_(coastTauParam(params)),
      fc_tau_s_(params.get("forecast_tau_s", kDefaultForecastTauS, 0.0, 1e6)),
      fc_floor_(std::log(params.get("forecast_floor", kDefaultForecastFloor, 1e-12, 0.5))),
      fc_calibrate_(params.get("forecast_calibration", 1.0, 0.0, 1.0) >= 0.5),
      shrink_a_sigmas_(params.get("shrink_sigmas", kDefaultShrinkSigmasKfCa, 0.0, 1e3)),
      shrink_v_sigmas_(params.get("shrink_v_sigmas", kDefaultShrinkVelocityKfCa ? shrink_a_sigmas_ : 0.0, 0.0, 1e3)),
      blend_tau_s_(holdBlendTauParam(params)),  // as every per-channel filter (channel_predictor.h)
      blend_frames_(holdBlendFramesParam(params)),
      blend_sigmas_(holdBlendSigmasParam(params)),
      blend_prior_(holdBlendPriorParam(params)),
      blend_split_(holdBlendSplitParam(params)),
      extrapolation_cap_(extrapolationCapParam(params)),
      coast_stop_fraction_(coastStopFractionParam(params)),
      coast_fast_ratio_(coastFastRatioParam(params)),
      coast_lag_sigmas_(coastLagSigmasParam(params)),
      coast_lag_share_(coastLagShareParam(params)),
      coast_shape_(coastShapeParam(params)),
      coast_crossing_(coastCrossingParam(params)),
      coast_cp_(params.get("coast_cp", kDefaultCoastCp, 0.0, 1.0)),
      gap_weight_power_(params.get("gap_weight_power", kDefaultGapWeightPower, 0.0, 1.0)),
      q_raise_cv_exponent_(params.get("q_raise_cv_exponent", kDefaultQRaiseCvExponent, 0.0, 1.0)),
      q_raise_from_ca_(params.get("q_raise_from_ca", 1.0, 0.0, 1.0) >= 0.5),
      ff_weight_tau_s_(params.get("ff_weight_tau_s", kDefaultFeedforwardWeightTauS, 1e-3, 1e6)),
      blend_per_mode_(params.get("blend_per_mode", 1.0, 0.0, 1.0) >= 0.5),
      mix_ca_(params.get("mix_ca", 0.0, 0.0, 1.0) >= 0.5),
      r_auto_(isAutoMeasurementNoise(params)) {
  if (!r_auto_) r_ = params.get("r", 1.0, 1e-12, 1e12);
  // The raise of q (process_noise_adapt.h) as kf-cv's and kf-ca's: on the combined innovation, it
  // scales the CA mode's density and, to the power q_raise_cv_exponent, the CV mode's (imm.h, "The
  // raise of q on each mode"); only when neither q_cv nor q_ca is given.
  q_raise_ = processNoiseRaise(params, {"q_cv", "q_ca"}, blend_tau_s_ > 0.0, InnovationStatistic::Whiteness,
                               kDefaultQWhiteRhoAcceleration);
  // Without the CP mode in a closed loop unless `cp` is given (imm.h, "In a closed loop"); there
  // the feed-forward learns its own weights (imm.h, "The feed-forward's velocity").
  const bool with_cp = params.get("cp", closedLoopParam(params) ? 0.0 : 1.0, 0.0, 1.0) >= 0.5;
  learn_feedforward_ = closedLoopParam(params) && blend_tau_s_ > 0.0;
  const double tau_cp = params.get("tau_cp_s", 5.0, 1e-6, 1e6);
  const double tau_cv = params.get("tau_cv_s", 30.0, 1e-6, 1e6);
  const double tau_ca = params.get("tau_ca_s", 3.0, 1e-6, 1e6);
  if (with_cp) modes_.push_back({ImmMode::Cp, 1, tau_cp});
  modes_.push_back({ImmMode::Cv, 2, tau_cv});
  modes_.push_back({ImmMode::Ca, 3, tau_ca});
  // Rate matrix: leave mode i at rate 1 / tau_i, to each other mode with equal share.
  const int m = modeCount();
  rates_.setZero(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      rates_(i, j) = i == j ? -1.0 / modes_[static_cast<size_t>(i)].tau_s
                            : 1.0 / (modes_[static_cast<size_t>(i)].tau_s * (m - 1));
  fc_floor_exp_ = std::exp(fc_floor_);
  reset();
}

void ImmPredictor::reset() {
  resetClock();
  Channel init;
  init.mu.fill(0.0);
  for (int j = 0; j < modeCount(); ++j) init.mu[static_cast<size_t>(j)] = 1.0 / modeCount();
  init.fw = init.mu;
  int moving = 0;
  for (const Mode& md : modes_) moving += md.dim > 1;
  for (int j = 0; j < modeCount(); ++j) init.ff_w[static_cast<size_t>(j)] = modes_[static_cast<size_t>(j)].dim > 1 ? 1.0 / moving : 0.0;
  init.fc_cal.fill(1.0);
  init.q_raise = q_raise_.value_or(ProcessNoiseMatcher());
  chan_.assign(static_cast<size_t>(channels()), init);
}

double ImmPredictor::measurementNoise(int c) const {
  return r_auto_ ? chan_.at(static_cast<size_t>(c)).r_est.variance() : r_;
}

double ImmPredictor::modeProbability(int c, ImmMode mode) const {
  const Channel& ch = chan_.at(static_cast<size_t>(c));
  for (int j = 0; j < modeCount(); ++j)
    if (modes_[static_cast<size_t>(j)].kind == mode) return ch.mu[static_cast<size_t>(j)];
  return 0.0;
}

double ImmPredictor::forecastWeight(int c, ImmMode mode) const {
  const std::array<double, kMaxModes>& w = forecastWeights(chan_.at(static_cast<size_t>(c)));
  for (int j = 0; j < modeCount(); ++j)
    if (modes_[static_cast<size_t>(j)].kind == mode) return w[static_cast<size_t>(j)];
  return 0.0;
}

Mat<3> ImmPredictor::transition(int j, double dt) const {
  Mat<3> F = Mat<3>::Zero();
  switch (modes_[static_cast<size_t>(j)].kind) {
    case ImmMode::Cp:
      F(0, 0) = 1.0;
      break;
    case ImmMode::Cv:
      F(0, 0) = F(1, 1) = 1.0;
      F(0, 1) = dt;
      break;
    case ImmMode::Ca:
      F = alpha_ > 0.0 ? singerTransition(alpha_, dt) : caTransition(dt);
      break;
  }
  return F;
}

Mat<3> ImmPredictor::processNoise(int j, double dt, double scale) const {
  Mat<3> Q = Mat<3>::Zero();
  switch (modes_[static_cast<size_t>(j)].kind) {
    case ImmMode::Cp:
      Q(0, 0) = q_cp_ * dt;
      break;
    case ImmMode::Cv:
      Q.topLeftCorner<2, 2>() = cvProcessNoise(q_cv_ * scale, dt);
      break;
    case ImmMode::Ca:
      Q = alpha_ > 0.0 ? singerProcessNoise(alpha_, q_ca_ * scale / (2.0 * alpha_), dt) : caProcessNoise(q_ca_ * scale, dt);
      break;
  }
  return Q;
}

double ImmPredictor::modeRaise(const Channel& ch, int j) const {
  switch (modes_[static_cast<size_t>(j)].kind) {
    case ImmMode::Cp: return 1.0;
    case ImmMode::Cv: return ch.q_raise_cv;
    case ImmMode::Ca: break;
  }
  return ch.q_raise.scale();
}

const std::array<Mat<3>, ImmPredictor::kMaxModes>& ImmPredictor::raisedProcessNoise(
    const Channel& ch, const std::array<Mat<3>, kMaxModes>& Q, std::array<Mat<3>, kMaxModes>& scratch) const {
  if (ch.q_raise.scale() == 1.0) return Q;
  for (int j = 0; j < modeCount(); ++j) {
    const auto jj = static_cast<size_t>(j);
    scratch[jj] = (Q[jj] * modeRaise(ch, j)).eval();  // CP's factor is 1
  }
  return scratch;
}

ImmPredictor::ModeMatrix ImmPredictor::chain(double dt) const { return periodModels(dt).chain; }

const ImmPredictor::PeriodModels& ImmPredictor::periodModels(double dt) const {
  return period_models_.get({dt}, [&] {
    PeriodModels e;
    e.chain = computeChain(dt);
    for (int j = 0; j < modeCount(); ++j) {
      e.F[static_cast<size_t>(j)] = transition(j, dt);
      e.Q[static_cast<size_t>(j)] = processNoise(j, dt);
    }
    e.keep = fc_tau_s_ > 0.0 ? std::exp(-dt / fc_tau_s_) : 0.0;
    e.blend_keep = blend_tau_s_ > 0.0 ? std::exp(-dt / blend_tau_s_) : 0.0;
    e.feedforward_keep = learn_feedforward_ ? std::exp(-dt / kFeedforwardTauS) : 0.0;  // read only then
    e.ff_weight_keep = learn_feedforward_ ? std::exp(-dt / ff_weight_tau_s_) : 0.0;
    return e;
  });
}

ImmPredictor::ModeMatrix ImmPredictor::computeChain(double dt) const {
  // exp(Lambda dt) by scaling and squaring: halve until the norm is below 1/2, Taylor to order 12
  // (truncation < 0.5^13 / 13! relative), square back. Rows of the result sum to one.
  const int m = modeCount();
  ModeMatrix A = rates_ * dt;
  int squarings = 0;
  double norm = A.cwiseAbs().rowwise().sum().maxCoeff();
  while (norm > 0.5) {
    A *= 0.5;
    norm *= 0.5;
    ++squarings;
  }
  ModeMatrix E = ModeMatrix::Identity(m, m), term = ModeMatrix::Identity(m, m);
  for (int k = 1; k <= 12; ++k) {
    term = (term * A / k).eval();
    E += term;
  }
  for (int s = 0; s < squarings; ++s) E = (E * E).eval();
  for (int i = 0; i < m; ++i) E.row(i) /= E.row(i).sum();
  return E;
}

namespace {

/// mixInto on D states of mode j, the M source modes of dimensions D0, D1(, D2) (a template so
/// that the loops over the states and the modes unroll and the tests on the dimensions fold away:
/// the same operations in the same order as with the dimensions known at run time).
template <int D, int M, int D0, int D1, int D2>
void mixStates(const std::array<Gaussian<3>, ImmPredictor::kMaxModes>& g,
               const std::array<double, ImmPredictor::kMaxModes>& w, int j, Gaussian<3>& out) {
  constexpr int m = M;
  constexpr int dims[ImmPredictor::kMaxModes] = {D0, D1, D2};
  const Gaussian<3>& own = g[static_cast<size_t>(j)];
  double sx[ImmPredictor::kMaxModes][D];
  double x[D];
  for (int r = 0; r < D; ++r) x[r] = 0.0;
  for (int i = 0; i < m; ++i) {
    const auto ii = static_cast<size_t>(i);
    for (int r = 0; r < D; ++r) sx[i][r] = r < dims[ii] ? g[ii].x(r) : own.x(r);
  }
  for (int i = 0; i < m; ++i)
    for (int r = 0; r < D; ++r) x[r] += w[static_cast<size_t>(i)] * sx[i][r];
  // The upper triangle only, mirrored: every P_i is exactly symmetric (each update ends with
  // symmetrize() or sets both entries alike) and d(r) d(c) = d(c) d(r), so entry (c, r) would be the
  // same bits as (r, c), and symmetrize() of the full matrix would leave both unchanged.
  double P[D][D];
  for (int r = 0; r < D; ++r)
    for (int c = 0; c < D; ++c) P[r][c] = 0.0;
  for (int i = 0; i < m; ++i) {
    const auto ii = static_cast<size_t>(i);
    const int di = dims[ii];
    double dd[D];
    for (int r = 0; r < D; ++r) dd[r] = sx[i][r] - x[r];
    for (int c = 0; c < D; ++c)
      for (int r = 0; r < D; ++r) {
        if (r > c) continue;  // (loops of constant trip count: unrolled, the test folds away)
        // A state the source has keeps its covariance, one it lacks takes mode j's,
        // uncorrelated with the rest.
        const double s = (r < di) != (c < di) ? 0.0 : (r < di ? g[ii].P(r, c) : own.P(r, c));
        P[r][c] += w[ii] * (s + dd[r] * dd[c]);
      }
  }
  out.x.setZero();
  out.P.setZero();
  for (int r = 0; r < D; ++r) {
    out.x(r) = x[r];
    for (int c = 0; c < D; ++c) out.P(r, c) = r <= c ? P[r][c] : P[c][r];
  }
}

}  // namespace

void ImmPredictor::mixInto(const std::array<Gaussian<3>, kMaxModes>& g, const std::array<double, kMaxModes>& w, int j,
                           Gaussian<3>& out) const {
  // combine() of the sources as mode j sees them (the mixing rule of imm.h: a state source i
  // lacks is mode j's own estimate, uncorrelated with the rest), entry by entry in its order (so
  // the same bits), on the d_j states mode j has only: the others are left 0, as mode j's F zeroes
  // them in the time update that follows (coasting scales them only).
  // The modes are CP, CV, CA (dimensions 1, 2, 3) or, without CP, CV, CA (2, 3): the constructor's.
  if (modeCount() == 3) {
    switch (j) {
      case 0: mixStates<1, 3, 1, 2, 3>(g, w, j, out); break;
      case 1: mixStates<2, 3, 1, 2, 3>(g, w, j, out); break;
      default: mixStates<3, 3, 1, 2, 3>(g, w, j, out);
    }
  } else if (j == 0) {
    mixStates<2, 2, 2, 3, 0>(g, w, j, out);
  } else {
    mixStates<3, 2, 2, 3, 0>(g, w, j, out);
  }
}

void ImmPredictor::update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) {
  const double dt = advanceClock(t_s, z);
  const int m = modeCount();
  // The chain, each mode's F and Q over dt and the two forgetting factors: the same for every channel.
  const PeriodModels& fm = periodModels(dt);
  const ModeMatrix& Pi = fm.chain;
  const std::array<Mat<3>, kMaxModes>& F = fm.F;
  const double keep = fm.keep;              // forecast weights' forgetting, exp(-dt / forecast_tau_s)
  const double blend_keep = fm.blend_keep;  // the blend's, exp(-dt / hold_blend_tau_s)
  const int ca = m - 1;  // the CA mode is the last (constructor)
  std::array<Mat<3>, kMaxModes> Q_raised;
  for (int c = 0; c < channels(); ++c) {
    Channel& ch = chan_[static_cast<size_t>(c)];
    ch.innovation = Innovation{};
    // Each mode's Q over dt, the moving modes' scaled by this channel's raise of q.
    const std::array<Mat<3>, kMaxModes>& Q = raisedProcessNoise(ch, fm.Q, Q_raised);
    if (r_auto_) ch.r_est.push(t_s, z(c));
    const double R = measurementNoise(c);
    if (!ch.initialized) {
      if (!isMeasured(z(c))) continue;
      for (int j = 0; j < m; ++j) {
        Gaussian<3>& g = ch.g[static_cast<size_t>(j)];
        const int d = modes_[static_cast<size_t>(j)].dim;
        g.x << z(c), 0.0, 0.0;
        g.P.setZero();
        g.P(0, 0) = R;
        if (d > 1) g.P(1, 1) = p0_vel_;
        if (d > 2) g.P(2, 2) = p0_acc_;
      }
      ch.initialized = true;
      ch.blend.z_hold = z(c);
      ch.blend.start(blend_prior_);
      for (BlendWeight& l : ch.longer) l.start(blend_prior_);
      for (BlendWeight& b : ch.mode_blend) b.start(blend_prior_);
      for (auto& longer : ch.mode_longer)
        for (BlendWeight& l : longer) l.start(blend_prior_);
      ch.blend.recent.remember(t_s, z(c), 0.0, 0.0, Innovation{});
      ch.last_measured = true;
      if (blend_tau_s_ > 0.0 && blend_frames_ > 1) rememberBlendStart(ch, t_s);
      continue;
    }
    // The CA mode's forecast start from its posterior of the last update (ch.g, replaced at the
    // end), shared by the blend's sample and the forecast weights' evidence below.
    const bool measured = isMeasured(z(c));
    Vec<3> x_ca = Vec<3>::Zero();
    if (measured && ((blend_tau_s_ > 0.0 && ch.last_measured) || fc_tau_s_ > 0.0))  // kept by the last update when it could
      x_ca = ch.start_run > 0 ? ch.starts[static_cast<size_t>(ch.start_head)].x[static_cast<size_t>(ca)] : forecastStartMean(ch, ca);
    // The blend with hold learns from the one-frame forecast of the previous update (channel_predictor.h):
    // each mode's (F x)(0), for CP and CV written out as in predictPosition (the same bits).
    // The step of the combination is the combination of the modes' steps, sum_j w_j (p_j - z_hold):
    // exactly 0 when every mode forecasts z_hold (the first sample after the start, all velocities
    // 0), where sum_j w_j p_j - z_hold would leave a rounding residual of either sign whose
    // regression weight y / d is clamped to 0 or 1 (imm.h, "The blend's step").
    // With the blend per mode, the forecast weights below score each mode's blended one-frame
    // forecast, z_hold + w_j (p_j - z_hold), with the hold and the weights w_j of the last update
    // (before this frame's sample joins them); after a gap, the unblended one.
    const bool score_blended = blendsPerMode() && ch.last_measured;
    const double z_hold_before = ch.blend.z_hold;
    const std::array<BlendWeight, kMaxModes> weight_before = ch.mode_blend;
    const std::array<ExtrapolationRates, kMaxModes> rates_before = ch.mode_rates;  // the forecast's cap then
    if (blend_tau_s_ > 0.0 && measured && ch.last_measured) {
      const std::array<double, kMaxModes>& fw = forecastWeights(ch);
      double d_step = 0.0;
      for (int j = 0; j < m; ++j) {
        const auto jj = static_cast<size_t>(j);
        const int d = modes_[jj].dim;
        const double pj = d == 1   ? ch.g[jj].x(0)
                          : d == 2 ? ch.g[jj].x(0) + F[jj](0, 1) * ch.g[jj].x(1)
                                   : Vec<3>((F[jj] * x_ca).eval())(0);
        d_step += fw[jj] * (pj - ch.blend.z_hold);
        if (blendsMode(j)) {
          const double p0 = d == 3 ? x_ca(0) : ch.g[jj].x(0);  // the mode's forecast start position
          ch.mode_blend[jj].learn(pj - ch.blend.z_hold, p0 - ch.blend.z_hold, z(c) - ch.blend.z_hold, blend_keep,
                                  blend_sigmas_, blend_split_, blend_prior_);
          if (extrapolation_cap_ > 0.0 && blend_split_) ch.mode_rates[jj].learn(pj - p0, dt, blend_keep);
        }
      }
      // the combination's step is not split (it is blended only with blend_per_mode 0)
      ch.blend.learn(d_step, 0.0, z(c) - ch.blend.z_hold, blend_keep, blend_sigmas_, false, blend_prior_);
      if (learn_feedforward_) learnFeedforward(ch, z(c), F, blend_keep, fm.feedforward_keep, fm.ff_weight_keep);
      if (blend_frames_ > 1) learnLongerBlend(ch, t_s, z(c), blend_keep);
    }
    const bool started_gap = ch.last_measured && !measured;
    ch.last_measured = measured;
    if (measured) ch.blend.z_hold = z(c);
    // Mixing: c_j = sum_i p_ij mu_i, mu_i|j = p_ij mu_i / c_j, moments of the mixture. Unless
    // mix_ca is set, the CA mode starts from its own posterior (imm.h, "The CA mode unmixed"); its
    // c_j is the chain's all the same.
    std::array<double, kMaxModes> cbar{};
    std::array<Gaussian<3>, kMaxModes> mixed;
    for (int j = 0; j < m; ++j) {
      const auto jj = static_cast<size_t>(j);
      for (int i = 0; i < m; ++i) cbar[jj] += Pi(i, j) * ch.mu[static_cast<size_t>(i)];
      if (j == ca && !mix_ca_) {
        mixed[jj] = ch.g[jj];
        continue;
      }
      std::array<double, kMaxModes> w{};
      for (int i = 0; i < m; ++i) {
        const auto ii = static_cast<size_t>(i);
        w[ii] = cbar[jj] > 0.0 ? Pi(i, j) * ch.mu[ii] / cbar[jj] : (i == j ? 1.0 : 0.0);
      }
      mixInto(ch.g, w, j, mixed[jj]);
    }
    // Coasting on an unmeasured frame (channel_predictor.h): velocity and acceleration decay; with
    // the blend, a gap that begins after a stop or at an unusual speed coasts shorter (on the
    // combined velocity and its P_vv), and any other gap with the shape coast_shape.
    if (coast_tau_s_ > 0.0 && !isMeasured(z(c))) {
      if (blend_tau_s_ > 0.0) {
        if (started_gap) {
          const double var_v = combinedVelocityVariance(ch);
          ch.blend.startGap(coast_tau_s_, coast_stop_fraction_, coast_fast_ratio_, coast_lag_sigmas_, coast_lag_share_, var_v, R);
          if (coast_crossing_) {  // the CA mode's acceleration (the others have none), on the combined velocity's crossing
            const double k = ch.blend.recent.gapAccelerationFactor(var_v);
            for (int j = 0; j < m; ++j) mixed[static_cast<size_t>(j)].x(2) *= k;
          }
        }
        const double e = ch.blend.gapDecay(t_s, dt, coast_tau_s_, coast_shape_);
        for (int j = 0; j < m; ++j) coastBy(mixed[static_cast<size_t>(j)].x, e);
      } else {
        for (int j = 0; j < m; ++j) coast(mixed[static_cast<size_t>(j)].x, dt, coast_tau_s_);
      }
    }
    // Mode-matched filters (each zeroes the states its model does not have).
    for (int j = 0; j < m; ++j) {
      const auto jj = static_cast<size_t>(j);
      switch (modes_[jj].dim) {
        case 1: timeUpdateCp(mixed[jj], Q[jj]); break;
        case 2: timeUpdateCv(mixed[jj], F[jj], Q[jj]); break;
        default: timeUpdate(mixed[jj], F[jj], Q[jj]);
      }
    }
    if (isMeasured(z(c))) {
      double xbar = 0.0;
      for (int j = 0; j < m; ++j) xbar += cbar[static_cast<size_t>(j)] * mixed[static_cast<size_t>(j)].x(0);
      double S = 0.0, maxll = -std::numeric_limits<double>::infinity();
      std::array<double, kMaxModes> loglik{};
      Innovation ca_innovation;  // the CA mode's own, which the raise observes (q_raise_from_ca)
      for (int j = 0; j < m; ++j) {
        const auto jj = static_cast<size_t>(j);
        const double d = mixed[jj].x(0) - xbar;
        S += cbar[jj] * (mixed[jj].P(0, 0) + R + d * d);
        const int dim = modes_[jj].dim;
        const Innovation in = dim == 1   ? measurementUpdateCp(mixed[jj], z(c), R)
                              : dim == 2 ? measurementUpdateCv(mixed[jj], z(c), R)
                                         : measurementUpdate(mixed[jj], z(c), R);
        loglik[jj] = -0.5 * (kLog2Pi + std::log(in.S) + in.eps * in.eps / in.S);
        maxll = std::max(maxll, loglik[jj]);
        if (j == ca) ca_innovation = in;
      }
      ch.innovation = Innovation{z(c) - xbar, S, true};
      if (q_raise_) {
        const double before = ch.q_raise.scale();
        // On the CA mode's own innovation (imm.h, "The raise of q on each mode"), or the combination's.
        const Innovation& seen = q_raise_from_ca_ ? ca_innovation : ch.innovation;
        ch.q_raise.observe(seen.eps, seen.S, dt);
        // The exponent damps raises only (imm.h, "The raise of q on each mode"): a fall below the
        // defaults (the closed loop's whitening) lowers the CV mode as much as the CA mode. pow(s, 1)
        // is s and pow(s, 0) is 1 exactly: the exponent's ends need no case of their own.
        if (ch.q_raise.scale() != before) {
          const double s = ch.q_raise.scale();
          ch.q_raise_cv = s > 1.0 ? std::pow(s, q_raise_cv_exponent_) : s;
        }
      }
      std::array<double, kMaxModes> w{};
      double sum = 0.0;
      for (int j = 0; j < m; ++j) {
        const auto jj = static_cast<size_t>(j);
        w[jj] = cbar[jj] * expOrOne(loglik[jj] - maxll);
        sum += w[jj];
      }
      if (fc_tau_s_ > 0.0) {
        std::array<double, kMaxModes> ev{}, ratio{};
        for (int j = 0; j < m; ++j) {
          // Mode j's forecast of z from its posterior of the last update (ch.g, not yet replaced):
          // mean f x and variance f P f' + Q(0, 0) + R, f = row 0 of F (only the measured entry
          // of the time update). For CP (f = [1, 0, 0]) and CV (f = [1, T, 0]) written out: the
          // states they lack are 0 in x and P, so every sum of the products has at most two
          // non-zero terms and P is exactly symmetric (the same bits as the generic products).
          const auto jj = static_cast<size_t>(j);
          const Gaussian<3>& g = ch.g[jj];
          double e, fpf;
          switch (modes_[jj].dim) {
            case 1:
              e = z(c) - g.x(0);
              fpf = g.P(0, 0);
              break;
            case 2: {
              const double T = F[jj](0, 1);
              e = z(c) - (g.x(0) + T * g.x(1));
              fpf = (g.P(0, 0) + T * g.P(1, 0)) + (g.P(0, 1) + T * g.P(1, 1)) * T;
              break;
            }
            default: {
              const Eigen::Matrix<double, 1, 3> f = F[jj].row(0);
              e = z(c) - f.dot(x_ca.transpose());
              fpf = f * g.P * f.transpose();
            }
          }
          if (score_blended && blendsMode(j)) {  // the forecast handed out then: capped, blended
            const double f = z(c) - e;
            if (blend_split_) {
              const double p0 = modes_[jj].dim == 3 ? x_ca(0) : g.x(0);
              const double fc = rates_before[jj].capped(extrapolation_cap_, p0, f, dt);
              e = z(c) - weight_before[jj].blendSplit(z_hold_before, p0, fc);
            } else {
              e = z(c) - weight_before[jj].blend(z_hold_before, f);
            }
          }
          // The forecast's variance as the model states it, lowered to the realised one where the
          // model overstates it (calibration, imm.h): v_j = min(1, c_j) s_j, c_j from the frames
          // before this one; then this frame's ratio e^2 / s_j joins c_j.
          const double S_h = fpf + Q[jj](0, 0) + R;
          const double v =
              fc_calibrate_ ? std::clamp(ch.fc_cal[jj], kMinForecastCalibration, 1.0) * S_h : S_h;
          ev[jj] = -0.5 * (std::log(v) + e * e / v);
          ratio[jj] = e * e / S_h;
        }
        if (fc_calibrate_) {
          ch.fc_cal_n = keep * ch.fc_cal_n + 1.0;  // forgetting count of the ratios (prior: 1 of 1)
          for (int j = 0; j < m; ++j) {
            const auto jj = static_cast<size_t>(j);
            ch.fc_cal[jj] += (ratio[jj] - ch.fc_cal[jj]) / ch.fc_cal_n;
          }
        }
        double mev = -std::numeric_limits<double>::infinity();
        for (int j = 0; j < m; ++j) mev = std::max(mev, ev[static_cast<size_t>(j)]);
        double mx = -std::numeric_limits<double>::infinity();
        for (int j = 0; j < m; ++j) {
          const auto jj = static_cast<size_t>(j);
          ch.logw[jj] = keep * ch.logw[jj] + (ev[jj] - mev);  // keep = exp(-dt / forecast_tau_s)
          mx = std::max(mx, ch.logw[jj]);
        }
        for (int j = 0; j < m; ++j) {
          const auto jj = static_cast<size_t>(j);
          ch.logw[jj] = std::max(fc_floor_, ch.logw[jj] - mx);
        }
        normaliseForecastWeights(ch);
      }
      if (sum > 0.0 && std::isfinite(sum)) {
        double s2 = 0.0;
        for (int j = 0; j < m; ++j) {
          const auto jj = static_cast<size_t>(j);
          ch.mu[jj] = std::max(kMuFloor, w[jj] / sum);
          s2 += ch.mu[jj];
        }
        for (int j = 0; j < m; ++j) ch.mu[static_cast<size_t>(j)] /= s2;
      } else {
        ch.mu = cbar;
      }
    } else {
      ch.mu = cbar;
      if (fc_tau_s_ > 0.0) {
        for (int j = 0; j < m; ++j) ch.logw[static_cast<size_t>(j)] *= keep;
        // The evidence of one-frame forecasts tempered for a gap's longer extrapolation (imm.h,
        // "The forecast weights in a gap"); the next measured frame goes back to the whole of it.
        normaliseForecastWeights(ch, gap_weight_power_);
        // While coasting, the CP mode's forecast weight is scaled by coast_cp (imm.h, "Coasting
        // without the CP mode"): the moving modes' coasted forecasts already tend to hold. The
        // next measured frame recomputes the weights from the scores, so this lasts the gap.
        if (coast_tau_s_ > 0.0 && coast_cp_ < 1.0 && modes_[0].kind == ImmMode::Cp) {
          ch.fw[0] *= coast_cp_;
          double sum = 0.0;
          for (int j = 0; j < m; ++j) sum += ch.fw[static_cast<size_t>(j)];
          for (int j = 0; j < m; ++j) ch.fw[static_cast<size_t>(j)] /= sum;
        }
      }
    }
    ch.g = mixed;
    if (blend_tau_s_ > 0.0 && isMeasured(z(c))) {
      ch.blend.recent.remember(t_s, z(c), combinedVelocity(ch), blendForgetting(t_s - ch.blend.recent.lastTime()),
                               ch.innovation);
      if (coast_crossing_ && ch.blend.recent.watching())
        ch.blend.recent.watchCrossing(combinedVelocityVariance(ch), blend_tau_s_);
    }
    if (blend_tau_s_ > 0.0 && blend_frames_ > 1) {
      if (isMeasured(z(c)))
        rememberBlendStart(ch, t_s);
      else
        ch.start_run = 0;
    }
  }
}

namespace {

/// A mode's share of the feed-forward before normalising, from the ratio r = S_min / S_j <= 1 of the
/// best mode's error sum to its own: r^kFeedforwardModePower (imm.h, "The feed-forward's velocity").
constexpr int kFeedforwardModePower = 16;
double feedforwardShare(double r) {
  static_assert(kFeedforwardModePower == 16, "the power is four squarings");
  r *= r;
  r *= r;
  r *= r;
  return r * r;
}

}  // namespace

void ImmPredictor::learnFeedforward(Channel& ch, double z, const std::array<Mat<3>, kMaxModes>& F, double lambda,
                                    double a, double a_w) const {
  // Each moving mode's one-frame step from its feed-forward start (the posterior of the last update,
  // still in ch.g), combined with the weights the feed-forward used over that frame.
  const int m = modeCount();
  const std::array<double, kMaxModes>& u = ch.ff_w;
  std::array<double, kMaxModes> step{};
  double d = 0.0;
  for (int j = 0; j < m; ++j) {
    const auto jj = static_cast<size_t>(j);
    if (modes_[jj].dim < 2) continue;  // CP does not move
    const Vec<3> x = feedforwardStartMean(ch, j);
    step[jj] = F[jj](0, 1) * x(1) + (modes_[jj].dim > 2 ? F[jj](0, 2) * x(2) : 0.0);
    d += u[jj] * step[jj];
  }
  const double y = z - ch.blend.z_hold;
  ch.feedforward.learn(d, y, a, lambda);
  // Each mode's step against the measured step, both low-passed with ff_weight_tau_s (a_w), and the
  // weights from the forgetting sums of their squared differences.
  ch.ff_y = a_w * ch.ff_y + (1.0 - a_w) * y;
  double best = std::numeric_limits<double>::infinity();
  for (int j = 0; j < m; ++j) {
    const auto jj = static_cast<size_t>(j);
    if (modes_[jj].dim < 2) continue;
    ch.ff_step[jj] = a_w * ch.ff_step[jj] + (1.0 - a_w) * step[jj];
    const double e = ch.ff_y - ch.ff_step[jj];
    ch.ff_sq[jj] = lambda * ch.ff_sq[jj] + e * e;
    best = std::min(best, ch.ff_sq[jj]);
  }
  double sum = 0.0;
  for (int j = 0; j < m; ++j) {
    const auto jj = static_cast<size_t>(j);
    ch.ff_w[jj] = modes_[jj].dim < 2 ? 0.0 : ch.ff_sq[jj] > 0.0 ? feedforwardShare(best / ch.ff_sq[jj]) : 1.0;
    sum += ch.ff_w[jj];
  }
  for (int j = 0; j < m; ++j) ch.ff_w[static_cast<size_t>(j)] /= sum;
}

void ImmPredictor::rememberBlendStart(Channel& ch, double t_s) const {
  ch.start_head = (ch.start_head + 1) % kMaxBlendFrames;
  Channel::BlendStart& st = ch.starts[static_cast<size_t>(ch.start_head)];
  const int m = modeCount();
  for (int j = 0; j < m; ++j)
    st.x[static_cast<size_t>(j)] = forecastStartMean(ch, j);
  st.fw = forecastWeights(ch);
  st.z_hold = ch.blend.z_hold;
  st.t_s = t_s;
  ch.start_run = std::min(ch.start_run + 1, kMaxBlendFrames);
}

double ImmPredictor::forecastPosition(int j, const Vec<3>& x, double dt) const {
  switch (modes_[static_cast<size_t>(j)].kind) {
    case ImmMode::Cp: return x(0);
    case ImmMode::Cv: return x(0) + dt * x(1);
    case ImmMode::Ca: break;
  }
  return alpha_ > 0.0 ? transition(j, dt).row(0).dot(x) : x(0) + dt * x(1) + 0.5 * dt * dt * x(2);
}

void ImmPredictor::learnLongerBlend(Channel& ch, double t_s, double z, double lambda) const {
  const int m = modeCount();
  // The start of update k - h is h - 1 places behind the newest (k - 1's); frames k - h .. k - 1
  // measured (start_run >= h) and k too (the caller).
  for (int h = 2; h <= blend_frames_ && h <= ch.start_run; ++h) {
    const Channel::BlendStart& st = ch.starts[blendRingSlot(ch.start_head, h - 1)];
    const double y = z - st.z_hold;
    double d = 0.0;
    for (int j = 0; j < m; ++j) {
      const auto jj = static_cast<size_t>(j);
      const double pj = forecastPosition(j, st.x[jj], t_s - st.t_s);
      d += st.fw[jj] * (pj - st.z_hold);
      if (blendsMode(j))
        ch.mode_longer[jj][static_cast<size_t>(h - 2)].learn(pj - st.z_hold, st.x[jj](0) - st.z_hold, y, lambda, blend_sigmas_,
                                                             blend_split_, blend_prior_);
    }
    ch.longer[static_cast<size_t>(h - 2)].learn(d, 0.0, y, lambda, blend_sigmas_, false, blend_prior_);
  }
  minOverHorizons(ch.blend, ch.longer, blend_frames_);
  for (int j = 0; j < m; ++j)
    minOverHorizons(ch.mode_blend[static_cast<size_t>(j)], ch.mode_longer[static_cast<size_t>(j)], blend_frames_);
}

double ImmPredictor::combinedVelocity(const Channel& ch) const {
  double v = 0.0;
  for (int j = 0; j < modeCount(); ++j) v += ch.mu[static_cast<size_t>(j)] * ch.g[static_cast<size_t>(j)].x(1);
  return v;
}

double ImmPredictor::combinedVelocityVariance(const Channel& ch) const {
  const double v = combinedVelocity(ch);
  double var = 0.0;
  for (int j = 0; j < modeCount(); ++j) {
    const auto jj = static_cast<size_t>(j);
    const double d = ch.g[jj].x(1) - v;
    var += ch.mu[jj] * (ch.g[jj].P(1, 1) + d * d);
  }
  return var;
}


Gaussian<3> ImmPredictor::combine(const std::array<Gaussian<3>, kMaxModes>& g, const std::array<double, kMaxModes>& w) const {
  // Written out on scalars, entry by entry, with the operations of the Eigen expressions
  //   x = 0; x += w_j x_j (each j);  P = 0; P += w_j (P_j + d_j d_j') (each j), d_j = x_j - x
  // in the same order (so the same bits): an outer product's entry is d(r) d(c), a sum of
  // matrices is entrywise.
  const int m = modeCount();
  Gaussian<3> out;
  double x[3] = {0.0, 0.0, 0.0};
  for (int j = 0; j < m; ++j) {
    const auto jj = static_cast<size_t>(j);
    for (int r = 0; r < 3; ++r) x[r] += w[jj] * g[jj].x(r);
  }
  double P[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
  for (int j = 0; j < m; ++j) {
    const auto jj = static_cast<size_t>(j);
    const double d[3] = {g[jj].x(0) - x[0], g[jj].x(1) - x[1], g[jj].x(2) - x[2]};
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) P[r][c] += w[jj] * (g[jj].P(r, c) + d[r] * d[c]);
  }
  for (int r = 0; r < 3; ++r) {
    out.x(r) = x[r];
    for (int c = 0; c < 3; ++c) out.P(r, c) = P[r][c];
  }
  symmetrize(out.P);
  return out;
}

void ImmPredictor::normaliseForecastWeights(Channel& ch, double power) const {
  // exp of the best mode's 0 is 1, of a floored one exp(fc_floor_) (kept): the same bits as exp.
  double sum = 0.0;
  for (int j = 0; j < modeCount(); ++j) {
    const auto jj = static_cast<size_t>(j);
    const double l = ch.logw[jj];
    ch.fw[jj] = power != 1.0 ? std::exp(power * l) : l == fc_floor_ ? fc_floor_exp_ : expOrOne(l);
    sum += ch.fw[jj];
  }
  for (int j = 0; j < modeCount(); ++j) ch.fw[static_cast<size_t>(j)] /= sum;
}

Vec<3> ImmPredictor::forecastStartMean(const Channel& ch, int j) const {
  // the feed-forward's start with the CA mode's v and a weighted by w_v (the same products in order)
  Vec<3> x = feedforwardStartMean(ch, j);
  if (modes_[static_cast<size_t>(j)].kind == ImmMode::Ca) {
    const Gaussian<3>& g = ch.g[static_cast<size_t>(j)];
    const double w_v = significanceWeight(g.x(1), g.P(1, 1), shrink_v_sigmas_);
    x(1) *= w_v;
    x(2) *= w_v;
  }
  return x;
}

Vec<3> ImmPredictor::feedforwardStartMean(const Channel& ch, int j) const {
  const Gaussian<3>& g = ch.g[static_cast<size_t>(j)];
  Vec<3> x = g.x;
  if (modes_[static_cast<size_t>(j)].kind == ImmMode::Ca) x(2) *= significanceWeight(g.x(2), g.P(2, 2), shrink_a_sigmas_);
  return x;
}

Gaussian<3> ImmPredictor::forecastStart(const Channel& ch, int j) const {
  Gaussian<3> g = ch.g[static_cast<size_t>(j)];
  g.x = forecastStartMean(ch, j);
  return g;
}

ChannelEstimate ImmPredictor::predict(int channel, double t_s) const {
  const Channel& ch = chan_.at(static_cast<size_t>(channel));
  ChannelEstimate e;
  if (!ch.initialized) {
    e.x = ChannelVector::Constant(3, std::numeric_limits<double>::quiet_NaN());
    e.P = ChannelMatrix::Constant(3, 3, std::numeric_limits<double>::quiet_NaN());
    return e;
  }
  const double dt = t_s - time();
  // A zero horizon: the posteriors mixed by the feed-forward's weights, as its velocity (in a closed
  // loop its own, u; else the forecast's: imm.h, "The feed-forward's velocity").
  if (!(dt > 0.0)) return toEstimate(combine(ch.g, feedforwardWeights(ch)));
  const std::array<double, kMaxModes>& w = forecastWeights(ch);
  std::array<Gaussian<3>, kMaxModes> g;
  for (int j = 0; j < modeCount(); ++j) {
    const auto jj = static_cast<size_t>(j);
    g[jj] = forecastStart(ch, j);
    const double p0 = g[jj].x(0);
    timeUpdate(g[jj], transition(j, dt), processNoise(j, dt, modeRaise(ch, j)));
    // the mode blended with hold by its own weight(s) (predictPosition's arithmetic)
    if (blendsMode(j) && splitsBlend(ch)) {
      ch.mode_rates[jj].capState(extrapolation_cap_, p0, g[jj].x, dt);
      ch.mode_blend[jj].blendStateSplit(ch.blend.z_hold, p0, g[jj].x);
    } else if (blendsMode(j)) {
      ch.mode_blend[jj].blendState(ch.blend.z_hold, g[jj].x);
    }
  }
  Gaussian<3> out = combine(g, w);
  if (blend_tau_s_ > 0.0 && !blendsPerMode()) ch.blend.blendState(ch.blend.z_hold, out.x);
  return toEstimate(out);
}

double ImmPredictor::feedforwardVelocity(int channel, double t_s) const {
  const Channel& ch = chan_.at(static_cast<size_t>(channel));
  if (!ch.initialized) return std::numeric_limits<double>::quiet_NaN();
  const double dt = t_s - time();
  if (!(dt > 0.0) && !learn_feedforward_) return predict(channel, t_s).velocity();  // as before the feed-forward's own (imm.h)
  const std::array<double, kMaxModes>& u = feedforwardWeights(ch);
  double v = 0.0;
  if (!(dt > 0.0)) {  // a zero horizon: the posteriors' velocities, without w_ff (imm.h)
    for (int j = 0; j < modeCount(); ++j)
      if (modes_[static_cast<size_t>(j)].dim > 1) v += u[static_cast<size_t>(j)] * ch.g[static_cast<size_t>(j)].x(1);
    return v;
  }
  for (int j = 0; j < modeCount(); ++j) {
    if (modes_[static_cast<size_t>(j)].dim < 2) continue;  // a constant position: no velocity
    v += u[static_cast<size_t>(j)] * predictedMean(feedforwardStartMean(ch, j), transition(j, dt))(1);
  }
  return learn_feedforward_ ? ch.feedforward.weight(blend_prior_) * v : v;
}

double ImmPredictor::predictPosition(int channel, double t_s) const {
  const Channel& ch = chan_.at(static_cast<size_t>(channel));
  if (!ch.initialized) return std::numeric_limits<double>::quiet_NaN();
  const double dt = t_s - time();
  if (!(dt > 0.0)) return predict(channel, t_s).position();
  // Each mode's (F x)(0): for CP and CV written out (their states beyond d are 0, so the sum has
  // one or two non-zero terms: the same bits), for CA predictedPosition (kalman_math.h).
  const std::array<double, kMaxModes>& w = forecastWeights(ch);
  double p = 0.0;
  for (int j = 0; j < modeCount(); ++j) {
    const auto jj = static_cast<size_t>(j);
    const int d = modes_[jj].dim;
    const double pj = d == 1   ? ch.g[jj].x(0)
                      : d == 2 ? ch.g[jj].x(0) + dt * ch.g[jj].x(1)
                               : predictedPosition(forecastStartMean(ch, j), transition(j, dt));
    if (!blendsMode(j)) {
      p += w[jj] * pj;
    } else if (splitsBlend(ch)) {
      const double p0 = ch.g[jj].x(0);
      p += w[jj] * ch.mode_blend[jj].blendSplit(ch.blend.z_hold, p0, ch.mode_rates[jj].capped(extrapolation_cap_, p0, pj, dt));
    } else {
      p += w[jj] * ch.mode_blend[jj].blend(ch.blend.z_hold, pj);
    }
  }
  return blend_tau_s_ > 0.0 && !blendsPerMode() ? ch.blend.position(p) : p;
}

NamedValues ImmPredictor::diagnostics() const {
  NamedValues out;
  for (int c = 0; c < channels(); ++c)
    for (int j = 0; j < modeCount(); ++j) {
      const Mode& md = modes_[static_cast<size_t>(j)];
      out.emplace_back(std::string("mu_") + immModeName(md.kind) + "_" + std::to_string(c),
                       chan_[static_cast<size_t>(c)].mu[static_cast<size_t>(j)]);
    }
  // The forecast weights after the mode probabilities: the weights the forecast combines the
  // modes with (the probabilities themselves when forecast_tau_s = 0).
  for (int c = 0; c < channels(); ++c)
    for (int j = 0; j < modeCount(); ++j)
      out.emplace_back(std::string("fw_") + immModeName(modes_[static_cast<size_t>(j)].kind) + "_" + std::to_string(c),
                       forecastWeight(c, modes_[static_cast<size_t>(j)].kind));
  // Then, when it learns them (a closed loop), the feed-forward's weights of the moving modes (imm.h,
  // "The feed-forward's velocity").
  if (!learn_feedforward_) return out;
  for (int c = 0; c < channels(); ++c)
    for (int j = 0; j < modeCount(); ++j)
      if (modes_[static_cast<size_t>(j)].dim > 1)
        out.emplace_back(std::string("ff_") + immModeName(modes_[static_cast<size_t>(j)].kind) + "_" + std::to_string(c),
                         chan_[static_cast<size_t>(c)].ff_w[static_cast<size_t>(j)]);
  return out;
}

// Noise-fit support (calibration/noise_fit.h): what seeds a fit of imm.
std::vector<FitSeed> ImmPredictor::fitSeeds() const {
  std::vector<FitSeed> seeds = {motionDensitySeed<2>("q_cv")};
  if (alpha_ == 0.0) seeds.push_back(motionDensitySeed<3>("q_ca"));
  return seeds;
}

// The CP mode is imm's one structural choice of modes: without it, imm is the IMM of its two
// single models (kf-cv's and kf-ca's), whose forecast weights then choose between those alone.
// Measured (docs/PERFORMANCE.md "Warm start"): on hand 60 Hz 1.5 px #1 the fitted imm with CP is
// 1.15 times kf-ca fitted, without it 0.99.
std::vector<Params> ImmPredictor::structuralVariants() const {
  Params with_cp, without_cp;
  with_cp.set("cp", 1.0);
  without_cp.set("cp", 0.0);
  return {with_cp, without_cp};
}

}  // namespace predvs
