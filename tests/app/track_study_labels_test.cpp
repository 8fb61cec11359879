// `predvs track-study --predictors` with [LABEL=]TYPE[:KEY=VALUE...] elements (compare's syntax,
// app/scenario_run.h): one predictor under two labels with their own parameters, each its own rows
// of study.csv and of the tables, the same figures as the same parameters given with --param; hold
// listed anywhere is the reference of every ratio.
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

class TrackStudyLabels : public apptest::ScratchDirTest {
 protected:
  TrackStudyLabels() : ScratchDirTest("predvs_ts_labels_test") {}
  /// track-study on two turns tracks (30 Hz, 1.5 px, seeds 1-2, 8 s) with these --predictors and
  /// extra options; study.csv's RMSE vs truth per (predictor, seed) and its ratio to hold.
  std::map<std::string, std::pair<std::string, std::string>> study(const std::string& dir, const std::string& predictors,
                                                                   const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args = {"track-study", "--kinds", "turns", "--rates", "30", "--noise", "1.5",
                                     "--seeds", "2", "--duration-s", "8", "--predictors", predictors,
                                     "--out", path(dir)};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 0) << r.err;
    last_out_ = r.out;
    std::map<std::string, std::pair<std::string, std::string>> out;
    // kind,rate_hz,noise_px,seed,predictor,rmse_truth_px,rmse_meas_px,n,ratio_to_hold,fit_variant
    for (const auto& row : csvRows(slurp(path(dir) + "/study.csv")))
      if (row.size() > 8 && row[0] != "kind") out[row[4] + "#" + row[3]] = {row[5], row[8]};
    return out;
  }
  std::string last_out_;
};

TEST_F(TrackStudyLabels, OnePredictorUnderTwoLabelsIsTheSameAsWithParam) {
  // GIVEN imm as itself and labelled with coast_cp 1, hold listed last
  const auto both = study("both", "kf-cv,kf-ca,imm,imm-cp1=imm:coast_cp=1,hold");
  // WHEN the labelled one's parameters are given to imm with --param instead
  const auto plain = study("plain", "kf-cv,kf-ca,imm", {"--param", "imm.coast_cp=1"});
  // THEN the label has rows of its own with the figures of its type run with those parameters,
  // and every ratio is to hold (listed last, still the reference)
  for (const char* seed : {"1", "2"}) {
    const std::string s = seed;
    ASSERT_TRUE(both.count("imm-cp1#" + s)) << s;
    EXPECT_EQ(both.at("imm-cp1#" + s), plain.at("imm#" + s)) << s;
    EXPECT_EQ(both.at("kf-cv#" + s), plain.at("kf-cv#" + s)) << s;
    EXPECT_EQ(both.at("hold#" + s).second, "1") << s;
    EXPECT_LT(std::stod(both.at("kf-cv#" + s).second), 1.0) << s;
  }
  EXPECT_NE(last_out_.find("imm / best of kf-cv, kf-ca"), std::string::npos) << last_out_;
}

TEST_F(TrackStudyLabels, ListsThatCannotRunAreRefused) {
  const std::string none = path("none");
  expectError(run({"track-study", "--predictors", "kf-cv,kf-cv=kf-ca", "--out", none}), "--predictors: 'kf-cv' is listed twice", none);
  expectError(run({"track-study", "--predictors", "kf-cv,x=nope", "--out", none}), "unknown predictor 'nope'", none);
  expectError(run({"track-study", "--predictors", "hold=kf-cv", "--out", none}), "the label 'hold' is hold's own", none);
  expectError(run({"track-study", "--predictors", "k2=kf-cv:zz=1", "--out", none}), "zz", none);
}

}  // namespace
}  // namespace predvs
