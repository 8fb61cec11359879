// imm's feed-forward weights in a closed loop (imm.h, "The feed-forward's velocity", ff_weight_tau_s;
// docs/PERFORMANCE.md "imm's feed-forward weights over two seconds"), run as a user runs them:
// `predvs compare` on the two e8 scenarios (a loop without vision delay, so the loop acts on imm's
// zero-horizon state), every predictor at its defaults (the list replaced), imm also with the
// weights' low-pass of 1 s it had before, ten seeds (compare's first ten runs).
#include "cli_test_utils.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>

using namespace predvs::apptest;

namespace {

class ImmFeedforwardWeights : public ScratchDirTest {
 protected:
  ImmFeedforwardWeights() : ScratchDirTest("predvs_imm_ff_weights_test") {}
};

TEST_F(ImmFeedforwardWeights, OnTheE8LoopsImmKeepsWithinTenPercentOfItsBetterSingleModel) {
  // GIVEN e8-ibvs and e8-vtc with kf-cv, kf-ca, imm and imm with a 1 s low-pass of its weights
  const CliRun r = run({"compare", "--scenarios", "e8-ibvs,e8-vtc", "--runs", "10", "--set",
                        "predictors=[kf-cv, kf-ca, imm, {name: imm-1s, type: imm, params: {ff_weight_tau_s: 1}}]",
                        "--no-plots", "--out", path("cmp")});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::map<std::string, double> mean = leaderboardMeans(path("cmp") + "/leaderboard.csv");
  auto at = [&](const std::string& v, const std::string& p) { return mean.at(v + "/" + p + "/rmse"); };
  for (const char* v : {"e8-ibvs", "e8-vtc"}) {
    SCOPED_TRACE(v);
    ASSERT_TRUE(mean.count(std::string(v) + "/imm-1s/rmse"));
    const double best = std::min(at(v, "kf-cv"), at(v, "kf-ca"));
    // THEN imm is within 10 % of the better of kf-cv and kf-ca (item 4; measured 0.96 and 0.82 times)
    EXPECT_LT(at(v, "imm"), 1.1 * best);
    // AND no worse than with the 1 s low-pass (measured 0.85 and 0.96 times)
    EXPECT_LT(at(v, "imm"), at(v, "imm-1s"));
  }
  // AND on e8-ibvs the longer low-pass is what keeps imm there: with 1 s its weights left the image's
  // u channels to the CV mode through the board's deceleration and imm was 1.13 times kf-ca
  // (measured 2.72-2.75 px against 2.32 with 2 s)
  EXPECT_LT(at("e8-ibvs", "imm"), 0.9 * at("e8-ibvs", "imm-1s"));
}

TEST_F(ImmFeedforwardWeights, ALowPassOfZeroIsOneLineNamingTheKey) {
  // GIVEN a weights' low-pass outside (0, 1e6] s THEN compare says so in one line, exits 2 and writes nothing
  const CliRun r = run({"compare", "--scenarios", "e8-ibvs", "--runs", "1", "--set",
                        "predictors=[{name: imm, type: imm, params: {ff_weight_tau_s: 0}}]", "--no-plots", "--out",
                        path("bad")});
  expectError(r, "ff_weight_tau_s", path("bad"));
}

}  // namespace
