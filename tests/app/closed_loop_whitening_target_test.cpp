// The closed loop's whitening target and imm's feed-forward (process_noise_adapt.h, "The whitening's
// target"; imm.h, "The feed-forward's velocity"; docs/PERFORMANCE.md "A lagging acceleration model
// in the closed loop"), run as a user runs them: `predvs compare` on the default loop's scenario and
// its delay sweep, every predictor with its defaults (the list replaced), three seeds; with ibvs's
// feed-forward undamped (the papers' law) and damped (the default; ibvs_task.h).
#include "cli_test_utils.h"

#include "predvs/tasks/ibvs_task.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <utility>

using namespace predvs::apptest;

namespace {

class ClosedLoopWhiteningTarget : public ScratchDirTest {
 protected:
  ClosedLoopWhiteningTarget() : ScratchDirTest("predvs_closed_loop_target_test") {}
  /// compare on ibvs-moving-target and delay-study (the same loop, 0, 1 and 2 frames of vision delay)
  /// with kf-cv, kf-ca and imm at their defaults and kf-ca with white innovations (q_white_rho 0, the
  /// target before it), three seeds, ibvs's feed-forward damped by `damping`: the leaderboard's means
  /// (leaderboardMeans(), keyed by key()).
  std::map<std::string, double> compareTargets(const std::string& damping) {
    const CliRun r = run({"compare", "--scenarios", "ibvs-moving-target,delay-study", "--runs", "3", "--set",
                          "predictors=[kf-cv, kf-ca, imm, {name: kf-ca-white, type: kf-ca, params: {q_white_rho: 0}}]",
                          "--set", "task.feedforward_damping=" + damping, "--no-plots", "--out", path("cmp" + damping)});
    EXPECT_EQ(r.code, 0) << r.err;
    return leaderboardMeans(path("cmp" + damping) + "/leaderboard.csv");
  }
  /// leaderboardMeans()'s key of a variant, predictor and metric.
  static std::string key(const std::string& v, const std::string& p, const std::string& metric) {
    return v + "/" + p + "/" + metric;
  }
};

TEST_F(ClosedLoopWhiteningTarget, TheAccelerationModelLagsALittleAndImmKeepsUpWithItsBetterModel) {
  // GIVEN the loops with the papers' undamped feed-forward and with the default damped one
  auto undamped = compareTargets("0");
  auto damped = compareTargets(std::to_string(predvs::kDefaultFeedforwardDamping));
  int variants = 0;
  for (const char* v : {"ibvs-moving-target", "delay-study@delay_frames=0", "delay-study@delay_frames=1",
                        "delay-study@delay_frames=2"}) {
    SCOPED_TRACE(v);
    ASSERT_TRUE(undamped.count(key(v, "kf-ca-white", "rmse")));
    ASSERT_TRUE(damped.count(key(v, "kf-ca-white", "rmse")));
    ++variants;
    for (auto* m : {&undamped, &damped}) {
      auto rmse = [&](const char* p) { return (*m)[key(v, p, "rmse")]; };
      // THEN imm is within 10 % of the better of kf-cv and kf-ca (measured 0.92-1.02 times)
      EXPECT_LT(rmse("imm"), 1.1 * std::min(rmse("kf-cv"), rmse("kf-ca")));
    }
    // AND with the undamped feed-forward kf-ca follows the target far closer with its default target
    // (0.2) than with white innovations (measured 0.19-0.52 times at these seeds): the velocity's
    // noise, multiplied by the ill-conditioned inverse, went to the robot
    const double ca = undamped[key(v, "kf-ca", "rmse")], ca_white = undamped[key(v, "kf-ca-white", "rmse")];
    EXPECT_LT(ca, 0.7 * ca_white);
    // AND damped, white innovations cost kf-ca far less (0.51-1.70 px against 2.7-4.8), the target
    // 0.2 is within 10 % of them either way (0.84-1.08 times), kf-ca is no worse than undamped, and its
    // control effort falls more than fivefold (measured 11-16x)
    const double d_ca = damped[key(v, "kf-ca", "rmse")], d_white = damped[key(v, "kf-ca-white", "rmse")];
    EXPECT_LT(d_white, 0.7 * ca_white);
    EXPECT_LT(d_ca, 1.1 * d_white);
    EXPECT_LT(d_ca, 1.02 * ca);
    const double effort = damped[key(v, "kf-ca", "effort")], effort_undamped = undamped[key(v, "kf-ca", "effort")];
    EXPECT_LT(effort, 0.2 * effort_undamped);
  }
  EXPECT_EQ(variants, 4);
}

}  // namespace
