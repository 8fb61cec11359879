#include "predvs/tasks/vsc_task.h"
#include "predictors/eigen_test_utils.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {
namespace {

constexpr double kPeriod_s = 0.04;
// The reaching law is solved exactly through a linear model: what remains is round-off on
// features of a few hundred pixels.
constexpr double kExactTol_px = 1e-9;
// After several seconds at a contraction of ~0.76 per tick the error is at round-off level.
constexpr double kConvergedTol_px = 1e-6;
// Features of ~600 px carry ~1e-13 px of round-off: below this a "decrease" cannot be asked for.
constexpr double kRoundOff_px = 1e-9;

CommandSpace xyStageSpace() { return {"stage-velocity", {"vx_m_per_s", "vy_m_per_s"}}; }
CommandSpace twistSpace() { return {"camera-twist", {"vx", "vy", "vz", "wx", "wy", "wz"}}; }

TaskContext makeContext(const Eigen::VectorXd& desired_uv, const Eigen::VectorXd& desired_Z, CommandSpace space) {
  TaskContext c;
  c.desired_points.uv_px = desired_uv;
  c.desired_points.Z_m = desired_Z;
  c.desired_points.seen.assign(static_cast<size_t>(desired_Z.size()), true);
  c.command_space = std::move(space);
  c.base_period_s = kPeriod_s;
  c.frame_period_s = kPeriod_s;
  return c;
}

/// Camera on an x-y stage, translating parallel to a plane at depth Z that carries one point:
/// s = s0 + v t - (px / Z, py / Z) p, p the stage position (m). Robot Jacobian [I2; 0].
struct XyStage {
  CameraIntrinsics camera;
  double Z_m = 0.5;
  Eigen::Vector2d s0_px{510.0, 160.0};    // where the point is seen with the stage at p = 0
  Eigen::Vector2d target_px_per_s{0, 0};  // image rate of the target itself
  Eigen::Vector2d p_m{0.0, 0.0};
  double t_s = 0.0;
  Eigen::MatrixXd robot_jacobian = (Eigen::MatrixXd(6, 2) << 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0).finished();

  Eigen::VectorXd features() const {
    return s0_px + target_px_per_s * t_s - Eigen::Vector2d(camera.px / Z_m * p_m(0), camera.py / Z_m * p_m(1));
  }
  void apply(const Eigen::VectorXd& u, double dt) {
    p_m += dt * u;
    t_s += dt;
  }
};

/// One control tick of `task` on features s with depths Z.
Eigen::VectorXd tick(VscTask& task, double t, const Eigen::VectorXd& s, const Eigen::VectorXd& Z,
                     const Eigen::MatrixXd& robot_jacobian, const Eigen::VectorXd& ft = Eigen::VectorXd()) {
  const Eigen::VectorXd state = Eigen::VectorXd::Zero(robot_jacobian.cols());
  const Eigen::MatrixXd truth;
  TaskInput in{t, t, s, s, ft, Z, robot_jacobian, state, truth};
  return task.computeCommand(in);
}

double diagnostic(const Task& task, const std::string& key) {
  for (const auto& kv : task.diagnostics())
    if (kv.first == key) return kv.second;
  ADD_FAILURE() << "no diagnostic " << key;
  return std::numeric_limits<double>::quiet_NaN();
}

Eigen::VectorXd one(double x) { return Eigen::VectorXd::Constant(1, x); }
Eigen::VectorXd desiredOffCentre() { return Eigen::Vector2d(620.0, 240.0); }  // 300 px right of the centre

/// Free-flying camera looking at points given in the camera frame (m); a twist (v, w) moves them
/// as dP/dt = -v - w x P, integrated in small substeps that are each a rigid motion (an exact
/// rotation, then the translation), so the point set never deforms.
struct FreeCamera {
  CameraIntrinsics camera;
  std::vector<Eigen::Vector3d> P;
  Eigen::VectorXd features() const {
    Eigen::VectorXd s(2 * P.size());
    for (size_t i = 0; i < P.size(); ++i) {
      s(2 * i) = camera.u0 + camera.px * P[i].x() / P[i].z();
      s(2 * i + 1) = camera.v0 + camera.py * P[i].y() / P[i].z();
    }
    return s;
  }
  Eigen::VectorXd depths() const {
    Eigen::VectorXd Z(P.size());
    for (size_t i = 0; i < P.size(); ++i) Z(i) = P[i].z();
    return Z;
  }
  void apply(const Eigen::VectorXd& u, double dt, int substeps = 20) {
    const Eigen::Vector3d v = u.head<3>(), w = u.tail<3>();
    const double h = dt / substeps;
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    if (w.norm() > 0.0) R = Eigen::AngleAxisd(-h * w.norm(), w.normalized()).toRotationMatrix();
    for (int k = 0; k < substeps; ++k)
      for (auto& p : P) p = R * p - h * v;
  }
};

std::vector<Eigen::Vector3d> square(double side_m, double Z_m) {
  const double a = side_m / 2;
  return {{-a, -a, Z_m}, {a, -a, Z_m}, {a, a, Z_m}, {-a, a, Z_m}};
}

TEST(VscTask, DrivesXyStageToStaticGoalWithGentleStart) {
  // GIVEN a stage camera seeing the point at (510, 160) and a goal 300 px right of the centre
  XyStage plant;
  VscTask task(Params{}, makeContext(desiredOffCentre(), one(plant.Z_m), xyStageSpace()));
  VscTask constant_gain(Params{{"q_far", 4.0}}, makeContext(desiredOffCentre(), one(plant.Z_m), xyStageSpace()));
  XyStage plant_constant = plant;
  double peak_rate = 0.0, peak_rate_constant = 0.0;
  // WHEN both laws run 6 s
  for (int k = 0; k < 150; ++k) {
    const Eigen::VectorXd u = tick(task, plant.t_s, plant.features(), one(plant.Z_m), plant.robot_jacobian);
    const Eigen::VectorXd uc = tick(constant_gain, plant_constant.t_s, plant_constant.features(), one(plant.Z_m),
                                    plant.robot_jacobian);
    peak_rate = std::max(peak_rate, (task.featureJacobian() * u).norm());
    peak_rate_constant = std::max(peak_rate_constant, (constant_gain.featureJacobian() * uc).norm());
    plant.apply(u, kPeriod_s);
    plant_constant.apply(uc, kPeriod_s);
  }
  // THEN the point sits on the goal, and the scheduled gain starts slower than a constant q_near
  EXPECT_LT(task.trackingError(plant.features()), kConvergedTol_px);
  EXPECT_LT(task.runSummary().front().second, kConvergedTol_px);
  EXPECT_LT(peak_rate, 0.5 * peak_rate_constant) << peak_rate << " vs " << peak_rate_constant;
  EXPECT_NEAR(diagnostic(task, "gain_q"), 4.0, 1e-9);  // q_near at the goal
}

TEST(VscTask, FeatureJacobianMatchesFiniteDifferences) {
  // GIVEN a free-flying camera seeing a tilted, off-centre set of 4 points
  FreeCamera cam;
  cam.P = {{-0.1, -0.08, 0.9}, {0.12, -0.1, 1.0}, {0.1, 0.11, 1.1}, {-0.09, 0.1, 0.95}};
  VscTask task(Params{}, makeContext(cam.features(), cam.depths(), twistSpace()));
  const Eigen::MatrixXd I6 = Eigen::MatrixXd::Identity(6, 6);
  tick(task, 0.0, cam.features(), cam.depths(), I6);
  // WHEN each twist component is applied for +-tau
  constexpr double tau = 1e-6;
  Eigen::MatrixXd fd(8, 6);
  for (int j = 0; j < 6; ++j) {
    FreeCamera plus = cam, minus = cam;
    plus.apply(I6.col(j), tau, 1);
    minus.apply(-I6.col(j), tau, 1);
    fd.col(j) = (plus.features() - minus.features()) / (2 * tau);
  }
  // THEN J = L_px * robot Jacobian equals ds/du (central differences: O(tau^2) and round-off
  // of 1e-10 px / 1e-6 s on entries of up to ~1000 px)
  constexpr double kFdTol = 1e-5;
  EXPECT_TRUE(matricesNear(task.featureJacobian(), fd, kFdTol));
}

TEST(VscTask, ReachingLawHoldsExactlyOnLinearPlant) {
  // GIVEN a stage plant whose target moves at a constant image rate, the rate fed forward exactly
  XyStage plant;
  plant.target_px_per_s = {3.0, -8.0};
  VscTask task(Params{{"eps_s", 20.0}, {"phi", 10.0}}, makeContext(desiredOffCentre(), one(plant.Z_m), xyStageSpace()));
  const VscTaskConfig& c = task.config();
  int outside_layer = 0;
  for (int k = 0; k < 100; ++k) {
    // WHEN one step is applied
    const Eigen::VectorXd u = tick(task, plant.t_s, plant.features(), one(plant.Z_m), plant.robot_jacobian,
                                   plant.target_px_per_s);
    const Eigen::VectorXd S = task.slidingVariable();
    const double q = diagnostic(task, "gain_q");
    const Eigen::VectorXd sat = (S / c.phi_px).cwiseMax(-1.0).cwiseMin(1.0);
    const Eigen::VectorXd predicted = (1 - q * kPeriod_s) * S - c.eps_px_per_s * kPeriod_s * sat;
    if (S.cwiseAbs().maxCoeff() > c.phi_px) ++outside_layer;
    plant.apply(u, kPeriod_s);
    // THEN S(k+1) = (1 - qT) S(k) - eps_s T sat(S(k) / phi)
    const Eigen::VectorXd S_next = plant.features() - desiredOffCentre();
    ASSERT_TRUE(matricesNear(S_next, predicted, kExactTol_px)) << "tick " << k;
  }
  EXPECT_GT(outside_layer, 10);  // both branches of sat were exercised
}

TEST(VscTask, ReachingLawHoldsExactlyForWideJacobian) {
  // GIVEN one point seen by a free-flying camera (J is 2 x 6: minimum-norm command) and the
  // local linear model s(k+1) = s(k) + T J u as the plant, with c_u != c_v
  const Eigen::VectorXd Z = one(0.8);
  Eigen::VectorXd s = Eigen::Vector2d(100.0, 400.0);
  VscTask task(Params{{"c_u", 2.0}, {"c_v", 0.5}}, makeContext(desiredOffCentre(), Z, twistSpace()));
  const Eigen::MatrixXd I6 = Eigen::MatrixXd::Identity(6, 6);
  for (int k = 0; k < 50; ++k) {
    // WHEN one step is applied
    const Eigen::VectorXd u = tick(task, k * kPeriod_s, s, Z, I6);
    const Eigen::VectorXd S = task.slidingVariable();
    const double q = diagnostic(task, "gain_q");
    const Eigen::VectorXd sat = (S / task.config().phi_px).cwiseMax(-1.0).cwiseMin(1.0);
    const Eigen::VectorXd predicted = (1 - q * kPeriod_s) * S - task.config().eps_px_per_s * kPeriod_s * sat;
    s += kPeriod_s * task.featureJacobian() * u;
    // THEN the reaching law holds with S = C e
    const Eigen::VectorXd S_next = Eigen::Vector2d(2.0, 0.5).cwiseProduct(s - desiredOffCentre());
    ASSERT_TRUE(matricesNear(S_next, predicted, kExactTol_px)) << "tick " << k;
  }
}

TEST(VscTask, NoChatteringInsideBoundaryLayer) {
  // GIVEN the stage plant and a static target
  XyStage plant;
  VscTask task(Params{}, makeContext(desiredOffCentre(), one(plant.Z_m), xyStageSpace()));
  const double phi = task.config().phi_px;
  std::vector<Eigen::VectorXd> commands;
  Eigen::VectorXd prev_S;
  double peak_u = 0.0;
  // WHEN the law runs 8 s
  for (int k = 0; k < 200; ++k) {
    const Eigen::VectorXd u = tick(task, plant.t_s, plant.features(), one(plant.Z_m), plant.robot_jacobian);
    const Eigen::VectorXd S = task.slidingVariable();
    // THEN inside the layer every component of S keeps its sign and shrinks (no switching)
    if (prev_S.size() && prev_S.cwiseAbs().maxCoeff() < phi)
      for (int i = 0; i < 2; ++i) {
        if (std::abs(prev_S(i)) < kRoundOff_px) continue;  // at round-off, equal values are fine
        EXPECT_GE(S(i) / prev_S(i), 0.0) << "tick " << k;
        EXPECT_LT(std::abs(S(i)), std::abs(prev_S(i))) << "tick " << k;
      }
    prev_S = S;
    peak_u = std::max(peak_u, u.norm());
    commands.push_back(u);
    plant.apply(u, kPeriod_s);
  }
  // AND the command is smooth at the end: its total variation over the last second is negligible
  double tv = 0.0;
  for (size_t k = commands.size() - 25; k < commands.size(); ++k) tv += (commands[k] - commands[k - 1]).norm();
  constexpr double kSmoothFraction = 1e-6;  // geometric decay at 0.76 per tick: ~1e-15 left after 7 s
  EXPECT_LT(tv, kSmoothFraction * peak_u);
}

TEST(VscTask, MeasurementNoiseDoesNotMakeTheCommandSwitch) {
  // GIVEN the stage plant at the goal and seeded 0.2 px measurement noise
  XyStage plant;
  plant.s0_px = desiredOffCentre();
  VscTask task(Params{}, makeContext(desiredOffCentre(), one(plant.Z_m), xyStageSpace()));
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::vector<Eigen::VectorXd> rates;
  // WHEN the law runs 4 s on noisy features
  for (int k = 0; k < 100; ++k) {
    const Eigen::VectorXd s = plant.features() + Eigen::Vector2d(noise(rng), noise(rng));
    const Eigen::VectorXd u = tick(task, plant.t_s, s, one(plant.Z_m), plant.robot_jacobian);
    rates.push_back(task.featureJacobian() * u);
    plant.apply(u, kPeriod_s);
  }
  // THEN the commanded image rate moves by about q_eff * noise per tick (q_eff = 6 /s: ~2.4 px/s
  // RMS over two axes, ~3 px/s with the plant's response), far below the jumps of 2 eps_s per
  // axis (~28 px/s) a sign() law would make around the goal
  double sum_sq = 0.0;
  for (size_t k = 1; k < rates.size(); ++k) sum_sq += (rates[k] - rates[k - 1]).squaredNorm();
  const double rms_jump = std::sqrt(sum_sq / (rates.size() - 1));
  EXPECT_LT(rms_jump, 0.5 * task.config().eps_px_per_s) << rms_jump;
  EXPECT_LT(task.trackingError(plant.features()), 1.0);
}

struct VelocityRun {
  double final_error_px;
  double final_q;
};

VelocityRun runConstantVelocity(const Eigen::Vector2d& v_px_per_s, bool feed_forward) {
  XyStage plant;
  plant.target_px_per_s = v_px_per_s;
  VscTask task(Params{}, makeContext(desiredOffCentre(), one(plant.Z_m), xyStageSpace()));
  for (int k = 0; k < 300; ++k) {
    const Eigen::VectorXd ft = feed_forward ? Eigen::VectorXd(v_px_per_s) : Eigen::VectorXd();
    plant.apply(tick(task, plant.t_s, plant.features(), one(plant.Z_m), plant.robot_jacobian, ft), kPeriod_s);
  }
  return {task.trackingError(plant.features()), diagnostic(task, "gain_q")};
}

TEST(VscTask, ConstantVelocityTargetFeedForwardRemovesTheLag) {
  // GIVEN a target moving at 10 px/s in the image (E5's line, scaled)
  const Eigen::Vector2d v(0.0, 10.0);
  // WHEN the law runs 12 s with the exact target rate fed forward, and without
  const VelocityRun with = runConstantVelocity(v, true);
  const VelocityRun without = runConstantVelocity(v, false);
  // THEN with it the error vanishes; without it the error settles at v / q_eff, q_eff = q + eps_s/phi
  EXPECT_LT(with.final_error_px, kConvergedTol_px);
  const VscTaskConfig c;
  const double q_eff = without.final_q + c.eps_px_per_s / c.phi_px;
  EXPECT_NEAR(without.final_error_px, v.norm() / q_eff, kConvergedTol_px);
  constexpr double kScheduleShift = 0.01;  // q(1.7 px) is within 0.2 % of q_near
  EXPECT_NEAR(without.final_error_px, v.norm() / (c.q_near_per_s + c.eps_px_per_s / c.phi_px),
              kScheduleShift * without.final_error_px);
}

TEST(VscTask, FreeFlyingCameraReachesFourPointGoal) {
  // GIVEN a 0.2 m square at 1 m as the goal and a camera shifted and rolled by 15 deg
  FreeCamera goal;
  goal.P = square(0.2, 1.0);
  FreeCamera cam;
  const double a = 15.0 * 3.14159265358979323846 / 180.0;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (const auto& p : goal.P) cam.P.push_back(R * p + Eigen::Vector3d(0.05, -0.04, 0.25));
  VscTask task(Params{}, makeContext(goal.features(), goal.depths(), twistSpace()));
  const double initial = task.trackingError(cam.features());
  const Eigen::MatrixXd I6 = Eigen::MatrixXd::Identity(6, 6);
  // WHEN the law runs 10 s on the rigid-motion plant (4 points, J is 8 x 6: least squares)
  for (int k = 0; k < 250; ++k) cam.apply(tick(task, k * kPeriod_s, cam.features(), cam.depths(), I6), kPeriod_s);
  // THEN the points reach the goal
  EXPECT_GT(initial, 20.0);
  constexpr double kFreeFlyingTol_px = 1e-3;  // nonlinear plant, Euler substeps: converged, not exact
  EXPECT_LT(task.trackingError(cam.features()), kFreeFlyingTol_px);
}

TEST(VscTask, SingularJacobianAndLostPointsGiveAFiniteCommand) {
  FreeCamera goal;
  goal.P = square(0.2, 1.0);
  VscTask task(Params{}, makeContext(goal.features(), goal.depths(), twistSpace()));
  Eigen::VectorXd s = goal.features() + Eigen::VectorXd::Constant(8, 20.0);
  // GIVEN a robot that cannot move the camera at all
  const Eigen::VectorXd u0 = tick(task, 0.0, s, goal.depths(), Eigen::MatrixXd::Zero(6, 6));
  // THEN the command is zero, not an exception
  EXPECT_TRUE(u0.allFinite());
  EXPECT_EQ(u0.norm(), 0.0);
  // GIVEN one point lost and unknown depths (the desired depths stand in)
  s.segment<2>(2).setConstant(std::numeric_limits<double>::quiet_NaN());
  const Eigen::VectorXd Z = Eigen::VectorXd::Constant(4, std::numeric_limits<double>::quiet_NaN());
  const Eigen::VectorXd u1 = tick(task, 0.0, s, Z, Eigen::MatrixXd::Identity(6, 6));
  // THEN the command is finite, nonzero, and the lost point's rows are left out
  EXPECT_TRUE(u1.allFinite());
  EXPECT_GT(u1.norm(), 0.0);
  EXPECT_EQ(task.featureJacobian().middleRows<2>(2).norm(), 0.0);
  EXPECT_EQ(task.slidingVariable().segment<2>(2).norm(), 0.0);
  // GIVEN an x-y stage whose second axis is almost parallel to the first (condition ~1e8)
  XyStage plant;
  VscTask stage(Params{}, makeContext(desiredOffCentre(), one(plant.Z_m), xyStageSpace()));
  const Eigen::VectorXd u_good = tick(stage, 0.0, plant.features(), one(plant.Z_m), plant.robot_jacobian);
  Eigen::MatrixXd near_singular = Eigen::MatrixXd::Zero(6, 2);
  near_singular(0, 0) = 1.0;
  near_singular(0, 1) = 1.0;
  near_singular(1, 1) = 1e-8;
  const Eigen::VectorXd u_damped = tick(stage, 0.0, plant.features(), one(plant.Z_m), near_singular);
  // THEN the damped inverse keeps the command of the order of the well-posed one (an exact
  // inverse would ask ~1e8 times more along the weak direction)
  EXPECT_TRUE(u_damped.allFinite());
  EXPECT_LT(u_damped.norm(), 10.0 * u_good.norm()) << u_damped.transpose();
  // GIVEN every point lost: zero command
  const Eigen::VectorXd lost = Eigen::VectorXd::Constant(8, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(tick(task, 0.0, lost, Z, Eigen::MatrixXd::Identity(6, 6)).norm(), 0.0);
}

TEST(VscTask, DiagnosticsAndSummaryNames) {
  XyStage plant;
  VscTask task(Params{}, makeContext(desiredOffCentre(), one(plant.Z_m), xyStageSpace()));
  // GIVEN no tick yet THEN the summary is NaN
  EXPECT_TRUE(std::isnan(task.runSummary().at(0).second));
  EXPECT_EQ(task.runSummary().at(0).first, "sliding_rms_final");
  // WHEN one tick runs at e = (510 - 620, 160 - 240)
  tick(task, 0.0, plant.features(), one(plant.Z_m), plant.robot_jacobian);
  const NamedValues d = task.diagnostics();
  ASSERT_EQ(d.size(), 4u);
  EXPECT_EQ(d[0].first, "sliding_norm");
  EXPECT_EQ(d[1].first, "s_u");
  EXPECT_EQ(d[2].first, "s_v");
  EXPECT_EQ(d[3].first, "gain_q");
  // THEN |S|, S and q follow the definitions (q = 1 + 3 / (1 + (|S| / 50)^2))
  const double norm = std::hypot(110.0, 80.0);
  EXPECT_NEAR(d[0].second, norm, 1e-9);
  EXPECT_NEAR(d[1].second, -110.0, 1e-9);
  EXPECT_NEAR(d[2].second, -80.0, 1e-9);
  EXPECT_NEAR(d[3].second, 1.0 + 3.0 / (1.0 + (norm / 50.0) * (norm / 50.0)), 1e-12);
  EXPECT_EQ(task.name(), "vsc");
}

void expectRejected(const Params& p, const std::string& key, CommandSpace space = xyStageSpace(),
                    double period_s = kPeriod_s) {
  TaskContext c = makeContext(desiredOffCentre(), one(0.5), std::move(space));
  c.base_period_s = period_s;
  try {
    VscTask task(p, c);
    ADD_FAILURE() << "accepted; expected an error naming " << key;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(VscTask, RejectsBadParameters) {
  expectRejected({{"q_near", 0.0}}, "q_near");
  expectRejected({{"q_near", 30.0}}, "q_near");            // (30 + 2) * 0.04 > 1
  expectRejected({{"eps_s", 30.0}, {"phi", 1.0}}, "eps_s");  // (4 + 30) * 0.04 > 1
  expectRejected({{"phi", 0.0}}, "phi");
  expectRejected({{"q_far", 5.0}}, "q_far");  // larger than q_near: not the paper's schedule
  expectRejected({{"eps_s", -1.0}}, "eps_s");
  expectRejected({{"s_half", -1.0}}, "s_half");
  expectRejected({{"c_v", 0.0}}, "c_v");
  expectRejected({{"rcond", 0.0}}, "rcond");
  expectRejected({}, "q_near", xyStageSpace(), 0.2);  // defaults too fast for T = 0.2 s
  expectRejected({}, "base_period_s", xyStageSpace(), 0.0);
  expectRejected({}, "command space", CommandSpace{});
}

TEST(VscTask, QFarDefaultFollowsALowQNear) {
  // GIVEN q_near below the default q_far (1 /s) and no q_far
  const TaskContext c = makeContext(desiredOffCentre(), one(0.5), xyStageSpace());
  // WHEN the law is built THEN it is accepted as a constant gain (q_far = q_near), not rejected for
  // a q_far the user never wrote
  const VscTask task(Params{{"q_near", 0.8}}, c);
  EXPECT_DOUBLE_EQ(task.config().q_far_per_s, 0.8);
  EXPECT_DOUBLE_EQ(task.config().gain(1e3), 0.8);
  // AND a q_far given above q_near is an error that names both keys and their values
  try {
    VscTask bad(Params{{"q_near", 0.8}, {"q_far", 2.0}}, c);
    ADD_FAILURE() << "accepted q_far > q_near";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("q_far = 2"), std::string::npos) << what;
    EXPECT_NE(what.find("q_near = 0.8"), std::string::npos) << what;
  }
}

TEST(VscTask, RejectsUnknownParameter) { expectRejected({{"lambda", 1.0}}, "unknown parameter 'lambda'"); }

}  // namespace
}  // namespace predvs
