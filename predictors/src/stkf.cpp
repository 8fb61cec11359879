#include "predvs/predictors/stkf.h"

#include <Eigen/Cholesky>

#include <stdexcept>
#include <string>

namespace predvs {

namespace {

int windowParam(const Params& params) {
  const double k = params.get("window", 15.0, 0.0, 1000.0);
  if (k != static_cast<int>(k) || (k > 0.0 && k < 3.0))
    throw std::invalid_argument("predictor parameter 'window' must be 0 (off) or an integer >= 3, got " +
                                std::to_string(k));
  return static_cast<int>(k);
}

}  // namespace

Eigen::MatrixXd StkfPredictor::makeResidualMaker(int k) {
  if (k < 3) throw std::invalid_argument("stkf: residual maker needs k >= 3");
  Eigen::MatrixXd A(k, 2);
  for (int i = 0; i < k; ++i) A.row(i) << i + 1.0, 1.0;
  const Eigen::Matrix2d AtA = A.transpose() * A;
  // (A'A)^-1 A' by a solve: X = argmin, no explicit inverse.
  const Eigen::MatrixXd pinvA = AtA.ldlt().solve(A.transpose());
  return Eigen::MatrixXd::Identity(k, k) - A * pinvA;
}

StkfPredictor::StkfPredictor(int channels, const Params& params)
    : ChannelPredictor<2>(channels, measurementNoiseParam(params, 1.0), params.get("p0_vel", 1.0, 0.0, 1e12), 0.0),
      q_pos_(params.get("q_pos", 0.0, 0.0, 1e12)),
      q_vel_(params.get("q_vel", 3000.0, 0.0, 1e12)),
      q_period_s_(params.get("q_period_s", 0.1, 1e-9, 1e3)),
      p0_pos_(params.get("p0_pos", 1.0, 0.0, 1e12)),
      window_(windowParam(params)),
      squared_(params.get("squared", 0.0, 0.0, 1.0) != 0.0),
      reinit_threshold_(params.get("reinit_threshold", 4800.0, 1e-12, 1e300)),
      known_v_px_s_(Eigen::VectorXd::Zero(channels)),
      window_y_(static_cast<size_t>(channels), Eigen::VectorXd::Zero(window_)),
      window_count_(static_cast<size_t>(channels), 0),
      r_(static_cast<size_t>(channels), r0_),
      pending_(static_cast<size_t>(channels), 0) {
  if (window_ > 0) T_st_ = makeResidualMaker(window_);
  readCoastParam(params);
  if (isAutoMeasurementNoise(params)) enableAutoNoise();
}

Mat<2> StkfPredictor::processNoise(int, double dt) const {
  Mat<2> Q = Mat<2>::Zero();
  const double scale = dt / q_period_s_;
  Q(0, 0) = scale * q_pos_;
  Q(1, 1) = scale * q_vel_;
  return Q;
}

void StkfPredictor::resetAdaptation() {
  for (size_t c = 0; c < r_.size(); ++c) {
    window_count_[c] = 0;
    r_[c] = r0_;
    pending_[c] = 0;
  }
  known_v_px_s_.setZero();
  reinits_ = 0;
}

void StkfPredictor::pushSample(int c, double z) {
  const size_t i = static_cast<size_t>(c);
  if (window_ == 0) return;
  Eigen::VectorXd& y = window_y_[i];
  if (window_count_[i] < window_) {
    y(window_count_[i]++) = z;
  } else {
    y.head(window_ - 1) = y.tail(window_ - 1).eval();
    y(window_ - 1) = z;
  }
  if (window_count_[i] < window_) {
    r_[i] = nominalNoise(c);
    return;
  }
  // Residuals of the least-squares line through the window (mean zero: the fit has an intercept).
  const Eigen::VectorXd eps = T_st_ * y;
  const double var = eps.squaredNorm() / (window_ - 1);
  r_[i] = nominalNoise(c) + (squared_ ? var * var : var);
}

void StkfPredictor::initialize(int c, double z) {
  const size_t i = static_cast<size_t>(c);
  window_count_[i] = 0;
  pushSample(c, z);  // first sample of a new window: R = R_0
  Gaussian<2>& g = state_[i].g;
  g.x << z, 0.0;
  g.P.setZero();
  g.P(0, 0) = p0_pos_;
  g.P(1, 1) = p0_vel_;
  pending_[i] = 0;
}

void StkfPredictor::step(int c, double dt, double z) {
  const size_t i = static_cast<size_t>(c);
  ChannelState& s = state_[i];
  if (pending_[i] != 0) {
    if (isMeasured(z)) {
      initialize(c, z);
      return;
    }
    // Still occluded: keep extrapolating so that predict() stays usable.
    timeUpdate(s.g, transition(c, dt), processNoise(c, dt));
    s.g.x(0) += dt * known_v_px_s_(c);
    return;
  }
  // Paper 001 step (3): store the measurement and re-tune R before propagating.
  if (isMeasured(z))
    pushSample(c, z);
  else
    window_count_[i] = 0;  // the fixed T_st assumes consecutive, equally spaced samples
  if (window_ == 0) r_[i] = nominalNoise(c);
  timeUpdate(s.g, transition(c, dt), processNoise(c, dt));
  s.g.x(0) += dt * known_v_px_s_(c);  // B u: known robot-induced image motion
  if (isMeasured(z)) s.innovation = measurementUpdate(s.g, z, r_[i]);
  if (s.g.P.diagonal().maxCoeff() > reinit_threshold_) {
    pending_[i] = 1;
    window_count_[i] = 0;
    r_[i] = nominalNoise(c);
    ++reinits_;
  }
}

void StkfPredictor::update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) {
  ChannelPredictor<2>::update(t_s, z);
  known_v_px_s_.setZero();
}

ChannelEstimate StkfPredictor::predict(int channel, double t_s) const {
  ChannelEstimate e = ChannelPredictor<2>::predict(channel, t_s);
  const double dt = t_s - time();
  if (dt > 0.0 && initialized(channel)) e.x(0) += dt * known_v_px_s_(channel);
  return e;
}

double StkfPredictor::predictPosition(int channel, double t_s) const {
  double p = ChannelPredictor<2>::predictPosition(channel, t_s);
  const double dt = t_s - time();
  if (dt > 0.0 && initialized(channel)) p += dt * known_v_px_s_(channel);
  return p;
}

void StkfPredictor::setKnownImageVelocity(const Eigen::VectorXd& v_px_s) {
  if (v_px_s.size() != channels())
    throw std::invalid_argument("stkf: known image velocity has " + std::to_string(v_px_s.size()) +
                                " entries, expected " + std::to_string(channels()));
  known_v_px_s_ = v_px_s;
}

}  // namespace predvs
