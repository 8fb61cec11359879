// Tests of `ibvs-broyden` (docs/MODELS.md §7): closed-loop convergence on a static target for two small
// plants written here (a linear map s = s0 + A p, and a free-flying camera looking at 4 points),
// with and without delay compensation, the learnt Jacobian against finite differences of the
// plant, the damped inverse on singular estimates, diagnostics and configuration errors.
#include "predvs/tasks/ibvs_broyden_task.h"

#include "predictors/eigen_test_utils.h"

#include <visp3/core/vpExponentialMap.h>
#include <visp3/core/vpHomogeneousMatrix.h>

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

const Eigen::VectorXd kNoRate;  // the plant tests feed no predictor rate

constexpr double kPeriod = 0.1;  // delta = T (E9's frame period)

CommandSpace commandSpace(int m) {
  CommandSpace c{"test", {}};
  for (int i = 0; i < m; ++i) c.names.push_back("u" + std::to_string(i));
  return c;
}

/// s = s0 + A p, p the command integral (m inputs, 8 features).
struct LinearPlant {
  Eigen::VectorXd s0;
  Eigen::MatrixXd A;
  Eigen::VectorXd p;
  Eigen::VectorXd features() const { return s0 + A * p; }
  Eigen::MatrixXd trueJacobian() const { return A; }
  void apply(const Eigen::VectorXd& u, double dt) { p += u * dt; }
};

/// A free-flying camera (command: its twist in its own frame, as vpSimulatorCamera) looking at the
/// corners of a 10 cm square. Pose integration: oMc <- oMc exp(v dt).
struct CameraPlant {
  CameraIntrinsics camera;
  vpHomogeneousMatrix cMo;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(6);
  static constexpr double kHalfSide = 0.05;

  Eigen::VectorXd features() const { return project(cMo).first; }
  std::pair<Eigen::VectorXd, Eigen::VectorXd> project(const vpHomogeneousMatrix& M) const {
    Eigen::VectorXd uv(8), Z(4);
    const double corners[4][2] = {{-kHalfSide, -kHalfSide}, {kHalfSide, -kHalfSide}, {kHalfSide, kHalfSide}, {-kHalfSide, kHalfSide}};
    for (int i = 0; i < 4; ++i) {
      const vpColVector X = M * vpColVector({corners[i][0], corners[i][1], 0.0, 1.0});
      uv(2 * i) = camera.u0 + camera.px * X[0] / X[2];
      uv(2 * i + 1) = camera.v0 + camera.py * X[1] / X[2];
      Z(i) = X[2];
    }
    return {uv, Z};
  }
  Eigen::MatrixXd trueJacobian() const {
    const auto [uv, Z] = project(cMo);
    return PointTask::pixelInteraction(uv, Z, camera);
  }
  static vpHomogeneousMatrix moved(const vpHomogeneousMatrix& cMo, const Eigen::VectorXd& u, double dt) {
    vpColVector v(6);
    for (int i = 0; i < 6; ++i) v[i] = u(i);
    return vpExponentialMap::direct(v, dt).inverse() * cMo;
  }
  void apply(const Eigen::VectorXd& u, double dt) {
    cMo = moved(cMo, u, dt);
    p += u * dt;
  }
};

/// cMo at the desired pose: the square centred 0.5 m in front, parallel to the image.
vpHomogeneousMatrix desiredPose() { return vpHomogeneousMatrix(0.0, 0.0, 0.5, 0.0, 0.0, 0.0); }
/// A start 2 cm / 1 cm / 5 cm off with 0.1 rad about the optical axis and 0.05 rad about x.
vpHomogeneousMatrix startPose() {
  return vpHomogeneousMatrix(0.02, -0.01, 0.55, 0.05, 0.0, 0.1);
}

TaskContext contextFor(const Eigen::VectorXd& desired_px, int inputs, double delay_frames = 0.0) {
  TaskContext c;
  c.desired_points.uv_px = desired_px;
  c.desired_points.Z_m = Eigen::VectorXd::Constant(desired_px.size() / 2, std::nan(""));
  c.desired_points.seen.assign(static_cast<size_t>(desired_px.size() / 2), true);
  c.command_space = commandSpace(inputs);
  c.base_period_s = kPeriod;
  c.frame_period_s = kPeriod;
  c.nominal_delay_frames = delay_frames;
  return c;
}

struct RunResult {
  double final_error_px = 0.0;      ///< trackingError of the true features at the end
  double max_error_px = 0.0;        ///< after exploration
  double explore_end_s = -1.0;
  Eigen::MatrixXd J_after_explore;  ///< estimate when exploration ended
  Eigen::MatrixXd J_true_at_start;  ///< plant Jacobian at the first tick
};

/// Closed loop with delta = T, a vision delay of `delay_frames` frames, no target motion.
/// `used` (what delay compensation acts on) is the perfect forecast: the true features now.
template <class Plant>
RunResult run(IbvsBroydenTask& task, Plant& plant, int ticks, int delay_frames, double noise_px = 0.0,
              std::uint64_t seed = 1) {
  struct Sample {
    double t;
    Eigen::VectorXd s, p;
  };
  std::deque<Sample> queue;
  std::mt19937 rng(static_cast<std::mt19937::result_type>(seed));
  std::normal_distribution<double> noise(0.0, noise_px);
  RunResult out;
  Eigen::VectorXd measured, none, depths = Eigen::VectorXd::Constant(task.featureSize() / 2, std::nan(""));
  const Eigen::MatrixXd robot_jacobian;
  const Eigen::VectorXd robot_state;
  for (int k = 0; k < ticks; ++k) {
    const double t = k * kPeriod;
    Eigen::VectorXd z = plant.features();
    if (noise_px > 0.0)
      for (Eigen::Index i = 0; i < z.size(); ++i) z(i) += noise(rng);
    queue.push_back({t, z, plant.p});
    while (!queue.empty() && queue.front().t <= t - delay_frames * kPeriod + 1e-9) {
      task.observe(TaskMeasurement{queue.front().t, queue.front().s, queue.front().p, kNoRate});
      measured = queue.front().s;
      queue.pop_front();
    }
    const Eigen::VectorXd used = plant.features();
    const Eigen::MatrixXd J_true = plant.trueJacobian();
    if (k == 0) out.J_true_at_start = J_true;
    const bool was_exploring = task.exploring() || k == 0;
    const Eigen::VectorXd u =
        task.computeCommand(TaskInput{t, t - delay_frames * kPeriod, measured, used, none, depths, robot_jacobian,
                                      robot_state, J_true});
    if (was_exploring && !task.exploring() && out.explore_end_s < 0.0) {
      out.explore_end_s = t;
      out.J_after_explore = task.featureJacobian();
    }
    if (!task.exploring() && out.explore_end_s >= 0.0)
      out.max_error_px = std::max(out.max_error_px, task.trackingError(plant.features()));
    EXPECT_TRUE(u.allFinite()) << "tick " << k;
    plant.apply(u, kPeriod);
  }
  out.final_error_px = task.trackingError(plant.features());
  return out;
}

LinearPlant linearPlant(std::uint64_t seed) {
  std::mt19937 rng(static_cast<std::mt19937::result_type>(seed));
  std::normal_distribution<double> g(0.0, 300.0);
  LinearPlant plant;
  plant.s0 = Eigen::VectorXd(8);
  plant.s0 << 250, 170, 390, 170, 390, 310, 250, 310;
  plant.A = Eigen::MatrixXd(8, 3);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 3; ++j) plant.A(i, j) = g(rng);
  plant.p = Eigen::VectorXd::Zero(3);
  return plant;
}

// The four-point square's Jacobian has one weak mode (vx against wy, and vy against wx: they move
// the image alike up to the x^2 terms), sigma / sigma_max ~ 0.005 here. The default damping 1e-2
// (chosen for tracking, see the header) slows that mode to a fraction of K; the tight convergence
// tests use damping 1e-3, and FreeCameraWithDefaultDampingStillConverges shows the default's price.
constexpr double kTightDamping = 1e-3;

// Convergence threshold: 0.01 px is far below anything visible and, with K T = 0.1, reached
// after ~100 ticks from tens of pixels when the estimate is right.
constexpr double kConvergedPx = 0.01;

class BroydenMethods : public ::testing::TestWithParam<std::string> {};

TEST_P(BroydenMethods, LinearPlantConvergesAndLearnsTheMap) {
  // GIVEN a linear plant s = s0 + A p (8 x 3), a reachable goal s* = s0 + A p*, no delay
  LinearPlant plant = linearPlant(3);
  const Eigen::Vector3d p_star(0.05, -0.03, 0.04);
  const Eigen::VectorXd desired = plant.s0 + plant.A * p_star;
  Params params{{"gain", 1.0}};
  params.setText("method", GetParam());
  IbvsBroydenTask task(params, contextFor(desired, 3));
  // WHEN the uncalibrated law explores, then servoes for 20 s
  const RunResult r = run(task, plant, 200, 0);
  // THEN it learnt A during exploration. Exact map: for RLS only the bias of the prior J0 = 0
  // remains, weight 1 against p0 sum |dp|^2 = 1e6 * 2 * 2.5e-5 = 50 per axis (+ and - probe),
  // i.e. 1/51 ~ 2 %; Broyden's secant on orthogonal probes is exact.
  const double kLinearJacobianTol = GetParam() == "rls" ? 0.025 : 1e-9;
  ASSERT_GE(r.explore_end_s, 0.0);
  EXPECT_LT((r.J_after_explore - plant.A).norm() / plant.A.norm(), kLinearJacobianTol);
  // AND converges to the goal
  EXPECT_LT(r.final_error_px, kConvergedPx);
  EXPECT_TRUE(matricesNear(plant.p, Eigen::VectorXd(p_star), 1e-4));
}

INSTANTIATE_TEST_SUITE_P(IbvsBroydenTask, BroydenMethods, ::testing::Values("rls", "broyden"));

TEST(IbvsBroydenTask, CameraPlantJacobianMatchesFiniteDifferences) {
  // GIVEN the free-camera plant at the start pose
  CameraPlant plant;
  plant.cMo = startPose();
  const Eigen::MatrixXd L = plant.trueJacobian();
  // WHEN each twist component is applied for a tiny time, both ways
  constexpr double kStep = 1e-6;
  Eigen::MatrixXd fd(8, 6);
  for (int j = 0; j < 6; ++j) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(6, j);
    fd.col(j) = (plant.project(CameraPlant::moved(plant.cMo, e, kStep)).first -
                 plant.project(CameraPlant::moved(plant.cMo, -e, kStep)).first) /
                (2.0 * kStep);
  }
  // THEN the pixel interaction matrix is the plant's ds/du (central differences: O(step^2)
  // truncation, round-off ~1e-16 * 400 px / 1e-6 ~ 1e-8 px per unit against entries of ~1e3)
  constexpr double kFdTol = 1e-6;
  EXPECT_TRUE(matricesNear(L / 1000.0, fd / 1000.0, kFdTol));
}

TEST(IbvsBroydenTask, FreeCameraConvergesOnStaticTargetAndLearnsTheLocalJacobian) {
  // GIVEN a free camera off its goal, four points, no delay, no noise
  CameraPlant plant;
  plant.cMo = desiredPose();
  const Eigen::VectorXd desired = plant.features();
  plant.cMo = startPose();
  IbvsBroydenTask task(Params{{"gain", 1.0}, {"damping", kTightDamping}}, contextFor(desired, 6));
  // WHEN the law explores (12 probes, 1.3 s) and servoes
  const RunResult r = run(task, plant, 150, 0);
  // THEN after exploration the estimate matches the plant's Jacobian at the start (finite
  // differences of the plant, checked above). Tolerance: probes of 5 mm / 5 mrad on a plant whose
  // Jacobian changes by a few percent over such moves, each probe is learnt at a slightly
  // different pose (the camera returns only approximately), and the prior J0 = 0 biases RLS by
  // ~2 % (see the linear plant). Measured: 1.8 %.
  constexpr double kExploredJacobianTol = 0.05;
  ASSERT_GE(r.explore_end_s, 0.0);
  EXPECT_LT((r.J_after_explore - r.J_true_at_start).norm() / r.J_true_at_start.norm(), kExploredJacobianTol);
  EXPECT_LT(r.explore_end_s, 1.5);
  // AND the camera reaches the goal
  EXPECT_LT(r.final_error_px, kConvergedPx);
  const NamedValues summary = task.runSummary();
  ASSERT_EQ(summary.size(), 2u);
  EXPECT_EQ(summary[0].first, "jacobian_error_final");
  EXPECT_EQ(summary[1].first, "jacobian_updates");
  EXPECT_GE(summary[1].second, 12.0);
}

TEST(IbvsBroydenTask, FreeCameraWithDefaultDampingStillConverges) {
  // GIVEN the free camera and every parameter at its default (damping 1e-2)
  CameraPlant plant;
  plant.cMo = desiredPose();
  const Eigen::VectorXd desired = plant.features();
  plant.cMo = startPose();
  IbvsBroydenTask task(Params{}, contextFor(desired, 6));
  // WHEN it runs 15 and then 40 s
  const double after15 = run(task, plant, 150, 0).final_error_px;
  const double after40 = run(task, plant, 250, 0).final_error_px;
  // THEN the error keeps falling, only slower along the weak mode (measured 0.094 px at 15 s, from
  // 36 px at the start; bounds with a factor ~2 margin)
  constexpr double kSlowModePx = 0.2;
  EXPECT_LT(after15, kSlowModePx);
  EXPECT_LT(after40, 0.5 * after15);
}

TEST(IbvsBroydenTask, DelayCompensationOffAndOnBothConvergeOnStaticTarget) {
  for (const double compensation : {0.0, 1.0}) {
    // GIVEN the free camera with a 2-frame vision delay (K T = 0.1, far below the delayed loop's
    // stability limit of ~0.62) and 0.1 px of measurement noise
    CameraPlant plant;
    plant.cMo = desiredPose();
    const Eigen::VectorXd desired = plant.features();
    plant.cMo = startPose();
    IbvsBroydenTask task(Params{{"gain", 1.0}, {"delay_compensation", compensation}, {"damping", kTightDamping}},
                         contextFor(desired, 6, 2.0));
    // WHEN it runs 20 s
    const RunResult r = run(task, plant, 200, 2, 0.1);
    // THEN it converges to the noise level: 0.1 px noise passes the loop attenuated by about
    // sqrt(K T / 2) ~ 0.2 (measured 0.017 px off, 0.003 px on, which acts on the noise-free forecast)
    constexpr double kNoisyConvergedPx = 0.05;
    EXPECT_LT(r.final_error_px, kNoisyConvergedPx) << "delay_compensation " << compensation;
    EXPECT_TRUE(task.featureJacobian().allFinite());
  }
}

TEST(IbvsBroydenTask, PairsDelayedMeasurementsWithTheCommandIntegralAtAcquisition) {
  // GIVEN the linear plant seen with a 3-frame delay, so that while a probe's image arrives the
  // robot has already moved on to the next probe
  LinearPlant plant = linearPlant(5);
  IbvsBroydenTask task(Params{}, contextFor(plant.s0 + plant.A * Eigen::Vector3d(0.02, 0.02, -0.02), 3, 3.0));
  // WHEN it explores and servoes
  const RunResult r = run(task, plant, 200, 3);
  // THEN it learns A as well as without delay (the ~2 % prior bias of the linear-plant test):
  // each measured increment is paired with p between the same acquisition times. Pairing it with
  // the increment of p up to now would mix in the next probe's axis and miss by ~100 %.
  constexpr double kDelayedJacobianTol = 0.025;
  ASSERT_GE(r.explore_end_s, 0.0);
  EXPECT_LT((r.J_after_explore - plant.A).norm() / plant.A.norm(), kDelayedJacobianTol);
  EXPECT_LT(r.final_error_px, kConvergedPx);
}

TEST(IbvsBroydenTask, ExplorationOnAMovingTargetIgnoresTheForecastRate) {
  // GIVEN the linear plant with the target drifting at a steady image rate c (s = s0 + A p + c t,
  // c of the order of E9's target motion: ~50 px/s), seen with a 2-frame delay, and a loop that
  // hands the task, as the target rate, the rate of the features it receives: what a predictor on
  // f - E gives while J (hence E) is still zero, the probe motion included
  LinearPlant plant = linearPlant(7);
  Eigen::VectorXd c(8);
  c << 40, -30, 45, -25, 50, -35, 42, -28;
  constexpr int kDelay = 2;
  IbvsBroydenTask task(Params{}, contextFor(plant.s0, 3, kDelay));
  std::deque<std::pair<double, Eigen::VectorXd>> queue, p_queue;
  Eigen::VectorXd measured, previous, rate;
  const Eigen::VectorXd depths = Eigen::VectorXd::Constant(4, std::nan("")), robot_state;
  const Eigen::MatrixXd robot_jacobian, J_true = plant.A;
  bool explored = false;
  for (int k = 0; k < 40 && !explored; ++k) {
    const double t = k * kPeriod;
    queue.emplace_back(t, plant.features() + c * t);
    p_queue.emplace_back(t, plant.p);
    while (!queue.empty() && queue.front().first <= t - kDelay * kPeriod + 1e-9) {
      task.observe(TaskMeasurement{queue.front().first, queue.front().second, p_queue.front().second, kNoRate});
      previous = measured;
      measured = queue.front().second;
      queue.pop_front();
      p_queue.pop_front();
    }
    rate = previous.size() ? Eigen::VectorXd((measured - previous) / kPeriod) : Eigen::VectorXd();
    const bool was_exploring = task.exploring() || k == 0;
    const Eigen::VectorXd u = task.computeCommand(
        TaskInput{t, t - kDelay * kPeriod, measured, measured, rate, depths, robot_jacobian, robot_state, J_true});
    explored = was_exploring && !task.exploring() && k > 0;
    plant.apply(u, kPeriod);
  }
  // WHEN the exploration has ended
  ASSERT_TRUE(explored);
  // THEN the estimate is as good as on a static target: each +dp / -dp probe pair cancels the
  // steady drift by itself (J dp = (df+ - df-) / 2), so only the ~2 % prior bias of RLS remains
  // (see LinearPlantConvergesAndLearnsTheMap; measured 2.5 %). Subtracting the forecast rate
  // instead, which holds the previous probe's motion, misses by ~110 % here.
  constexpr double kDriftJacobianTol = 0.04;
  EXPECT_LT((task.featureJacobian() - plant.A).norm() / plant.A.norm(), kDriftJacobianTol);
}

TEST(IbvsBroydenTask, ModelInitialisationStartsFromThePerturbedTruth) {
  // GIVEN init = model with zero model error
  CameraPlant plant;
  plant.cMo = desiredPose();
  const Eigen::VectorXd desired = plant.features();
  plant.cMo = startPose();
  Params params{{"gain", 1.0}, {"model_error", 0.0}};
  params.setText("init", "model");
  IbvsBroydenTask task(params, contextFor(desired, 6));
  // WHEN it runs one tick
  run(task, plant, 1, 0);
  // THEN there was no exploration and the estimate is the truth (jacobian_error 0)
  EXPECT_FALSE(task.exploring());
  const NamedValues d = task.diagnostics();
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].first, "jacobian_error");
  EXPECT_NEAR(d[0].second, 0.0, 1e-12);
  EXPECT_EQ(d[1].first, "updated");
  EXPECT_EQ(d[2].first, "exploring");
  // AND with a 20 % model error it converges anyway, from the same seed to the same result
  plant.cMo = startPose();
  Params noisy{{"gain", 1.0}, {"model_error", 0.2}, {"damping", kTightDamping}};
  noisy.setText("init", "model");
  IbvsBroydenTask task2(noisy, contextFor(desired, 6));
  EXPECT_LT(run(task2, plant, 150, 0).final_error_px, kConvergedPx);
}

TEST(IbvsBroydenTask, SingularEstimateGivesBoundedCommand) {
  // GIVEN a zero and a rank-1 estimate
  const Eigen::VectorXd r = Eigen::VectorXd::Constant(4, 10.0);
  // THEN the damped solve returns zero for J = 0 and a finite least-squares answer for rank 1
  EXPECT_EQ(IbvsBroydenTask::dampedSolve(Eigen::MatrixXd::Zero(4, 3), r, 1e-3), Eigen::VectorXd::Zero(3));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(4, 3);
  J.col(0).setConstant(2.0);
  const Eigen::VectorXd u = IbvsBroydenTask::dampedSolve(J, r, 1e-3);
  ASSERT_TRUE(u.allFinite());
  // J u = r exactly along the column space: u0 = 5 (damping 1e-3 changes it by 1e-6 relative)
  EXPECT_NEAR(u(0), 5.0, 1e-5);
  EXPECT_EQ(u(1), 0.0);
  // AND lost rows (NaN) are dropped, not propagated
  Eigen::VectorXd r_lost = r;
  r_lost(2) = std::nan("");
  EXPECT_TRUE(IbvsBroydenTask::dampedSolve(J, r_lost, 1e-3).allFinite());
}

TEST(IbvsBroydenTask, UpdatedFlagFollowsExcitation) {
  // GIVEN the linear plant and a huge skip threshold: nothing is ever learnt
  LinearPlant plant = linearPlant(4);
  IbvsBroydenTask still(Params{{"min_dp", 1.0}}, contextFor(plant.s0, 3));
  run(still, plant, 30, 0);
  EXPECT_EQ(still.estimator().updates(), 0);
  EXPECT_EQ(still.diagnostics()[1].second, 0.0);
  // AND with the default threshold the probes are learnt (one update per probe at least)
  LinearPlant plant2 = linearPlant(4);
  IbvsBroydenTask learning(Params{}, contextFor(plant2.s0, 3));
  run(learning, plant2, 30, 0);
  EXPECT_GE(learning.estimator().updates(), 6);
}

TEST(IbvsBroydenTask, RejectsBadParametersNamingTheKey) {
  const TaskContext context = contextFor(linearPlant(1).s0, 3);
  const auto expectThrowNaming = [&](Params params, const std::string& key) {
    try {
      IbvsBroydenTask task(params, context);
      ADD_FAILURE() << key << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  expectThrowNaming(Params{{"gian", 1.0}}, "gian");
  expectThrowNaming(Params{{"gain", 0.0}}, "gain");
  expectThrowNaming(Params{{"lambda", 0.0}}, "lambda");
  expectThrowNaming(Params{{"lambda", 1.2}}, "lambda");
  expectThrowNaming(Params{{"delay_compensation", 0.5}}, "delay_compensation");
  expectThrowNaming(Params{{"probe_frames", 1.5}}, "probe_frames");
  Params method;
  method.setText("method", "newton");
  expectThrowNaming(method, "method");
  Params init;
  init.setText("init", "oracle");
  expectThrowNaming(init, "init");
  TaskContext no_robot = context;
  no_robot.command_space = {};
  EXPECT_THROW(IbvsBroydenTask(Params{}, no_robot), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
