#include "predvs/predictors/lifting.h"

#include <stdexcept>
#include <string>

namespace predvs {
namespace {

void requirePattern(const SamplingPattern& pattern, int frame_ticks, Eigen::Index components, const char* what) {
  if (pattern.rows() != frame_ticks || pattern.cols() != components)
    throw std::invalid_argument(std::string("lifting: the ") + what + " pattern is " + std::to_string(pattern.rows()) +
                                " x " + std::to_string(pattern.cols()) + ", expected " + std::to_string(frame_ticks) +
                                " x " + std::to_string(components));
}

void requireSetAtPhaseZero(const SamplingPattern& pattern, const char* what) {
  for (Eigen::Index w = 0; w < pattern.cols(); ++w)
    if (!pattern(0, w))
      throw std::invalid_argument(std::string("lifting: ") + what + " component " + std::to_string(w) +
                                  " is not set at phase 0 (its held value would carry over to the next frame)");
}

/// Index of entry (i, w) in the reduced vector, or -1 when not sampled; `count` = |reduced|.
Eigen::MatrixXi reducedIndex(const SamplingPattern& pattern, int& count) {
  Eigen::MatrixXi index = Eigen::MatrixXi::Constant(pattern.rows(), pattern.cols(), -1);
  count = 0;
  for (Eigen::Index i = 0; i < pattern.rows(); ++i)
    for (Eigen::Index w = 0; w < pattern.cols(); ++w)
      if (pattern(i, w)) index(i, w) = count++;
  return index;
}

}  // namespace

SamplingPattern sampledEveryTick(int frame_ticks, int components) {
  return SamplingPattern::Constant(frame_ticks, components, true);
}

SamplingPattern sampledAtFrameStart(int frame_ticks, int components) {
  SamplingPattern p = SamplingPattern::Constant(frame_ticks, components, false);
  if (frame_ticks > 0) p.row(0).setConstant(true);
  return p;
}

LiftedSystem liftSystem(const LinearSystem& sys, int N, const SamplingPattern& inputs, const SamplingPattern& outputs) {
  const Eigen::Index n = sys.A.rows(), m = sys.B.cols(), p = sys.C.rows();
  if (N < 1) throw std::invalid_argument("lifting: frame_ticks must be >= 1, got " + std::to_string(N));
  if (sys.A.cols() != n || sys.B.rows() != n || sys.C.cols() != n || sys.D.rows() != p || sys.D.cols() != m)
    throw std::invalid_argument("lifting: inconsistent A (" + std::to_string(n) + "x" + std::to_string(sys.A.cols()) +
                                "), B, C, D sizes");
  requirePattern(inputs, N, m, "input");
  requirePattern(outputs, N, p, "output");
  requireSetAtPhaseZero(inputs, "input");

  // Powers A^0 .. A^N.
  std::vector<Eigen::MatrixXd> Apow(static_cast<size_t>(N) + 1);
  Apow[0] = Eigen::MatrixXd::Identity(n, n);
  for (int i = 1; i <= N; ++i) Apow[static_cast<size_t>(i)] = sys.A * Apow[static_cast<size_t>(i) - 1];

  // Full lifted matrices (every phase sampled).
  Eigen::MatrixXd B_full(n, N * m), C_full(N * p, n), D_full = Eigen::MatrixXd::Zero(N * p, N * m);
  for (int j = 0; j < N; ++j) B_full.middleCols(j * m, m) = Apow[static_cast<size_t>(N - 1 - j)] * sys.B;
  for (int i = 0; i < N; ++i) {
    C_full.middleRows(i * p, p) = sys.C * Apow[static_cast<size_t>(i)];
    D_full.block(i * p, i * m, p, m) = sys.D;
    for (int j = 0; j < i; ++j) D_full.block(i * p, j * m, p, m) = sys.C * Apow[static_cast<size_t>(i - 1 - j)] * sys.B;
  }

  // Hold M: full input entry (i, w) takes the reduced entry of the phase where w was last set.
  int mu = 0, py = 0;
  const Eigen::MatrixXi uidx = reducedIndex(inputs, mu);
  const Eigen::MatrixXi yidx = reducedIndex(outputs, py);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(N * m, mu);
  for (Eigen::Index w = 0; w < m; ++w) {
    int last = -1;
    for (int i = 0; i < N; ++i) {
      if (uidx(i, w) >= 0) last = uidx(i, w);
      M(i * m + w, last) = 1.0;
    }
  }
  // Selection S of the sampled outputs.
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(py, N * p);
  for (int i = 0; i < N; ++i)
    for (Eigen::Index v = 0; v < p; ++v)
      if (yidx(i, v) >= 0) S(yidx(i, v), i * p + v) = 1.0;

  LiftedSystem lifted;
  lifted.A = Apow[static_cast<size_t>(N)];
  lifted.B = B_full * M;
  lifted.C = S * C_full;
  lifted.D = S * D_full * M;
  lifted.frame_ticks = N;
  lifted.inputs = inputs;
  lifted.outputs = outputs;
  return lifted;
}

Eigen::VectorXd liftSignal(const std::vector<Eigen::VectorXd>& samples, const SamplingPattern& pattern) {
  if (static_cast<Eigen::Index>(samples.size()) != pattern.rows())
    throw std::invalid_argument("lifting: " + std::to_string(samples.size()) + " samples for a pattern of " +
                                std::to_string(pattern.rows()) + " phases");
  int count = 0;
  const Eigen::MatrixXi index = reducedIndex(pattern, count);
  Eigen::VectorXd lifted(count);
  for (Eigen::Index i = 0; i < pattern.rows(); ++i) {
    const Eigen::VectorXd& s = samples[static_cast<size_t>(i)];
    if (s.size() != pattern.cols())
      throw std::invalid_argument("lifting: sample " + std::to_string(i) + " has " + std::to_string(s.size()) +
                                  " entries, expected " + std::to_string(pattern.cols()));
    for (Eigen::Index w = 0; w < pattern.cols(); ++w)
      if (index(i, w) >= 0) lifted(index(i, w)) = s(w);
  }
  return lifted;
}

std::vector<Eigen::VectorXd> inverseLift(const Eigen::VectorXd& lifted, const SamplingPattern& pattern) {
  requireSetAtPhaseZero(pattern, "lifted");
  int count = 0;
  const Eigen::MatrixXi index = reducedIndex(pattern, count);
  if (lifted.size() != count)
    throw std::invalid_argument("lifting: lifted vector has " + std::to_string(lifted.size()) + " entries, the pattern " +
                                std::to_string(count));
  std::vector<Eigen::VectorXd> samples(static_cast<size_t>(pattern.rows()), Eigen::VectorXd(pattern.cols()));
  for (Eigen::Index i = 0; i < pattern.rows(); ++i)
    for (Eigen::Index w = 0; w < pattern.cols(); ++w)
      samples[static_cast<size_t>(i)](w) = index(i, w) >= 0 ? lifted(index(i, w)) : samples[static_cast<size_t>(i) - 1](w);
  return samples;
}

}  // namespace predvs
