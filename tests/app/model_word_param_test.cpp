// A predictor parameter that is a word, `model=cv` (st-akf, st-akf-pm, fakf-classic,
// docs/MODELS.md §3, §5), reaches the predictor wherever parameters are given: track-study, predict
// and fit-noise `--param`, a parameter file (`--params`, as fit-noise writes), and a servo
// `--predictors LABEL=TYPE:KEY=VALUE`; a word the predictor does not take is a one-line error.
#include "app/cli_test_utils.h"

#include <gtest/gtest.h>

#include <string>

namespace predvs {
namespace {

using apptest::CliRun;
using apptest::run;
using apptest::slurp;

class ModelWordParam : public apptest::ScratchDirTest {
 protected:
  ModelWordParam() : ScratchDirTest("predvs_model_word_test") {}
};

TEST_F(ModelWordParam, TrackStudyModelChangesTheFilterAndABadOneIsNamed) {
  // GIVEN one short track, st-akf on its default model and on `model=cv`
  const std::vector<std::string> grid = {"track-study", "--kinds", "stops", "--rates", "15", "--noise", "1",
                                         "--seeds", "1", "--duration-s", "5", "--predictors", "st-akf"};
  auto with = [&grid](std::vector<std::string> extra) {
    std::vector<std::string> a = grid;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const CliRun ca = run(with({"--out", path("ca")}));
  const CliRun cv = run(with({"--param", "st-akf.model=cv", "--out", path("cv")}));
  const CliRun ca_spelt = run(with({"--param", "st-akf.model=ca", "--out", path("ca_spelt")}));
  ASSERT_EQ(ca.code, 0) << ca.err;
  ASSERT_EQ(cv.code, 0) << cv.err;
  ASSERT_EQ(ca_spelt.code, 0) << ca_spelt.err;
  // THEN `model=ca` is the default, and `model=cv` is another filter (other errors on the same track)
  EXPECT_EQ(slurp(path("ca") + "/study.csv"), slurp(path("ca_spelt") + "/study.csv"));
  EXPECT_NE(slurp(path("ca") + "/study.csv"), slurp(path("cv") + "/study.csv"));
  // AND a word the predictor does not know, or a word for a numeric key, is a one-line error
  expectError(run(with({"--param", "st-akf.model=singer", "--out", path("bad")})), "'model'", path("bad"));
  expectError(run(with({"--param", "st-akf.q=fast", "--out", path("bad")})), "'q'", path("bad"));
  expectError(run(with({"--param", "st-akf.q=1e", "--out", path("bad")})), "expected a number or a word", path("bad"));
}

TEST_F(ModelWordParam, PredictFitNoiseParamFilesAndServoTakeTheModelWord) {
  // GIVEN a generated track
  const std::string track = path("track.csv");
  ASSERT_EQ(run({"make-track", "--kind", "turns", "--rate-hz", "30", "--duration-s", "4", "--out", track}).code, 0);
  auto predict = [&](std::vector<std::string> extra, const std::string& out) {
    std::vector<std::string> a = {"predict", "--input", track, "--predictor", "fakf-classic", "--delay-frames", "2",
                                  "--no-plots", "--out", out};
    a.insert(a.end(), extra.begin(), extra.end());
    return run(a);
  };
  // WHEN predict runs fakf-classic on its default, with --param model=ca, and with a parameter
  // file that says model: ca
  const CliRun cv = predict({}, path("cv"));
  const CliRun ca = predict({"--param", "model=ca"}, path("ca"));
  const std::string file = write("ca.yaml", "predictors:\n  - {name: fakf-classic, params: {model: ca}}\n");
  const CliRun ca_file = predict({"--params", file}, path("ca_file"));
  ASSERT_EQ(cv.code, 0) << cv.err;
  ASSERT_EQ(ca.code, 0) << ca.err;
  ASSERT_EQ(ca_file.code, 0) << ca_file.err;
  // THEN the file and the option give the same (CA) filter, another than the default
  EXPECT_EQ(slurp(path("ca") + "/predictions.csv"), slurp(path("ca_file") + "/predictions.csv"));
  EXPECT_NE(slurp(path("cv") + "/predictions.csv"), slurp(path("ca") + "/predictions.csv"));
  // AND summary.json records the word with the numbers, as track's and servo's do
  for (const char* out : {"ca", "ca_file"}) {
    const std::string summary = slurp(path(out) + "/summary.json");
    EXPECT_NE(summary.find("\"model\": \"ca\""), std::string::npos) << out << ": " << summary;
  }
  expectError(predict({"--param", "model=singer"}, path("bad")), "'model'", path("bad"));
  const std::string bad_file = write("bad.yaml", "predictors:\n  - {name: fakf-classic, params: {model: jerk}}\n");
  expectError(predict({"--params", bad_file}, path("bad")), "bad.yaml:2: ", path("bad"));
  // AND fit-noise fits st-akf on the CV model and writes the word back into params.yaml, which
  // predict reads
  const CliRun fit = run({"fit-noise", "--input", track, "--predictor", "st-akf", "--param", "model=cv", "--objective",
                          "prediction", "--out", path("fit")});
  ASSERT_EQ(fit.code, 0) << fit.err;
  const std::string yaml = slurp(path("fit") + "/params.yaml");
  EXPECT_NE(yaml.find("model: cv"), std::string::npos) << yaml;
  const CliRun again = run({"predict", "--input", track, "--predictor", "st-akf", "--params", path("fit") + "/params.yaml",
                            "--delay-frames", "2", "--no-plots", "--out", path("again")});
  EXPECT_EQ(again.code, 0) << again.err;
  // AND servo takes it in a predictor choice
  const CliRun servo = run({"servo", "--scenario", "e2-accel-jump", "--predictors", "hold,cv=st-akf:model=cv",
                            "--no-plots", "--out", path("servo")});
  EXPECT_EQ(servo.code, 0) << servo.err;
  expectError(run({"servo", "--scenario", "e2-accel-jump", "--predictors", "hold,x=st-akf:model=sing",
                   "--no-plots", "--out", path("servo_bad")}),
              "'model'", path("servo_bad"));
}

}  // namespace
}  // namespace predvs
