// The Viper850 arm in the closed loop (docs/MODELS.md §10 E9; paper 002 §3): classic `ibvs` (vpServo
// through the arm's camera Jacobian cVe eJe(q)) and the uncalibrated `ibvs-broyden` drive the real
// ServoLoop to a static target; the camera the loop scores is where ViSP's own kinematic model
// (vpViper850, placed by the base pose) puts it; the online Jacobian learnt by exploration on the
// arm matches the true interaction matrix L cVe eJe(q). Set-up of the E9 scenarios
// (data/scenarios/e9-*.yaml): T = delta = 0.1 s, 2-frame vision delay, 10 cm square at 0.5 m,
// the camera 2 cm / 1 cm off, 5 cm back and turned 0.1 rad; no noise unless a test says so.
#include "predvs/predictors/registry.h"
#include "predvs/servo/servo_loop.h"
#include "predvs/servo/viper850_robot.h"
#include "predvs/tasks/point_task.h"
#include "servo/visp_test_utils.h"

#include <visp3/robot/vpViper850.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace predvs {
namespace {

constexpr double kPeriod = 0.1;  // delta = T (E9)

/// The E9 loop with a static target (no noise by default), driven by `task` on the arm.
ServoConfig armConfig(const std::string& task, const Params& task_params, double duration_s) {
  ServoConfig c;
  c.timing.base_period_s = kPeriod;
  c.timing.frame_period_n = 1;
  c.timing.acquisition_lag_s = kPeriod;  // vision latency t_ac + t_p = 2 T
  c.timing.processing_lag_s = kPeriod;
  c.duration_s = duration_s;
  c.seed = 900;
  c.scene.trajectory = "static";
  c.scene.trajectory_params = Params{};
  c.initial_pose = (Pose6() << 0.02, -0.01, -0.05, 0.0, 0.0, 0.1).finished();
  c.noise.kind = NoiseKind::None;
  c.task = {task, task_params};
  c.robot = {"viper850", {}};
  c.forecast = ForecastMode::Both;
  return c;
}

/// Column index of `name` in the loop's trace columns (-1 when absent).
int column(const ServoLoop& loop, const std::string& name) {
  const std::vector<std::string> c = loop.traceColumns();
  for (size_t i = 0; i < c.size(); ++i)
    if (c[i] == name) return static_cast<int>(i);
  return -1;
}

// Round-off of the same kinematics evaluated along two paths (ViSP's fMc(q) against the robot's
// incrementally updated pose): a few ulps of entries of order 1.
constexpr double kKinematicsTol = 1e-12;
// Projection of points 0.5 m away by two round-off-level different poses: 800 px * 1e-12 / 0.5.
constexpr double kProjectionTolPx = 1e-8;

TEST(E9ArmLoop, ClassicIbvsOnViper850ConvergesAndTheCameraFollowsViSPsKinematics) {
  // GIVEN classic ibvs (lambda 1 /s, current interaction matrix) on the arm, static target, no noise
  const ServoConfig c = armConfig("ibvs", Params{{"lambda", 1.0}}, 20.0);
  auto hold = makePredictor("hold", 8);
  ServoLoop loop(c, *hold);
  const auto& arm = dynamic_cast<const Viper850Robot&>(loop.robot());
  // AND an independent ViSP model of the arm, placed as the loop places it: the base wMf such that
  // the camera is at the initial pose with the joints at q0
  vpViper850 viper;
  viper.init(vpViper850::TOOL_PTGREY_FLEA2_CAMERA, vpCameraParameters::perspectiveProjWithoutDistortion);
  const Scene scene(c.scene);
  const vpHomogeneousMatrix wMc0 = scene.desiredCameraPose() * poseMatrix(c.initial_pose);
  vpHomogeneousMatrix fMc0;
  viper.get_fMc(toVisp(arm.initialJointPositions()), fMc0);
  const vpHomogeneousMatrix wMf = wMc0 * fMc0.inverse();
  EXPECT_LT(maxAbsDiff(arm.baseInWorld(), wMf), kKinematicsTol);
  // WHEN the loop runs
  const int first_command = column(loop, "qdot1_radps");
  ASSERT_GE(first_command, 0);
  Eigen::VectorXd q_integrated = arm.initialJointPositions();
  double start_error = -1.0;
  while (!loop.done()) {
    // THEN at every tick the camera the loop projects the target with is wMf fMc(q) of ViSP's
    // model at the arm's joint positions, and the true features it scores are that camera's view
    const Eigen::VectorXd q = arm.state();
    vpHomogeneousMatrix fMc;
    viper.get_fMc(toVisp(q), fMc);
    const vpHomogeneousMatrix wMc = wMf * fMc;
    ASSERT_LT(maxAbsDiff(arm.cameraPose(), wMc), kKinematicsTol);
    const ServoSample& s = loop.step();
    const PointFeatures seen = scene.project(s.t_s, wMc, c.camera);
    ASSERT_LT((s.truth - seen.uv_px).cwiseAbs().maxCoeff(), kProjectionTolPx) << "t = " << s.t_s;
    if (start_error < 0.0) start_error = s.error;
    // AND the joints move by exactly the applied command (no joint reaches a limit here)
    EXPECT_LT((q - q_integrated).cwiseAbs().maxCoeff(), kKinematicsTol) << "t = " << s.t_s;
    q_integrated += s.command * kPeriod;
  }
  // AND the loop converges: from 36 px to nothing visible (lambda = 1 /s: about exp(-t), 1e-6 of
  // the start after 14 s; measured 2e-11 px at 20 s)
  constexpr double kConvergedPx = 1e-3;
  EXPECT_GT(start_error, 30.0);
  EXPECT_LT(loop.step().error, kConvergedPx);
  // AND the camera is at the goal pose (4 points fix the pose: 1e-3 px is ~1e-6 m at 0.5 m)
  constexpr double kGoalPoseTol = 1e-5;
  EXPECT_LT(maxAbsDiff(arm.cameraPose(), scene.desiredCameraPose()), kGoalPoseTol);
}

TEST(E9ArmLoop, BroydenOnViper850LearnsTheArmsJacobianAndConverges) {
  // GIVEN ibvs-broyden with the E9 scenarios' arm keys (probe_speed 0.2 rad/s, damping 0.05) on
  // the arm, static target, no noise
  const ServoConfig c =
      armConfig("ibvs-broyden", Params{{"gain", 1.0}, {"probe_speed", 0.2}, {"damping", 0.05}}, 30.0);
  auto hold = makePredictor("hold", 8);
  ServoLoop loop(c, *hold);
  const int exploring = column(loop, "exploring"), jacobian_error = column(loop, "jacobian_error");
  ASSERT_GE(exploring, 0);
  ASSERT_GE(jacobian_error, 0);
  const int diag0 = static_cast<int>(loop.traceColumns().size()) - 3;  // the task's 3 diagnostics
  // WHEN it explores (12 probes of one frame, 1.5 s with the delay) and servoes
  double explore_end_s = -1.0, error_after_explore = -1.0, start_error = -1.0;
  bool was_exploring = false;
  ServoSample last;
  while (!loop.done()) {
    last = loop.step();
    if (start_error < 0.0) start_error = last.error;
    const bool now = last.diagnostics.size() && last.diagnostics(exploring - diag0) == 1.0;
    if (was_exploring && !now && explore_end_s < 0.0) {
      explore_end_s = last.t_s;
      error_after_explore = last.diagnostics(jacobian_error - diag0);
    }
    was_exploring = now;
  }
  // THEN exploration ended once the last probe's image arrived: first image at 0.2 s, 13 frames
  // of probing and waiting, 2 frames of delay
  EXPECT_NEAR(explore_end_s, 1.7, 1e-9);
  // AND the learnt Jacobian is the true one, L(s, Z) cVe eJe(q) at the arm's configuration: probes
  // of 20 mrad on a Jacobian that changes along them, and the RLS prior J0 = 0 (~2 % on the linear
  // plant of tests/tasks/ibvs_broyden_task_test.cpp) (measured 0.6 %)
  constexpr double kExploredJacobianTol = 0.02;
  EXPECT_LT(error_after_explore, kExploredJacobianTol);
  // AND it converges on the static target, from 36 px to under a pixel. Not to zero: with damping
  // 0.05 the weak mode of the 4-point image (y translation against x rotation, singular value
  // ~5 px per unit against mu = 0.05 sigma_max ~ 150) is corrected with a time constant of ~1000 s,
  // so the camera stays ~3 cm / 0.07 rad off along it (measured 0.56 px at 30 s)
  constexpr double kStaticResidualPx = 1.0;
  EXPECT_GT(start_error, 30.0);
  EXPECT_LT(last.error, kStaticResidualPx);
  // AND the estimate stays near the truth, though no longer updated once the arm slows down while
  // the true Jacobian changes with the 5 cm move to the goal (measured 8.8 %; the scene is static,
  // so no target motion is confounded with the robot's)
  constexpr double kConvergedJacobianTol = 0.15;
  EXPECT_LT(last.diagnostics(jacobian_error - diag0), kConvergedJacobianTol);
}

}  // namespace
}  // namespace predvs
