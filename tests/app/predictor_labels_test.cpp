// Tests of labelled predictor entries (issue 11 item 5): one registry predictor listed several
// times under its own labels with different parameters, in a scenario file
// ({name: LABEL, type: TYPE, params}) and on the command line (--predictors LABEL=TYPE:KEY=VALUE),
// and the labels in the leaderboard and the servo trace.
#include "cli_test_utils.h"
#include "scenario.h"
#include "scenario_file.h"
#include "scenario_run.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>

namespace fs = std::filesystem;
using namespace predvs::apptest;

namespace {

class PredictorLabelsTest : public ScratchDirTest {
 protected:
  PredictorLabelsTest() : ScratchDirTest("predvs_labels_test") {}

  /// A 3 s open-loop line with the given `predictors:` list (YAML flow or block text).
  std::string scenario(const std::string& predictors) const {
    return write("labels.yaml",
                 "description: labels\nkind: open-loop\nseed: 4\nruns: 2\nduration_s: 3\n"
                 "timing: {base_period_s: 0.1, delay_frames: 1}\n"
                 "noise: {model: gaussian, sigma: 1}\n"
                 "trajectory: {type: line, vx: 10, vy: 10}\n"
                 "predictors:\n" +
                     predictors);
  }
};

TEST_F(PredictorLabelsTest, ScenarioListsOnePredictorTwiceUnderTwoLabels) {
  // GIVEN kf-cv under its own name and again as kf-cv-r5 with another r
  const std::string file = scenario("  - kf-cv\n  - {name: kf-cv-r5, type: kf-cv, params: {r: 5}}\n");
  // WHEN loaded
  const predvs::Scenario sc = predvs::loadScenario(file);
  // THEN both entries are there, with their labels, the same type and their own parameters
  ASSERT_EQ(sc.predictors.size(), 2u);
  EXPECT_EQ(sc.predictors[0].name, "kf-cv");
  EXPECT_EQ(sc.predictors[0].typeName(), "kf-cv");
  EXPECT_FALSE(sc.predictors[0].params.has("r"));
  EXPECT_EQ(sc.predictors[1].name, "kf-cv-r5");
  EXPECT_EQ(sc.predictors[1].typeName(), "kf-cv");
  EXPECT_EQ(sc.predictors[1].params.values().at("r"), 5.0);
}

TEST_F(PredictorLabelsTest, ScenarioRejectsARepeatedLabelAnUnknownTypeAndABadLabel) {
  // A label twice: the error names the file, the line of the second entry and the label.
  try {
    predvs::loadScenario(scenario("  - kf-cv\n  - {name: kf-cv, params: {r: 5}}\n"));
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("labels.yaml:11:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'kf-cv' listed twice"), std::string::npos) << msg;
  }
  // An unknown type names the type.
  try {
    predvs::loadScenario(scenario("  - {name: mine, type: kf-cw}\n"));
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("kf-cw"), std::string::npos) << e.what();
  }
  // A label with a character of the --predictors syntax or of a --set path is rejected.
  for (const char* bad : {"a.b", "a:b", "a=b", "a b"}) {
    try {
      predvs::loadScenario(scenario(std::string("  - {name: '") + bad + "', type: kf-cv}\n"));
      ADD_FAILURE() << "no exception for " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("predictor label"), std::string::npos) << e.what();
    }
  }
}

TEST(PredictorChoice, ParsesLabelTypeAndParameters) {
  using predvs::parsePredictorChoice;
  const auto plain = parsePredictorChoice("kf-cv", "--predictors");
  EXPECT_EQ(plain.label, "kf-cv");
  EXPECT_EQ(plain.type, "kf-cv");
  EXPECT_FALSE(plain.labelled);
  EXPECT_TRUE(plain.params.values().empty());

  const auto full = parsePredictorChoice("paper=kf-cv:r=5:q=2e1", "--predictors");
  EXPECT_EQ(full.label, "paper");
  EXPECT_EQ(full.type, "kf-cv");
  EXPECT_TRUE(full.labelled);
  EXPECT_EQ(full.params.values().at("r"), 5.0);
  EXPECT_EQ(full.params.values().at("q"), 20.0);

  const auto unlabelled = parsePredictorChoice("st-akf-pm:pm_band=4", "--predictors");
  EXPECT_EQ(unlabelled.label, "st-akf-pm");
  EXPECT_EQ(unlabelled.params.values().at("pm_band"), 4.0);
  // A word is kept as a word (the predictor checks it when the scenario is built: model=cv).
  EXPECT_EQ(parsePredictorChoice("st-akf:model=cv", "--predictors").params.texts().at("model"), "cv");

  // Every malformed element is an error naming the option and the element.
  for (const char* bad : {"", "x=", "=kf-cv", "x=kf-cw", "kf-cw:r=1", "a.b", "a.b=kf-cv", "kf-cv:r", "kf-cv:r=", "kf-cv:=1",
                          "kf-cv:r=5x", "kf-cv:r=1:r=2", "kf-cv:r=inf"}) {
    try {
      parsePredictorChoice(bad, "--predictors");
      ADD_FAILURE() << "no exception for '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind(std::string("--predictors '") + bad + "'", 0), 0u) << e.what();
    }
  }
}

TEST(PredictorChoice, StartsFromTheScenarioParametersOfTheSameType) {
  // GIVEN E12, whose st-akf-pm carries q = 1e7 and the E12 tuning
  predvs::Scenario sc = predvs::loadScenario(predvs::resolveScenario("e12-discontinuity"));
  // WHEN the command line asks for st-akf-pm and a second one with the other alarm action
  predvs::choosePredictors(sc, {"st-akf-pm", "switch=st-akf-pm:pm_on_alarm=1", "plain=st-akf-pm"}, "--predictors");
  // THEN both keep the scenario's tuning, the second one with pm_on_alarm = 1 on top; a label that
  // the scenario does not list starts from the entry named TYPE too
  ASSERT_EQ(sc.predictors.size(), 3u);
  EXPECT_EQ(sc.predictors[0].name, "st-akf-pm");
  EXPECT_EQ(sc.predictors[0].params.values().at("q"), 1.0e7);
  EXPECT_FALSE(sc.predictors[0].params.has("pm_on_alarm"));
  EXPECT_EQ(sc.predictors[1].name, "switch");
  EXPECT_EQ(sc.predictors[1].typeName(), "st-akf-pm");
  EXPECT_EQ(sc.predictors[1].params.values().at("q"), 1.0e7);
  EXPECT_EQ(sc.predictors[1].params.values().at("pm_on_alarm"), 1.0);
  EXPECT_EQ(sc.predictors[2].params.values().at("q"), 1.0e7);
  // AND the scenario's own second entry keeps its parameters when chosen by its label
  predvs::Scenario sc2 = predvs::loadScenario(predvs::resolveScenario("e12-discontinuity"));
  predvs::choosePredictors(sc2, {"st-akf-pm-switch"}, "--predictors");
  EXPECT_EQ(sc2.predictors.at(0).typeName(), "st-akf-pm");
  EXPECT_EQ(sc2.predictors.at(0).params.values().at("pm_on_alarm"), 1.0);
  // AND a bare word that is neither a predictor nor one of the scenario's labels is an error that
  // names it and the labels
  predvs::Scenario sc4 = predvs::loadScenario(predvs::resolveScenario("e12-discontinuity"));
  try {
    predvs::choosePredictors(sc4, {"st-akf", "kf-cw"}, "--predictors");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown predictor 'kf-cw'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("st-akf-pm-switch"), std::string::npos) << e.what();
  }
  // AND a label twice is an error
  predvs::Scenario sc3 = predvs::loadScenario(predvs::resolveScenario("e12-discontinuity"));
  EXPECT_THROW(predvs::choosePredictors(sc3, {"st-akf", "st-akf=st-akf-pm"}, "--predictors"), std::invalid_argument);
}

TEST_F(PredictorLabelsTest, LabelsAreTheRowsOfTheLeaderboardAndTheTrace) {
  // GIVEN the line scenario WHEN compared with kf-cv three times, two of them labelled, one with
  // a measurement variance 100 times too large
  const std::string file = scenario("  - hold\n");
  const std::string out = path("cmp");
  const CliRun r = run({"compare", "--scenarios", file, "--predictors", "kf-cv,slow=kf-cv:r=100,same=kf-cv", "--out",
                        out, "--no-plots", "--jobs", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN the leaderboard has one row per label, with its type, and the labels in the printed table
  const auto j = readJson(out + "/leaderboard.json");
  std::map<std::string, double> rmse;
  for (const auto& p : j["scenarios"][0]["variants"][0]["predictors"]) {
    EXPECT_EQ(p["type"], "kf-cv");
    rmse[p["name"].get<std::string>()] = p["metrics"]["rmse"]["mean"].get<double>();
  }
  ASSERT_EQ(rmse.size(), 3u);
  EXPECT_EQ(rmse.at("same"), rmse.at("kf-cv"));  // same type, same parameters, same seeds
  EXPECT_NE(rmse.at("slow"), rmse.at("kf-cv"));  // other parameters
  EXPECT_NE(r.out.find("slow"), std::string::npos) << r.out;
  // AND `predvs servo` writes the labels into its trace
  const std::string sout = path("servo");
  const CliRun s = run({"servo", "--scenario", file, "--predictors", "kf-cv,slow=kf-cv:r=100", "--out", sout, "--no-plots"});
  ASSERT_EQ(s.code, 0) << s.err;
  std::set<std::string> labels;
  for (const auto& row : csvRows(slurp(sout + "/log.csv"))) labels.insert(row.at(0));
  EXPECT_EQ(labels, (std::set<std::string>{"kf-cv", "slow"}));
  const auto sj = readJson(sout + "/summary.json");
  EXPECT_EQ(sj["predictors"][1]["name"], "slow");
  EXPECT_EQ(sj["predictors"][1]["type"], "kf-cv");
}

TEST_F(PredictorLabelsTest, CommandLineErrorsFollowTheFailureContract) {
  const std::string file = scenario("  - hold\n");
  expectError(run({"compare", "--scenarios", file, "--predictors", "kf-cv,kf-cv:r=5", "--out", path("o1"), "--no-plots"}),
              "'kf-cv' listed twice", path("o1"));
  expectError(run({"compare", "--scenarios", file, "--predictors", "x=kf-cv:r=oops", "--out", path("o2"), "--no-plots"}),
              "parameter 'r' expects a number", path("o2"));
  expectError(run({"compare", "--scenarios", file, "--predictors", "x=kf-cv:nokey=1", "--out", path("o3"), "--no-plots"}),
              "nokey", path("o3"));
  expectError(run({"servo", "--scenario", file, "--predictors", "y=nope", "--out", path("o4"), "--no-plots"}),
              "unknown predictor 'nope'", path("o4"));
  expectError(run({"compare", "--scenarios", file, "--predictors", "hold,nope", "--out", path("o5"), "--no-plots"}),
              "unknown predictor 'nope'", path("o5"));
}

}  // namespace
