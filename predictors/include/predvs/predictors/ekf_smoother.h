// predvs — reference filtering: the extended Kalman filter / smoother that turns the goal s* into
// a sequence of feasible intermediate references (paper 003 §2.3 and §3.2, Algorithms 3 and 4;
// docs/MODELS.md §9).
//
// The state is a filtered reference s_hat* (the 3n features (x, y, Z) of n points). It starts at
// the current features, s_hat*(t|t) = s_t with P(t|t) = 0 (they are known), and evolves with the
// local model of the features under an unknown command, s(tau+1) = s(tau) + J q_dot dt with q_dot
// white noise of density Qc (paper eqs. 16-17: a null mean input, F = I), while the goal s* is
// taken as the observation of every step (C = I). Covariances of a step of dt seconds (eqs.
// 18-21, J = J(s_t, q_t) the Jacobian at the start, 3n x m):
//     Q_dt = dt J Qc J',            R_dt = dt^3 / 3 J Qc J' + dt Rc.
// So Q_dt lies in the range of J: the reference moves only in directions the robot can produce to
// first order (the robot's kinematic constraints), and the backward pass pulls the early
// references towards where the forward pass ended.
//
//  * Algorithm 4 (EKFS, single rate): `steps` steps of dt forward, then the RTS pass back; the
//    law uses reference(1) = s_hat*(t+1|T). SR-HF-EKFS: dt = delta, steps = h N; SR-LF-EKFS:
//    dt = N delta, steps = h.
//  * Algorithm 3 (DR-EKFS, dual rate): N fast steps of delta (Q_delta, R_delta, lines 2-8), then
//    h - 1 slow steps of N delta (Q_Ndelta, R_Ndelta, lines 9-16), to the same horizon
//    T = t + h N delta with N + h - 1 steps instead of h N; the backward pass runs slow then fast
//    (lines 17-23) and gives the N references s_hat*(t+i|T), i = 1..N, one per base period
//    (eq. 22), reference(1..N). Its cost is about 1/N of Algorithm 4's for a long horizon
//    ((N + h - 1) / (h N)), paper Fig. 7b.
// With F = I and H = I both are the generic KalmanSmoother (kalman_smoother.h) with a schedule
// of (Q, R) per step: the backward gain of a slow step, P(tau|tau) P(tau+N|tau)^-1, is the one of
// line 19 because P(tau+N|tau) = P(tau|tau) + Q_Ndelta.
#pragma once

#include "predvs/predictors/kalman_smoother.h"

#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {

template <int Dim = Eigen::Dynamic>
class ReferenceSmoother {
 public:
  using Vector = typename KalmanSmoother<Dim>::Vector;
  using Matrix = typename KalmanSmoother<Dim>::Matrix;

  explicit ReferenceSmoother(Eigen::Index dim = Dim == Eigen::Dynamic ? 0 : Dim) : filter_(dim) {}

  /// Covariances of eqs. 18-21 for one step of dt seconds, given J Qc J' and the diagonal of Rc.
  static void stepCovariances(const Matrix& JQcJt, const Vector& rc_diag, double dt, Matrix& Q, Matrix& R) {
    Q = dt * JQcJt;
    R = (dt * dt * dt / 3.0) * JQcJt;
    R.diagonal() += dt * rc_diag;
  }

  /// Algorithm 4: single-rate EKFS of `steps` steps of dt from s_t towards s_star.
  void runSingleRate(const Vector& s_t, const Vector& s_star, const Matrix& JQcJt, const Vector& rc_diag, double dt,
                     int steps) {
    check(s_t, s_star, JQcJt, rc_diag, dt, steps, "steps");
    stepCovariances(JQcJt, rc_diag, dt, Qf_, Rf_);
    start(s_t);
    for (int k = 1; k <= steps; ++k) step(s_star, Qf_, Rf_, k * dt);
    filter_.smooth();
  }

  /// Algorithm 3: dual-rate EKFS, N fast steps of delta then h - 1 slow steps of N delta.
  void runDualRate(const Vector& s_t, const Vector& s_star, const Matrix& JQcJt, const Vector& rc_diag, double delta,
                   int N, int h) {
    check(s_t, s_star, JQcJt, rc_diag, delta, N, "frame_ticks");
    if (h < 1) throw std::invalid_argument("ReferenceSmoother: the horizon h must be >= 1 frame, got " + std::to_string(h));
    stepCovariances(JQcJt, rc_diag, delta, Qf_, Rf_);
    stepCovariances(JQcJt, rc_diag, N * delta, Qs_, Rs_);
    start(s_t);
    for (int i = 1; i <= N; ++i) step(s_star, Qf_, Rf_, i * delta);               // lines 2-8
    for (int l = 2; l <= h; ++l) step(s_star, Qs_, Rs_, l * N * delta);           // lines 9-16
    filter_.smooth();                                                             // lines 17-23
  }

  /// Number of steps of the last run (the horizon in steps).
  int steps() const { return filter_.steps(); }
  /// Smoothed reference s_hat*(t_k|T) of step k = 1..steps() (for the dual-rate run, k = 1..N are
  /// the base periods of the coming frame).
  const Vector& reference(int k) const { return filter_.smoothed(k); }
  /// Forward (filtered) reference s_hat*(t_k|t_k) of step k.
  const Vector& filtered(int k) const { return filter_.filtered(k); }
  /// Time of step k after t (s).
  double stepTime(int k) const { return times_.at(static_cast<size_t>(k)); }
  const KalmanSmoother<Dim>& filter() const { return filter_; }

 private:
  void check(const Vector& s_t, const Vector& s_star, const Matrix& JQcJt, const Vector& rc_diag, double dt, int count,
             const char* what) const {
    const Eigen::Index n = filter_.dim();
    if (s_t.size() != n || s_star.size() != n || JQcJt.rows() != n || JQcJt.cols() != n || rc_diag.size() != n)
      throw std::invalid_argument("ReferenceSmoother: sizes do not match the state dimension " + std::to_string(n));
    if (!(dt > 0.0)) throw std::invalid_argument("ReferenceSmoother: the step must be > 0 s");
    if (count < 1) throw std::invalid_argument(std::string("ReferenceSmoother: ") + what + " must be >= 1");
  }
  void start(const Vector& s_t) {
    filter_.reset(s_t, Matrix::Zero(filter_.dim(), filter_.dim()));
    times_.assign(1, 0.0);
  }
  void step(const Vector& s_star, const Matrix& Q, const Matrix& R, double t_s) {
    filter_.predict(Q);
    filter_.update(s_star, R);
    times_.push_back(t_s);
  }

  KalmanSmoother<Dim> filter_;
  Matrix Qf_, Rf_, Qs_, Rs_;
  std::vector<double> times_;
};

}  // namespace predvs
