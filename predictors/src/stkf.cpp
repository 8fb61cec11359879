#include "predvs/predictors/stkf.h"

#include "predvs/predictors/kalman_baselines.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace predvs {

namespace {

/// The `model` word: "cv" or "ca" (absent: `fallback`); anything else is a one-line error naming the key.
std::string modelParam(const Params& params, const char* fallback) {
  const std::string m = params.text("model", fallback);
  if (m != "cv" && m != "ca")
    throw std::invalid_argument("predictor parameter 'model' must be cv or ca, got '" + m + "'");
  return m;
}

/// `window`: 0 (off) or an integer k >= min_k (min_k = number of polynomial coefficients + 1).
int windowParam(const Params& params, int min_k, double fallback) {
  const double k = params.get("window", fallback, 0.0, 1000.0);
  if (k != static_cast<int>(k) || (k > 0.0 && k < min_k))
    throw std::invalid_argument("predictor parameter 'window' must be 0 (off) or an integer >= " +
                                std::to_string(min_k) + (min_k > 3 ? " (model ca: a quadratic fit)" : "") +
                                ", got " + std::to_string(k));
  return static_cast<int>(k);
}

constexpr const char* kModelWord[] = {"", "", "cv", "ca"};

/// `process_noise`: true for `white-acceleration`, false for `diagonal` (the default); anything
/// else is a one-line error naming the key. Read on both models (ca: checked, unused; stkf.h).
bool whiteAccelerationParam(const Params& params) {
  const std::string w = params.text("process_noise", "diagonal");
  if (w != "diagonal" && w != "white-acceleration")
    throw std::invalid_argument("predictor parameter 'process_noise' must be diagonal or white-acceleration, got '" + w +
                                "'");
  return w == "white-acceleration";
}

/// Default p0_vel ((px/s)^2): the paper's 1 on the diagonal cv model, kf-cv's 1e4 on the
/// white-acceleration one, kf-ca's on ca.
template <int N>
double defaultP0Vel(const Params& params) {
  if (N == 3) return kDefaultStkfCaP0;
  return whiteAccelerationParam(params) ? 1e4 : 1.0;
}

}  // namespace

template <int N>
Eigen::MatrixXd StkfFilter<N>::makeResidualMaker(int k) {
  if (k < N + 1)
    throw std::invalid_argument(std::string("stkf: residual maker needs k >= ") + std::to_string(N + 1));
  Eigen::MatrixXd A(k, N);
  Eigen::MatrixXd pinvA;  // (A'A)^-1 A' by a solve: X = argmin, no explicit inverse.
  if constexpr (N == 2) {
    for (int i = 0; i < k; ++i) A.row(i) << i + 1.0, 1.0;
    const Eigen::Matrix2d AtA = A.transpose() * A;
    pinvA = AtA.ldlt().solve(A.transpose());
  } else {
    // [s^2, s, 1] with s affine in n = i + 1 spans the same space as [n^2, n, 1].
    for (int i = 0; i < k; ++i) {
      const double s = (2.0 * (i + 1.0) - k - 1.0) / (k - 1.0);
      A.row(i) << s * s, s, 1.0;
    }
    const Eigen::Matrix3d AtA = A.transpose() * A;
    pinvA = AtA.ldlt().solve(A.transpose());
  }
  return Eigen::MatrixXd::Identity(k, k) - A * pinvA;
}

template <int N>
StkfFilter<N>::StkfFilter(int channels, const Params& params)
    : Base(channels, measurementNoiseParam(params, 1.0), params.get("p0_vel", defaultP0Vel<N>(params), 0.0, 1e12),
           N == 3 ? params.get("p0_acc", kDefaultStkfCaP0, 0.0, 1e12) : 0.0),
      p0_pos_(params.get("p0_pos", 1.0, 0.0, 1e12)),
      white_acceleration_(N == 2 && whiteAccelerationParam(params)),
      p0_pos_is_r_(white_acceleration_ && !params.has("p0_pos")),
      window_(windowParam(params, N + 1, N == 2 ? 15.0 : kDefaultStkfCaWindow)),
      squared_(params.get("squared", 0.0, 0.0, 1.0) != 0.0),
      reinit_threshold_(params.get("reinit_threshold",
                                   white_acceleration_ ? std::numeric_limits<double>::infinity() : 4800.0, 1e-12,
                                   std::numeric_limits<double>::infinity())),
      reinit_threshold_vel_(N == 3 || white_acceleration_
                                ? params.get("reinit_threshold_vel", std::numeric_limits<double>::infinity(), 1e-12,
                                             std::numeric_limits<double>::infinity())
                                : reinit_threshold_),
      reinit_threshold_acc_(N == 3 ? params.get("reinit_threshold_acc", std::numeric_limits<double>::infinity(), 1e-12,
                                                std::numeric_limits<double>::infinity())
                                   : std::numeric_limits<double>::infinity()),
      known_v_px_s_(Eigen::VectorXd::Zero(channels)),
      window_y_(static_cast<size_t>(channels), Eigen::VectorXd::Zero(window_)),
      window_count_(static_cast<size_t>(channels), 0),
      r_(static_cast<size_t>(channels), r0_),
      pending_(static_cast<size_t>(channels), 0) {
  const std::string model = modelParam(params, kModelWord[N]);  // a class built directly is its own model
  if (model != kModelWord[N])
    throw std::invalid_argument("stkf: model '" + model + "' is built by makeStkfPredictor(), not by StkfFilter<" +
                                std::to_string(N) + "> (model " + kModelWord[N] + ")");
  whiteAccelerationParam(params);  // ca: checked, unused (stkf.h)
  if constexpr (N == 2) {
    q_pos_ = params.get("q_pos", 0.0, 0.0, 1e12);
    q_vel_ = params.get("q_vel", 3000.0, 0.0, 1e12);
    q_period_s_ = params.get("q_period_s", 0.1, 1e-9, 1e3);
    if (white_acceleration_) q_ = params.get("q", kDefaultQCv, 0.0, 1e12);
  } else {
    q_ = params.get("q", kDefaultQStkfCa, 0.0, 1e15);
  }
  if (window_ > 0) T_st_ = makeResidualMaker(window_);
  eps_.resize(window_);
  this->readCoastParam(params);
  this->readShrinkParams(params,
                         N == 3 ? kDefaultShrinkSigmasStkfCa
                                : (white_acceleration_ ? kDefaultShrinkSigmasKfCv : kDefaultShrinkSigmasStkf),
                         kDefaultShrinkVelocityStkf);
  // In a closed loop the spread, not the whitening (process_noise_adapt.h): the self-tuned R moves
  // with the window's scatter every frame, so the innovations' normalisation does too, and with the
  // whitening stkf lost 1.3-1.7x on ibvs-moving-target and e5-circle (docs/PERFORMANCE.md
  // "Innovations made white").
  this->readProcessNoiseRaise(params, {"q", "q_pos", "q_vel"}, InnovationStatistic::Spread);
  if (isAutoMeasurementNoise(params)) this->enableAutoNoise();
}

template <int N>
std::vector<NoiseParameter> StkfFilter<N>::noiseParameters() const {
  if constexpr (N == 2) {
    if (white_acceleration_) return {this->measurementNoiseParameter(), accelerationDensityParameter("q", q_)};
    return {this->measurementNoiseParameter(), {"q_pos", 1e-6, 1e4, q_pos_}, {"q_vel", 1e-4, 1e7, q_vel_}};
  } else {
    return {this->measurementNoiseParameter(), jerkDensityParameter("q", q_)};
  }
}

template <int N>
std::vector<FitSeed> StkfFilter<N>::fitSeeds() const {
  // ca and white-acceleration cv: the same density as kf-ca's / kf-cv's q. Diagonal cv: the
  // diagonal of kf-cv's white-acceleration Q over one q_period_s T_0, q [T_0^3/3, T_0].
  if (N == 3 || white_acceleration_) return {motionDensitySeed<N>("q")};
  const double T0 = q_period_s_;
  return {{"q_pos", "kf-cv", "q", T0 * T0 * T0 / 3.0, 1.0}, {"q_vel", "kf-cv", "q", T0, 1.0}};
}

template <int N>
std::vector<Params> StkfFilter<N>::structuralVariants() const {
  // The motion model, and for cv also the shortest self-tuning window: the window is an integer
  // a gradient fit cannot move, and on stops, bursts and zigzags the paper's k = 15 slows the
  // filter through every manoeuvre (docs/PERFORMANCE.md, "stkf on either motion model": the fit
  // choosing among the three is within 10 % of the best fitted fixed KF on 155/216 tracks, 121
  // with cv and ca alone). ca's default window is already its shortest (4). And each model with
  // window 0, the self-tuning off (the plain KF of the model): where the self-tuned R does not
  // pay on a track, the fit says so (as `adaptation: off` of the other adaptive filters).
  // Then the white-acceleration cv model with the same two windows, 3 and 0: with window 0 it is
  // kf-cv's filter (stkf.h), so the fit can always fall back on the best fixed cv filter.
  constexpr int kDefaultWindow = -1;
  const auto variant = [](const char* model, const char* process_noise, int window) {
    Params p;
    p.setText("model", model);
    if (process_noise != nullptr) p.setText("process_noise", process_noise);
    if (window != kDefaultWindow) p.set("window", window);
    return p;
  };
  const char* const wa = "white-acceleration";
  return {variant("cv", nullptr, kDefaultWindow), variant("cv", nullptr, 3), variant("ca", nullptr, kDefaultWindow),
          variant("cv", nullptr, 0),              variant("ca", nullptr, 0), variant("cv", wa, 3),
          variant("cv", wa, 0)};
}

template <int N>
Mat<N> StkfFilter<N>::transition(int, double dt) const {
  return motionTransition<N>(dt);
}

template <int N>
Mat<N> StkfFilter<N>::processNoise(int c, double dt) const {
  const double raise = this->processNoiseScale(c);  // the raise of q (process_noise_adapt.h); 1 when off
  if constexpr (N == 2) {
    if (white_acceleration_) return cvProcessNoise(q_ * raise, dt);
    Mat<2> Q = Mat<2>::Zero();
    const double scale = raise * dt / q_period_s_;
    Q(0, 0) = scale * q_pos_;
    Q(1, 1) = scale * q_vel_;
    return Q;
  } else {
    return caProcessNoise(q_ * raise, dt);
  }
}

template <int N>
bool StkfFilter<N>::pastReinitThreshold(const Mat<N>& P) const {
  if constexpr (N == 2) {
    if (white_acceleration_) return P(0, 0) > reinit_threshold_ || P(1, 1) > reinit_threshold_vel_;
    return P.diagonal().maxCoeff() > reinit_threshold_;
  }
  else
    return P(0, 0) > reinit_threshold_ || P(1, 1) > reinit_threshold_vel_ || P(2, 2) > reinit_threshold_acc_;
}

template <int N>
void StkfFilter<N>::resetAdaptation() {
  for (size_t c = 0; c < r_.size(); ++c) {
    window_count_[c] = 0;
    r_[c] = r0_;
    pending_[c] = 0;
  }
  known_v_px_s_.setZero();
  reinits_ = 0;
}

template <int N>
void StkfFilter<N>::pushSample(int c, double z) {
  const size_t i = static_cast<size_t>(c);
  if (window_ == 0) return;
  Eigen::VectorXd& y = window_y_[i];
  if (window_count_[i] < window_) {
    y(window_count_[i]++) = z;
  } else {
    std::copy(y.data() + 1, y.data() + window_, y.data());  // drop the oldest, in place (no allocation)
    y(window_ - 1) = z;
  }
  if (window_count_[i] < window_) {
    r_[i] = this->nominalNoise(c);
    return;
  }
  // Residuals of the least-squares polynomial through the window (mean zero: the fit has an
  // intercept).
  eps_.noalias() = T_st_ * y;  // into the kept buffer: no allocation per sample
  const double var = eps_.squaredNorm() / (window_ - 1);
  r_[i] = this->nominalNoise(c) + (squared_ ? var * var : var);
}

template <int N>
void StkfFilter<N>::initialize(int c, double z) {
  const size_t i = static_cast<size_t>(c);
  window_count_[i] = 0;
  pushSample(c, z);  // first sample of a new window: R = R_0
  Gaussian<N>& g = state_[i].g;
  g.x.setZero();
  g.x(0) = z;
  g.P.setZero();
  g.P(0, 0) = p0_pos_is_r_ ? this->nominalNoise(c) : p0_pos_;  // white-acceleration: kf-cv's P_0
  g.P(1, 1) = p0_vel_;
  if constexpr (N == 3) g.P(2, 2) = p0_acc_;
  pending_[i] = 0;
}

template <int N>
void StkfFilter<N>::step(int c, double dt, double z) {
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
  if (window_ == 0) r_[i] = this->nominalNoise(c);
  timeUpdate(s.g, transition(c, dt), processNoise(c, dt));
  s.g.x(0) += dt * known_v_px_s_(c);  // B u: known robot-induced image motion
  if (isMeasured(z)) s.innovation = measurementUpdate(s.g, z, r_[i]);
  if (pastReinitThreshold(s.g.P)) {
    pending_[i] = 1;
    window_count_[i] = 0;
    r_[i] = this->nominalNoise(c);
    ++reinits_;
  }
}

template <int N>
void StkfFilter<N>::update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) {
  Base::update(t_s, z);
  known_v_px_s_.setZero();
}

template <int N>
ChannelEstimate StkfFilter<N>::predict(int channel, double t_s) const {
  ChannelEstimate e = Base::predict(channel, t_s);
  const double dt = t_s - this->time();
  if (dt > 0.0 && this->initialized(channel)) e.x(0) += dt * known_v_px_s_(channel);
  return e;
}

template <int N>
double StkfFilter<N>::predictPosition(int channel, double t_s) const {
  double p = Base::predictPosition(channel, t_s);
  const double dt = t_s - this->time();
  if (dt > 0.0 && this->initialized(channel)) p += dt * known_v_px_s_(channel);
  return p;
}

template <int N>
void StkfFilter<N>::setKnownImageVelocity(const Eigen::VectorXd& v_px_s) {
  if (v_px_s.size() != this->channels())
    throw std::invalid_argument("stkf: known image velocity has " + std::to_string(v_px_s.size()) +
                                " entries, expected " + std::to_string(this->channels()));
  known_v_px_s_ = v_px_s;
}

template class StkfFilter<2>;
template class StkfFilter<3>;

std::unique_ptr<Predictor> makeStkfPredictor(int channels, const Params& params) {
  // The registry's default is ca (issue 11: with its weighted forecast it beats hold on every
  // generated track, the paper's cv filter on 213 of 216; docs/MODELS.md §4).
  if (modelParam(params, "ca") == "ca") return std::make_unique<StkfCaPredictor>(channels, params);
  return std::make_unique<StkfPredictor>(channels, params);
}

}  // namespace predvs
