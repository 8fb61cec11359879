// predvs — the lifting of a linear N-periodic (dual-rate) system into a linear time-invariant one
// at the frame period (paper 003 §2.1 and Appendix A, eqs. 23-34; Khargonekar et al. 1985).
//
// Base-period model (eqs. 23-24), tick t, base period delta:
//     x(t+1) = A x(t) + B u(t),       y(t) = C x(t) + D u(t).
// A frame spans the N ticks t = kN + i, i = 0..N-1 (the double index (k, i) of the paper). The
// sampling scheme is N-periodic (eqs. 29-32): input component w is set at phase i when
// inputs(i, w) is true and otherwise HOLDS the value it was last set to (the dual-rate hold);
// output component v is read at phase i when outputs(i, v) is true. Every input must be set at
// phase 0, so that no input value carries over from one frame to the next and the lifted model is
// exactly LTI.
//
// The sparse lifted vectors (eqs. 27-28) list, phase by phase (i = 0..N-1) and within a phase by
// component, only the sampled entries: u_bar (the values the inputs are set to) and y_bar (the
// outputs read). Then, at the frame period (eqs. 25-26),
//     x(t+N) = A_bar x(t) + B_bar u_bar(k),       y_bar(k) = C_bar x(t) + D_bar u_bar(k),
// with (eqs. 33-34), before reduction,
//     A_bar = A^N,
//     B_full = [A^(N-1) B, A^(N-2) B, ..., B]                         (n x N m),
//     C_full = [C; C A; ...; C A^(N-1)]                                (N p x n),
//     D_full(i, j) = D for j = i,  C A^(i-1-j) B for j < i,  0 for j > i   (N p x N m, blocks),
// and the reductions of the paper: B_bar = B_full M, D_bar = S D_full M, C_bar = S C_full, where
// M (N m x |u_bar|) is the hold (a column of an unsampled phase is added to the column of the
// phase where that input was last set: the paper's column reduction, "appended to their left")
// and S (|y_bar| x N p) keeps the rows of the sampled outputs (the paper's row reduction).
//
// Output convention: y(t+i) is read BEFORE the input of tick t+i acts on the state (eq. 24 as
// written, so D_full has D on its diagonal). The paper's displayed D_bar, with C B on its
// diagonal and C_bar built from C A, corresponds to outputs read one tick later,
// y(t+i) = C x(t+i+1); with that convention its DR-KF would read s(t) as s + delta s_dot (paper
// eq. 13). The tests check this lifting against a brute-force simulation of the periodic system.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace predvs {

/// Which components are sampled at each phase of a frame: entry (i, w) for phase i, component w
/// (N rows).
using SamplingPattern = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>;

/// Every component sampled at every phase (N x components, all true): the fast rate.
SamplingPattern sampledEveryTick(int frame_ticks, int components);
/// Every component sampled at phase 0 only (the frame rate).
SamplingPattern sampledAtFrameStart(int frame_ticks, int components);

/// Base-period linear model of eqs. 23-24.
struct LinearSystem {
  Eigen::MatrixXd A;  ///< n x n
  Eigen::MatrixXd B;  ///< n x m
  Eigen::MatrixXd C;  ///< p x n
  Eigen::MatrixXd D;  ///< p x m
};

/// The frame-period LTI model of eqs. 25-26.
struct LiftedSystem {
  Eigen::MatrixXd A;  ///< A_bar = A^N (n x n)
  Eigen::MatrixXd B;  ///< B_bar (n x |u_bar|)
  Eigen::MatrixXd C;  ///< C_bar (|y_bar| x n)
  Eigen::MatrixXd D;  ///< D_bar (|y_bar| x |u_bar|)
  int frame_ticks = 1;
  SamplingPattern inputs;   ///< N x m
  SamplingPattern outputs;  ///< N x p
};

/// Lifts `system` over a frame of `frame_ticks` ticks with the given sampling patterns (N x m and
/// N x p). Throws std::invalid_argument for inconsistent sizes, N < 1, or an input not set at
/// phase 0.
LiftedSystem liftSystem(const LinearSystem& system, int frame_ticks, const SamplingPattern& inputs,
                        const SamplingPattern& outputs);

/// Lifting operator (eq. 1, reduced as eqs. 27-28): the sampled entries of the N per-tick vectors
/// `samples` (each of the pattern's width), phase by phase.
Eigen::VectorXd liftSignal(const std::vector<Eigen::VectorXd>& samples, const SamplingPattern& pattern);
/// Inverse lifting: the N per-tick vectors of a reduced lifted input vector, unsampled entries
/// holding the value last set (every component must be sampled at phase 0). With
/// sampledEveryTick() this splits a full lifted vector into its N samples (paper 003 eq. 22).
std::vector<Eigen::VectorXd> inverseLift(const Eigen::VectorXd& lifted, const SamplingPattern& pattern);

}  // namespace predvs
