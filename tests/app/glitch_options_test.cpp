// The glitch options of the track commands: make-track / track-study --glitch P --glitch-px G (tracker
// glitches in the generated tracks) and predict / track-study --glitch-sigmas G (the glitch gate,
// predictors/include/predvs/predictors/glitch_gate.h, on every predictor that does not set it).
#include "app/cli_test_utils.h"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

namespace predvs {
namespace {

using apptest::CliRun;
using apptest::csvRows;
using apptest::run;
using apptest::slurp;

class GlitchOptions : public apptest::ScratchDirTest {
 protected:
  GlitchOptions() : ScratchDirTest("predvs_glitch_options_test") {}
};

TEST_F(GlitchOptions, TheGateOnGlitchedTracksBeatsTheSamePredictorWithout) {
  // GIVEN hand and turns tracks with a 40 px glitch on 2 % of the frames, and track-study's gate on
  // every predictor but the one labelled to keep it off
  const CliRun r = run({"track-study", "--kinds", "hand,turns", "--rates", "30", "--noise", "1", "--seeds", "2",
                        "--duration-s", "10", "--glitch", "0.02", "--glitch-px", "40", "--glitch-sigmas", "8",
                        "--predictors", "hold,kf-cv,kf-cv-off=kf-cv:glitch_sigmas=0", "--out", path("study")});
  ASSERT_EQ(r.code, 0) << r.err;
  // kind,rate_hz,noise_px,seed,predictor,rmse_truth_px,...
  std::map<std::string, std::map<std::string, double>> rmse;
  for (const auto& row : csvRows(slurp(path("study") + "/study.csv")))
    if (row.size() > 5 && row[0] != "kind") rmse[row[0] + "#" + row[3]][row[4]] = std::stod(row[5]);
  ASSERT_EQ(rmse.size(), 4u);
  for (const auto& [track, by] : rmse) {
    // THEN the gated kf-cv's error is below the ungated one's, which is not better than hold's
    EXPECT_LT(by.at("kf-cv"), 0.9 * by.at("kf-cv-off")) << track;
    EXPECT_LT(by.at("kf-cv"), by.at("hold")) << track;
  }
}

TEST_F(GlitchOptions, PredictSumsTheGatesSettledDoubtsInSummaryJson) {
  // GIVEN a track with 30 px glitches on 2 % of its frames
  ASSERT_EQ(run({"make-track", "--kind", "turns", "--noise-px", "1", "--glitch", "0.02", "--glitch-px", "30", "--out",
                 path("g.csv")})
                .code,
            0);
  // WHEN predict runs kf-cv behind the gate and hold
  const CliRun r = run({"predict", "--input", path("g.csv"), "--predictor", "hold,kf-cv", "--delay-frames", "2", "--glitch-sigmas", "8",
                        "--no-plots", "--out", path("p")});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN summary.json has kf-cv's doubts settled each way (most of them glitches), and none for hold
  const std::string json = slurp(path("p") + "/summary.json");
  const auto kf = json.find("\"name\": \"kf-cv\"");
  ASSERT_NE(kf, std::string::npos) << json;
  const auto tallies = json.find("\"tallies\"", kf);
  ASSERT_NE(tallies, std::string::npos) << json;
  const auto glitches = json.find("\"glitches\": ", tallies);
  ASSERT_NE(glitches, std::string::npos) << json;
  EXPECT_GE(std::stod(json.substr(glitches + 12)), 5.0) << json.substr(tallies, 80);
  EXPECT_EQ(json.find("\"tallies\""), tallies) << "hold has none";
}

TEST_F(GlitchOptions, BadValuesAreOneLineErrors) {
  expectError(run({"make-track", "--glitch", "0.7", "--out", path("t.csv")}), "--glitch: expected a probability",
              path("t.csv"));
  expectError(run({"make-track", "--glitch", "0.1", "--glitch-px", "0", "--out", path("t.csv")}), "--glitch-px",
              path("t.csv"));
  expectError(run({"track-study", "--seeds", "1", "--glitch-sigmas", "-1", "--out", path("s")}), "--glitch-sigmas",
              path("s"));
  ASSERT_EQ(run({"make-track", "--duration-s", "2", "--out", path("ok.csv")}).code, 0);
  expectError(run({"predict", "--input", path("ok.csv"), "--predictor", "kf-cv", "--glitch-sigmas", "x", "--out",
                   path("p")}),
              "--glitch-sigmas", path("p"));
}

}  // namespace
}  // namespace predvs
