#include "predvs/predictors/lifting.h"
#include "predictors/eigen_test_utils.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

namespace predvs {
namespace {

// The lifted matrices are sums of at most N products of O(1) matrices: round-off only.
constexpr double kLiftTol = 1e-12;


/// Brute force: runs the base-period system tick by tick over `frames` frames, inputs set where
/// the pattern says and held otherwise; returns the state at every frame start and the sampled
/// outputs of every frame (in the lifted order).
struct Simulation {
  std::vector<Eigen::VectorXd> frame_states;  // x(kN), k = 0..frames
  std::vector<Eigen::VectorXd> lifted_inputs;  // u_bar(k)
  std::vector<Eigen::VectorXd> lifted_outputs;  // y_bar(k)
};

Simulation simulate(const LinearSystem& sys, int N, const SamplingPattern& in, const SamplingPattern& out,
                    const Eigen::VectorXd& x0, int frames, std::mt19937& rng) {
  Simulation sim;
  Eigen::VectorXd x = x0, u = Eigen::VectorXd::Zero(sys.B.cols());
  sim.frame_states.push_back(x);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int k = 0; k < frames; ++k) {
    std::vector<double> ubar, ybar;
    for (int i = 0; i < N; ++i) {
      for (Eigen::Index w = 0; w < u.size(); ++w)
        if (in(i, w)) {
          u(w) = g(rng);
          ubar.push_back(u(w));
        }
      const Eigen::VectorXd y = sys.C * x + sys.D * u;
      for (Eigen::Index v = 0; v < y.size(); ++v)
        if (out(i, v)) ybar.push_back(y(v));
      x = sys.A * x + sys.B * u;
    }
    sim.frame_states.push_back(x);
    sim.lifted_inputs.push_back(Eigen::Map<Eigen::VectorXd>(ubar.data(), static_cast<Eigen::Index>(ubar.size())));
    sim.lifted_outputs.push_back(Eigen::Map<Eigen::VectorXd>(ybar.data(), static_cast<Eigen::Index>(ybar.size())));
  }
  return sim;
}

TEST(Lifting, MatchesBruteForceSimulationOfThePeriodicSystem) {
  // GIVEN a random 4-state, 2-input, 3-output system over frames of N = 5 ticks, input 0 set
  // every tick, input 1 at phases 0 and 3 (held in between), output 0 read at phases 0 and 2,
  // output 1 at phase 4, output 2 every tick
  std::mt19937 rng(7);
  LinearSystem sys{randomMatrix(4, 4, rng, 0.4), randomMatrix(4, 2, rng), randomMatrix(3, 4, rng),
                   randomMatrix(3, 2, rng)};
  const int N = 5;
  SamplingPattern in = SamplingPattern::Constant(N, 2, false), out = SamplingPattern::Constant(N, 3, false);
  in.col(0).setConstant(true);
  in(0, 1) = in(3, 1) = true;
  out(0, 0) = out(2, 0) = out(4, 1) = true;
  out.col(2).setConstant(true);
  // WHEN the system is lifted and, separately, simulated tick by tick over 3 frames
  const LiftedSystem lifted = liftSystem(sys, N, in, out);
  const Simulation sim = simulate(sys, N, in, out, randomMatrix(4, 1, rng), 3, rng);
  // THEN the lifted model reproduces every frame-start state and every sampled output
  ASSERT_EQ(lifted.B.cols(), 5 + 2);
  ASSERT_EQ(lifted.C.rows(), 2 + 1 + 5);
  for (size_t k = 0; k < sim.lifted_inputs.size(); ++k) {
    const Eigen::VectorXd x_next = lifted.A * sim.frame_states[k] + lifted.B * sim.lifted_inputs[k];
    const Eigen::VectorXd y = lifted.C * sim.frame_states[k] + lifted.D * sim.lifted_inputs[k];
    EXPECT_TRUE(matricesNear(x_next, sim.frame_states[k + 1], kLiftTol)) << "frame " << k;
    EXPECT_TRUE(matricesNear(y, sim.lifted_outputs[k], kLiftTol)) << "frame " << k;
  }
}

TEST(Lifting, ConstantVelocityModelGivesPaperEquation12) {
  // GIVEN the constant-velocity model of one feature at delta with its acceleration as input
  // (paper 003 eq. 4), the noise set every tick and the position read at the frame start
  const double d = 0.01;
  const int N = 8;
  LinearSystem cv{(Eigen::Matrix2d() << 1, d, 0, 1).finished(), (Eigen::Vector2d() << d * d / 2, d).finished(),
                  (Eigen::RowVector2d() << 1, 0).finished(), Eigen::MatrixXd::Zero(1, 1)};
  // WHEN lifted over the frame
  const LiftedSystem L = liftSystem(cv, N, sampledEveryTick(N, 1), sampledAtFrameStart(N, 1));
  // THEN A_bar = [[1, N delta], [0, 1]], B_bar's column j = [(2(N-1-j)+1) delta^2 / 2; delta]
  // (eq. 12), C_bar = [1, 0] and D_bar = 0
  EXPECT_TRUE(matricesNear(L.A, (Eigen::Matrix2d() << 1, N * d, 0, 1).finished(), kLiftTol));
  ASSERT_EQ(L.B.cols(), N);
  for (int j = 0; j < N; ++j) {
    EXPECT_NEAR(L.B(0, j), (2 * (N - 1 - j) + 1) * d * d / 2, kLiftTol) << j;
    EXPECT_NEAR(L.B(1, j), d, kLiftTol) << j;
  }
  EXPECT_TRUE(matricesNear(L.C, (Eigen::RowVector2d() << 1, 0).finished(), kLiftTol));
  EXPECT_TRUE(matricesNear(L.D, Eigen::MatrixXd::Zero(1, N), kLiftTol));
}

TEST(Lifting, InverseLiftingRestoresTheHeldSamples) {
  // GIVEN N = 4 samples of a 2-vector, component 1 set only at phases 0 and 2
  SamplingPattern p = sampledEveryTick(4, 2);
  p(1, 1) = p(3, 1) = false;
  const std::vector<Eigen::VectorXd> samples = {Eigen::Vector2d(1, 10), Eigen::Vector2d(2, 10), Eigen::Vector2d(3, 30),
                                                Eigen::Vector2d(4, 30)};
  // WHEN lifted and inverse-lifted
  const Eigen::VectorXd lifted = liftSignal(samples, p);
  const std::vector<Eigen::VectorXd> back = inverseLift(lifted, p);
  // THEN the lifted vector holds the 6 sampled entries phase by phase and the round trip is exact
  EXPECT_TRUE(matricesNear(lifted, (Eigen::VectorXd(6) << 1, 10, 2, 3, 30, 4).finished(), 0.0));
  ASSERT_EQ(back.size(), samples.size());
  for (size_t i = 0; i < samples.size(); ++i) EXPECT_TRUE(matricesNear(back[i], samples[i], 0.0)) << i;
}

TEST(Lifting, RejectsAnInputNotSetAtTheFrameStartAndWrongSizes) {
  LinearSystem sys{Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Ones(2, 1), Eigen::MatrixXd::Ones(1, 2),
                   Eigen::MatrixXd::Zero(1, 1)};
  SamplingPattern late = sampledEveryTick(3, 1);
  late(0, 0) = false;
  EXPECT_THROW(liftSystem(sys, 3, late, sampledEveryTick(3, 1)), std::invalid_argument);
  EXPECT_THROW(liftSystem(sys, 3, sampledEveryTick(2, 1), sampledEveryTick(3, 1)), std::invalid_argument);
  EXPECT_THROW(liftSystem(sys, 0, sampledEveryTick(0, 1), sampledEveryTick(0, 1)), std::invalid_argument);
  EXPECT_THROW(inverseLift(Eigen::VectorXd::Zero(2), sampledEveryTick(3, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
