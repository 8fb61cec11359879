// Trajectories: values at known instants and velocities against finite differences.
#include "predvs/servo/trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

constexpr double kValueTol = 1e-9;  // closed forms evaluated in double precision
// Central difference with step 1e-5 s: truncation ~ h^2 |p'''| / 6 (< 1e-8 here) plus rounding
// ~ eps |p| / h (< 1e-8 for |p| < 1e3).
constexpr double kFdStep = 1e-5;
constexpr double kFdTol = 1e-6;

TEST(Trajectory, PaperDefaults) {
  // GIVEN the default parameters (paper 000 §6.1–6.2)
  const auto line = makeTrajectory("line");
  const auto jump = makeTrajectory("accel-jump");
  const auto zig = makeTrajectory("zigzag");
  const auto circle = makeTrajectory("circle");
  // THEN E1 moves at (10, 10) per s from the origin
  EXPECT_NEAR(line->position(3.0).x(), 30.0, kValueTol);
  EXPECT_NEAR(line->velocity(3.0).y(), 10.0, kValueTol);
  // E2: v0 = 20, a = 1 until 14 s, then a = 30 with continuous velocity
  EXPECT_NEAR(jump->velocity(13.999).x(), 20.0 + 13.999, 1e-9);
  EXPECT_NEAR(jump->velocity(15.0).x(), 34.0 + 30.0, kValueTol);
  EXPECT_NEAR(jump->position(14.0).x(), 20.0 * 14 + 0.5 * 14 * 14, kValueTol);
  // E3: v_y = 10 until 9 s, then -10; v_x = 1
  EXPECT_NEAR(zig->position(9.0).y(), 90.0, kValueTol);
  EXPECT_NEAR(zig->position(12.0).y(), 60.0, kValueTol);
  EXPECT_NEAR(zig->velocity(12.0).y(), -10.0, kValueTol);
  // E4: radius 20, 0.15 rad/s
  EXPECT_NEAR(circle->position(0.0).x(), 20.0, kValueTol);
  EXPECT_NEAR(circle->velocity(5.0).norm(), 3.0, kValueTol);
}

TEST(Trajectory, PeriodicZigzagIsATriangle) {
  const auto zig = makeTrajectory("zigzag", Params{{"periodic", 1}, {"t_switch", 2}, {"vy", 5}});
  EXPECT_NEAR(zig->position(2.0).y(), 10.0, kValueTol);
  EXPECT_NEAR(zig->position(4.0).y(), 0.0, kValueTol);
  EXPECT_NEAR(zig->position(5.0).y(), 5.0, kValueTol);
  EXPECT_NEAR(zig->velocity(5.0).y(), 5.0, kValueTol);
  EXPECT_NEAR(zig->velocity(3.0).y(), -5.0, kValueTol);
}

TEST(Trajectory, SinusoidPerAxis) {
  const auto s = makeTrajectory("sinusoid", Params{{"amp_x", 2}, {"freq_x", 0.25}, {"amp_y", 3}, {"phase_y", M_PI / 2}});
  EXPECT_NEAR(s->position(1.0).x(), 2.0, kValueTol);  // sin(pi/2)
  EXPECT_NEAR(s->position(0.0).y(), 3.0, kValueTol);  // sin(pi/2)
}

class TrajectoryFiniteDifference : public ::testing::TestWithParam<std::string> {};

TEST_P(TrajectoryFiniteDifference, VelocityIsTheDerivativeOfPosition) {
  // GIVEN each trajectory with its default parameters
  const auto traj = makeTrajectory(GetParam());
  // WHEN differentiating numerically away from switching instants (9, 14 s)
  for (double t : {0.3, 2.7, 8.1, 11.3, 16.9, 23.4}) {
    const Eigen::Vector2d fd = (traj->position(t + kFdStep) - traj->position(t - kFdStep)) / (2 * kFdStep);
    // THEN it matches velocity()
    EXPECT_NEAR((fd - traj->velocity(t)).norm(), 0.0, kFdTol) << GetParam() << " at t = " << t;
  }
}

INSTANTIATE_TEST_SUITE_P(All, TrajectoryFiniteDifference, ::testing::ValuesIn(trajectoryNames()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

TEST(Trajectory, RejectsUnknownNamesAndKeys) {
  EXPECT_THROW(makeTrajectory("spiral"), std::invalid_argument);
  try {
    makeTrajectory("circle", Params{{"radious", 3}});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("radious"), std::string::npos) << e.what();
  }
  EXPECT_THROW(makeTrajectory("circle", Params{{"radius", -1}}), std::invalid_argument);
  EXPECT_THROW(makeTrajectory("zigzag", Params{{"t_switch", 0}}), std::invalid_argument);
}

TEST(Trajectory, ManoeuvresOfThePaperMotions) {
  // E1: the start along v; E2: the jump along a_jump - a; E3: the switch along -v_y
  const Manoeuvre line = makeTrajectory("line")->manoeuvre();
  ASSERT_TRUE(line.exists());
  EXPECT_EQ(line.t_s, 0.0);
  EXPECT_NEAR(line.direction(0), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(line.direction(1), std::sqrt(0.5), 1e-15);
  const Manoeuvre jump = makeTrajectory("accel-jump", Params{{"ax_jump", 1}, {"ay_jump", 5}})->manoeuvre();
  ASSERT_TRUE(jump.exists());
  EXPECT_EQ(jump.t_s, 14.0);
  EXPECT_NEAR(jump.direction(0), 0.0, 1e-15);
  EXPECT_NEAR(jump.direction(1), 1.0, 1e-15);
  const Manoeuvre zig = makeTrajectory("zigzag")->manoeuvre();
  ASSERT_TRUE(zig.exists());
  EXPECT_EQ(zig.t_s, 9.0);
  EXPECT_NEAR(zig.direction(1), -1.0, 1e-15);
  // no fixed direction on turning motions, none when nothing changes
  EXPECT_FALSE(makeTrajectory("circle")->manoeuvre().exists());
  EXPECT_FALSE(makeTrajectory("sinusoid")->manoeuvre().exists());
  EXPECT_FALSE(makeTrajectory("static")->manoeuvre().exists());
  EXPECT_FALSE(makeTrajectory("line", Params{{"vx", 0}, {"vy", 0}})->manoeuvre().exists());
}

}  // namespace
}  // namespace predvs
