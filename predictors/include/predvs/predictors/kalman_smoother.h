// predvs — a Gaussian (Kalman) filter stepped by its caller, with separate predict and update
// steps, that records its forward pass for a Rauch-Tung-Striebel backward pass (paper 003 §2.3,
// §3.2 and its Algorithms 3-4; Rauch, Tung & Striebel 1965).
//
// This is the interface the reference filters of paper 003 need and the per-channel `Predictor`
// (predictor.h) does not offer: the caller supplies the model of every step (F, Q for a time
// update, H, R for a measurement update), and smooth() runs the backward pass over what was
// recorded since reset().
//
// Forward pass, step k -> k+1:
//     predict:  x(k+1|k) = F x(k|k),          P(k+1|k) = F P(k|k) F' + Q
//     update:   S = H P H' + R,  K = P H' S^-1 (an LDLT solve, never an inverse),
//               x <- x + K (z - H x),
//               P <- (I - K H) P (I - K H)' + K R K'      (Joseph form: symmetric PSD for any K)
// Backward pass (means only, as paper 003 §3.2: its smoother does not use the smoothed
// covariances), from x(K|K):
//     x(k|K) = x(k|k) + G_k (x(k+1|K) - x(k+1|k)),     G_k = P(k|k) F' P(k+1|k)^-1.
// P(k+1|k) may be singular: in the reference filter the process noise J Qc J' has the rank of the
// robot Jacobian (6 for 12 features) and P starts at 0, so the whole pass lives in the range of J.
// The gain is then applied through a generalised inverse (a pivoted LDLT whose pivots below
// kPsdPivotTolerance times the largest are treated as zero). Since the range of P(k|k) lies in that
// of P(k+1|k) = F P F' + Q and x(k+1|K) - x(k+1|k) lies in it too, any generalised inverse gives
// the same smoothed mean as the Moore-Penrose one.
//
// Dim: the state size when known at compile time (12 for the (x, y, Z) features of 4 points: the
// hot path), Eigen::Dynamic otherwise.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {

/// Relative size below which an LDLT pivot of a PSD matrix is taken as an exact zero: round-off on
/// a null direction is ~1e-16 of the largest pivot; a genuine direction of the reference filter is
/// within ~1e-6 of it (features in normalised units and metres).
constexpr double kPsdPivotTolerance = 1e-10;

/// x = A^g b with A symmetric PSD factorised by `ldlt` (A = P' L D L' P): pivots |D_i| <=
/// rel_tol max|D| are treated as zero (that component of the solution is 0), which gives a
/// generalised inverse A^g (A A^g A = A) instead of amplifying round-off on a null direction.
template <class MatrixType, class Rhs>
typename Rhs::PlainObject solvePsd(const Eigen::LDLT<MatrixType>& ldlt, const Eigen::MatrixBase<Rhs>& b,
                                   double rel_tol = kPsdPivotTolerance) {
  typename Rhs::PlainObject x = ldlt.transpositionsP() * b;
  ldlt.matrixL().solveInPlace(x);
  const auto D = ldlt.vectorD();
  const double tol = rel_tol * D.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < D.size(); ++i) {
    if (std::abs(D(i)) > tol)
      x.row(i) /= D(i);
    else
      x.row(i).setZero();
  }
  ldlt.matrixU().solveInPlace(x);
  x = ldlt.transpositionsP().transpose() * x;
  return x;
}

template <int Dim = Eigen::Dynamic>
class KalmanSmoother {
 public:
  using Vector = Eigen::Matrix<double, Dim, 1>;
  using Matrix = Eigen::Matrix<double, Dim, Dim>;

  /// `dim`: the state size (only for Dim = Eigen::Dynamic; ignored otherwise).
  explicit KalmanSmoother(Eigen::Index dim = Dim == Eigen::Dynamic ? 0 : Dim) : dim_(Dim == Eigen::Dynamic ? dim : Dim) {}

  Eigen::Index dim() const { return dim_; }

  /// Starts a new forward pass at x(0|0) = x0, P(0|0) = P0 (the recorded pass is cleared; the
  /// buffers are kept, so a pass of the same length allocates nothing).
  void reset(const Vector& x0, const Matrix& P0) {
    if (x0.size() != dim_ || P0.rows() != dim_ || P0.cols() != dim_)
      throw std::invalid_argument("KalmanSmoother: reset with a state of " + std::to_string(x0.size()) +
                                  " entries for dimension " + std::to_string(dim_));
    steps_ = 0;
    record(0).x_filt = x0;
    record(0).P_filt = P0;
    smoothed_valid_ = false;
  }

  /// Time update with transition F and process noise Q.
  void predict(const Matrix& F, const Matrix& Q) {
    Step& next = record(steps_ + 1);  // may grow the buffer: take `prev` after it
    const Step& prev = records_[static_cast<size_t>(steps_)];
    next.F = F;
    next.F_identity = false;
    next.x_pred.noalias() = F * prev.x_filt;
    tmp_.noalias() = F * prev.P_filt;
    next.P_pred.noalias() = tmp_ * F.transpose();
    next.P_pred += Q;
    symmetrize(next.P_pred);
    finishPredict(next);
  }
  /// Time update of a random walk (F = I): x(k+1|k) = x(k|k), P(k+1|k) = P(k|k) + Q.
  void predict(const Matrix& Q) {
    Step& next = record(steps_ + 1);
    const Step& prev = records_[static_cast<size_t>(steps_)];
    next.F_identity = true;
    next.x_pred = prev.x_filt;
    next.P_pred = prev.P_filt + Q;
    symmetrize(next.P_pred);
    finishPredict(next);
  }

  /// Measurement update with z = H x + v, v ~ N(0, R) (Joseph form, LDLT solve).
  template <int M>
  void update(const Eigen::Matrix<double, M, 1>& z, const Eigen::Matrix<double, M, Dim>& H,
              const Eigen::Matrix<double, M, M>& R) {
    using MatMM = Eigen::Matrix<double, M, M>;
    using MatMD = Eigen::Matrix<double, M, Dim>;
    Step& s = record(steps_);
    const MatMD HP = H * s.P_filt;
    MatMM S = HP * H.transpose();
    S += R;
    const Eigen::LDLT<MatMM> ldlt(S);
    // K' = S^-1 H P (S and P symmetric).
    const MatMD Kt = ldlt.solve(HP);
    s.x_filt.noalias() += Kt.transpose() * (z - H * s.x_filt);
    Matrix IKH = Matrix::Identity(dim_, dim_);
    IKH.noalias() -= Kt.transpose() * H;
    tmp_.noalias() = IKH * s.P_filt;
    s.P_filt.noalias() = tmp_ * IKH.transpose();
    const MatMD RKt = R * Kt;
    s.P_filt.noalias() += Kt.transpose() * RKt;
    symmetrize(s.P_filt);
    smoothed_valid_ = false;
  }
  /// Measurement update of the whole state (H = I): z = x + v, v ~ N(0, R).
  void update(const Vector& z, const Matrix& R) {
    Step& s = record(steps_);
    S_ = s.P_filt + R;
    ldlt_.compute(S_);
    // K' = S^-1 P, K = P S^-1.
    Kt_ = ldlt_.solve(s.P_filt);
    s.x_filt.noalias() += Kt_.transpose() * (z - s.x_filt);
    // (I - K) P (I - K)' + K R K'
    IKH_.setIdentity(dim_, dim_);
    IKH_ -= Kt_.transpose();
    tmp_.noalias() = IKH_ * s.P_filt;
    s.P_filt.noalias() = tmp_ * IKH_.transpose();
    tmp_.noalias() = R * Kt_;
    s.P_filt.noalias() += Kt_.transpose() * tmp_;
    symmetrize(s.P_filt);
    smoothed_valid_ = false;
  }

  /// Current filtered estimate x(k|k), P(k|k) (k = steps()).
  const Vector& state() const { return records_[static_cast<size_t>(steps_)].x_filt; }
  const Matrix& covariance() const { return records_[static_cast<size_t>(steps_)].P_filt; }
  /// Number of time updates since reset().
  int steps() const { return steps_; }
  /// Filtered estimate x(k|k) of step k (0..steps()).
  const Vector& filtered(int k) const { return records_.at(static_cast<size_t>(k)).x_filt; }
  const Matrix& filteredCovariance(int k) const { return records_.at(static_cast<size_t>(k)).P_filt; }
  /// Predicted estimate x(k|k-1), P(k|k-1) of step k (1..steps()).
  const Vector& predicted(int k) const { return records_.at(static_cast<size_t>(k)).x_pred; }
  const Matrix& predictedCovariance(int k) const { return records_.at(static_cast<size_t>(k)).P_pred; }

  /// The backward (RTS) pass over the recorded steps: smoothed means x(k|K), k = 0..K = steps().
  void smooth() {
    xs_.resize(static_cast<size_t>(steps_) + 1);
    xs_[static_cast<size_t>(steps_)] = state();
    for (int k = steps_ - 1; k >= 0; --k) {
      const Step& cur = records_[static_cast<size_t>(k)];
      const Step& next = records_[static_cast<size_t>(k) + 1];
      // G (x(k+1|K) - x(k+1|k)) = P(k|k) F' P(k+1|k)^g d
      d_ = xs_[static_cast<size_t>(k) + 1] - next.x_pred;
      y_ = solvePsd(next.ldlt_pred, d_);
      if (!next.F_identity) {
        d_.noalias() = next.F.transpose() * y_;
        y_ = d_;
      }
      xs_[static_cast<size_t>(k)] = cur.x_filt;
      xs_[static_cast<size_t>(k)].noalias() += cur.P_filt * y_;
    }
    smoothed_valid_ = true;
  }
  /// Smoothed mean x(k|K) of step k (after smooth(); throws if the pass changed since).
  const Vector& smoothed(int k) const {
    if (!smoothed_valid_) throw std::logic_error("KalmanSmoother: smoothed() before smooth()");
    return xs_.at(static_cast<size_t>(k));
  }

  /// P <- (P + P') / 2.
  static void symmetrize(Matrix& P) {
    const Eigen::Index n = P.rows();
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = i + 1; j < n; ++j) P(i, j) = P(j, i) = 0.5 * (P(i, j) + P(j, i));
  }

 private:
  struct Step {
    Vector x_filt, x_pred;
    Matrix P_filt, P_pred, F;
    bool F_identity = true;
    Eigen::LDLT<Matrix> ldlt_pred;  // of P_pred, for the backward pass
  };

  Step& record(int k) {
    if (static_cast<int>(records_.size()) <= k) records_.resize(static_cast<size_t>(k) + 1);
    return records_[static_cast<size_t>(k)];
  }
  void finishPredict(Step& next) {
    next.x_filt = next.x_pred;
    next.P_filt = next.P_pred;
    next.ldlt_pred.compute(next.P_pred);
    ++steps_;
    smoothed_valid_ = false;
  }

  Eigen::Index dim_;
  int steps_ = 0;
  bool smoothed_valid_ = false;
  std::vector<Step> records_;
  std::vector<Vector> xs_;
  // Work space (no allocation per step for a fixed Dim).
  Matrix tmp_, S_, Kt_, IKH_;
  Vector d_, y_;
  Eigen::LDLT<Matrix> ldlt_;
};

}  // namespace predvs
