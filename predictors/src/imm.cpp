#include "predvs/predictors/imm.h"

#include "predvs/predictors/cs_akf.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

constexpr double kLog2Pi = 1.8378770664093453;

/// Mixture moments: x = sum w_j x_j, P = sum w_j (P_j + (x_j - x)(x_j - x)').
Gaussian<3> combine(const std::array<Gaussian<3>, 2>& g, const std::array<double, 2>& w) {
  Gaussian<3> out;
  out.x = w[0] * g[0].x + w[1] * g[1].x;
  out.P.setZero();
  for (int j = 0; j < 2; ++j) {
    const Vec<3> d = g[static_cast<size_t>(j)].x - out.x;
    out.P += w[static_cast<size_t>(j)] * (g[static_cast<size_t>(j)].P + d * d.transpose());
  }
  symmetrize(out.P);
  return out;
}

}  // namespace

ImmPredictor::ImmPredictor(int channels, const Params& params)
    : Predictor(channels),
      q_cv_(params.get("q_cv", 100.0, 0.0, 1e12)),
      q_ca_(params.get("q_ca", 1e6, 0.0, 1e15)),
      alpha_(params.get("alpha", 5.0, 1e-6, 1e3)),
      r_(1.0),
      tau_cv_s_(params.get("tau_cv_s", 10.0, 1e-6, 1e6)),
      tau_ca_s_(params.get("tau_ca_s", 0.5, 1e-6, 1e6)),
      mu0_ca_(params.get("mu0_ca", 0.5, 0.0, 1.0)),
      p0_vel_(params.get("p0_vel", 1e4, 0.0, 1e12)),
      p0_acc_(params.get("p0_acc", 1e4, 0.0, 1e12)),
      r_auto_(isAutoMeasurementNoise(params)) {
  if (!r_auto_) r_ = params.get("r", 1.0, 1e-12, 1e12);
  reset();
}

void ImmPredictor::reset() {
  resetClock();
  Channel init;
  init.mu = {1.0 - mu0_ca_, mu0_ca_};
  chan_.assign(static_cast<size_t>(channels()), init);
}

double ImmPredictor::measurementNoise(int c) const {
  return r_auto_ ? chan_.at(static_cast<size_t>(c)).r_est.variance() : r_;
}

Mat<3> ImmPredictor::transition(int mode, double dt) const {
  if (mode == 1) return singerTransition(alpha_, dt);
  Mat<3> F = Mat<3>::Zero();
  F(0, 0) = 1.0;
  F(0, 1) = dt;
  F(1, 1) = 1.0;
  return F;
}

Mat<3> ImmPredictor::processNoise(int mode, double dt) const {
  if (mode == 1) return singerProcessNoise(alpha_, q_ca_ / (2.0 * alpha_), dt);
  Mat<3> Q = Mat<3>::Zero();
  Q.topLeftCorner<2, 2>() = cvProcessNoise(q_cv_, dt);
  return Q;
}

Mat<2> ImmPredictor::chain(double dt) const {
  const double p00 = std::exp(-dt / tau_cv_s_), p11 = std::exp(-dt / tau_ca_s_);
  Mat<2> P;
  P << p00, 1.0 - p00, 1.0 - p11, p11;
  return P;
}

void ImmPredictor::update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) {
  if (z.size() != channels())
    throw std::invalid_argument(name() + ": measurement has " + std::to_string(z.size()) + " entries, expected " +
                                std::to_string(channels()));
  const double dt = advanceClock(t_s);
  const Mat<2> Pi = chain(dt);
  for (int c = 0; c < channels(); ++c) {
    Channel& ch = chan_[static_cast<size_t>(c)];
    ch.innovation = Innovation{};
    if (r_auto_) ch.r_est.push(t_s, z(c));
    const double R = measurementNoise(c);
    if (!ch.initialized) {
      if (!isMeasured(z(c))) continue;
      for (auto& g : ch.g) {
        g.x << z(c), 0.0, 0.0;
        g.P.setZero();
        g.P(0, 0) = R;
        g.P(1, 1) = p0_vel_;
        g.P(2, 2) = p0_acc_;
      }
      ch.initialized = true;
      continue;
    }
    // Mixing.
    std::array<double, 2> cbar{};
    for (int j = 0; j < 2; ++j) cbar[static_cast<size_t>(j)] = Pi(0, j) * ch.mu[0] + Pi(1, j) * ch.mu[1];
    std::array<Gaussian<3>, 2> mixed;
    for (int j = 0; j < 2; ++j) {
      std::array<double, 2> w{};
      for (int i = 0; i < 2; ++i)
        w[static_cast<size_t>(i)] = cbar[static_cast<size_t>(j)] > 0.0
                                        ? Pi(i, j) * ch.mu[static_cast<size_t>(i)] / cbar[static_cast<size_t>(j)]
                                        : (i == j ? 1.0 : 0.0);
      mixed[static_cast<size_t>(j)] = combine(ch.g, w);
    }
    // Mode-matched filters.
    for (int j = 0; j < 2; ++j) timeUpdate(mixed[static_cast<size_t>(j)], transition(j, dt), processNoise(j, dt));
    if (isMeasured(z(c))) {
      const double xbar = cbar[0] * mixed[0].x(0) + cbar[1] * mixed[1].x(0);
      double S = 0.0;
      std::array<double, 2> loglik{};
      for (int j = 0; j < 2; ++j) {
        const auto jj = static_cast<size_t>(j);
        const double d = mixed[jj].x(0) - xbar;
        S += cbar[jj] * (mixed[jj].P(0, 0) + R + d * d);
        const Innovation in = measurementUpdate(mixed[jj], z(c), R);
        loglik[jj] = -0.5 * (kLog2Pi + std::log(in.S) + in.eps * in.eps / in.S);
      }
      ch.innovation = Innovation{z(c) - xbar, S, true};
      const double m = std::max(loglik[0], loglik[1]);
      std::array<double, 2> w{};
      double sum = 0.0;
      for (int j = 0; j < 2; ++j) {
        const auto jj = static_cast<size_t>(j);
        w[jj] = cbar[jj] * std::exp(loglik[jj] - m);
        sum += w[jj];
      }
      if (sum > 0.0 && std::isfinite(sum)) {
        // A floor keeps either mode recoverable after a long stretch dominated by the other.
        for (int j = 0; j < 2; ++j) ch.mu[static_cast<size_t>(j)] = std::max(1e-6, w[static_cast<size_t>(j)] / sum);
        const double s2 = ch.mu[0] + ch.mu[1];
        ch.mu[0] /= s2;
        ch.mu[1] /= s2;
      } else {
        ch.mu = cbar;
      }
    } else {
      ch.mu = cbar;
    }
    ch.g = mixed;
  }
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
  const Mat<2> Pi = chain(dt);
  std::array<Gaussian<3>, 2> g = ch.g;
  std::array<double, 2> w{};
  for (int j = 0; j < 2; ++j) {
    timeUpdate(g[static_cast<size_t>(j)], transition(j, dt), processNoise(j, dt));
    w[static_cast<size_t>(j)] = Pi(0, j) * ch.mu[0] + Pi(1, j) * ch.mu[1];
  }
  return toEstimate(combine(g, w));
}

NamedValues ImmPredictor::diagnostics() const {
  NamedValues out;
  for (int c = 0; c < channels(); ++c) out.emplace_back("mu_ca_" + std::to_string(c), modeProbability(c, 1));
  return out;
}

}  // namespace predvs
