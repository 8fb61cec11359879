// The unicycle with a tilt camera (servo/unicycle_tilt_robot.h) and paper 001's tracking law
// (tasks/vtc_task.h) on it: camera Jacobian and B_i against finite differences through the robot,
// exact integration, reset round trip, wheel-speed limits and quantisation (paper §5.4), and a
// small closed loop (no delay, no noise) on a static board.
#include "predvs/servo/unicycle_tilt_robot.h"
#include "predvs/tasks/vtc_task.h"

#include "predictors/eigen_test_utils.h"

#include <visp3/core/vpThetaUVector.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Five-point differences with h = 1e-4 on poses of ~1 m and features of a few hundred px: about
// 1e-10 (truncation h^4, rounding 1e-16 * 400 / 1e-4), well inside the 1e-8 of docs/DESIGN.md (the unicycle's Jacobians against the paper's own model).
constexpr double kFdStep = 1e-4;
constexpr double kFdTol = 1e-8;

// d f(q + t g) / dt at t = 0 by the five-point stencil.
template <class F>
Eigen::VectorXd derivative(const F& f, const Eigen::Vector4d& q, const Eigen::Vector4d& g) {
  const Eigen::Vector4d h = kFdStep * g;
  return (-f(q + 2 * h) + 8 * f(q + h) - 8 * f(q - h) + f(q - 2 * h)) / (12.0 * kFdStep);
}

const CameraIntrinsics kCamera{393.4, 391.8, 320.0, 240.0};  // paper 001 Table 1 focal lengths

Eigen::Vector3d cameraPoint(const vpHomogeneousMatrix& wMc, const Eigen::Vector3d& wP) {
  const vpHomogeneousMatrix cMw = wMc.inverse();
  Eigen::Vector3d c;
  for (unsigned r = 0; r < 3; ++r) c(r) = cMw[r][0] * wP(0) + cMw[r][1] * wP(1) + cMw[r][2] * wP(2) + cMw[r][3];
  return c;
}

// Pinhole projection of world points (3 x N) seen from wMc.
PointFeatures project(const Eigen::Matrix3Xd& wP, const vpHomogeneousMatrix& wMc) {
  PointFeatures p;
  const int n = static_cast<int>(wP.cols());
  p.uv_px.resize(2 * n);
  p.Z_m.resize(n);
  p.seen.assign(static_cast<size_t>(n), true);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d c = cameraPoint(wMc, wP.col(k));
    p.uv_px(2 * k) = kCamera.u0 + kCamera.px * c(0) / c(2);
    p.uv_px(2 * k + 1) = kCamera.v0 + kCamera.py * c(1) / c(2);
    p.Z_m(k) = c(2);
    p.seen[static_cast<size_t>(k)] = c(2) > 0.0;
  }
  return p;
}

// A vertical square board of side w centred at c, facing -x (towards a robot at the origin).
Eigen::Matrix3Xd board(const Eigen::Vector3d& c, double w = 0.12) {
  Eigen::Matrix3Xd P(3, 4);
  const double a = w / 2.0;
  P << c(0), c(0), c(0), c(0),  //
      c(1) + a, c(1) - a, c(1) - a, c(1) + a,  //
      c(2) + a, c(2) + a, c(2) - a, c(2) - a;
  return P;
}

Eigen::Vector4d dq(const Eigen::Vector4d& q, int j) {  // dq/dt per unit command j (paper eq. 1)
  Eigen::Vector4d g = Eigen::Vector4d::Zero();
  if (j == 0) g << std::cos(q(2)), std::sin(q(2)), 0.0, 0.0;
  if (j == 1) g(2) = 1.0;
  if (j == 2) g(3) = 1.0;
  return g;
}

TaskContext unicycleContext(std::uint64_t seed = 1) {
  TaskContext c;
  c.camera = kCamera;
  c.command_space = UnicycleTiltRobot().commandSpace();
  c.frame_period_s = c.base_period_s = 0.1;
  c.seed = seed;
  return c;
}

TEST(UnicycleTiltRobot, CameraJacobianMatchesFiniteDifferencesOfThePose) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const UnicycleTiltConfig config;
  for (int trial = 0; trial < 10; ++trial) {
    // GIVEN a random state
    const Eigen::Vector4d q(U(rng), U(rng), 3.0 * U(rng), 1.2 * U(rng));
    UnicycleTiltRobot robot(config);
    robot.setState(q);
    const vpHomogeneousMatrix cMw = robot.cameraPose().inverse();
    // WHEN each command component moves the state along eq. 1: (translation, theta-u) of cMc(t)
    auto relative = [&](const Eigen::Vector4d& s) {
      const vpHomogeneousMatrix cMs = cMw * UnicycleTiltRobot::cameraPoseAt(s, config);
      const vpThetaUVector tu(cMs);
      Eigen::VectorXd v(6);
      v << cMs[0][3], cMs[1][3], cMs[2][3], tu[0], tu[1], tu[2];
      return v;
    };
    Eigen::MatrixXd J(6, 3);
    for (int j = 0; j < 3; ++j) J.col(j) = derivative(relative, q, dq(q, j));
    // THEN the camera twist (camera frame) per unit command is cameraJacobian()
    EXPECT_TRUE(matricesNear(robot.cameraJacobian(), J, kFdTol)) << "trial " << trial;
  }
}

TEST(UnicycleTiltRobot, StepIntegratesTheKinematicsExactly) {
  UnicycleTiltRobot once, twice, straight;
  const Eigen::Vector4d q0(0.3, -0.2, 0.7, 0.1);
  once.setState(q0);
  twice.setState(q0);
  const Eigen::Vector3d u(0.4, 0.9, -0.2);
  // GIVEN one step of 1 s and two of 0.5 s: an exact flow composes (an Euler step would not)
  once.step(u, 1.0);
  twice.step(u, 0.5);
  twice.step(u, 0.5);
  EXPECT_TRUE(matricesNear(once.state(), twice.state(), 1e-14));
  // AND a full turn comes back to the start
  UnicycleTiltRobot circle;
  circle.setState(q0);
  circle.step(Eigen::Vector3d(0.5, 2.0 * kPi, 0.0), 1.0);
  EXPECT_TRUE(matricesNear(circle.state().head<2>(), q0.head<2>(), 1e-14));
  // AND omega = 0 is the straight line
  straight.setState(q0);
  straight.step(Eigen::Vector3d(0.5, 0.0, 0.3), 2.0);
  const Eigen::Vector4d expected(0.3 + std::cos(0.7), -0.2 + std::sin(0.7), 0.7, 0.7);
  EXPECT_TRUE(matricesNear(straight.state(), expected, 1e-14));
}

TEST(UnicycleTiltRobot, ResetRoundTripsAnAchievablePose) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    // GIVEN the camera pose of a random state
    const Eigen::Vector4d q(U(rng), U(rng), 3.0 * U(rng), 1.4 * U(rng));
    UnicycleTiltRobot robot;
    const vpHomogeneousMatrix wMc = UnicycleTiltRobot::cameraPoseAt(q, robot.config());
    // WHEN the robot is reset there
    robot.reset(wMc);
    // THEN it has that state and that pose
    EXPECT_TRUE(matricesNear(robot.state(), q, 1e-12)) << "trial " << trial;
    const vpHomogeneousMatrix back = robot.cameraPose();
    for (unsigned r = 0; r < 3; ++r)
      for (unsigned c = 0; c < 4; ++c) EXPECT_NEAR(back[r][c], wMc[r][c], 1e-12);
  }
}

TEST(UnicycleTiltRobot, ResetDropsRollAndHeightAndRejectsAVerticalAxis) {
  // GIVEN a camera 1 m high, rolled by 0.3 rad about its optical axis, looking along +y, tilted up
  const Eigen::Vector4d q(0.5, 0.2, kPi / 2, 0.2);
  UnicycleTiltRobot robot;
  vpHomogeneousMatrix wMc = UnicycleTiltRobot::cameraPoseAt(q, robot.config());
  wMc = wMc * vpHomogeneousMatrix(0, 0, 0, 0, 0, 0.3);
  wMc[2][3] = 1.0;
  robot.reset(wMc);
  // THEN the optical axis and the x-y position of the camera centre are kept
  const vpHomogeneousMatrix got = robot.cameraPose();
  for (unsigned r = 0; r < 3; ++r) EXPECT_NEAR(got[r][2], wMc[r][2], 1e-12);
  EXPECT_NEAR(got[0][3], wMc[0][3], 1e-12);
  EXPECT_NEAR(got[1][3], wMc[1][3], 1e-12);
  // AND the height is the robot's own, the camera x axis horizontal
  EXPECT_NEAR(got[2][3], 0.30 + 0.10 * std::cos(0.2), 1e-12);
  EXPECT_NEAR(got[2][0], 0.0, 1e-15);
  // GIVEN a camera looking straight up THEN reset throws
  const vpHomogeneousMatrix up = UnicycleTiltRobot::cameraPoseAt(Eigen::Vector4d(0, 0, 0, kPi / 2), robot.config());
  EXPECT_THROW(robot.reset(up), std::invalid_argument);
}

TEST(UnicycleTiltRobot, LimitScalesWheelSpeedsKeepingTheDirection) {
  // GIVEN the paper's card: |wheel| <= 1.27 m/s, tilt rate <= 1 rad/s, no quantisation
  UnicycleTiltRobot robot(Params{{"max_wheel_speed", 1.27}, {"max_tilt_rate_rad_s", 1.0}});
  const Eigen::Vector3d u(1.5, 2.0, 0.4);  // wheels 1.1 and 1.9 m/s
  const Eigen::VectorXd out = robot.limit(u);
  // THEN the command is scaled by one factor (same direction) so that the fast wheel is at 1.27
  EXPECT_TRUE(matricesNear(out, u * (1.27 / 1.9), 1e-14));
  // AND the tilt rate limit scales the whole command too
  EXPECT_TRUE(matricesNear(robot.limit(Eigen::Vector3d(0.1, 0.0, 2.0)), Eigen::Vector3d(0.05, 0.0, 1.0), 1e-14));
  // AND a command within the limits is untouched
  EXPECT_TRUE(matricesNear(robot.limit(Eigen::Vector3d(0.2, 0.5, -0.3)), Eigen::Vector3d(0.2, 0.5, -0.3), 1e-15));
}

TEST(UnicycleTiltRobot, LimitQuantisesWheelSpeedsAsThePaper) {
  // GIVEN integer cm/s wheel speeds (the paper's 8-bit card)
  UnicycleTiltRobot floor_robot(Params{{"wheel_speed_step", 0.01}});
  Params nearest_params{{"wheel_speed_step", 0.01}};
  nearest_params.setText("quantisation", "nearest");
  UnicycleTiltRobot nearest_robot(nearest_params);
  // THEN the paper's example: 2.9925 cm/s on both wheels becomes 2 cm/s (floor), 3 cm/s (nearest)
  EXPECT_NEAR(floor_robot.limit(Eigen::Vector3d(0.029925, 0.0, 0.0))(0), 0.02, 1e-15);
  EXPECT_NEAR(nearest_robot.limit(Eigen::Vector3d(0.029925, 0.0, 0.0))(0), 0.03, 1e-15);
  // AND a turn: v_l = 0.1 - 0.2 * 0.4 / 2 = 0.06, v_r = 0.14 -> exact steps, unchanged
  EXPECT_TRUE(matricesNear(floor_robot.limit(Eigen::Vector3d(0.1, 0.2, 0.0)), Eigen::Vector3d(0.1, 0.2, 0.0), 1e-12));
  // AND with a wheel radius the step is in rad/s of the wheel: 5 cm radius, 1 rad/s steps = 5 cm/s
  UnicycleTiltRobot wheel(Params{{"wheel_speed_step", 1.0}, {"wheel_radius_m", 0.05}});
  EXPECT_NEAR(wheel.limit(Eigen::Vector3d(0.12, 0.0, 0.0))(0), 0.10, 1e-15);
  // AND the unknown key is rejected, naming it
  try {
    UnicycleTiltRobot bad(Params{{"max_wheel_sped", 1.0}});
    ADD_FAILURE() << "unknown key accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_wheel_sped"), std::string::npos);
  }
}

TEST(UnicycleTiltRobot, RobotGeometryIsThePaperAppendixModel) {
  // GIVEN a target centre P of width W seen through the robot's camera pose, the paper's features
  // (fx X / Z, fy Y / Z, fx W / Z) (appendix eq. A.3)
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const UnicycleTiltConfig config;
  const VtcModel model{kCamera.px, kCamera.py, 0.12, config.camera_offset_y_m};
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector4d q(U(rng), U(rng), U(rng), 0.5 * U(rng));
    const Eigen::Vector3d P(q(0) + 1.5 * std::cos(q(2)) + 0.3 * U(rng), q(1) + 1.5 * std::sin(q(2)) + 0.3 * U(rng),
                            0.4 + 0.4 * U(rng));
    auto features = [&](const Eigen::Vector4d& s) {
      const Eigen::Vector3d c = cameraPoint(UnicycleTiltRobot::cameraPoseAt(s, config), P);
      return Eigen::Vector3d(model.fx_px * c(0) / c(2), model.fy_px * c(1) / c(2), model.fx_px * model.width_m / c(2));
    };
    Eigen::Matrix3d fd;
    for (int j = 0; j < 3; ++j) fd.col(j) = derivative(features, q, dq(q, j));
    // THEN B_i at those features and the robot's tilt is their derivative along the command
    EXPECT_TRUE(matricesNear(VtcTask::robotImageJacobian(features(q), q(3), model), fd, kFdTol)) << trial;
  }
}

TEST(UnicycleTiltRobot, BoardFeaturesFollowBiAtTheGoal) {
  // GIVEN the board parallel to the image, centred, at the goal depth fx W / 35 (paper Table 1)
  const double Z = kCamera.px * 0.12 / 35.0;
  UnicycleTiltRobot robot;
  VtcTask task(Params{}, unicycleContext());
  const Eigen::Matrix3Xd P = board(Eigen::Vector3d(Z, 0.0, 0.40));
  const Eigen::Vector4d q = Eigen::Vector4d::Zero();
  auto features = [&](const Eigen::Vector4d& s) {
    return Eigen::Vector3d(task.features(project(P, UnicycleTiltRobot::cameraPoseAt(s, robot.config()))));
  };
  // THEN the features are the goal
  EXPECT_TRUE(matricesNear(features(q), Eigen::Vector3d(0.0, 0.0, 35.0), 1e-12));
  Eigen::Matrix3d fd;
  for (int j = 0; j < 3; ++j) fd.col(j) = derivative(features, q, dq(q, j));
  // AND B_i predicts their motion up to the perspective of the outline: the centroid of the
  // projected corners drifts by (half side / Z)^2 ~ 0.2 % of the image motion under a rotation
  constexpr double kPerspectiveTol = 5e-3;
  const Eigen::Matrix3d B = VtcTask::robotImageJacobian(features(q), 0.0, task.trueModel());
  EXPECT_LT((B - fd).norm() / B.norm(), kPerspectiveTol) << "B_i\n" << B << "\nfinite differences\n" << fd;
}

struct LoopResult {
  double initial_error = 0.0, final_error = 0.0;
  NamedValues summary;
};

// The small closed loop: the robot sees the board, the task computes u, the robot executes it for
// one frame period T = 0.1 s (paper Table 1); no delay, no noise, no limits.
LoopResult runStaticLoop(const Params& task_params, std::uint64_t seed, double duration_s) {
  const double T = 0.1;
  UnicycleTiltRobot robot;
  robot.setState(Eigen::Vector4d(0.0, 0.0, -0.2, 0.15));  // turned right of the board, looking up
  VtcTask task(task_params, unicycleContext(seed));
  const Eigen::Matrix3Xd P = board(Eigen::Vector3d(1.8, 0.3, 0.30));
  const Eigen::VectorXd empty, depths;
  const Eigen::MatrixXd none;
  LoopResult r;
  const int steps = static_cast<int>(std::lround(duration_s / T));
  for (int k = 0; k <= steps; ++k) {
    const PointFeatures p = project(P, robot.cameraPose());
    const Eigen::VectorXd X = task.features(p);
    if (k == 0) r.initial_error = task.trackingError(X);
    r.final_error = task.trackingError(X);
    if (k == steps) break;
    const Eigen::VectorXd state = robot.state();
    const Eigen::MatrixXd J = robot.cameraJacobian();
    const TaskInput in{k * T, k * T, X, X, empty, p.Z_m, J, state, none};
    robot.step(robot.limit(task.computeCommand(in)), T);
  }
  r.summary = task.runSummary();
  return r;
}

TEST(VtcClosedLoop, DrivesAStaticBoardToTheDesiredFeatures) {
  // GIVEN the board 1.8 m ahead, 30 cm to the left, 10 cm below the camera, the robot turned 0.2 rad
  // to the right and looking up 0.15 rad: X = (-152, 83, 31) px at the start, RMS error 100 px;
  // exact parameters
  const LoopResult r = runStaticLoop(Params{}, 1, 40.0);
  EXPECT_GT(r.initial_error, 40.0);
  // THEN after 40 s (13 time constants of the slowest pole, 1/3 /s) the error is gone (measured
  // 5e-6 px)
  EXPECT_LT(r.final_error, 1e-3);
  // AND with exact parameters and a static target the Lyapunov bound holds at every tick
  EXPECT_DOUBLE_EQ(r.summary[0].second, 1.0);
}

TEST(VtcClosedLoop, ConvergesWithTenPercentParameterErrors) {
  // GIVEN rho ~ U[-0.1, 0.1] on fx, fy, W, dy (paper eq. 43), three seeds
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const LoopResult r = runStaticLoop(Params{{"param_error", 0.1}}, seed, 40.0);
    // THEN it still converges (the goal is a fixed point whatever the model error; measured 1e-6 to
    // 2e-5 px after 40 s)
    EXPECT_LT(r.final_error, 1e-3) << "seed " << seed;
    // AND on a static target the bound of eq. 45 stays positive throughout (measured: every tick)
    EXPECT_DOUBLE_EQ(r.summary[0].second, 1.0) << "seed " << seed;
  }
}

struct MovingResult {
  double rms_error = 0.0, peak_error = 0.0;
  NamedValues summary;
};

// The board translating on the world ground plane with paper 001's eq. 44 motion (speed
// 0.15 cos(pi t / 20) m/s, heading turning at 5 pi / 72 rad/s, piecewise constant over T), the
// robot starting at the goal; the feed-forward is the exact target image rate (or none).
MovingResult runMovingLoop(const Params& task_params, bool feed_forward, std::uint64_t seed) {
  const double T = 0.1, Z = kCamera.px * 0.12 / 35.0;
  UnicycleTiltRobot robot;
  VtcTask task(task_params, unicycleContext(seed));
  Eigen::Vector3d centre(Z, 0.0, 0.40);
  const Eigen::VectorXd depths;
  const Eigen::MatrixXd none;
  MovingResult r;
  const int steps = 200;
  double sum = 0.0;
  for (int k = 0; k < steps; ++k) {
    const double speed = 0.15 * std::cos(k * kPi * T / 20.0), heading = k * T * 5.0 * kPi / 72.0;
    const Eigen::Vector3d V(speed * std::cos(heading), speed * std::sin(heading), 0.0);
    const vpHomogeneousMatrix wMc = robot.cameraPose();
    auto seen = [&](double dt) { return Eigen::Vector3d(task.features(project(board(centre + dt * V), wMc))); };
    const Eigen::VectorXd X = seen(0.0);
    const double e = task.trackingError(X);
    sum += e * e;
    r.peak_error = std::max(r.peak_error, e);
    const double h = 1e-4;
    const Eigen::VectorXd rate = feed_forward ? Eigen::VectorXd((-seen(2 * h) + 8 * seen(h) - 8 * seen(-h) + seen(-2 * h)) / (12 * h))
                                              : Eigen::VectorXd();
    const Eigen::VectorXd state = robot.state();
    const Eigen::MatrixXd J = robot.cameraJacobian();
    const TaskInput in{k * T, k * T, X, X, rate, depths, J, state, none};
    robot.step(task.computeCommand(in), T);
    centre += T * V;
  }
  r.rms_error = std::sqrt(sum / steps);
  r.summary = task.runSummary();
  return r;
}

TEST(VtcClosedLoop, TargetRateFeedForwardRemovesTheLagOnTheEq44Motion) {
  // GIVEN the board moving with eq. 44 for 20 s from the goal, exact parameters
  const MovingResult without = runMovingLoop(Params{}, false, 1);
  const MovingResult with = runMovingLoop(Params{}, true, 1);
  // THEN the law without Xdot_t lags (measured RMS 12.5 px) and with the exact Xdot_t it does not
  // (measured 0.14 px: what remains is the zero-order hold of u over T = 0.1 s)
  EXPECT_GT(without.rms_error, 5.0);
  EXPECT_LT(with.rms_error, 0.5);
  // GIVEN 10 % parameter errors (seed 1) THEN it still tracks (measured 1.1 px) but the bound of
  // eq. 45 is positive only part of the time (measured 28.5 % of the ticks; f(u) 41.5 %), as
  // docs/MODELS.md §11 reports for E8
  const MovingResult perturbed = runMovingLoop(Params{{"param_error", 0.1}}, true, 1);
  EXPECT_LT(perturbed.rms_error, 3.0);
  EXPECT_GT(perturbed.summary[0].second, 0.05);
  EXPECT_LT(perturbed.summary[0].second, 0.9);
  EXPECT_LE(perturbed.summary[0].second, perturbed.summary[1].second);
}

}  // namespace
}  // namespace predvs
