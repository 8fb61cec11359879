#include "predvs/tasks/reference_filtering_task.h"

#include "predictors/eigen_test_utils.h"
#include "predvs/tasks/ibvs_task.h"
#include "tasks/dual_rate_plant.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {
namespace {

using testing_plant::FreeCamera;
using testing_plant::PlantTiming;
using testing_plant::RunOutcome;
using testing_plant::rotatedSquare;

constexpr double kDeg = M_PI / 180.0;
// Central differences with tau = 1e-6 on O(1) features: truncation ~tau^2, round-off ~1e-16 / tau.
constexpr double kFiniteDiffTol = 1e-7;
// The same least-squares problem solved by vpServo and by our SVD: round-off on O(1) twists.
constexpr double kSameLawTol = 1e-9;
// "Converged": the RMS point error below a hundredth of a pixel (the plant is noise-free).
constexpr double kConvergedTol_px = 0.01;
// The EKFS laws servo to s_hat*(t+1|T), a fraction of the way to s*, so they approach the goal more
// slowly than lambda alone says (at lambda = 2 /s about 0.6 /s on the arm-like Jacobian): after
// 10 s they are below a tenth of a pixel from a start ~100 px away.
constexpr double kSubPixelTol_px = 0.1;

const std::vector<std::string> kLaws = {"sr-lf-ibvs", "sr-hf-ibvs", "sr-lf-ekfs-ibvs", "sr-hf-ekfs-ibvs",
                                        "dr-ekfs-ibvs"};

std::unique_ptr<Task> makeLaw(const std::string& name, const Params& params, const TaskContext& context) {
  return makeTask(name, params, context);
}

/// A tilted, off-centre set of 4 points in the camera frame.
FreeCamera tiltedPoints() {
  FreeCamera cam;
  cam.P = {{-0.1, -0.08, 0.9}, {0.12, -0.1, 1.0}, {0.1, 0.11, 1.1}, {-0.09, 0.1, 0.95}};
  return cam;
}

/// One call of computeCommand with the plant's features as measurement and features to act on.
Eigen::VectorXd command(Task& task, double t, double t_acq, const PointFeatures& f,
                        const Eigen::MatrixXd& robot_jacobian = Eigen::MatrixXd::Identity(6, 6)) {
  const Eigen::VectorXd state = Eigen::VectorXd::Zero(robot_jacobian.cols()), no_rate;
  const Eigen::MatrixXd no_truth;
  const TaskInput in{t, t_acq, f.uv_px, f.uv_px, no_rate, f.Z_m, robot_jacobian, state, no_truth};
  return task.computeCommand(in);
}

TEST(ReferenceFilteringTask, InteractionMatrixWithDepthRowMatchesFiniteDifferences) {
  // GIVEN 4 tilted points and their (x, y, Z) features
  const FreeCamera cam = tiltedPoints();
  PlantTiming timing;
  ReferenceFilteringTask task(ReferenceFilteringLaw::SrHfIbvs, Params{},
                              testing_plant::makeContext(cam, timing));
  const Eigen::VectorXd s = task.toXyz(cam.features().uv_px, cam.features().Z_m);
  // WHEN each twist component is applied for +-tau
  constexpr double tau = 1e-6;
  Eigen::MatrixXd fd(12, 6);
  for (int j = 0; j < 6; ++j) {
    FreeCamera plus = cam, minus = cam;
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(6, j);
    plus.apply(e, tau, 1);
    minus.apply(e, -tau, 1);
    fd.col(j) = (task.toXyz(plus.features().uv_px, plus.features().Z_m) -
                 task.toXyz(minus.features().uv_px, minus.features().Z_m)) /
                (2 * tau);
  }
  // THEN the stacked L_f of paper eq. 2 (with its depth row) is ds/d(twist)
  EXPECT_TRUE(matricesNear(ReferenceFilteringTask::interactionMatrix(s), fd, kFiniteDiffTol));
}

TEST(ReferenceFilteringTask, SingleRateLawIsClassicIbvsForEveryInteractionChoice) {
  // GIVEN the desired view of a centred square and a current view of the tilted points
  const FreeCamera cam = tiltedPoints();
  FreeCamera desired;
  desired.P = rotatedSquare(0.2, 0.8, 0.0);
  PlantTiming timing;
  for (const std::string interaction : {"current", "desired", "mean"}) {
    Params p{{"lambda", 0.7}};
    p.setText("interaction", interaction);
    Params q = p;
    SrHfIbvsTask ours(p, testing_plant::makeContext(desired, timing));
    IbvsTask visp(q, testing_plant::makeContext(desired, timing));
    // WHEN both compute a command on the same features (robot: an arm-like camera Jacobian)
    Eigen::MatrixXd Jr = Eigen::MatrixXd::Identity(6, 6);
    Jr.topRightCorner<3, 3>() << 0, 0.3, -0.1, -0.3, 0, 0.2, 0.1, -0.2, 0;
    const Eigen::VectorXd u = command(ours, 0.0, 0.0, cam.features(), Jr);
    const Eigen::VectorXd state = Eigen::VectorXd::Zero(6), no_rate;
    const Eigen::MatrixXd no_truth;
    const PointFeatures f = cam.features();
    const Eigen::VectorXd u_visp =
        visp.computeCommand(TaskInput{0.0, 0.0, f.uv_px, f.uv_px, no_rate, f.Z_m, Jr, state, no_truth});
    // THEN they agree: -lambda (H L J_c)^+ H (s - s*) is vpServo's -lambda (L J_c)^+ (s - s*)
    EXPECT_TRUE(matricesNear(u, u_visp, kSameLawTol)) << interaction;
    // AND the loop's Jacobian is ViSP's pixel one
    EXPECT_TRUE(matricesNear(ours.featureJacobian(), visp.featureJacobian(), kSameLawTol)) << interaction;
  }
}

TEST(ReferenceFilteringTask, DepthParameterSetsEveryDepthOfFeaturesAndGoal) {
  // GIVEN the tilted points seen at their true depths (0.9 .. 1.1 m)
  const FreeCamera cam = tiltedPoints();
  PlantTiming timing;
  const auto ctx = testing_plant::makeContext(cam, timing);
  ReferenceFilteringTask measured(ReferenceFilteringLaw::SrLfIbvs, Params{}, ctx);
  ReferenceFilteringTask constant(ReferenceFilteringLaw::SrLfIbvs, Params{{"depth", 0.5}}, ctx);
  Eigen::VectorXd Z = cam.features().Z_m;
  Z(2) = std::numeric_limits<double>::quiet_NaN();
  // WHEN the features are converted
  const Eigen::VectorXd a = measured.toXyz(cam.features().uv_px, Z), b = constant.toXyz(cam.features().uv_px, Z);
  // THEN depth = 0 uses the measured depth (the desired one where it is unknown), depth = 0.5 uses
  // 0.5 for every point of s and of s*
  for (int i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(a(3 * i + 2), i == 2 ? ctx.desired_points.Z_m(2) : Z(i));
    EXPECT_DOUBLE_EQ(b(3 * i + 2), 0.5);
    EXPECT_DOUBLE_EQ(constant.desiredXyz()(3 * i + 2), 0.5);
    EXPECT_DOUBLE_EQ(a(3 * i), b(3 * i));
  }
}

TEST(ReferenceFilteringTask, RejectsBadParametersNamingTheKey) {
  FreeCamera desired;
  desired.P = rotatedSquare(0.3, 0.38, 0.0);
  const auto ctx = testing_plant::makeContext(desired, PlantTiming{});
  auto expectThrowNaming = [&](const std::string& law, const Params& p, const std::string& key) {
    try {
      makeLaw(law, p, ctx);
      ADD_FAILURE() << law << ": no exception for " << key;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  expectThrowNaming("dr-ekfs-ibvs", Params{{"lambda", 0.0}}, "lambda");
  expectThrowNaming("sr-lf-ibvs", Params{{"horizon", 8}}, "horizon");  // no filter: unknown key
  expectThrowNaming("sr-hf-ekfs-ibvs", Params{{"kf_accel", 8}}, "kf_accel");  // no DR-KF
  expectThrowNaming("dr-ekfs-ibvs", Params{{"horizon", 2.5}}, "horizon");
  expectThrowNaming("sr-lf-ibvs", Params{{"depth", -1}}, "depth");
  expectThrowNaming("sr-lf-ibvs", Params{{"depth_rows", 2}}, "depth_rows");
  Params bad;
  bad.setText("interaction", "mixed");
  expectThrowNaming("sr-hf-ibvs", bad, "interaction");
  TaskContext odd = ctx;
  odd.frame_period_s = 0.025;  // not a whole number of 10 ms base periods
  EXPECT_THROW(makeLaw("dr-ekfs-ibvs", Params{}, odd), std::invalid_argument);
}

TEST(ReferenceFilteringTask, LowRateLawsHoldTheirCommandForTheFrameAndHighRateLawsDoNot) {
  // GIVEN a frame acquired at t = 0, then features that change while no new frame arrives
  FreeCamera desired;
  desired.P = rotatedSquare(0.3, 0.38, 0.0);
  FreeCamera cam;
  cam.P = rotatedSquare(0.3, 0.38, 30 * kDeg);
  const auto ctx = testing_plant::makeContext(desired, PlantTiming{});
  FreeCamera moved = cam;
  moved.apply((Eigen::VectorXd(6) << 0.01, 0, 0, 0, 0, 0.1).finished(), 0.1);
  for (const std::string& law : {std::string("sr-lf-ibvs"), std::string("sr-lf-ekfs-ibvs"), std::string("sr-hf-ibvs"),
                                 std::string("sr-hf-ekfs-ibvs")}) {
    auto task = makeLaw(law, Params{{"lambda", 1.0}}, ctx);
    const Eigen::VectorXd u0 = command(*task, 0.0, 0.0, cam.features());
    // WHEN the next tick brings other features with the same acquisition time (a forecast), and
    // then a new frame arrives
    const Eigen::VectorXd u1 = command(*task, 0.01, 0.0, moved.features());
    const Eigen::VectorXd u2 = command(*task, 0.08, 0.08, moved.features());
    // THEN a low-rate law keeps its frame's command until the new frame; a high-rate one follows
    const bool low_rate = law.find("-lf-") != std::string::npos;
    EXPECT_EQ(matricesNear(u1, u0, 0.0), low_rate) << law;
    EXPECT_FALSE(matricesNear(u2, u0, 1e-6)) << law;
  }
}

TEST(ReferenceFilteringTask, DualRateLawAppliesOneCommandPerBasePeriodAndReplansWithoutAFrame) {
  // GIVEN dr-ekfs-ibvs (N = 8) fed two frames of a rotating view, so that its KF has a velocity
  FreeCamera desired;
  desired.P = rotatedSquare(0.3, 0.38, 0.0);
  const PlantTiming timing{0.01, 8, 8};
  DrEkfsIbvsTask task(Params{{"lambda", 1.0}}, testing_plant::makeContext(desired, timing));
  FreeCamera cam;
  cam.P = rotatedSquare(0.3, 0.38, 40 * kDeg);
  const PointFeatures f0 = cam.features();
  cam.apply((Eigen::VectorXd(6) << 0, 0, 0, 0, 0, -0.5).finished(), 0.08);
  const PointFeatures f1 = cam.features();
  command(task, 0.08, 0.0, f0);
  // WHEN the second frame (acquired at 0.08 s) is delivered at 0.16 s and no other frame follows
  std::vector<Eigen::VectorXd> u;
  for (int i = 0; i < 9; ++i) u.push_back(command(task, 0.16 + 0.01 * i, 0.08, f1));
  // THEN the 8 commands of the frame differ from tick to tick (inverse lifting of Algorithm 5),
  // and the 9th tick, past the frame, is a new plan from the KF's prediction, not a repeat
  for (int i = 1; i < 8; ++i) EXPECT_FALSE(matricesNear(u[static_cast<size_t>(i)], u[static_cast<size_t>(i) - 1], 1e-9)) << i;
  EXPECT_FALSE(matricesNear(u[8], u[7], 1e-9));
  for (const auto& ui : u) EXPECT_TRUE(ui.allFinite());
  EXPECT_EQ(task.diagnostics().size(), 2u);
  EXPECT_GT(task.runSummary().front().second, 0.0);
}

/// The five laws on two robots: the free camera and a constant, non-orthogonal camera Jacobian
/// standing in for an arm's.
struct LawCase {
  std::string law;
  bool arm;
};

class EveryLaw : public ::testing::TestWithParam<LawCase> {};

TEST_P(EveryLaw, DrivesAStaticSquareToItsGoal) {
  // GIVEN a 0.3 m square at 0.38 m, the camera 30 deg about its axis, 3 cm off and 5 cm back;
  // delta = 10 ms, N = 4, one frame (40 ms) of latency
  const LawCase c = GetParam();
  const PlantTiming timing{0.01, 4, 4};
  FreeCamera desired;
  desired.P = rotatedSquare(0.3, 0.38, 0.0);
  FreeCamera start;
  start.P = rotatedSquare(0.3, 0.38, 30 * kDeg);
  start.apply((Eigen::VectorXd(6) << 0.03, -0.02, -0.05, 0, 0, 0).finished(), 1.0);
  Eigen::MatrixXd Jr = Eigen::MatrixXd::Identity(6, 6);
  if (c.arm) {
    Jr << 0.8, 0.1, 0, 0, 0.2, 0, 0, 1.1, 0.1, -0.2, 0, 0, 0.1, 0, 0.9, 0, 0, 0.1,  //
        0, 0, 0, 1.2, 0.1, 0, 0, 0, 0, 0, 0.9, 0.1, 0, 0, 0, 0.1, 0, 1.0;
  }
  auto task = makeLaw(c.law, Params{{"lambda", 2.0}}, testing_plant::makeContext(desired, timing));
  // WHEN it runs 10 s
  const RunOutcome out = testing_plant::run(*task, start, timing, 10.0, Jr);
  // THEN the points sit on their goal and the camera never came near the object plane
  EXPECT_FALSE(out.crossed) << c.law;
  EXPECT_LT(out.final_error_px(), kSubPixelTol_px) << c.law;
  EXPECT_GT(out.min_depth_m, 0.25) << c.law;
  EXPECT_NEAR(task->runSummary().front().second, out.peak_command, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(ReferenceFilteringTask, EveryLaw,
                         ::testing::Values(LawCase{"sr-lf-ibvs", false}, LawCase{"sr-hf-ibvs", false},
                                           LawCase{"sr-lf-ekfs-ibvs", false}, LawCase{"sr-hf-ekfs-ibvs", false},
                                           LawCase{"dr-ekfs-ibvs", false}, LawCase{"sr-lf-ibvs", true},
                                           LawCase{"sr-hf-ibvs", true}, LawCase{"sr-lf-ekfs-ibvs", true},
                                           LawCase{"sr-hf-ekfs-ibvs", true}, LawCase{"dr-ekfs-ibvs", true}),
                         [](const auto& info) {
                           std::string n = info.param.law + (info.param.arm ? "_arm" : "_free");
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

/// E10 (paper 003 §4.1, docs/MODELS.md §10-11): 4 coplanar points, a 300 mm square at 0.38 m, the camera
/// rotated 150 deg about its optical axis; delta = 10 ms, N = 8, one frame of latency; CURRENT
/// interaction matrix, true depth, no saturation.
struct E10 {
  PlantTiming timing{0.01, 8, 8};
  FreeCamera desired, start;
  E10() {
    desired.P = rotatedSquare(0.3, 0.38, 0.0);
    start.P = rotatedSquare(0.3, 0.38, 150 * kDeg);
  }
  RunOutcome run(const std::string& law, double lambda, double duration_s, int latency_ticks = 8) const {
    PlantTiming t = timing;
    t.latency_ticks = latency_ticks;
    auto task = makeTask(law, Params{{"lambda", lambda}}, testing_plant::makeContext(desired, t));
    return testing_plant::run(*task, start, t, duration_s);
  }
};

TEST(ReferenceFilteringTask, E10DualRateConvergesWhereSingleRateFailsFromLatency) {
  const E10 e10;
  for (const double lambda : {1.4, 2.0, 3.0}) {
    // GIVEN a gain at which the single-rate law converges without latency (the failure below is
    // the latency's, not the gain's)
    const RunOutcome sr_no_delay = e10.run("sr-lf-ibvs", lambda, 10.0, 0);
    ASSERT_LT(sr_no_delay.final_error_px(), kConvergedTol_px) << lambda;
    // WHEN SR-LF-IBVS and DR-EKFS-IBVS run with one frame of latency
    const RunOutcome sr = e10.run("sr-lf-ibvs", lambda, 10.0);
    const RunOutcome dr = e10.run("dr-ekfs-ibvs", lambda, 10.0);
    // THEN the single-rate camera backs away and comes through the object plane on stale
    // commands, while the dual-rate one converges
    EXPECT_TRUE(sr.crossed) << "lambda " << lambda << ": final " << sr.final_error_px() << " px";
    EXPECT_FALSE(dr.crossed) << "lambda " << lambda;
    EXPECT_LT(dr.final_error_px(), kConvergedTol_px) << "lambda " << lambda;
  }
}

TEST(ReferenceFilteringTask, E10DualRateNeedsASmallerPeakCommandWhereBothConverge) {
  // GIVEN lambda = 1.2 /s, where both laws converge with one frame of latency
  const E10 e10;
  const RunOutcome sr = e10.run("sr-lf-ibvs", 1.2, 10.0), dr = e10.run("dr-ekfs-ibvs", 1.2, 10.0);
  ASSERT_LT(sr.final_error_px(), 1.0);
  ASSERT_LT(dr.final_error_px(), 1.0);
  // THEN the dual-rate law's largest command is smaller (paper Fig. 5): its N commands per frame
  // servo to the filtered reference, the single-rate one holds one large command per frame
  EXPECT_LT(dr.peak_command, 0.5 * sr.peak_command) << dr.peak_command << " vs " << sr.peak_command;
}

}  // namespace
}  // namespace predvs
