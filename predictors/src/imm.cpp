#include "predvs/predictors/imm.h"

#include "predvs/predictors/cs_akf.h"
#include "predvs/predictors/kalman_baselines.h"

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
      r_auto_(isAutoMeasurementNoise(params)) {
  if (!r_auto_) r_ = params.get("r", 1.0, 1e-12, 1e12);
  const bool with_cp = params.get("cp", 1.0, 0.0, 1.0) >= 0.5;
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
  chain_dt_.fill(std::numeric_limits<double>::quiet_NaN());  // equal to no dt: every entry empty
  reset();
}

void ImmPredictor::reset() {
  resetClock();
  Channel init;
  init.mu.fill(0.0);
  for (int j = 0; j < modeCount(); ++j) init.mu[static_cast<size_t>(j)] = 1.0 / modeCount();
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

Mat<3> ImmPredictor::processNoise(int j, double dt) const {
  Mat<3> Q = Mat<3>::Zero();
  switch (modes_[static_cast<size_t>(j)].kind) {
    case ImmMode::Cp:
      Q(0, 0) = q_cp_ * dt;
      break;
    case ImmMode::Cv:
      Q.topLeftCorner<2, 2>() = cvProcessNoise(q_cv_, dt);
      break;
    case ImmMode::Ca:
      Q = alpha_ > 0.0 ? singerProcessNoise(alpha_, q_ca_ / (2.0 * alpha_), dt) : caProcessNoise(q_ca_, dt);
      break;
  }
  return Q;
}

ImmPredictor::ModeMatrix ImmPredictor::chain(double dt) const { return cachedChain(dt); }

const ImmPredictor::ModeMatrix& ImmPredictor::cachedChain(double dt) const {
  for (int k = 0; k < kChainCacheSize; ++k)
    if (chain_dt_[static_cast<size_t>(k)] == dt) return chain_[static_cast<size_t>(k)];
  const auto slot = static_cast<size_t>(chain_next_);
  chain_next_ = (chain_next_ + 1) % kChainCacheSize;
  chain_[slot] = computeChain(dt);
  chain_dt_[slot] = dt;
  return chain_[slot];
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

Gaussian<3> ImmPredictor::embed(const Gaussian<3>& from, int dim_from, const Gaussian<3>& into, int dim_into) {
  if (dim_from >= dim_into) return from;
  Gaussian<3> g = from;
  for (int k = dim_from; k < 3; ++k) {
    g.P.row(k).setZero();
    g.P.col(k).setZero();
  }
  for (int k = dim_from; k < dim_into; ++k) {
    g.x(k) = into.x(k);
    for (int l = dim_from; l < dim_into; ++l) g.P(k, l) = into.P(k, l);
  }
  return g;
}

void ImmPredictor::update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) {
  if (z.size() != channels())
    throw std::invalid_argument(name() + ": measurement has " + std::to_string(z.size()) + " entries, expected " +
                                std::to_string(channels()));
  const double dt = advanceClock(t_s);
  const int m = modeCount();
  const ModeMatrix& Pi = cachedChain(dt);
  // Each mode's F and Q over dt, the same for every channel.
  std::array<Mat<3>, kMaxModes> F, Q;
  for (int j = 0; j < m; ++j) {
    F[static_cast<size_t>(j)] = transition(j, dt);
    Q[static_cast<size_t>(j)] = processNoise(j, dt);
  }
  for (int c = 0; c < channels(); ++c) {
    Channel& ch = chan_[static_cast<size_t>(c)];
    ch.innovation = Innovation{};
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
      continue;
    }
    // Mixing: c_j = sum_i p_ij mu_i, mu_i|j = p_ij mu_i / c_j, moments of the mixture.
    std::array<double, kMaxModes> cbar{};
    std::array<Gaussian<3>, kMaxModes> mixed;
    for (int j = 0; j < m; ++j) {
      const auto jj = static_cast<size_t>(j);
      for (int i = 0; i < m; ++i) cbar[jj] += Pi(i, j) * ch.mu[static_cast<size_t>(i)];
      std::array<Gaussian<3>, kMaxModes> src;
      std::array<double, kMaxModes> w{};
      for (int i = 0; i < m; ++i) {
        const auto ii = static_cast<size_t>(i);
        w[ii] = cbar[jj] > 0.0 ? Pi(i, j) * ch.mu[ii] / cbar[jj] : (i == j ? 1.0 : 0.0);
        src[ii] = embed(ch.g[ii], modes_[ii].dim, ch.g[jj], modes_[jj].dim);
      }
      mixed[jj] = combine(src, w);
    }
    // Coasting on an unmeasured frame (channel_predictor.h): velocity and acceleration decay.
    if (coast_tau_s_ > 0.0 && !isMeasured(z(c)))
      for (int j = 0; j < m; ++j) coast(mixed[static_cast<size_t>(j)].x, dt, coast_tau_s_);
    // Mode-matched filters (each zeroes the states its model does not have).
    for (int j = 0; j < m; ++j) timeUpdate(mixed[static_cast<size_t>(j)], F[static_cast<size_t>(j)], Q[static_cast<size_t>(j)]);
    if (isMeasured(z(c))) {
      double xbar = 0.0;
      for (int j = 0; j < m; ++j) xbar += cbar[static_cast<size_t>(j)] * mixed[static_cast<size_t>(j)].x(0);
      double S = 0.0, maxll = -std::numeric_limits<double>::infinity();
      std::array<double, kMaxModes> loglik{};
      for (int j = 0; j < m; ++j) {
        const auto jj = static_cast<size_t>(j);
        const double d = mixed[jj].x(0) - xbar;
        S += cbar[jj] * (mixed[jj].P(0, 0) + R + d * d);
        const Innovation in = measurementUpdate(mixed[jj], z(c), R);
        loglik[jj] = -0.5 * (kLog2Pi + std::log(in.S) + in.eps * in.eps / in.S);
        maxll = std::max(maxll, loglik[jj]);
      }
      ch.innovation = Innovation{z(c) - xbar, S, true};
      std::array<double, kMaxModes> w{};
      double sum = 0.0;
      for (int j = 0; j < m; ++j) {
        const auto jj = static_cast<size_t>(j);
        w[jj] = cbar[jj] * std::exp(loglik[jj] - maxll);
        sum += w[jj];
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
    }
    ch.g = mixed;
  }
}

Gaussian<3> ImmPredictor::combine(const std::array<Gaussian<3>, kMaxModes>& g, const std::array<double, kMaxModes>& w) const {
  // Written out on scalars, entry by entry, with the operations of the Eigen expressions
  //   x = 0; x += w_j x_j (each j);  P = 0; P += w_j (P_j + d_j d_j') (each j), d_j = x_j - x
  // in the same order (so the same bits): an outer product's entry is d(r) d(c), a sum of
  // matrices is entrywise. About three times faster than the Eigen expressions on these
  // runtime-counted 3-state loops (the hot path of imm's mixing).
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

ChannelEstimate ImmPredictor::predict(int channel, double t_s) const {
  const Channel& ch = chan_.at(static_cast<size_t>(channel));
  ChannelEstimate e;
  if (!ch.initialized) {
    e.x = ChannelVector::Constant(3, std::numeric_limits<double>::quiet_NaN());
    e.P = ChannelMatrix::Constant(3, 3, std::numeric_limits<double>::quiet_NaN());
    return e;
  }
  const double dt = t_s - time();
  if (!(dt > 0.0)) return toEstimate(combine(ch.g, ch.mu));
  std::array<Gaussian<3>, kMaxModes> g = ch.g;
  for (int j = 0; j < modeCount(); ++j) timeUpdate(g[static_cast<size_t>(j)], transition(j, dt), processNoise(j, dt));
  return toEstimate(combine(g, ch.mu));
}

double ImmPredictor::predictPosition(int channel, double t_s) const {
  const Channel& ch = chan_.at(static_cast<size_t>(channel));
  if (!ch.initialized) return std::numeric_limits<double>::quiet_NaN();
  const double dt = t_s - time();
  if (!(dt > 0.0)) return predict(channel, t_s).position();
  double p = 0.0;
  for (int j = 0; j < modeCount(); ++j) {
    const auto jj = static_cast<size_t>(j);
    p += ch.mu[jj] * predictedPosition(ch.g[jj], transition(j, dt));
  }
  return p;
}

NamedValues ImmPredictor::diagnostics() const {
  NamedValues out;
  for (int c = 0; c < channels(); ++c)
    for (int j = 0; j < modeCount(); ++j) {
      const Mode& md = modes_[static_cast<size_t>(j)];
      out.emplace_back(std::string("mu_") + immModeName(md.kind) + "_" + std::to_string(c),
                       chan_[static_cast<size_t>(c)].mu[static_cast<size_t>(j)]);
    }
  return out;
}

}  // namespace predvs
