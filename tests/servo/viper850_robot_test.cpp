// Robot "viper850": kinematics against ViSP's vpViper850, the Jacobian against finite differences
// of the pose, reset, joint limits, the velocity limit and the parameters.
#include "predvs/servo/viper850_robot.h"
#include "servo/visp_test_utils.h"

#include <visp3/core/vpExponentialMap.h>
#include <visp3/core/vpVelocityTwistMatrix.h>
#include <visp3/robot/vpRobot.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

using Joints = Viper850Robot::Joints;

constexpr double kSameCodeTol = 1e-12;     // the same ViSP functions evaluated twice
constexpr double kFiniteDiffRelTol = 1e-6; // central difference, h = 1e-5 s: O(h^2) truncation
constexpr double kLimitTol = 1e-12;        // scaling a vector by a ratio of its own entries

Params jointParams(const Joints& q0) {
  Params p;
  for (int i = 0; i < 6; ++i) p.set("q0_" + std::to_string(i + 1), q0(i));
  return p;
}

/// Random joint positions at least `margin` rad inside vpViper850's limits (seeded).
Joints randomJoints(std::mt19937& rng, double margin = 0.3) {
  const Viper850Robot reference;
  Joints q;
  for (int i = 0; i < 6; ++i) {
    std::uniform_real_distribution<double> u(reference.jointMin()(i) + margin, reference.jointMax()(i) - margin);
    q(i) = u(rng);
  }
  return q;
}

/// An arbitrary camera pose in the world: 1 m above the x-y plane, tilted.
vpHomogeneousMatrix someCameraPose() { return vpHomogeneousMatrix(0.3, -0.2, 1.0, 2.9, 0.4, -0.7); }

/// An independent ViSP model with the same tool as the robot.
vpViper850 vispModel() {
  vpViper850 v;
  v.init(vpViper850::TOOL_PTGREY_FLEA2_CAMERA, vpCameraParameters::perspectiveProjWithoutDistortion);
  return v;
}

TEST(Viper850Robot, DefaultsAreViSPsRestPositionAndWellConditioned) {
  // GIVEN the robot with default parameters
  const Viper850Robot robot;
  // THEN it is in joint-velocity control at vpSimulatorViper850's rest position
  EXPECT_EQ(robot.name(), "viper850");
  EXPECT_EQ(robot.commandSpace().kind, "joint-velocity");
  ASSERT_EQ(robot.commandSpace().size(), 6);
  EXPECT_EQ(robot.commandSpace().names.front(), "qdot1_radps");
  EXPECT_EQ(robot.stateNames().back(), "q6");
  const Joints q0 = (Joints() << 0.0, -M_PI / 2, M_PI, 0.0, M_PI / 2, 0.0).finished();
  EXPECT_NEAR((robot.jointPositions() - q0).norm(), 0.0, kSameCodeTol);
  EXPECT_TRUE((robot.maxJointSpeeds().array() == 0.7).all());
  // AND the camera Jacobian there is far from singular (condition number ~9.4)
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(robot.cameraJacobian());
  const double condition = svd.singularValues()(0) / svd.singularValues()(5);
  EXPECT_LT(condition, 20.0);
  // AND every joint is at least 0.5 rad from its limits
  EXPECT_GT((q0 - robot.jointMin()).minCoeff(), 0.5);
  EXPECT_GT((robot.jointMax() - q0).minCoeff(), 0.5);
}

TEST(Viper850Robot, PoseAndJacobianMatchViSPsViper850) {
  std::mt19937 rng(850);
  const vpViper850 viper = vispModel();
  vpVelocityTwistMatrix cVe;
  viper.get_cVe(cVe);
  for (int trial = 0; trial < 20; ++trial) {
    // GIVEN the arm started at a random configuration and stepped once
    const Joints q0 = randomJoints(rng);
    Viper850Robot robot(jointParams(q0));
    robot.reset(someCameraPose());
    const Eigen::VectorXd qdot = (Eigen::VectorXd(6) << 0.1, -0.2, 0.3, -0.1, 0.2, 0.4).finished();
    robot.step(qdot, 0.04);
    // WHEN the kinematics are evaluated by ViSP at the integrated joints
    const Joints q = q0 + 0.04 * qdot;
    ASSERT_NEAR((robot.jointPositions() - q).norm(), 0.0, kSameCodeTol);
    vpHomogeneousMatrix fMc;
    viper.get_fMc(toVisp(q), fMc);
    vpMatrix eJe;
    viper.get_eJe(toVisp(q), eJe);
    const vpMatrix J = cVe * eJe;
    // THEN the pose is wMf fMc(q) and the Jacobian cVe eJe(q)
    EXPECT_LT(maxAbsDiff(robot.cameraPose(), robot.baseInWorld() * fMc), kSameCodeTol) << "trial " << trial;
    const Eigen::MatrixXd Jr = robot.cameraJacobian();
    for (unsigned r = 0; r < 6; ++r)
      for (unsigned c = 0; c < 6; ++c) EXPECT_NEAR(Jr(r, c), J[r][c], kSameCodeTol);
  }
}

TEST(Viper850Robot, JacobianMatchesFiniteDifferenceOfPose) {
  std::mt19937 rng(6);
  std::normal_distribution<double> n(0.0, 0.3);
  constexpr double h = 1e-5;
  for (int trial = 0; trial < 20; ++trial) {
    // GIVEN a random configuration and a random joint velocity
    const Joints q0 = randomJoints(rng);
    Eigen::VectorXd qdot(6);
    for (int i = 0; i < 6; ++i) qdot(i) = n(rng);
    Viper850Robot before(jointParams(q0)), after(jointParams(q0));
    before.reset(someCameraPose());
    after.reset(someCameraPose());
    const Viper850Robot middle = after;
    // WHEN the arm moves from q0 - qdot h to q0 + qdot h
    before.step(-qdot, h);
    after.step(qdot, h);
    // THEN the camera twist of that motion (camera frame) is J(q0) qdot
    const vpHomogeneousMatrix cMc = before.cameraPose().inverse() * after.cameraPose();
    const vpColVector twist = vpExponentialMap::inverse(cMc, 2.0 * h);
    Eigen::VectorXd fd(6);
    for (int i = 0; i < 6; ++i) fd(i) = twist[static_cast<unsigned>(i)];
    const Eigen::VectorXd analytic = middle.cameraJacobian() * qdot;
    EXPECT_LT((fd - analytic).norm() / analytic.norm(), kFiniteDiffRelTol) << "trial " << trial;
  }
}

TEST(Viper850Robot, ResetPutsTheCameraExactlyAtTheRequestedPose) {
  // GIVEN an arm that has moved
  Viper850Robot robot;
  robot.step(Eigen::VectorXd::Constant(6, 0.3), 0.5);
  // WHEN reset to a camera pose
  const vpHomogeneousMatrix wMc = someCameraPose();
  robot.reset(wMc);
  // THEN the camera is there, the joints are at q0, and the base is placed consistently
  EXPECT_EQ(maxAbsDiff(robot.cameraPose(), wMc), 0.0);
  EXPECT_EQ(robot.jointPositions(), robot.initialJointPositions());
  vpHomogeneousMatrix fMc;
  vispModel().get_fMc(toVisp(robot.initialJointPositions()), fMc);
  EXPECT_LT(maxAbsDiff(robot.baseInWorld() * fMc, wMc), kSameCodeTol);
  // AND a zero command leaves it there
  robot.step(Eigen::VectorXd::Zero(6), 0.1);
  EXPECT_LT(maxAbsDiff(robot.cameraPose(), wMc), kSameCodeTol);
}

TEST(Viper850Robot, JointLimitStopsTheJointOnly) {
  // GIVEN the arm at rest position (joint 5 at pi/2, its limit at 120 deg)
  Viper850Robot robot;
  const Joints q0 = robot.jointPositions();
  // WHEN joint 5 is driven up for long enough to pass its limit while joint 1 turns slowly
  const Eigen::VectorXd qdot = (Eigen::VectorXd(6) << 0.1, 0, 0, 0, 0.7, 0).finished();
  for (int k = 0; k < 25; ++k) robot.step(qdot, 0.04);
  // THEN joint 5 stops exactly at its limit and joint 1 moves on
  EXPECT_EQ(robot.jointPositions()(4), robot.jointMax()(4));
  EXPECT_NEAR(robot.jointPositions()(0), q0(0) + 0.1, 1e-12);
  // AND driving it back moves it off the limit
  robot.step(-qdot, 0.04);
  EXPECT_NEAR(robot.jointPositions()(4), robot.jointMax()(4) - 0.7 * 0.04, 1e-12);
  // AND the lower limit holds as well
  robot.step(-qdot, 10.0);
  EXPECT_EQ(robot.jointPositions()(4), robot.jointMin()(4));
}

TEST(Viper850Robot, LimitDropsTheComponentPushingAJointAgainstItsLimit) {
  // GIVEN the arm with joint 5 driven onto its upper limit and joint 2 onto its lower one
  Viper850Robot robot;
  robot.step((Eigen::VectorXd(6) << 0, 0, 0, 0, 0.7, 0).finished(), 10.0);
  robot.step((Eigen::VectorXd(6) << 0, -0.7, 0, 0, 0, 0).finished(), 10.0);
  ASSERT_EQ(robot.jointPositions()(4), robot.jointMax()(4));
  ASSERT_EQ(robot.jointPositions()(1), robot.jointMin()(1));
  // WHEN a command pushes both further while the other joints move
  const Eigen::VectorXd u = (Eigen::VectorXd(6) << 0.1, -0.3, 0.2, -0.1, 0.5, 0.05).finished();
  const Eigen::VectorXd l = robot.limit(u);
  // THEN those two components are dropped and the others pass unchanged (all within the bounds)
  const Eigen::VectorXd expected = (Eigen::VectorXd(6) << 0.1, 0.0, 0.2, -0.1, 0.0, 0.05).finished();
  EXPECT_EQ(l, expected);
  // AND the limited command is exactly the motion the arm makes, so that its integral (the loop's
  // command integral p) stays equal to the joint displacement
  const Joints before = robot.jointPositions();
  robot.step(l, 0.1);
  EXPECT_LT((robot.jointPositions() - before - 0.1 * l).norm(), kSameCodeTol);
  // AND a command pulling the joints off their limits is executed in full
  const Eigen::VectorXd back = (Eigen::VectorXd(6) << 0, 0.3, 0, 0, -0.5, 0).finished();
  EXPECT_EQ(robot.limit(back), back);
  // AND the speed scaling applies to what is left: the 1.4 rad/s of joint 1 is halved, the
  // dropped joint 5 does not count
  const Eigen::VectorXd fast = (Eigen::VectorXd(6) << 1.4, 0, 0, 0, 3.0, 0).finished();
  robot.reset(someCameraPose());
  robot.step((Eigen::VectorXd(6) << 0, 0, 0, 0, 0.7, 0).finished(), 10.0);
  EXPECT_LT((robot.limit(fast) - (Eigen::VectorXd(6) << 0.7, 0, 0, 0, 0, 0).finished()).norm(), kLimitTol);
}

TEST(Viper850Robot, LimitKeepsTheDirectionAndRespectsEachBound) {
  // GIVEN per-joint bounds that differ
  Params p;
  const Joints bound = (Joints() << 0.5, 0.6, 0.7, 0.8, 0.9, 1.5).finished();
  for (int i = 0; i < 6; ++i) p.set("max_qdot_" + std::to_string(i + 1), bound(i));
  const Viper850Robot robot(p);
  std::mt19937 rng(42);
  std::normal_distribution<double> n(0.0, 1.5);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::VectorXd u(6);
    for (int i = 0; i < 6; ++i) u(i) = n(rng);
    // WHEN a command is limited
    const Eigen::VectorXd l = robot.limit(u);
    // THEN it is u scaled by s in (0, 1], within every bound, on a bound when it had to shrink
    const double s = l.norm() / u.norm();
    EXPECT_GT(s, 0.0);
    EXPECT_LE(s, 1.0);
    EXPECT_LT((l - s * u).norm(), kLimitTol * u.norm());
    EXPECT_TRUE((l.cwiseAbs().array() <= bound.array() + kLimitTol).all());
    const bool exceeded = (u.cwiseAbs().array() > bound.array()).any();
    if (exceeded) {
      EXPECT_NEAR((bound.array() - l.cwiseAbs().array()).minCoeff(), 0.0, kLimitTol);
    } else {
      EXPECT_EQ(l, u);
    }
    // AND it is exactly what ViSP's vpRobot::saturateVelocities gives
    const vpColVector v = vpRobot::saturateVelocities(toVisp(u), toVisp(bound));
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(l(i), v[static_cast<unsigned>(i)], kLimitTol);
  }
}

TEST(Viper850Robot, SaturationOffExecutesAnySpeedButKeepsTheJointLimits) {
  // GIVEN the arm with `saturation: 0` and the default one
  const Viper850Robot free_arm(Params{{"saturation", 0.0}});
  const Viper850Robot bounded;
  EXPECT_FALSE(free_arm.saturation());
  EXPECT_TRUE(bounded.saturation());
  // WHEN a command 10 times over the 0.7 rad/s bound is limited
  const Eigen::VectorXd fast = (Eigen::VectorXd(6) << 7.0, -3.0, 0.5, 0.0, 2.0, -1.0).finished();
  // THEN without saturation it is executed as it is, with saturation scaled down to the bound
  EXPECT_EQ(free_arm.limit(fast), fast);
  EXPECT_NEAR(bounded.limit(fast).cwiseAbs().maxCoeff(), 0.7, kLimitTol);
  // AND without saturation the arm moves at that speed
  Viper850Robot arm(Params{{"saturation", 0.0}});
  const Joints q0 = arm.jointPositions();
  arm.step(arm.limit(fast), 0.01);
  EXPECT_LT((arm.jointPositions() - q0 - 0.01 * Joints(fast)).norm(), kSameCodeTol);
  // AND a joint against its limit still does not take a command pushing it further
  arm.step((Eigen::VectorXd(6) << 0, 0, 0, 0, 5.0, 0).finished(), 10.0);
  ASSERT_EQ(arm.jointPositions()(4), arm.jointMax()(4));
  EXPECT_EQ(arm.limit(fast)(4), 0.0);
  EXPECT_EQ(arm.limit(fast)(0), 7.0);
}

TEST(Viper850Robot, AtLimitWhileAJointRestsOnItsStop) {
  // GIVEN the arm at its rest position, inside every limit
  Viper850Robot robot;
  EXPECT_FALSE(robot.atLimit());
  // WHEN joint 5 is driven onto its upper limit THEN it is at a limit
  robot.step((Eigen::VectorXd(6) << 0, 0, 0, 0, 0.7, 0).finished(), 10.0);
  EXPECT_TRUE(robot.atLimit());
  // AND driving it back clears it
  robot.step((Eigen::VectorXd(6) << 0, 0, 0, 0, -0.7, 0).finished(), 0.04);
  EXPECT_FALSE(robot.atLimit());
  // AND a start on a lower limit is at a limit from the start
  EXPECT_TRUE(Viper850Robot(Params{{"q0_2", robot.jointMin()(1)}}).atLimit());
}

TEST(Viper850Robot, FaultyCommandHoldsStill) {
  // GIVEN a command with a NaN
  Viper850Robot robot;
  const Joints q0 = robot.jointPositions();
  Eigen::VectorXd u = Eigen::VectorXd::Constant(6, 0.1);
  u(2) = std::numeric_limits<double>::quiet_NaN();
  // WHEN limited and executed
  // THEN the limited command is zero and the arm does not move
  EXPECT_EQ(robot.limit(u), Eigen::VectorXd::Zero(6));
  robot.step(u, 0.04);
  EXPECT_EQ(robot.jointPositions(), q0);
  // AND a wrongly sized command or a negative period is a programming error
  EXPECT_THROW(robot.step(Eigen::VectorXd::Zero(5), 0.04), std::invalid_argument);
  EXPECT_THROW(robot.limit(Eigen::VectorXd::Zero(7)), std::invalid_argument);
  EXPECT_THROW(robot.step(Eigen::VectorXd::Zero(6), -0.04), std::invalid_argument);
}

void expectRejected(const Params& p, const std::string& key) {
  try {
    Viper850Robot robot(p);
    ADD_FAILURE() << "accepted bad parameter " << key;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(Viper850Robot, BadParametersAreRejectedNamingTheKey) {
  // GIVEN a misspelt key, a start outside the joint limits, a zero speed bound
  // THEN each is rejected with the key in the message
  expectRejected(Params{{"q0_7", 0.0}}, "q0_7");
  expectRejected(Params{{"max_qdot", 1.0}}, "max_qdot");
  expectRejected(Params{{"q0_2", 1.0}}, "q0_2");  // joint 2 max is 45 deg
  expectRejected(Params{{"max_qdot_3", 0.0}}, "max_qdot_3");
  expectRejected(Params{{"saturation", 2.0}}, "saturation");
  // AND good keys are taken
  const Viper850Robot robot(Params{{"q0_1", 0.2}, {"max_qdot_6", 2.0}});
  EXPECT_EQ(robot.jointPositions()(0), 0.2);
  EXPECT_EQ(robot.maxJointSpeeds()(5), 2.0);
}

}  // namespace
}  // namespace predvs
