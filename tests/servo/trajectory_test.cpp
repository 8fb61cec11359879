// Trajectories: values at known instants and velocities against finite differences.
#include "predvs/servo/trajectory.h"

#include <gtest/gtest.h>

#include <algorithm>
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


// E8 (paper 001 eq. 44 in the plane, metres by default).
constexpr double kPi = 3.14159265358979323846;

TEST(E8Target, VelocityIsTheDerivativeOfPositionOverTheWholeRun) {
  // GIVEN the default e8-target (0.15 m/s, speed period 40 s, turning 5 pi / 72 rad/s)
  const auto traj = makeTrajectory("e8-target");
  // WHEN its closed-form position is differentiated numerically every 0.37 s over 40 s (through
  // the speed reversal at 10 s and 30 s)
  for (double t = 0.0; t <= 40.0; t += 0.37) {
    const Eigen::Vector2d fd = (traj->position(t + kFdStep) - traj->position(t - kFdStep)) / (2 * kFdStep);
    // THEN it matches velocity() (positions of about 1 m: the FD tolerance above holds)
    EXPECT_NEAR((fd - traj->velocity(t)).norm(), 0.0, kFdTol) << "t = " << t;
  }
  // AND the closed form also holds where the two phase rates b -+ a meet (b = a: E(0, t) = t)
  const auto equal = makeTrajectory("e8-target", Params{{"speed_omega", 0.3}, {"turn_rate", 0.3}});
  for (double t : {0.5, 4.0, 9.5}) {
    const Eigen::Vector2d fd = (equal->position(t + kFdStep) - equal->position(t - kFdStep)) / (2 * kFdStep);
    EXPECT_NEAR((fd - equal->velocity(t)).norm(), 0.0, kFdTol) << "t = " << t;
  }
}

TEST(E8Target, HeadsAlongPlusXAndTurnsLeftAsThePapersTarget) {
  const auto traj = makeTrajectory("e8-target");
  // GIVEN t = 0 THEN it starts at the origin moving along +x (away from a robot at the origin
  // looking along +x) at v0 = 0.15 m/s
  EXPECT_NEAR(traj->position(0.0).norm(), 0.0, kValueTol);
  EXPECT_NEAR(traj->velocity(0.0).x(), 0.15, kValueTol);
  EXPECT_NEAR(traj->velocity(0.0).y(), 0.0, kValueTol);
  // AND the heading turns counter-clockwise (to the robot's left, +y) at 5 pi / 72 rad/s while the
  // speed is v0 cos(pi t / 20): the velocity is the paper's (v sin th, 0, v cos th) in its frame
  // x left, y up, z forward, i.e. (x, y)_world = (z, x)_paper
  for (double t : {0.0, 1.0, 3.3, 7.2, 12.5, 19.9}) {
    const double v = 0.15 * std::cos(kPi * t / 20.0), th = 5.0 * kPi / 72.0 * t;
    const Eigen::Vector3d paper(v * std::sin(th), 0.0, v * std::cos(th));  // (x left, y up, z forward)
    EXPECT_NEAR(traj->velocity(t).x(), paper.z(), kValueTol) << "t = " << t;
    EXPECT_NEAR(traj->velocity(t).y(), paper.x(), kValueTol) << "t = " << t;
  }
  const Eigen::Vector2d v0 = traj->velocity(0.0), v2 = traj->velocity(2.0);
  EXPECT_GT(v0.x() * v2.y() - v0.y() * v2.x(), 0.0);  // z of v(0) x v(2): a left turn
  EXPECT_GT(traj->position(5.0).y(), 0.2);            // measured 0.32 m to the left after 5 s
  // AND it stops at 10 s and comes back (the speed is negative from 10 s to 30 s)
  EXPECT_NEAR(traj->velocity(10.0).norm(), 0.0, kValueTol);
  const double heading_12s = 5.0 * kPi / 72.0 * 12.0;
  EXPECT_LT(traj->velocity(12.0).dot(Eigen::Vector2d(std::cos(heading_12s), std::sin(heading_12s))), 0.0);
}

TEST(E8Target, TheExactIntegralAgreesWithThePapersEulerRecursion) {
  // GIVEN the paper's discrete model: v(n) = v0 cos(n pi T / 20), th(n) = n T 5 pi / 72 and
  // P(n) = P(n-1) + T V(n-1), T = 0.1 s
  const auto traj = makeTrajectory("e8-target", Params{{"x0", 1.349}, {"y0", 0.0}});
  const double T = 0.1;
  Eigen::Vector2d P(1.349, 0.0);
  double worst = 0.0;
  for (int n = 0; n <= 200; ++n) {
    worst = std::max(worst, (traj->position(n * T) - P).norm());
    const double v = 0.15 * std::cos(n * kPi * T / 20.0), th = n * T * 5.0 * kPi / 72.0;
    P += T * v * Eigen::Vector2d(std::cos(th), std::sin(th));
  }
  // THEN over 20 s the Euler samples stay within a centimetre of the exact curve (measured
  // 8.6 mm: the recursion uses V(n-1) over [(n-1) T, n T], about half a frame of travel, v0 T / 2 =
  // 7.5 mm, behind, plus the drift of that lag on the turn), and they are not identical
  constexpr double kEulerGap_m = 0.01;
  EXPECT_LT(worst, kEulerGap_m);
  EXPECT_GT(worst, 0.1 * kEulerGap_m);
}

TEST(E8Target, RejectsNonFiniteAndUnknownKeys) {
  EXPECT_THROW(makeTrajectory("e8-target", Params{{"turn", 1}}), std::invalid_argument);
  EXPECT_THROW(makeTrajectory("e8-target", Params{{"v0", std::nan("")}}), std::invalid_argument);
}

}  // namespace
}  // namespace predvs
